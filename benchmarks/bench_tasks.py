"""Run the whole workflow on a suite of tasks and tabulate what each front delivers.

Each task (points, payload) runs in a fresh copy of the workflow at a reduced size (``--samples``
LHS samples, ``--mechanisms`` mechanisms; default 30,000 / 2,000), everything else from
config/config.yaml, on the real 600 x 350 x 350 mm printer. Per task it prints one table row:
feasible mechanisms; per front the share of Pareto designs that truly hold the task, the share
that is printable, the true hypervolume, the share with drives and their median drive mass; the
selected design (printable or not, its true peak torques, its drives and their mass); wall time.
A run that stops (a rejected config, a task nothing holds) shows its error instead.

    python benchmarks/bench_tasks.py [--tasks default near_light ...] [--out tasks.json]
        [--set cad.section=sized optimization.objectives=drive_mass ...]

``--set KEY=VALUE`` overrides one config key (dotted path; VALUE read as YAML) in every task.
"""

from __future__ import annotations

import argparse
import json
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import pandas as pd
import yaml

from qsm.embodiment.drives.report import drive_of
from qsm.realization.accuracy.accuracy_budget import TERMS

ROOT = Path(__file__).resolve().parents[1]

#: name: (what it exercises, task points in m, payload in kg)
TASKS: dict[str, tuple[str, list[list[float]], float]] = {
    "default": (
        "palletising cell 0.62 m out, 0.11 m circle",
        [[-0.53, 0.17], [-0.70, 0.02], [-0.60, 0.02], [-0.70, 0.12], [-0.60, 0.12]],
        5.0,
    ),
    "near_light": ("0.35 m out, 0.04 m circle", [[-0.38, 0.05], [-0.30, 0.05]], 1.0),
    "far_heavy": (
        "1.0 m out, 0.2 m circle",
        [[-1.15, 0.0], [-0.75, 0.0], [-0.95, 0.15]],
        10.0,
    ),
    "above_wide": (
        "high on the left (polar 112 deg), 0.13 m circle",
        [[-0.35, 0.55], [-0.15, 0.65], [-0.25, 0.42]],
        3.0,
    ),
    "below_heavy": (
        "below the base (polar 216 deg), 0.08 m circle",
        [[-0.55, -0.30], [-0.45, -0.42]],
        8.0,
    ),
    "right_side": (
        "the default cell mirrored to x > 0 (designed as the mirror image)",
        [[0.53, 0.17], [0.70, 0.02], [0.60, 0.02], [0.70, 0.12], [0.60, 0.12]],
        5.0,
    ),
    "single_point": ("one point", [[-0.6, 0.1]], 5.0),
    "impossible": (
        "a circle round the base, which nothing can hold",
        [[-0.5, 0.0], [0.5, 0.0]],
        5.0,
    ),
}


def copy_workflow(dest: Path) -> None:
    """What a run needs: Snakefile, workflow, config, src."""
    shutil.copy2(ROOT / "Snakefile", dest / "Snakefile")
    for name in ("workflow", "config", "src"):
        shutil.copytree(
            ROOT / name,
            dest / name,
            symlinks=True,
            ignore=shutil.ignore_patterns("__pycache__", "*.egg-info"),
        )


def front_medians(path: Path) -> dict[str, Any]:
    """Median true peak torques (N m) and link mass (kg) over a verified front's designs whose
    dynamics ran, and the truly feasible designs' true (eta, tau1, tau2) (to compare runs on
    one normalisation)."""
    table = pd.read_parquet(path)
    ok = table[table["dynamics_status"].eq("ok")]
    keys = ("tau1_true_Nm", "tau2_true_Nm", "mass_links_kg")
    out: dict[str, Any] = {f"median_{k}": float(ok[k].median()) for k in keys if k in ok}
    feasible = ok[ok["feasible"].astype(bool)]
    out["true_points"] = feasible[["eta_true", "tau1_true_Nm", "tau2_true_Nm"]].to_numpy().tolist()
    return out


def row(work: Path, name: str) -> dict[str, Any]:
    """Figures of a finished run."""
    res = work / "results"
    filters = json.loads((res / "mechanisms/filter_report.json").read_text())
    fronts = json.loads((res / "optimization/comparison.json").read_text())["fronts"]
    selected = json.loads((res / "realization/selected.json").read_text())
    topology = json.loads((res / "realization/topology.json").read_text())
    payload = json.loads((res / "realization/payload_test.json").read_text())
    return {
        "task": name,
        "feasible_mechanisms": filters["task_fits"],
        "samples": filters["samples"],
        "fronts": {
            k: {
                "holds_task": v["holds_task_share"],
                "printable": v["printable_share"],
                "feasible_and_printable": v["feasible_and_printable_share"],
                "median_rel_error": v["median_rel_error"],
                "true_hypervolume": v["true_hypervolume"],
                "holds_loads": v["holds_loads_share"],
                "has_drives": v["has_drives_share"],
                **front_medians(res / f"optimization/{k}/verification.parquet"),
                "true_hypervolume_drive_mass": v.get("true_hypervolume_drive_mass"),
                "median_drive_mass_kg": v.get("median_drive_mass_kg"),
            }
            for k, v in fronts.items()
        },
        "embodiment": embodiment(selected, topology, payload),
        "machine": machine_of(json.loads((res / "realization/machine.json").read_text()), selected),
        "kit": kit_of(json.loads((res / "realization/kit/kit.json").read_text())),
        "infill": {
            k: json.loads((res / f"optimization/{k}/infill.json").read_text())["rounds"]
            for k in fronts
        },
        "cycle": cycle_of(selected.get("cycle")),
        "accuracy": accuracy(
            selected,
            {
                k: json.loads((res / f"optimization/{k}/verification.json").read_text())
                for k in fronts
            },
        ),
        "selected": {
            "source": selected["source"],
            "printable": selected["printable"],
            "tau1_true_Nm": selected["candidate"]["tau1_true_Nm"],
            "tau2_true_Nm": selected["candidate"]["tau2_true_Nm"],
            "mass_links_kg": selected["candidate"].get("mass_links_kg"),
            "holds_loads": selected.get("strength", {}).get("holds_loads"),
            "sections_mm": {
                k: [v.get("width_mm"), v.get("thickness_mm")]
                for k, v in selected.get("strength", {}).get("links", {}).items()
            },
            "scale_m": selected["scale_m"],
            "needed_volume_mm": selected.get("printing_advice", {}).get("needed_volume_mm"),
            "drives": drives_of(selected.get("drives", {})),
        },
    }


def machine_of(machine: dict[str, Any], selected: dict[str, Any]) -> dict[str, Any]:
    """The realised machine's loop and limits: the realisation loop's iterations and tool-flange
    masses (kg), each drive's torque limit (N m), the placing error against the tolerance (mm),
    and the verdict."""
    budget = selected.get("stiffness") or {}
    return {
        "fixed_point": machine["fixed_point"],
        "torque_limits_Nm": machine["torque_limits_Nm"],
        "placing_error_mm": (budget.get("worst") or {}).get("error_budget_mm"),
        "tolerance_mm": budget.get("tolerance_mm"),
        "verdict": selected.get("verdict"),
    }


def kit_of(kit: dict[str, Any]) -> dict[str, Any]:
    """The kit: whether it holds, its problems, whether an assembly order exists and its
    steps, and the base's error at the tool (mm)."""
    sequence = kit.get("assembly_sequence", {})
    return {
        "holds": kit["holds"],
        "problems": kit["problems"],
        "sequence_exists": sequence.get("exists"),
        "steps": len(sequence.get("steps", [])),
        "base_mm": kit["base"]["tool_error_mm"],
    }


def drives_of(report: dict[str, Any]) -> dict[str, Any]:
    """Each motor's drive (or the nearest, marked) from a selected.json ``drives`` report."""
    out: dict[str, Any] = {"has_drives": report.get("has_drives")}
    for key, m in report.get("motors", {}).items():
        d = drive_of(m)
        out[key] = {
            "name": f"{d['motor']} + {d['gearbox']}" + ("" if d["chosen"] else " (NONE)"),
            "ratio": d["ratio"],
            "mass_kg": d["mass_kg"],
        }
    return out


def overrides(pairs: list[str]) -> dict[str, Any]:
    """``["a.b=1", "c=x"]`` -> ``{"a": {"b": 1}, "c": "x"}`` (values read as YAML)."""
    tree: dict[str, Any] = {}
    for pair in pairs:
        key, sep, value = pair.partition("=")
        if not sep or not key:
            raise SystemExit(f"--set expects KEY=VALUE, got {pair!r}")
        *parents, leaf = key.split(".")
        node = tree
        for part in parents:
            node = node.setdefault(part, {})
        node[leaf] = yaml.safe_load(value)
    return tree


def merged(base: dict[str, Any], extra: dict[str, Any]) -> dict[str, Any]:
    """``base`` with ``extra`` merged in, nested dictionaries key by key."""
    out = dict(base)
    for key, value in extra.items():
        both = isinstance(value, dict) and isinstance(out.get(key), dict)
        out[key] = merged(out[key], value) if both else value
    return out


def embodiment(
    selected: dict[str, Any], topology: dict[str, Any], payload: dict[str, Any]
) -> dict[str, Any]:
    """The selected design's strength, drives, optimised links and payload test."""
    links = selected["strength"]["links"]
    weakest = min(
        links, key=lambda k: links[k]["safety_factor"] / links[k]["required_safety_factor"]
    )
    motors = selected["drives"]["motors"]
    return {
        "holds_loads": selected["holds_loads"],
        "weakest_link": weakest,
        "weakest_stress_MPa": links[weakest]["stress_peak_MPa"],
        "allowable_MPa": links[weakest]["allowable_MPa"],
        "min_buckling_factor": min(v["buckling_factor"] for v in links.values()),
        "drives": {
            k: (
                f"{m['drive']['motor']} + {m['drive']['gearbox']} ({m['drive']['ratio']:.4g}:1)"
                if m["has_drive"]
                else "none"
            )
            for k, m in motors.items()
        },
        "min_drive_margin": min(
            (min(m["margins"].values()) for m in motors.values() if m["has_drive"]), default=None
        ),
        "drive_mass_kg": sum(drive_of(m).get("mass_kg", 0.0) for m in motors.values()),
        "optimised_links": {
            k: {
                "stress_MPa": v["max_von_mises_after_MPa"],
                "allowable_MPa": v["allowable_stress_MPa"],
                "kept_solid": v["kept_solid"],
            }
            for k, v in topology["links"].items()
        },
        "payload_test_passed": payload["passed"],
    }


def accuracy(selected: dict[str, Any], fronts: dict[str, Any]) -> dict[str, Any]:
    """The selected design's accuracy budget (worst over the task points), the serial-arm
    comparison, and each front's g15 (``fronts``: their verification.json): its share within the
    tolerance, or that it was dropped."""
    budget = selected.get("stiffness") or {}
    worst = budget.get("worst", {})
    serial = budget.get("serial_arm") or {}
    return {
        "tolerance_mm": budget.get("tolerance_mm"),
        **{k: worst.get(k) for k in TERMS},
        "meets": budget.get("meets_requirements"),
        "serial_sag_mm": serial.get("serial", {}).get("sag_mm"),
        "serial_first_mode_hz": serial.get("serial", {}).get("first_mode_hz"),
        "g15": {
            k: "dropped"
            if "g15 dropped" in (v.get("constraints") or "")
            else f"{100 * v.get('within_tolerance_share', float('nan')):.0f} %"
            for k, v in fronts.items()
        },
    }


def cycle_of(cycle: dict[str, Any] | None) -> dict[str, Any]:
    """The selected design's cycle: time, rate, what binds its moves, how much it was slowed and
    why, how much faster than the raster, and its checks."""
    if not cycle or not cycle.get("planned"):
        return {"planned": False, "reason": (cycle or {}).get("reason")}
    return {
        "planned": True,
        **{k: cycle[k] for k in ("cycle_time_s", "cycles_per_hour", "time_optimal_s",
                                 "slowed_by", "slowed_for", "faster_than_raster", "thermal_ok",
                                 "links_hold", "ok", "strength_utilisation")},
        "binding": sorted({m["optimal_binding"] for m in cycle["moves"]}),
        "mujoco": cycle["simulation"]["reason"],
    }  # fmt: skip


def cycle_markdown(rows: list[dict[str, Any]]) -> str:
    """One row per task that ran: the selected design's time-optimal cycle."""
    lines = [
        "| task | cycle (s) | cycles per hour | time-optimal (s), binding | slowed | x raster "
        "| links | thermal | MuJoCo |",
        "| --- | --- | --- | --- | --- | --- | --- | --- | --- |",
    ]
    for r in rows:
        c = r.get("cycle") or {}
        if "error" in r or not c.get("planned"):
            lines.append(f"| {r['task']} | no cycle: {c.get('reason') or r.get('error')} |")
            continue
        slowed = f"{c['slowed_by']:g}x" + (f" ({c['slowed_for'][0][:60]})" if c["slowed_for"]
                                           else "")  # fmt: skip
        lines.append(
            f"| {r['task']} | {c['cycle_time_s']:.2f} | {c['cycles_per_hour']:,.0f} | "
            f"{c['time_optimal_s']:.2f}, {' / '.join(c['binding'])} | {slowed} | "
            f"{c['faster_than_raster']:.1f} | {c['strength_utilisation']:.2f} | "
            f"{'ok' if c['thermal_ok'] else c['thermal_ok']} | {c['mujoco'][:40]} |"
        )
    return "\n".join(lines)


def accuracy_markdown(rows: list[dict[str, Any]]) -> str:
    """One row per task that ran: the selected design's accuracy and each front's g15."""
    lines = [
        "| task | g15: paper / ratios front | sag, rigid drives (mm) | sag, printed with drives "
        "(mm) | dynamic sag (mm) | creep (mm) | lost motion (mm) | tracking (mm) | budget / "
        "tolerance (mm) | first mode (Hz) | serial 2R arm: sag (mm), first mode (Hz) |",
        "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |",
    ]

    def num(v: Any, fmt: str = ".1f") -> str:
        return "-" if v is None else format(v, fmt)

    for r in rows:
        if "error" in r:
            continue
        a = r["accuracy"]
        g15 = " / ".join(a["g15"].get(k, "-") for k in ("paper", "ratios"))
        budget = f"{num(a['error_budget_mm'])} / {num(a['tolerance_mm'], 'g')}"
        budget += "" if a["meets"] else " (NOT met)"
        lines.append(
            f"| {r['task']} | {g15} | {num(a['sag_rigid_drives_mm'])} | {num(a['sag_mm'])} | "
            f"{num(a['dynamic_sag_mm'])} | {num(a.get('creep_mm'))} | {num(a['lost_motion_mm'])} | "
            f"{num(a['tracking_error_mm'], '.2f')} | {budget} | {num(a['first_mode_hz'])} | "
            f"{num(a['serial_sag_mm'])}, {num(a['serial_first_mode_hz'])} |"
        )
    return "\n".join(lines)


def run_task(
    name: str,
    samples: int,
    mechanisms: int,
    cores: int,
    extra: dict[str, Any] | None = None,
    keep: Path | None = None,
) -> dict[str, Any]:
    """Run the default target for one task in a fresh directory (config keys ``extra`` overridden;
    kept as ``keep``/NAME when given); its row or its error."""
    _, points, payload = TASKS[name]
    with tempfile.TemporaryDirectory(prefix=f"qsm-task-{name}-") as tmp:
        work = Path(tmp) if keep is None else keep / name
        work.mkdir(parents=True, exist_ok=True)
        copy_workflow(work)
        overlay = {
            "sampling": {"n_samples": samples, "n_mechanisms": mechanisms},
            "task": {"points": points, "payload_kg": payload},
        }
        overlay = merged(overlay, extra or {})
        (work / "task.yaml").write_text(yaml.safe_dump(overlay))
        cmd = [sys.executable, "-m", "snakemake", "--cores", str(cores)]
        cmd += ["--configfile", "config/config.yaml", "task.yaml"]
        start = time.perf_counter()
        out = subprocess.run(cmd, cwd=work, capture_output=True, text=True, check=False)
        wall = time.perf_counter() - start
        if out.returncode != 0:
            text = out.stdout + out.stderr
            error = next(
                (
                    line.strip()
                    for line in text.splitlines()
                    if "task.points" in line and "warning" not in line
                ),
                text.strip().splitlines()[-1] if text.strip() else "failed",
            )
            return {"task": name, "error": error, "wall_s": wall}
        result = row(work, name)
        result["wall_s"] = wall
        return result


def markdown(rows: list[dict[str, Any]]) -> str:
    """One table row per task."""
    lines = [
        "| task | what | feasible mechanisms "
        "| paper: hold task / printable / true HV / drives / drive mass "
        "| ratios: hold task / printable / true HV / drives / drive mass "
        "| selected: source, printable, tau1 / tau2 (N m) | selected drives | wall (s) |",
        "| --- | --- | --- | --- | --- | --- | --- | --- |",
    ]
    for r in rows:
        what = TASKS[r["task"]][0] + f", {TASKS[r['task']][2]:g} kg"
        if "error" in r:
            lines.append(
                f"| {r['task']} | {what} | stopped: {r['error']} | | | | | {r['wall_s']:.0f} |"
            )
            continue
        cells = []
        for front in ("paper", "ratios"):
            f = r["fronts"].get(front)
            cells.append(
                f"{100 * f['holds_task']:.0f} % / {100 * f['printable']:.0f} % / "
                f"{f['true_hypervolume']:.3f} / {100 * (f['has_drives'] or 0):.0f} % / "
                f"{f['median_drive_mass_kg'] or float('nan'):.2f} kg"
                if f
                else "-"
            )
        s = r["selected"]
        sel = (
            f"{s['source']}, {'printable' if s['printable'] else 'NOT printable'}, "
            f"{s['tau1_true_Nm']:.1f} / {s['tau2_true_Nm']:.1f}"
        )
        drives = "; ".join(
            f"{d['name']} {d['ratio']:.4g}:1 {d['mass_kg']:.2f} kg"
            for k, d in s["drives"].items()
            if k != "has_drives"
        )
        lines.append(
            f"| {r['task']} | {what} | {r['feasible_mechanisms']:,} of {r['samples']:,} "
            f"| {cells[0]} | {cells[1]} | {sel} | {drives} | {r['wall_s']:.0f} |"
        )
    return "\n".join(lines)


def embodiment_markdown(rows: list[dict[str, Any]]) -> str:
    """One row per task that ran: strength and drives of the fronts and the selected design."""
    lines = [
        "| task | paper / ratios front: hold loads, have drives "
        "| selected: weakest link (stress / allowed MPa), least buckling factor "
        "| drives (motor 1; motor 2), least margin, drive mass "
        "| optimised links: peak / allowed MPa | payload test |",
        "| --- | --- | --- | --- | --- | --- |",
    ]
    for r in rows:
        if "error" in r:
            continue
        e = r["embodiment"]
        fronts = " ; ".join(
            f"{100 * f['holds_loads']:.0f} %, {100 * f['has_drives']:.0f} %"
            for f in (r["fronts"].get("paper"), r["fronts"].get("ratios"))
            if f
        )
        link = (
            f"{e['weakest_link'].replace('_', ' ')} ({e['weakest_stress_MPa']:.1f} / "
            f"{e['allowable_MPa']:.1f}), {e['min_buckling_factor']:.1f}"
        )
        margin = "-" if e["min_drive_margin"] is None else f"{100 * e['min_drive_margin']:.0f} %"
        drives = f"{'; '.join(e['drives'].values())}, {margin}, {e['drive_mass_kg']:.2f} kg"
        topo = ", ".join(
            f"{k.replace('_', ' ')} {v['stress_MPa']:.1f} / {v['allowable_MPa']:.1f}"
            + (" (kept solid)" if v["kept_solid"] else "")
            for k, v in e["optimised_links"].items()
        )
        passed = "passed" if e["payload_test_passed"] else "FAILED"
        lines.append(f"| {r['task']} | {fronts} | {link} | {drives} | {topo} | {passed} |")
    return "\n".join(lines)


def _errors(r: dict[str, Any]) -> str:
    """A round's median / 90th-percentile errors (%) of eta, tau1, tau2."""
    med, p90 = r["median_rel_error"], r["p90_rel_error"]
    return " / ".join(f"{100 * med[k]:.1f}, {100 * p90[k]:.1f}" for k in med)


def infill_markdown(rows: list[dict[str, Any]]) -> str:
    """One table row per task and front: the surrogate's errors on the front before and after
    the adaptive infill, its rounds and true evaluations, and the true hypervolumes."""
    lines = [
        "| task | front | errors before, % (median, p90: eta / tau1 / tau2) | after | rounds "
        "| true evaluations | true HV before / after |",
        "| --- | --- | --- | --- | --- | --- | --- |",
    ]
    for r in rows:
        for front, rounds in r.get("infill", {}).items():
            if not rounds:
                continue
            first, last = rounds[0], rounds[-1]
            lines.append(
                f"| {r['task']} | {front} | {_errors(first)} | {_errors(last)} | "
                f"{len(rounds) - 1} | {last['true_evaluations']} | "
                f"{first['hypervolume']:.4f} / {last['hypervolume']:.4f} |"
            )
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tasks", nargs="+", default=list(TASKS), choices=list(TASKS))
    parser.add_argument("--samples", type=int, default=30_000)
    parser.add_argument("--mechanisms", type=int, default=2_000)
    parser.add_argument("--cores", type=int, default=2)
    parser.add_argument("--out", type=Path, help="also write the rows as JSON here")
    parser.add_argument("--keep", type=Path, help="keep each task's run in this folder")
    parser.add_argument(
        "--set", nargs="+", default=[], metavar="KEY=VALUE", help="config overrides, every task"
    )
    args = parser.parse_args()
    extra = overrides(args.set)
    rows = []
    for name in args.tasks:
        rows.append(run_task(name, args.samples, args.mechanisms, args.cores, extra, args.keep))
        print(f"{name}: {json.dumps(rows[-1])}", flush=True)
    print(markdown(rows))
    print()
    print(embodiment_markdown(rows))
    print()
    print(accuracy_markdown(rows))
    print()
    print(cycle_markdown(rows))
    print()
    print(infill_markdown(rows))
    if args.out:
        args.out.write_text(json.dumps(rows, indent=2))


if __name__ == "__main__":
    main()
