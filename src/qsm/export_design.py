"""Any design out in one call: MJCF, link STLs, URDF, a JSON of its true performance, a drawing.

``python -m qsm export --front paper --rank 1`` (a Pareto design; ranks as in
:mod:`qsm.optimisation.ranking` and the interactive front), ``--id 12`` (a dataset mechanism) or
``--ratios L2 L3 L4 EEX EEY [--task-points X Y ...]`` (any unit design, scaled to the task as
Stage 1 does), or in Python :func:`export`. The folder holds:

* ``model.xml``: the MuJoCo model (MJCF) with the loop closed by an equality, as Stage 2 uses;
* ``stl/<link>.stl``: the four link solids in millimetres, in their link frames;
* ``model.urdf``: the spanning tree of the closed chain with the cut at D stated in the file
  (:mod:`qsm.physics.urdf`; URDF has no loops);
* ``design.json``: the design, where it came from, its true performance from a fresh evaluation
  (:func:`qsm.optimisation.verify.verify_design`: containment of the task at its own scale, eta,
  the MuJoCo peak torques over the duty), its printability per link and, for a front or dataset
  design, the run's own values beside;
* ``design.png``: the design with its workspace, task and link outlines;
* ``README.md``: these files in words.

A front or dataset design is evaluated under ``config``, which must be the run's: the settings
stored in the run's ``dataset.parquet`` are compared with it first, and a difference is an error
naming the keys.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from numpy.typing import ArrayLike

from qsm import settings
from qsm.config import load_config, validate_config
from qsm.embodiment.parts import link_parts, part_meshes
from qsm.embodiment.printing import fits_build_volume, needed_volume_mm
from qsm.embodiment.verdict import strength_record
from qsm.evaluate import checked_lengths, checked_ratios, evaluate_ratios
from qsm.mechanisms.dataset import DATASET_COLUMNS
from qsm.optimisation.constraints import printability_violation_mm
from qsm.optimisation.ranking import front_ranks
from qsm.optimisation.verify import verify_design
from qsm.physics.cad import CadError, link_outlines
from qsm.physics.duty import duty_cycle
from qsm.physics.dynamics import loop_state
from qsm.physics.kinematics import DESIGN_COLUMNS, DESIGN_NAMES, RATIO_NAMES, as_design
from qsm.physics.mirror import design_points, task_record
from qsm.physics.mjcf import mjcf_xml
from qsm.physics.task import min_enclosing_circle
from qsm.physics.urdf import LOOP_NOTE, urdf_xml
from qsm.physics.workspace import OperatingRange
from qsm.realisation.assembly import bearing_rows
from qsm.realisation.export import export_stls
from qsm.realisation.selection import printing_advice
from qsm.report.drawing import draw_links
from qsm.report.figures import draw_design
from qsm.workflow.tables import read_meta, read_table

#: Values of a front's row the JSON carries beside the fresh evaluation.
FRONT_VALUES: tuple[str, ...] = (
    "eta_pred",
    "tau1_pred_Nm",
    "tau2_pred_Nm",
    "eta_true",
    "tau1_true_Nm",
    "tau2_true_Nm",
    "task_contained",
    "printable",
)
#: What :func:`qsm.optimisation.verify.verify_design` evaluates for one design.
TRUE_KEYS: tuple[str, ...] = (
    "crank_rocker",
    "loop_closes",
    "transmission_ok",
    "containment_margin_m",
    "task_contained",
    "feasible",
    "eta_true",
    "tau1_true_Nm",
    "tau2_true_Nm",
    "dynamics_status",
)
#: Where each key of the run's stored settings (dataset.parquet) lives in the config.
SETTING_PATHS: dict[str, tuple[str, ...]] = {
    "task_points": ("task", "points"),
    "payload_kg": ("task", "payload_kg"),
    "duty": ("dynamics", "duty"),
}


def _plain(value: Any) -> Any:
    """JSON-friendly: numpy scalars and arrays as Python values, non-finite floats as None."""
    if isinstance(value, Mapping):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, list | tuple | np.ndarray):
        return [_plain(v) for v in value]
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


#: Settings a run derives and stores beside the config's (the drive catalogue's hash).
DERIVED_KEYS = frozenset({"catalogue_sha256"})


def _same(stored: Any, current: Any) -> bool:
    """Whether ``current`` holds every value of ``stored`` (numbers compared as floats), the
    derived :data:`DERIVED_KEYS` aside."""
    if isinstance(stored, Mapping):
        return isinstance(current, Mapping) and all(
            _same(v, current.get(k)) for k, v in stored.items() if k not in DERIVED_KEYS
        )
    if isinstance(stored, list | tuple):
        return (
            isinstance(current, list | tuple)
            and len(stored) == len(current)
            and all(_same(a, b) for a, b in zip(stored, current, strict=True))
        )
    if isinstance(stored, int | float) and not isinstance(stored, bool):
        return isinstance(current, int | float) and float(stored) == float(current)
    return stored == current


def check_run_config(dataset_path: str | Path, config: Mapping[str, Any]) -> None:
    """``ValueError`` naming the settings in which ``config`` differs from the run that wrote
    ``dataset_path`` (its metadata holds the settings of Stages 1 and 2; all but ``sampling``
    decide how one design evaluates)."""
    stored = read_meta(dataset_path).get("settings", {})
    differ = []
    for key, value in stored.items():
        if key == "sampling":  # which designs the run drew, not how one design is evaluated
            continue
        current: Any = config
        for part in SETTING_PATHS.get(key, (key,)):
            current = current.get(part) if isinstance(current, Mapping) else None
        if key == "task_points" and current is not None:  # the run stores the designed points
            current = design_points(current)
        if not _same(value, current):
            differ.append(key)
    if differ:
        raise ValueError(
            f"the config differs from the run that wrote '{dataset_path}' in: "
            f"{', '.join(differ)}; pass the run's config with --config"
        )


def front_table(results: str | Path, front: str) -> pd.DataFrame:
    """A verified front of a run with its ``rank`` column first (:mod:`qsm.optimisation.ranking`);
    ``ValueError`` naming the fronts there when ``front`` is not one of them."""
    folder = Path(results) / "optimization"
    path = folder / front / "verification.parquet"
    if not path.is_file():
        fronts = sorted(p.parent.name for p in folder.glob("*/verification.parquet"))
        have = ", ".join(fronts) if fronts else "none (run the workflow first)"
        raise ValueError(f"unknown front '{front}' (--front): {folder} holds the fronts: {have}")
    table = read_table(path)
    table.insert(0, "rank", front_ranks(table))
    return table


def front_design(results: str | Path, front: str, rank: int) -> tuple[np.ndarray, dict[str, Any]]:
    """The design of ``front`` at ``rank`` and its source record (with the run's values)."""
    table = front_table(results, front)
    n = len(table)
    if not 1 <= rank <= n:
        raise ValueError(f"--rank {rank} is out of range: the {front} front has ranks 1 to {n}")
    row = table.loc[table["rank"] == rank].iloc[0]
    source = {
        "kind": "front",
        "front": front,
        "rank": rank,
        "n_designs": n,
        "table": str(Path(results) / "optimization" / front / "verification.parquet"),
        "run_values": {k: row[k] for k in FRONT_VALUES},
    }
    return row[list(DESIGN_COLUMNS)].to_numpy(float), source


def dataset_design(results: str | Path, mechanism_id: int) -> tuple[np.ndarray, dict[str, Any]]:
    """The dataset mechanism ``mechanism_id`` and its source record (with the run's values)."""
    path = Path(results) / "dataset.parquet"
    table = read_table(path, DATASET_COLUMNS)
    row = table.loc[table["mechanism_id"] == mechanism_id]
    if row.empty:
        raise ValueError(
            f"--id {mechanism_id} is not a mechanism_id in '{path}' ({len(table)} mechanisms, "
            f"ids {table['mechanism_id'].min()} to {table['mechanism_id'].max()})"
        )
    first = row.iloc[0]
    source = {
        "kind": "dataset",
        "mechanism_id": int(mechanism_id),
        "table": str(path),
        "run_values": {k: first[k] for k in ("eta", "tau1_Nm", "tau2_Nm", "status")},
    }
    return first[list(DESIGN_COLUMNS)].to_numpy(float), source


def ratios_design(ratios: Sequence[float], config: Mapping[str, Any]) -> tuple[np.ndarray, dict]:
    """The unit design ``ratios`` scaled to the config's task as Stage 1 does."""
    try:
        r = checked_ratios(ratios)
    except ValueError as exc:
        raise ValueError(f"--ratios: {exc}") from exc
    result = evaluate_ratios(r, config)
    if not result["feasible"]:
        raise ValueError(f"--ratios: this design cannot hold the task: {result['reason']}")
    design = np.array(list(result["design_m"].values()))
    return design, {"kind": "ratios", "ratios": dict(zip(RATIO_NAMES, r.tolist(), strict=True))}


def drawing(
    design: ArrayLike,
    config: Mapping[str, Any],
    boxes: Mapping[str, Mapping[str, Any]],
    title: str,
    path: str | Path,
) -> Path:
    """PNG: the design with workspace, task disk and points, and its link outlines with their
    boxes (mm) against the printer."""
    d = as_design(design)
    op = settings.operating_range(config["operating_range"])
    points = np.asarray(design_points(config["task"]["points"]))
    fig, (ax, ax_links) = plt.subplots(1, 2, figsize=(12, 5.2), width_ratios=(1, 1.1))
    draw_design(ax, d, op, min_enclosing_circle(points), title)
    ax.plot(points[:, 0], points[:, 1], "x", color="tab:red", ms=6, mew=1.5)
    y = 0.0
    volume = " x ".join(f"{v:g}" for v in config["printing"]["build_volume_mm"])
    for name, outline in link_outlines(d, settings.cad(config["cad"], config["material"])).items():
        xy = outline * 1e3
        y -= xy[:, 1].max()
        ax_links.fill(xy[:, 0], xy[:, 1] + y, color="0.75", ec="k", lw=0.8)
        box = boxes[name]
        ax_links.text(
            xy[:, 0].min(),
            y + xy[:, 1].max() + 8,
            f"{name}: {' x '.join(f'{v:.0f}' for v in box['box_mm'])} mm, "
            f"{'fits' if box['fits'] else 'does NOT fit'}",
            fontsize=8,
        )
        y += xy[:, 1].min() - 45
    ax_links.set_aspect("equal")
    ax_links.set_xlabel("mm (link frames)")
    ax_links.set_yticks([])
    ax_links.set_title(f"links as printed, printer {volume} mm", fontsize=9)
    fig.tight_layout()
    out = Path(path)
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return out


def export_design(
    design: ArrayLike,
    config: Mapping[str, Any],
    out: str | Path,
    source: Mapping[str, Any] | None = None,
) -> dict[str, Any]:
    """Write the export folder (see the module docstring) of ``design`` (6 lengths, m) under a
    validated ``config``; returns the record written to ``design.json``."""
    d = np.asarray(as_design(design), dtype=float)
    folder = Path(out)
    folder.mkdir(parents=True, exist_ok=True)
    cad = settings.cad(config["cad"], config["material"])
    payload = float(config["task"]["payload_kg"])
    volume = tuple(float(v) for v in config["printing"]["build_volume_mm"])
    fit = settings.fit(
        config["operating_range"],
        config["task"]["points"],
        config["scale"],
        config["workspace"],
        config["filters"],
    )
    try:
        link_outlines(d, cad)
    except CadError as exc:
        raise ValueError(f"config 'cad': the link section does not fit this design: {exc}") from exc
    duty_settings = settings.duty(config["dynamics"]["duty"], config["operating_range"])
    duty = duty_cycle(duty_settings)
    verified = verify_design(d, fit, duty, cad, payload)
    performance = {k: verified[k] for k in TRUE_KEYS}
    task = task_record(config["task"]["points"])
    xml = mjcf_xml(d, cad, payload, home_pose(d, fit.op), mirrored=bool(task["mirrored"]))
    (folder / "model.xml").write_text(xml)
    check = settings.strength_check(
        config["cad"], config["material"], config["strength"], payload, duty_settings
    )
    strength = strength_record(d, check)
    part_settings = settings.parts(config["cad"], config["material"], config["strength"])
    names = {j: b["designation"] for j, b in strength["bearings"].items()}
    parts = link_parts(d, bearing_rows(names, part_settings.table), part_settings)
    stl = export_stls(part_meshes(parts, cad), folder / "stl", volume)
    draw_links(d, parts, folder / "drawing", cad)
    fits = fits_build_volume(d, cad, volume)
    links = {
        name: {
            "file": f"stl/{name}.stl",
            "box_mm": list(fits[name]["dims_mm"]),
            "fits": fits[name]["fits"],
            "watertight": stl[name]["watertight"],
        }
        for name in fits
    }
    printable = all(link["fits"] for link in links.values())
    printability: dict[str, Any] = {
        "printable": printable,
        "build_volume_mm": list(volume),
        "print_excess_mm": float(printability_violation_mm(d[None], cad, volume)[0]),
        "needed_volume_mm": needed_volume_mm(d[None], None, cad)[0].tolist(),
        "links": links,
    }
    if not printable:
        printability["advice"] = printing_advice(d, cad, volume, fit.disk)
    test = config["payload_test"]
    op = config["operating_range"]
    drives = settings.drive_check(
        config["drives"],
        config["cad"],
        config["material"],
        payload,
        settings.duty(config["dynamics"]["duty"], op),
    ).report(d)
    effort = test["torque_limits_Nm"] or _drive_efforts(drives, config)
    urdf = urdf_xml(
        d,
        cad,
        payload,
        motor_range_deg=(op["theta1_deg"], (op["theta2_min_deg"], op["theta1_deg"][1])),
        effort_Nm=effort,
        velocity_rad_s=math.radians(config["dynamics"]["duty"]["peak_speed_deg_s"]),
    )
    (folder / "model.urdf").write_text(urdf)
    record: dict[str, Any] = {
        "design": {
            "lengths_m": dict(zip(DESIGN_NAMES, d.tolist(), strict=True)),
            "scale_m": float(d[0]),
            "ratios": dict(zip(RATIO_NAMES, (d[1:] / d[0]).tolist(), strict=True)),
        },
        "source": dict(source or {"kind": "design"}),
        "task": {
            **task,
            "payload_kg": payload,
            "disk": {"centre_m": list(fit.disk.centre), "radius_m": fit.disk.radius},
        },
        "true_performance": performance,
        "printability": printability,
        "strength": strength,
        "parts": {name: {"holes": p.holes} for name, p in parts.items()},
        "drives": drives,
        "files": {
            "mjcf": "model.xml",
            "urdf": "model.urdf",
            "stl": [link["file"] for link in links.values()],
            "drawing": "design.png",
            "dimensioned_drawing": ["drawing.svg", "drawing.png"],
            "json": "design.json",
        },
        "urdf": {
            "written": True,
            "closed_loop": LOOP_NOTE,
        },
    }
    record = _plain(record)
    title = (
        f"{_describe(record['source'])}: l1 {d[0]:.3f} m\n"
        f"true eta {_fmt(performance['eta_true'], 4)}, tau1 {_fmt(performance['tau1_true_Nm'], 1)}"
        f" N m, tau2 {_fmt(performance['tau2_true_Nm'], 1)} N m; "
        f"{'holds the task' if performance['feasible'] else 'does NOT hold the task'}, "
        f"{'printable' if printable else 'NOT printable'}, "
        f"{'links hold their loads' if strength['holds_loads'] else 'NOT STRONG ENOUGH'}"
        + ("; designed MIRRORED (x -> -x)" if task["mirrored"] else "")
    )
    drawing(d, config, links, title, folder / "design.png")
    (folder / "design.json").write_text(json.dumps(record, indent=2) + "\n")
    (folder / "README.md").write_text(_readme(record, title))
    return record


def home_pose(design: ArrayLike, op: OperatingRange) -> np.ndarray:
    """Joint positions (rad, :data:`qsm.physics.mjcf.JOINT_NAMES` order) of the loop at the
    middle of the motor ranges: theta1 mid-range, theta2 midway between its limit and theta1."""
    t1 = 0.5 * (op.theta1_min + op.theta1_max)
    t2 = 0.5 * (op.theta2_min + t1)
    zero = np.zeros((1, 2))
    return loop_state(design, [[t1, t2]], zero, zero).q[0]


def _fmt(value: float | None, digits: int) -> str:
    return "n/a" if value is None or not np.isfinite(value) else f"{value:.{digits}f}"


def _describe(source: Mapping[str, Any]) -> str:
    kind = source.get("kind")
    if kind == "front":
        return f"{source['front']} front, rank {source['rank']} of {source['n_designs']}"
    if kind == "dataset":
        return f"dataset mechanism {source['mechanism_id']}"
    if kind == "ratios":
        return "ratios " + ", ".join(f"{k} {v:.4g}" for k, v in source["ratios"].items())
    if kind == "lengths":
        return "lengths (m) " + ", ".join(f"{k} {v:.4g}" for k, v in source["lengths_m"].items())
    return "design"


def _readme(record: Mapping[str, Any], title: str) -> str:
    heading = title.replace("\n", "; ")
    return (
        f"# {_describe(record['source'])}\n\n{heading}.\n\n"
        "| file | what |\n| --- | --- |\n"
        "| `model.xml` | MuJoCo model (MJCF): the closed chain, its loop closed by an equality "
        "`connect` at D |\n"
        "| `stl/*.stl` | the four links to print, in millimetres, in their link frames: solid "
        "plates (not topology-optimised; the workflow's `realization/stl/after` has those) with "
        "a through bore per joint, sized for the joint's bearing (seat at B, C, D, pin or motor "
        "shaft in the other link; `design.json`, `strength.bearings`) |\n"
        "| `drawing.svg`, `drawing.png` | the dimensioned drawing of the links: lengths, hole "
        "centres, bore diameters, section |\n"
        "| `model.urdf` | the spanning tree of the closed chain (see below) |\n"
        "| `design.json` | the design, its source, its true performance from a fresh "
        "evaluation and its printability |\n"
        "| `design.png` | the design with workspace, task and link outlines |\n\n"
        "The MJCF's keyframe `home` is a pose with the loop closed (the middle of the motor "
        "ranges). The payload is a point mass at E merged into the upper arm's inertial (the "
        "site `payload` marks E).\n\n"
        f"URDF and the closed loop: {LOOP_NOTE}\n"
        + (
            f"\nMirrored: {record['task']['note']}. `model.xml` is the mirrored arm (x negated, "
            "hinge axes reversed; its end effector visits your points); the STLs are the plates "
            "to print (turn them over to assemble); `design.png`, the drawing and `model.urdf` "
            "show the design as computed, at x < 0.\n"
            if record["task"]["mirrored"]
            else ""
        )
    )


def export(
    *,
    front: str | None = None,
    rank: int | None = None,
    mechanism_id: int | None = None,
    ratios: Sequence[float] | None = None,
    lengths: Sequence[float] | None = None,
    task_points: Sequence[Sequence[float]] | None = None,
    config: str | Path | Mapping[str, Any] | None = None,
    results: str | Path = "results",
    out: str | Path | None = None,
) -> dict[str, Any]:
    """Export one design (see the module docstring): a Pareto design (``front`` and ``rank``), a
    dataset mechanism (``mechanism_id``), a unit design (``ratios``, scaled to the task, which
    ``task_points`` may replace) or a design's six ``lengths`` (m, at that scale). ``config`` is
    a YAML path, a config mapping or None (defaults); ``results`` the run's results folder;
    ``out`` the export folder (default ``results/exports/...``). Returns the ``design.json``
    record with ``folder``."""
    given = [v is not None for v in (front, mechanism_id, ratios, lengths)]
    if sum(given) != 1:
        raise ValueError("give exactly one of --front (with --rank), --id, --ratios or --lengths")
    if (front is None) != (rank is None):
        raise ValueError("--front and --rank go together: --front NAME --rank K")
    if task_points is not None and ratios is None and lengths is None:
        raise ValueError(
            "--task-points applies to --ratios and --lengths only: a front or dataset design was "
            "made for the run's task"
        )
    cfg = dict(config) if isinstance(config, Mapping) else load_config(config)
    if task_points is not None:
        cfg["task"] = {**cfg["task"], "points": [list(map(float, p)) for p in task_points]}
        try:
            cfg = validate_config(cfg)
        except ValueError as exc:
            raise ValueError(f"--task-points: {exc}") from exc
    if front is not None:
        design, source = front_design(results, front, int(rank))  # type: ignore[arg-type]
        default = f"{front}-rank-{rank}"
    elif mechanism_id is not None:
        design, source = dataset_design(results, int(mechanism_id))
        default = f"mechanism-{mechanism_id}"
    elif lengths is not None:
        try:
            design = checked_lengths(lengths)
        except ValueError as exc:
            raise ValueError(f"--lengths: {exc}") from exc
        source = {
            "kind": "lengths",
            "lengths_m": dict(zip(DESIGN_NAMES, design.tolist(), strict=True)),
        }
        default = "lengths-" + "-".join(f"{v:.4f}" for v in design)
    else:
        design, source = ratios_design(ratios, cfg)  # type: ignore[arg-type]
        default = "ratios-" + "-".join(f"{v:.4f}" for v in source["ratios"].values())
    if source["kind"] not in ("ratios", "lengths"):
        check_run_config(Path(results) / "dataset.parquet", cfg)
    folder = Path(out) if out is not None else Path(results) / "exports" / default
    record = export_design(design, cfg, folder, source)
    return {"folder": str(folder), **record}


def _drive_efforts(drives: Mapping[str, Any], config: Mapping[str, Any]) -> list[float]:
    """Each motor's standstill peak torque at the joint (N m) of its drive (or the nearest) in a
    :meth:`qsm.embodiment.drive_checks.DriveCheck.report`; 0 where the loop is undefined."""
    from qsm.embodiment.drives.selection import OutputEnvelope

    cat = settings.catalogue(config["drives"])
    out = []
    for j in ("motor1", "motor2"):
        m = drives["motors"].get(j)
        if m is None:
            out.append(0.0)
            continue
        d = m.get("drive") or m["best_drive"]
        env = OutputEnvelope.of(cat, d["motor_key"], d["gearbox_key"])
        out.append(float(env.limit(1.0, 0.0)))
    return out
