"""Any design out in one call: MJCF, link STLs, URDF, a JSON of its true performance, a drawing.

``python -m qsm export --front paper --rank 1`` (a Pareto design; ranks as in
:mod:`qsm.optimization.ranking` and the interactive front), ``--id 12`` (a dataset mechanism) or
``--ratios L2 L3 L4 EEX EEY [--task-points X Y ...]`` (any unit design, scaled to the task as
Stage 1 does), or in Python :func:`export`. The folder holds:

* ``model.xml``: the MuJoCo model (MJCF) with the loop closed by an equality, as Stage 2 uses;
* ``stl/<link>.stl``: the four link solids in millimetres, in their link frames;
* ``model.urdf``: the spanning tree of the closed chain with the cut at D stated in the file
  (:mod:`qsm.physics.urdf`; URDF has no loops);
* ``design.json``: the design, where it came from, its true performance from a fresh evaluation
  (:func:`qsm.optimization.verify.verify_design`: containment of the task at its own scale, eta,
  the MuJoCo peak torques over the duty), its printability per link and, for a front or dataset
  design, the run's own values beside;
* ``machine.json``: the realised machine (:func:`qsm.realization.selection.machine.machine_record`),
  built as the workflow builds its ``realization/machine.json``: the same design under the same
  config gives the same record;
* ``design.png``: the design with its workspace, task and link outlines;
* ``README.md``: these files in words.

A front or dataset design is evaluated under ``config``, which must be the run's: the settings
stored in the run's ``dataset.parquet`` are compared with it first, and a difference is an error
naming the keys.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from qsm.app.evaluate import checked_lengths
from qsm.app.export_readme import describe_source, export_readme, fmt
from qsm.app.locate import (
    TRUE_KEYS,
    check_run_config,
    dataset_design,
    front_design,
    plain,
    ratios_design,
)
from qsm.config.reading import load_config, validate_config
from qsm.config.settings import actuation, physics, realization
from qsm.embodiment.drives.report import DriveReport, report_json
from qsm.embodiment.parts.link_parts import part_meshes
from qsm.embodiment.parts.printing import link_printability
from qsm.embodiment.strength.record import strength_json
from qsm.optimization.verify import verify_design
from qsm.physics.cad import CadError, CadSettings, mass_properties
from qsm.physics.duty import duty_cycle
from qsm.physics.dynamics import loop_state
from qsm.physics.kinematics import DESIGN_NAMES, RATIO_NAMES, as_design
from qsm.physics.mirror import design_points, task_record
from qsm.physics.mjcf import mjcf_xml
from qsm.physics.task import Disk
from qsm.physics.urdf import LOOP_NOTE, urdf_xml
from qsm.physics.workspace import OperatingRange
from qsm.realization.selection.choice import printing_advice
from qsm.realization.selection.machine import machine_record
from qsm.realization.selection.outputs import export_stls
from qsm.realization.selection.pipeline import Realization, budget_of, carrying, realize
from qsm.report.design_sheet import design_sheet
from qsm.report.drawing import draw_links
from qsm.workflow.json_files import write_json


def _files(links: Mapping[str, Any]) -> dict[str, Any]:
    """The export folder's files, by kind."""
    return {
        "mjcf": "model.xml",
        "urdf": "model.urdf",
        "stl": [link["file"] for link in links.values()],
        "drawing": "design.png",
        "dimensioned_drawing": ["drawing.svg", "drawing.png"],
        "json": "design.json",
    }


def _accuracy(done: Realization, config: Mapping[str, Any]) -> dict[str, Any]:
    """The accuracy budget of the exported (solid) parts at the task points the design serves,
    or why there is none (a point it cannot reach)."""
    try:
        points = design_points(config["task"]["points"])
        settings = carrying(realization.realization_of(config), done.tool_kg)
        budget = budget_of(done, settings, points)
    except ValueError as exc:
        return {"meets_requirements": False, "verdict": f"no accuracy budget: {exc}"}
    budget["verdict"] += " (solid parts; without tracking error: qsm export runs no payload test)"
    return budget


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
    cad = physics.cad(config["cad"], config["material"])
    payload = float(config["task"]["payload_kg"])
    volume = tuple(float(v) for v in config["printing"]["build_volume_mm"])
    fit = physics.fit_of(config)
    duty = duty_cycle(physics.duty(config["dynamics"]["duty"], config["operating_range"]))
    try:
        done = realize(d, realization.realization_of(config))
    except CadError as exc:
        raise ValueError(f"config 'cad': the link section does not fit this design: {exc}") from exc
    accuracy = _accuracy(done, config)
    scale, parts = done.scale, done.parts
    verified = verify_design(d, fit, duty, cad, payload, None if scale is None else np.array(scale))
    performance = {k: verified[k] for k in TRUE_KEYS}
    task = task_record(config["task"]["points"])
    printability = _write_models(done, config, bool(task["mirrored"]), folder)
    links = printability["links"]
    drives = report_json(done.drives)
    record: dict[str, Any] = {
        "design": _lengths(d),
        "source": dict(source or {"kind": "design"}),
        "task": {
            **task,
            "payload_kg": payload,
            "disk": {"centre_m": list(fit.disk.centre), "radius_m": fit.disk.radius},
        },
        "true_performance": performance,
        "printability": printability,
        "strength": strength_json(done.strength),
        "parts": {name: {"holes": p.holes} for name, p in parts.items()},
        "drives": drives,
        "tool_flange_kg": done.tool_kg,
        "torque_limits_Nm": list(done.torque_limits_Nm),
        "stiffness": accuracy,
        "files": _files(links),
        "urdf": {"written": True, "closed_loop": LOOP_NOTE},
    }
    record = plain(record)
    title = _title(record, d)
    points = design_points(config["task"]["points"])
    design_sheet(d, fit.op, cad, points, volume, links, title, folder / "design.png", scale)
    write_json(folder / "design.json", record)
    write_json(folder / "machine.json", machine_record(done))  # the workflow's record, the same way
    (folder / "README.md").write_text(export_readme(record, title))
    return record


def _lengths(d: np.ndarray) -> dict[str, Any]:
    """``design.json``'s design: the lengths (m), the scale l1 (m) and the ratios to it."""
    return {
        "lengths_m": dict(zip(DESIGN_NAMES, d.tolist(), strict=True)),
        "scale_m": float(d[0]),
        "ratios": dict(zip(RATIO_NAMES, (d[1:] / d[0]).tolist(), strict=True)),
    }


def _write_models(
    done: Realization, config: Mapping[str, Any], mirrored: bool, folder: Path
) -> dict[str, Any]:
    """Write the MJCF, URDF, STL files and drawing of the realised design ``done`` into
    ``folder``; returns its printability (:func:`_printability`)."""
    d, scale = done.design, done.scale
    cad = physics.cad(config["cad"], config["material"])
    payload = float(config["task"]["payload_kg"]) + done.tool_kg  # the tool flange at E
    volume = tuple(float(v) for v in config["printing"]["build_volume_mm"])
    fit = physics.fit_of(config)
    props = mass_properties(d, cad, scale)  # the solid links of each link's section
    pose = home_pose(d, fit.op)
    xml = mjcf_xml(d, cad, payload, pose, mirrored, props, done.torque_limits_Nm)
    (folder / "model.xml").write_text(xml)
    stl = export_stls(part_meshes(done.parts), folder / "stl", volume)
    draw_links(d, done.parts, folder / "drawing")
    _write_urdf(d, cad, payload, props, done.drives, config, folder / "model.urdf")
    return _printability(d, cad, scale, volume, stl, fit.disk)


def _printability(
    d: np.ndarray,
    cad: CadSettings,
    scale: tuple[float, ...] | None,
    volume: tuple[float, ...],
    stl: Mapping[str, Mapping[str, Any]],
    disk: Disk,
) -> dict[str, Any]:
    """``design.json``'s printability: each link's box (mm), fit, STL file and whether it is
    watertight, the excess and the volume needed, and the advice when a link does not fit."""
    boxes = link_printability(d, cad, scale, volume)
    fits = boxes["links"]
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
        "print_excess_mm": boxes["print_excess_mm"],
        "needed_volume_mm": boxes["needed_volume_mm"],
        "links": links,
    }
    if not printable:
        printability["advice"] = printing_advice(d, cad, volume, disk, scale)
    return printability


def _write_urdf(
    d: np.ndarray,
    cad: CadSettings,
    payload: float,
    props: Mapping[str, Any],
    drives: DriveReport,
    config: Mapping[str, Any],
    path: Path,
) -> None:
    """The URDF with the motors' ranges, efforts (the override, or the drives') and speed."""
    op = config["operating_range"]
    effort = config["payload_test"]["torque_limits_Nm"] or _drive_efforts(drives, config)
    urdf = urdf_xml(
        d,
        cad,
        payload,
        motor_range_deg=(op["theta1_deg"], (op["theta2_min_deg"], op["theta1_deg"][1])),
        effort_Nm=effort,
        velocity_rad_s=math.radians(config["dynamics"]["duty"]["peak_speed_deg_s"]),
        props=props,
    )
    path.write_text(urdf)


def _title(record: Mapping[str, Any], d: np.ndarray) -> str:
    """The design sheet's title: the source, scale, true objectives and the verdicts."""
    performance = record["true_performance"]
    return (
        f"{describe_source(record['source'])}: l1 {d[0]:.3f} m\n"
        f"true eta {fmt(performance['eta_true'], 4)}, tau1 {fmt(performance['tau1_true_Nm'], 1)}"
        f" N m, tau2 {fmt(performance['tau2_true_Nm'], 1)} N m; "
        f"{'holds the task' if performance['feasible'] else 'does NOT hold the task'}, "
        f"{'printable' if record['printability']['printable'] else 'NOT printable'}, "
        f"{'links hold their loads' if record['strength']['holds_loads'] else 'NOT STRONG ENOUGH'}"
        + ("; designed MIRRORED (x -> -x)" if record["task"]["mirrored"] else "")
    )


def home_pose(design: ArrayLike, op: OperatingRange) -> np.ndarray:
    """Joint positions (rad, :data:`qsm.physics.mjcf.JOINT_NAMES` order) of the loop at the
    middle of the motor ranges: theta1 mid-range, theta2 midway between its limit and theta1."""
    t1 = 0.5 * (op.theta1_min + op.theta1_max)
    t2 = 0.5 * (op.theta2_min + t1)
    zero = np.zeros((1, 2))
    return loop_state(design, [[t1, t2]], zero, zero).q[0]


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


def _drive_efforts(drives: DriveReport, config: Mapping[str, Any]) -> list[float]:
    """Each motor's standstill peak torque at the joint (N m) of its drive (or the nearest) in a
    :meth:`qsm.embodiment.drives.drive_checks.DriveCheck.report`; 0 where the loop is undefined."""
    from qsm.embodiment.drives.envelope import OutputEnvelope

    cat = actuation.catalogue(config["drives"])
    out = []
    for j in ("motor1", "motor2"):
        m = drives.motors.get(j)
        if m is None:
            out.append(0.0)
            continue
        env = OutputEnvelope.of(cat, m.drive.motor_key, m.drive.gearbox_key)
        out.append(float(env.limit(1.0, 0.0)))
    return out
