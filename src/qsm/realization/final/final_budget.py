"""The final record of the realised design: its accuracy budget as measured, with the optimised
plates, the payload test's tracking error, the cycle's peak payload force and the base, and
``selected.json``'s content."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from qsm.physics.cad import MassProperties
from qsm.physics.inverse_kinematics import joint_path
from qsm.physics.kinematics import LINK_NAMES
from qsm.physics.task import min_enclosing_circle
from qsm.physics.task_points import visited_points
from qsm.prose import fixed
from qsm.realization.accuracy.accuracy_budget import with_base
from qsm.realization.accuracy.accuracy_sizing import STRUCTURE_SHARE, AccuracyChoice
from qsm.realization.accuracy.iso9283 import largest_plane, play_opens, pose_characteristics
from qsm.realization.accuracy.iso_record import IsoSettings, iso_record, random_terms
from qsm.realization.selection.pipeline import (
    Realization,
    RealizationSettings,
    arm_model,
    budget_of,
)


def plate_factors(topology: Mapping[str, Any]) -> NDArray[np.float64]:
    """Each link's stiffness factor (4,): an optimised plate's FE compliance before over after
    optimisation under its own load cases (1 for a solid link or a plate kept solid)."""
    links = topology.get("links", {})
    out = np.ones(len(LINK_NAMES))
    for k, name in enumerate(LINK_NAMES):
        r = links.get(name)
        if r and not r.get("kept_solid") and r.get("compliance_after_J"):
            out[k] = r["compliance_before_J"] / r["compliance_after_J"]
    return out


def tracking_per_point(points: ArrayLike, point_error_mm: Sequence[float]) -> NDArray[np.float64]:
    """The payload test's end-effector error at each task point (n,) mm: at the point's hold
    where the test visits it (the worse of the first hold and the return's for the first point),
    else the largest error of any hold."""
    pts = np.asarray(points, dtype=float).reshape(-1, 2)
    err = np.asarray(point_error_mm, dtype=float)
    out = np.full(len(pts), float(err.max()) if err.size else 0.0)
    visited = visited_points(pts)
    out[visited] = err[: len(visited)]
    if len(err) > len(visited) and len(visited):  # the return to the first point: its worse hold
        out[visited[0]] = max(out[visited[0]], float(err[-1]))
    return out


def measured_budget(
    done: Realization,
    parts: tuple[Mapping[str, Any], dict[str, MassProperties]],
    payload: Mapping[str, Any],
    settings: RealizationSettings,
    points: ArrayLike,
    cycle_load_N: float | None = None,
    base_mm: float = 0.0,
) -> dict[str, Any]:
    """The accuracy budget of the realised design as measured: its optimised plates (``parts``:
    the topology record and their mass properties), the payload test's tracking error, the
    payload's peak force over the duty and (``cycle_load_N``, N) the task's cycle, and the
    base's compliance at the tool (``base_mm``, the builder's kit's; 0: none)."""
    topology, props = parts
    tracking = tracking_per_point(points, payload.get("point_error_mm", []))
    factors = plate_factors(topology)
    budget = budget_of(done, settings, points, props, factors, tracking, cycle_load_N)
    return with_base(budget, base_mm, settings.accuracy) if base_mm else budget


def iso_figures(
    done: Realization,
    parts: tuple[Mapping[str, Any], dict[str, MassProperties]],
    payload: Mapping[str, Any],
    settings: RealizationSettings,
    iso: IsoSettings,
    base_mm: float = 0.0,
    mirrored: bool = False,
    task_reverses: tuple[bool, bool] = (True, True),
) -> dict[str, Any]:
    """The realised arm's ISO 9283 AP and RP (:mod:`qsm.realization.accuracy.iso9283`) with its
    optimised plates (``parts``), drives, the ``payload`` test's settling and the base's
    ``base_mm``, on the test plane about the task disk's centre (``task_reverses``: whose
    torque reverses along the task, the budget's); ``simulated: false`` and the reason
    without a drive, after a failed payload test or where the arm does not reach the disk's
    centre."""
    if not done.drives.defined:
        return {"simulated": False, "reason": "the design's loop is undefined: no drive checked"}
    if not payload.get("passed"):
        return {"simulated": False, "reason": (
            f"the payload test failed (max tracking error "
            f"{fixed(payload.get('max_tracking_error_deg', float('nan')), 3)} deg), so the servo's "
            "settling, one of the random terms, is not known"
        )}  # fmt: skip
    topology, props = parts
    model = arm_model(done, settings, props, plate_factors(topology))
    op = settings.motion.operating_range.degrees
    centre = min_enclosing_circle(settings.task_points_m).centre
    try:
        plane = largest_plane(done.design, centre, *op)
    except ValueError as exc:
        return {"simulated": False, "reason": str(exc)}
    angles = joint_path(done.design, plane.points_m, *op)
    kg = settings.motion.payload_kg  # the payload on the tool flange
    opens = play_opens(model, angles, kg, task_reverses)
    terms, sources = random_terms(done.drives, settings.drives.catalogue, payload, iso, opens)
    pc = pose_characteristics(model, plane, angles, kg, terms, base_mm, iso.cycles, iso.seed)
    rated = round(kg - done.tool_kg, 9)
    record = iso_record(pc, sources, rated, iso.repeatability_mm, mirrored)
    return {"simulated": True} | record | {"tool_flange_kg": done.tool_kg}


def final_record(
    choice: Mapping[str, Any],
    done: Realization,
    parts: tuple[Mapping[str, Any], dict[str, MassProperties]],
    payload: Mapping[str, Any],
    settings: RealizationSettings,
    points: ArrayLike,
    cycle: Mapping[str, Any] | None = None,
    base_mm: float = 0.0,
    iso: IsoSettings | None = None,
) -> dict[str, Any]:
    """``choice`` (realised as ``done``) with its ``stiffness`` the final budget
    (:func:`measured_budget` with the ``cycle``'s load and the base's ``base_mm``), its
    ``cycle`` and, given ``iso``, its ``iso9283`` (:func:`iso_figures`);
    :func:`qsm.report.accuracy_report.final_verdict` adds the budget's sentence to its
    verdict."""
    load = None if not cycle or not cycle.get("planned") else cycle["peak_payload_force_N"]
    budget = measured_budget(done, parts, payload, settings, points, load, base_mm)
    record = dict(choice)
    if cycle is not None:
        record["cycle"] = dict(cycle)
    note = sizing_note(done.accuracy, budget)
    budget["would_meet"] = note + budget["would_meet"]
    budget["sizing_note"] = note  # the first of would_meet that says what the sizing did
    record["stiffness"] = budget | {"built_for_tolerance": done.accuracy.record()}
    if iso is not None:
        mirrored = bool(choice.get("task", {}).get("mirrored", False))
        joints = budget["joints"]
        reverses = (joints["motor1"]["torque_reverses"], joints["motor2"]["torque_reverses"])
        record["iso9283"] = iso_figures(
            done, parts, payload, settings, iso, base_mm, mirrored, reverses
        )
    return record


def sizing_note(sized: AccuracyChoice, budget: Mapping[str, Any]) -> list[str]:
    """Where the final ``budget`` misses the tolerance that the realisation ``sized`` the arm
    for: the limits its search stopped at, with their numbers, or (when it met its target on
    its own model) the two figures that disagree; nothing where the budget meets it or the arm
    was not sized for it."""
    if budget["meets_requirements"] or sized.meets is None:
        return []
    if not sized.meets and not sized.stopped_at:  # a point out of reach: the budget says so
        return []
    if sized.stopped_at:
        return ["more than the sizing may give: it stopped at " + "; ".join(sized.stopped_at)]
    error = budget["worst"]["error_budget_mm"]
    return [
        f"the sizing met its target on its own model ({sized.structure_mm:.2f} mm of "
        f"structural error, within {sized.target_mm:.2f} mm, {STRUCTURE_SHARE:.0%} of the "
        f"tolerance, at the duty's load and the plates' stiffness floor), but the arm as printed "
        f"errs {error:.2f} mm with the cycle's load, the tracking and the base: the share this "
        f"task leaves for those terms is too small"
    ]
