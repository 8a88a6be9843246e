"""An independent line-by-line check of a run's datasheet: every row of its table is parsed and
held against the run's records (``selected.json``, ``bom.csv``, the effective config), by a
checker for its quantity; a row no checker knows is an error, so a new line cannot go unbacked.

Run on a finished run: ``python tests/datasheet_lines.py <run dir>`` prints each line's result.
"""

from __future__ import annotations

import json
import re
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd


def rows(sheet: str) -> dict[str, str]:
    """The rows of the datasheet's ``| quantity | value |`` table, by quantity."""
    table = sheet.split("| quantity | value |\n| --- | --- |\n")[1].split("\n\n")[0]
    cells = (re.match(r"^\| (.+?) \| (.+) \|$", line).groups() for line in table.splitlines())
    return {k: v.replace("\\|", "|") for k, v in cells}


def _numbers(text: str) -> list[float]:
    return [float(v) for v in re.findall(r"-?\d+(?:\.\d+)?", text)]


def _payload(v: str, r: dict[str, Any]) -> None:
    s = r["selected"]
    assert v.startswith(f"{r['config']['task']['payload_kg']:g} kg at the tool")
    assert f"{s['tool_flange_kg']:.3f} kg tool flange" in v


def _task(v: str, r: dict[str, Any]) -> None:
    pts = np.asarray(r["config"]["task"]["points"], dtype=float)
    assert v.startswith(f"{len(pts)} points")
    x, y = pts[:, 0], pts[:, 1]
    assert f"x {x.min():.3f} to {x.max():.3f} m, y {y.min():.3f} to {y.max():.3f} m" in v


def _mass(v: str, r: dict[str, Any]) -> None:
    bom = r["bom"].dropna(subset=["mass_kg"])
    built = float((bom["mass_kg"] * bom["quantity"]).sum())
    total, as_built = _numbers(re.search(r"([0-9.]+) kg in all: ([0-9.]+) kg as built", v)[0])
    hardware = float(re.search(r"([0-9.]+) kg of bearings and fasteners, weighed", v)[1])
    assert as_built == round(built, 2) and abs(total - (as_built + hardware)) <= 0.011
    moving = r["bom"].loc[r["bom"]["category"].isin(["printed part", "turned part"])]
    moving_parts = float((moving["mass_kg"] * moving["quantity"]).sum())
    stated = re.search(r"([0-9.]+) kg of it moves .* flange, ([0-9.]+) kg of bearings", v)
    assert abs(float(stated[1]) - (moving_parts + float(stated[2]))) <= 0.011


def _drive(j: int) -> Callable[[str, dict[str, Any]], None]:
    def check(v: str, r: dict[str, Any]) -> None:
        motor = r["selected"]["drives"]["motors"][f"motor{j}"]
        d = motor.get("drive") or motor["best_drive"]
        assert v.startswith(f"{d['motor']} + {d['gearbox']} ({d['ratio']:g}:1")
        assert f"{d['mass_kg']:.2f} kg" in v

    return check


def _limits(v: str, r: dict[str, Any]) -> None:
    t = r["selected"]["torque_limits_Nm"]
    assert v.startswith(f"{t[0]:.1f} / {t[1]:.1f} N m")


def _bearings(v: str, r: dict[str, Any]) -> None:
    b = r["bom"].loc[r["bom"]["category"] == "bearing"]
    for where, designation in zip(b["where"], b["designation"], strict=True):
        assert f"{where} {designation}" in v
    assert "A: the drives' output bearings" in v


def _material(v: str, r: dict[str, Any]) -> None:
    assert v == f"{r['selected']['strength']['material']}, printed"


def _cycles(v: str, r: dict[str, Any]) -> None:
    c = r["selected"]["cycle"]
    if not c["planned"]:
        assert v == f"none: no cycle could be planned ({c['reason']})"
        return
    assert v.startswith(f"{3600 / c['cycle_time_s']:,.0f} on the task ({c['cycle_time_s']:.2f} s")
    assert ("checks pass" in v) == bool(c["ok"])
    if c.get("settling"):
        assert f"at most {max(s['ringing_mm'] for s in c['settling']):.2f} mm on arrival" in v
        assert ("longer where the arm must settle" in v) == (max(c["dwells_s"]) > c["dwell_s"])
    jerk = c.get("jerk") or {}
    if jerk.get("jerk_time_s") is not None:
        assert f"ramped over {1e3 * jerk['jerk_time_s']:.0f} ms" in v
        assert jerk["first_mode_hz"] is None or f"{jerk['first_mode_hz']:.2f} Hz first mode" in v
        for m in c["moves"]:  # the moves as run keep their stated jerk
            peak, limit = np.asarray(m["peak_jerk_rad_s3"]), np.asarray(m["jerk_limit_rad_s3"])
            assert (peak <= limit * (1 + 1e-6)).all()


def _mechanical(v: str, r: dict[str, Any]) -> None:
    c = r["selected"]["cycle"]
    n = _numbers(v)
    assert n[0:2] == [round(p) for p in c["peak_power_W"]]
    assert f"{c['energy_per_cycle_J']:.0f} J per cycle" in v


def _electrical(v: str, r: dict[str, Any]) -> None:
    for j, e in enumerate(r["selected"]["cycle"]["electrical"], start=1):
        expected = e if isinstance(e, str) else f"peak {e['peak_W']:.0f} W"
        assert f"motor {j}: {expected}" in v


def _placing(v: str, r: dict[str, Any]) -> None:
    per = r["selected"]["stiffness"]["per_point"]
    i = int(np.argmax(per["error_budget_mm"]))
    total = _numbers(v)[0]
    worst = per["error_budget_mm"][i]  # to 2 decimals, at most 4 significant digits
    assert abs(total - worst) <= 0.005 + 5e-4 * worst and f"task point {i + 1}" in v
    terms = [float(x) for x in re.findall(r"(?:sag|creep|motion|error|base) ([0-9.]+) mm", v)]
    assert abs(sum(terms) - total) <= 0.021 + 3e-3 * total


def _mode(v: str, r: dict[str, Any]) -> None:
    assert v.startswith(f"{r['selected']['stiffness']['worst']['first_mode_hz']:.1f} Hz")


def _ap(v: str, r: dict[str, Any]) -> None:
    iso = r["selected"]["iso9283"]
    i = int(np.argmax(iso["ap_mm"]))
    assert v.startswith(f"{iso['ap_mm'][i]:.2f} mm worst, at P{i + 1}")
    sag, base, rand = (float(x) for x in re.findall(r"(?:sag|base|error,) ([0-9.]+) mm", v)[:3])
    assert abs(iso["ap_mm"][i] - (sag + base)) <= rand + 0.011  # the triangle inequality


def _rp(v: str, r: dict[str, Any]) -> None:
    iso = r["selected"]["iso9283"]
    k = iso["worst_point"] - 1
    assert v.startswith(f"±{max(iso['rp_mm']):.3f} mm worst, at P{k + 1}")
    main = iso["main_random_term"]
    assert iso["rp_alone_mm"][main][k] == max(x[k] for x in iso["rp_alone_mm"].values())
    assert f"main random term {main}" in v


def _not_simulated(v: str, r: dict[str, Any]) -> None:
    iso = r["selected"]["iso9283"]
    assert not iso["simulated"] and v == f"not simulated: {iso['reason']}"


def _standard(v: str, r: dict[str, Any]) -> None:
    std = r["selected"]["standard_cycle"]
    if not std["planned"]:
        assert v == f"none: {std['reason']}"
        return
    for c in std["payloads"]:
        if not c["planned"]:
            assert f"at {c['payload_kg']:g} kg none could be planned ({c['reason']})" in v
            continue
        assert f"{c['cycle_time_s']:.2f} s at {c['payload_kg']:g} kg" in v
        assert ("its checks pass" in v) or not c["ok"]
    assert {c["payload_kg"] for c in std["payloads"]} == {r["config"]["task"]["payload_kg"], 1.0}


def _reach(v: str, r: dict[str, Any]) -> None:
    assert v.startswith(f"{r['reach_m']:.3f} m from the base joint A")


#: A checker per quantity (the standard cycle's label carries its stroke).
CHECKS: dict[str, Callable[[str, dict[str, Any]], None]] = {
    "payload": _payload,
    "reach": _reach,
    "task": _task,
    "mass": _mass,
    "drive 1": _drive(1),
    "drive 2": _drive(2),
    "torque limits": _limits,
    "bearings": _bearings,
    "material": _material,
    "cycles per hour": _cycles,
    "mechanical power": _mechanical,
    "electrical power": _electrical,
    "placing error": _placing,
    "first mode": _mode,
    "pose accuracy AP (ISO 9283)": _ap,
    "pose repeatability RP (ISO 9283)": _rp,
    "standard cycle": _standard,
    "pose accuracy and repeatability (ISO 9283)": _not_simulated,
}


def check_lines(sheet: str, records: dict[str, Any]) -> dict[str, str]:
    """Each row's quantity and ``ok`` or what is wrong; ``records``: ``selected``, ``bom``,
    ``config`` and ``reach_m`` (the farthest tool point within the operating range)."""
    out = {}
    for label, value in rows(sheet).items():
        key = "standard cycle" if label.startswith("standard cycle") else label
        if key not in CHECKS:
            out[label] = "no checker: an unbacked line"
            continue
        try:
            CHECKS[key](value, records)
            out[label] = "ok"
        except (AssertionError, KeyError, ValueError) as exc:
            out[label] = f"wrong: {type(exc).__name__} {exc}"
    return out


def run_records(run: Path, config: dict[str, Any], reach_m: float) -> dict[str, Any]:
    """The records of a finished ``run`` that the checkers read."""
    real = run / "results/realization"
    return {
        "selected": json.loads((real / "selected.json").read_text()),
        "bom": pd.read_csv(real / "bom.csv"),
        "config": config,
        "reach_m": reach_m,
    }


if __name__ == "__main__":
    from qsm.config.reading import load_config
    from qsm.physics.workspace import operating_reach

    run = Path(sys.argv[1])
    cfg = load_config(*sorted((run / "config").glob("config.yaml")), *run.glob("task.yaml"))
    sel = json.loads((run / "results/realization/selected.json").read_text())
    op = cfg["operating_range"]
    reach = operating_reach(sel["design_m"], op["theta1_deg"], op["theta2_min_deg"]).reach_m
    results = check_lines((run / "results/datasheet.md").read_text(), run_records(run, cfg, reach))
    for label, result in results.items():
        print(f"{label}: {result}")
    sys.exit(0 if all(v == "ok" for v in results.values()) else 1)
