"""How precisely a realised design places its payload at every task point: the accuracy budget.

At each task point (the motor angles of :func:`qsm.physics.inverse_kinematics.joint_path`), by
the frame of :mod:`qsm.embodiment.stiffness.frame`:

* ``sag_rigid_drives_mm``: the tool's displacement under the payload's weight, solid links of
  the drawn sections, rigid drives (the reference an independent frame model reproduces);
* ``sag_mm``: the same with the printed links (a topology-optimised plate's stiffness is its
  solid section's times its FE compliance ratio) and each gearbox's torsional stiffness;
* ``dynamic_sag_mm``: under the payload's peak inertial and weight force over the duty, in the
  worst direction;
* ``creep_mm``: the tool's drift as the printed links creep over the service time under their
  weight and the payload's for its share of the time (:mod:`qsm.embodiment.strength.printed`);
* ``lost_motion_mm``: each gearbox's backlash through the Jacobian, for the joints whose torque
  reverses along the task's motion (Newton-Euler along the payload test's reference path);
* ``tracking_error_mm``: the payload test's end-effector error at the end of each hold;
* ``error_budget_mm``: the worst-case sum, max(sag, dynamic sag) + creep + lost motion +
  tracking error;
* ``first_mode_hz``: the loaded arm's first natural frequency.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from qsm.embodiment.drives.compliance import ARCMIN_RAD
from qsm.embodiment.drives.report import DriveReport
from qsm.embodiment.stiffness.error_terms import (
    GRAVITY_M_S2,
    lost_motion_m,
    payload_force_N,
    peak_sag_m,
    sag_m,
    tool_acceleration,
    tool_jacobian,
    torque_reverses,
)
from qsm.embodiment.stiffness.frame import (
    TOOL,
    FrameSections,
    tool_compliance,
    tool_displacement,
    weight_loads,
)
from qsm.embodiment.stiffness.modes import loaded_first_mode_hz
from qsm.embodiment.stiffness.serial_arm import serial_comparison
from qsm.embodiment.strength.loads import Inertials, joint_loads
from qsm.embodiment.strength.printed import PrintedMaterial
from qsm.physics.duty import Duty
from qsm.physics.dynamics import loop_state
from qsm.physics.inverse_kinematics import joint_path
from qsm.prose import fixed
from qsm.realization.motion.payload import PayloadSettings, reference_trajectory
from qsm.schema.defaults import default

#: A drive without a stiffness beside one with: this many times the other's (as good as rigid).
RIGID_FACTOR = 1e6
#: Time step (s) of the task motion along which the joints' torques are checked for reversals.
MOTION_STEP_S = 0.01
#: The terms of the budget, per task point, in mm (and the first mode in Hz).
TERMS = (
    "sag_rigid_drives_mm",
    "sag_mm",
    "dynamic_sag_mm",
    "creep_mm",
    "lost_motion_mm",
    "tracking_error_mm",
    "error_budget_mm",
    "first_mode_hz",
)


@dataclass(frozen=True)
class AccuracySettings:
    """What the user needs: ``tolerance_mm`` (the largest placing error at a task point, mm) and
    ``min_first_mode_hz`` (the lowest first natural frequency, Hz; None: no requirement); the
    task ``points_m`` ((x, y) m each) where the realisation meets the tolerance (empty: it does
    not try), the largest section scale it may give a link for it (1: none larger), the
    printer's ``build_volume_mm`` the grown links must still fit, and the least stiffness factor
    the optimised plates keep (``topology.min_stiffness_factor``), at which it sizes them, and
    the ``printed`` material's creep over its service time."""

    tolerance_mm: float = default("task.tolerance_mm")
    min_first_mode_hz: float | None = default("task.min_first_mode_hz")
    points_m: tuple[tuple[float, float], ...] = ()
    max_section_scale: float = 1.0
    build_volume_mm: tuple[float, float, float] = tuple(default("printing.build_volume_mm"))
    plate_factor: float = default("topology.min_stiffness_factor")
    printed: PrintedMaterial = field(default_factory=PrintedMaterial)


class ArmModel(NamedTuple):
    """The realised arm as the budget sees it: ``sections`` (solid, per link), ``factor`` (4,)
    on each link's stiffness (plates; ones for solid links), link masses (4,) kg and inertials,
    and per drive its torsional stiffness (N m/rad), backlash (rad), reflected inertia (kg m^2)
    and mass (kg); the ``printed`` material's creep (None: none)."""

    design: NDArray[np.float64]
    sections: FrameSections
    factor: NDArray[np.float64]
    inertials: Inertials
    drive_stiffness: NDArray[np.float64]
    backlash_rad: NDArray[np.float64]
    reflected_kgm2: NDArray[np.float64]
    drive_mass_kg: NDArray[np.float64]
    printed: PrintedMaterial | None = None


def drive_terms(drives: DriveReport) -> tuple[NDArray, NDArray, NDArray, NDArray, dict]:
    """Each motor's gearbox stiffness (N m/rad), backlash (rad), reflected inertia (kg m^2),
    drive mass (kg) and their sources, from a drive report (the drive each motor is built
    with: the chosen, else the nearest)."""
    k, play, ref, mass, notes = [], [], [], [], {}
    for name, motor in drives.motors.items():
        d = motor.drive
        k.append(d.torsional_stiffness_Nm_rad)
        play.append(d.backlash_arcmin * ARCMIN_RAD)
        ref.append(d.reflected_inertia_kgm2)
        mass.append(d.mass_kg)
        keys = ("gearbox", "backlash_arcmin", "torsional_stiffness_Nm_rad")
        notes[name] = {key: getattr(d, key) for key in (*keys, "backlash_from", "stiffness_from")}
    if len(k) != 2:  # no drive report (an undefined design): rigid drives without play
        return np.full(2, math.inf), np.zeros(2), np.zeros(2), np.zeros(2), {}
    return _finite_when_any(np.array(k)), np.array(play), np.array(ref), np.array(mass), notes


def _finite_when_any(k: NDArray[np.float64]) -> NDArray[np.float64]:
    """Drive stiffnesses (2,) N m/rad with a missing (infinite) one made :data:`RIGID_FACTOR`
    times the other, so that one drive's value is not dropped with the other's."""
    if np.isfinite(k).any() and not np.isfinite(k).all():
        return np.where(np.isfinite(k), k, RIGID_FACTOR * k[np.isfinite(k)].max())
    return k


def task_motion_duty(angles: NDArray[np.float64], payload: PayloadSettings) -> Duty:
    """The payload test's reference motion through the task points' motor ``angles`` (n, 2)
    rad (its moves and holds, back to the first point when it returns) as a duty, each sample
    weighted by its time step."""
    way = (
        angles
        if not payload.return_to_start or len(angles) < 2
        else angles[[*range(len(angles)), 0]]
    )
    t, th, dth, ddth = reference_trajectory(
        way, payload.segment_duration_s, payload.dwell_s, MOTION_STEP_S
    )
    moving = (np.abs(dth) + np.abs(ddth)).max(axis=1) > 0
    return Duty(th, dth, ddth, ~moving, t, np.full(len(t), MOTION_STEP_S))


def task_motion_torques(
    model: ArmModel, angles: NDArray[np.float64], payload: PayloadSettings
) -> NDArray[np.float64]:
    """The joints' torques (N, 2) N m along the payload test's reference motion through the
    task points' motor ``angles`` (n, 2) rad, by Newton-Euler (without the drives' inertia)."""
    du = task_motion_duty(angles, payload)
    state = loop_state(model.design, du.theta, du.dtheta, du.ddtheta)
    return joint_loads(model.design, model.inertials, payload.payload_kg, state).tau


def peak_payload_force_N(
    design: ArrayLike, payload_kg: float, theta: ArrayLike, dtheta: ArrayLike, ddtheta: ArrayLike
) -> float:
    """The largest force (N) the payload puts on the tool, its weight and inertia, over a motion
    (motor angles rad, speeds rad/s, accelerations rad/s^2, (N, 2) each)."""
    accel = tool_acceleration(design, theta, dtheta, ddtheta)
    return float(np.nanmax(np.linalg.norm(payload_force_N(payload_kg, accel), axis=-1)))


def point_terms(
    model: ArmModel,
    angles: NDArray[np.float64],
    payload_kg: float,
    peak_N: float,
    reverses: ArrayLike,
) -> dict[str, NDArray[np.float64]]:
    """The budget's terms (n,) at the task points' motor ``angles`` (n, 2) rad, but the tracking
    error: mm, and the first mode in Hz. ``peak_N``: the payload's peak force on the tool over
    the motion (:func:`peak_payload_force_N`); ``reverses`` (2,): whose torque changes sign."""
    d, t1, t2 = model.design, angles[:, 0], angles[:, 1]
    weight = payload_force_N(payload_kg, np.zeros(2))
    printed = model.sections._replace(factor=model.factor)
    rigid = not np.isfinite(model.drive_stiffness).all()
    k = None if rigid else model.drive_stiffness
    compliance = tool_compliance(d, t1, t2, printed, k)
    mode = loaded_first_mode_hz(
        d, t1, t2, printed, model.inertials.mass_kg, payload_kg, k,
        None if rigid else model.reflected_kgm2,
    )  # fmt: skip
    jac = tool_jacobian(d, t1, t2)
    return {
        "sag_rigid_drives_mm": 1e3 * sag_m(tool_compliance(d, t1, t2, model.sections), weight),
        "sag_mm": 1e3 * sag_m(compliance, weight),
        "dynamic_sag_mm": 1e3 * peak_sag_m(compliance, peak_N),
        "creep_mm": 1e3 * np.linalg.norm(creep_drift_m(model, t1, t2, payload_kg), axis=-1),
        "lost_motion_mm": 1e3 * lost_motion_m(jac, model.backlash_rad, reverses),
        "first_mode_hz": mode,
    }


def creep_drift_m(
    model: ArmModel, theta1: ArrayLike, theta2: ArrayLike, payload_kg: float
) -> NDArray[np.float64]:
    """The tool's drift (..., 2) m as the printed links creep over the service time under the
    load they hold: their weight, and the payload's for its share of the time (linear
    viscoelasticity: the links at E / (1 + phi) under that load, less the links at E; the
    gearboxes do not creep). Zeros without a ``printed`` material or a service time."""
    creep = model.printed
    t1, t2 = np.asarray(theta1, dtype=float), np.asarray(theta2, dtype=float)
    if creep is None or creep.creep_coefficient == 0:
        return np.zeros((*np.broadcast_shapes(t1.shape, t2.shape), 2))
    printed = model.sections._replace(factor=model.factor)
    crept = printed._replace(youngs_pa=printed.youngs_pa / (1 + creep.creep_coefficient))
    k = model.drive_stiffness if np.isfinite(model.drive_stiffness).all() else None
    held = weight_loads(model.design, t1, t2, model.inertials.mass_kg, GRAVITY_M_S2)
    held[..., TOOL[1]] -= creep.payload_share * payload_kg * GRAVITY_M_S2
    after = tool_displacement(model.design, t1, t2, crept, held, k)
    return after - tool_displacement(model.design, t1, t2, printed, held, k)


def budget_mm(terms: dict[str, NDArray], tracking_mm: ArrayLike | None) -> NDArray[np.float64]:
    """The worst-case placing error (n,) mm: max(sag, dynamic sag) + creep + lost motion +
    tracking."""
    track = 0.0 if tracking_mm is None else np.asarray(tracking_mm, dtype=float)
    elastic = np.maximum(terms["sag_mm"], terms["dynamic_sag_mm"]) + terms["creep_mm"]
    return elastic + terms["lost_motion_mm"] + track


def _worst(per_point: dict[str, Any]) -> dict[str, float | None]:
    out: dict[str, float | None] = {}
    for key, values in per_point.items():
        if values is None:
            out[key] = None
        else:
            v = np.asarray(values, dtype=float)
            out[key] = float(v.min() if key == "first_mode_hz" else v.max())
    return out


#: How the budget models the arm, stated in its record.
MODEL_NOTE = (
    "planar Timoshenko frame of the links' drawn sections between joint centres (bosses and "
    "bores not modelled), pins and bearings rigid at B, C and D, each gearbox a torsional "
    "spring at A; for the static terms the servo holds each rotor rigidly, for the first mode "
    "the rotor's reflected inertia sits on its joint, on the arm's side of the gearbox spring; "
    "creep: the links at E / (1 + phi) under their weight and the payload's held share"
)


def _scaled(model: ArmModel, section: float = 1.0, modulus: float = 1.0) -> ArmModel:
    """``model`` with its sections ``section`` times as large (the links ``section^2`` times as
    heavy, which their creep feels) and its material ``modulus`` times as stiff."""
    s, i = model.sections, model.inertials
    return model._replace(
        sections=s._replace(
            width_m=s.width_m * section,
            thickness_m=s.thickness_m * section,
            youngs_pa=s.youngs_pa * modulus,
        ),
        inertials=i._replace(mass_kg=i.mass_kg * section**2),
    )


def smallest_factor(meets: Any, high: float) -> float | None:
    """The smallest factor in [1, high] for which ``meets(factor)`` holds (bisection, 1 %), or
    None when even ``high`` does not."""
    if not meets(high):
        return None
    low = 1.0
    while high / low > 1.01:
        mid = math.sqrt(low * high)
        low, high = (low, mid) if meets(mid) else (mid, high)
    return high


def advice(
    model: ArmModel, angles: NDArray, payload_kg: float, peak_N: float, reverses: NDArray,
    tracking_mm: ArrayLike | None, tolerance_mm: float,
) -> list[str]:  # fmt: skip
    """What would meet ``tolerance_mm``, each answer checked by the budget: a larger section, a
    stiffer material, or drives without compliance and play."""

    def meets(m: ArmModel) -> bool:
        terms = point_terms(m, angles, payload_kg, peak_N, reverses)
        return bool((budget_mm(terms, tracking_mm) <= tolerance_mm).all())

    out = []
    s = model.sections
    f = smallest_factor(lambda x: meets(_scaled(model, section=x)), 3.0)
    if f is not None:
        w, t = 1e3 * s.width_m * f, 1e3 * s.thickness_m * f
        sizes = ", ".join(f"{a:.0f} x {b:.0f}" for a, b in zip(w, t, strict=True))
        out.append(f"sections {f:.2f}x as large ({sizes} mm per link)")
    e = smallest_factor(lambda x: meets(_scaled(model, modulus=x)), 100.0)
    if e is not None:
        out.append(f"a material of Young's modulus {s.youngs_pa * e / 1e9:.1f} GPa or more")
    ideal = model._replace(drive_stiffness=np.full(2, math.inf), backlash_rad=np.zeros(2))
    if meets(ideal) and not np.isinf(model.drive_stiffness).all():
        out.append("stiffer gearboxes with less backlash (rigid drives without play would meet it)")
    return out or ["none of a section up to 3x, a material up to 100x as stiff, or rigid drives"]


def _label(per_point: dict[str, Any], i: int) -> str:
    """What dominates the placing error at point ``i``: sag, play or tracking."""
    track = per_point["tracking_error_mm"]
    terms = {
        "NOT STIFF ENOUGH": max(per_point["sag_mm"][i], per_point["dynamic_sag_mm"][i])
        + per_point["creep_mm"][i],
        "TOO MUCH PLAY": per_point["lost_motion_mm"][i],
        "TRACKS TOO LOOSELY": 0.0 if track is None else track[i],
    }
    return max(terms, key=terms.get)


def term_phrases(per_point: dict[str, Any], i: int) -> list[str]:
    """The placing error's terms at point ``i``, each named as the glossary names it (mm): the
    larger of the static and the dynamic sag (the one the error counts), creep, lost motion,
    tracking error and base, where the budget has them; they add up to ``error_budget_mm``."""
    static, dynamic = per_point["sag_mm"][i], per_point["dynamic_sag_mm"][i]
    sag = (
        f"static sag {fixed(static, 2)} mm"
        if static >= dynamic
        else (f"dynamic sag {fixed(dynamic, 2)} mm")
    )
    parts = [sag, f"creep {fixed(per_point['creep_mm'][i], 2)} mm"]
    parts.append(f"lost motion {fixed(per_point['lost_motion_mm'][i], 2)} mm")
    if per_point["tracking_error_mm"] is not None:
        parts.append(f"tracking error {fixed(per_point['tracking_error_mm'][i], 2)} mm")
    if per_point.get("base_mm") is not None:
        parts.append(f"base {fixed(per_point['base_mm'][i], 2)} mm")
    return parts


def _verdict(per_point: dict[str, Any], settings: AccuracySettings) -> tuple[str, bool]:
    """The budget's sentence, with its numbers, and whether the design meets the tolerance and
    the first-mode requirement."""
    budget = np.asarray(per_point["error_budget_mm"])
    i = int(np.argmax(budget))
    mode = float(np.min(per_point["first_mode_hz"]))
    tol, low = settings.tolerance_mm, settings.min_first_mode_hz
    parts = term_phrases(per_point, i)
    detail = f"{fixed(budget[i], 2)} mm at point {i + 1} ({', '.join(parts)}; tolerance {tol:g} mm)"
    problems = []
    if not budget[i] <= tol:
        problems.append(f"{_label(per_point, i)}: the tool's placing error reaches {detail}")
    if low is not None and not mode >= low:
        problems.append(f"RINGS TOO LOW: first mode {mode:.1f} Hz (required {low:g} Hz)")
    if problems:
        return "; ".join(problems), False
    return (
        f"within tolerance: the placing error is at most {detail}; first mode {mode:.1f} Hz",
        True,
    )


#: How the advice for the first mode begins (the tolerance's advice are alternatives to each
#: other; this one is needed besides them).
FIRST_MODE_FIX = "for a first mode of"


def _would_meet(
    model: ArmModel, angles: NDArray, payload: PayloadSettings, peak_N: float, reverses: NDArray,
    track: NDArray | None, settings: AccuracySettings, terms: dict[str, NDArray],
) -> list[str]:  # fmt: skip
    """What would meet each requirement the design misses, with the numbers: the tolerance
    (:func:`advice`) and the first mode (the stiffness it needs, as the mode grows with its
    square root); ``terms`` the design's own (:func:`point_terms`)."""
    out = []
    if not (budget_mm(terms, track) <= settings.tolerance_mm).all():
        out += advice(
            model, angles, payload.payload_kg, peak_N, reverses, track, settings.tolerance_mm
        )
    low, mode = settings.min_first_mode_hz, float(np.min(terms["first_mode_hz"]))
    if low is not None and not mode >= low:
        out.append(
            f"{FIRST_MODE_FIX} {low:g} Hz: an arm {(low / mode) ** 2:.1f}x as stiff for its "
            f"mass, or a lighter payload and links"
        )
    return out


def accuracy_record(
    model: ArmModel,
    points_m: ArrayLike,
    payload: PayloadSettings,
    loads: dict[str, float],
    settings: AccuracySettings,
    tracking_mm: ArrayLike | None = None,
    drive_notes: dict[str, Any] | None = None,
) -> dict[str, Any]:
    """JSON-ready accuracy budget of ``model`` at task ``points_m`` (n, 2) m: per point and worst
    (:data:`TERMS`), each drive's play and whether its torque reverses along the task's motion,
    the verdict against ``settings`` and, when it fails, what would meet it. ``loads``: the
    payload's peak force (N) on the tool over each motion it makes (the duty, the cycle), the
    largest of which gives the dynamic sag. ``tracking_mm``: the payload test's error per point
    (None before the test has run)."""
    peak_N = max(loads.values())
    points = np.asarray(points_m, dtype=float).reshape(-1, 2)
    angles = joint_path(model.design, points, *payload.operating_range.degrees)
    reverses = torque_reverses(task_motion_torques(model, angles, payload))
    terms = point_terms(model, angles, payload.payload_kg, peak_N, reverses)
    track = None if tracking_mm is None else np.asarray(tracking_mm, dtype=float)[: len(points)]
    per_point: dict[str, Any] = {k: v.tolist() for k, v in terms.items()}
    per_point["tracking_error_mm"] = None if track is None else track.tolist()
    per_point["error_budget_mm"] = budget_mm(terms, track).tolist()
    verdict, ok = _verdict(per_point, settings)
    joints = {
        name: (drive_notes or {}).get(name, {})
        | {"torque_reverses": bool(r), "backlash_counted": bool(r)}
        for name, r in zip(("motor1", "motor2"), reverses, strict=True)
    }
    return {
        "tolerance_mm": settings.tolerance_mm,
        "min_first_mode_hz": settings.min_first_mode_hz,
        "points_m": points.tolist(),
        "per_point": {k: per_point[k] for k in TERMS},
        "worst": _worst({k: per_point[k] for k in TERMS}),
        "worst_point": int(np.argmax(per_point["error_budget_mm"])) + 1,
        "joints": joints,
        "stiffness_factor": model.factor.tolist(),
        "meets_requirements": ok,
        "verdict": verdict,
        "would_meet": _would_meet(model, angles, payload, peak_N, reverses, track, settings, terms),
        "dynamic_load_N": dict(loads),
        "dynamic_load_from": max(loads, key=loads.get),
        "serial_arm": serial_record(model, angles, payload.payload_kg, terms),
        "model": MODEL_NOTE,
    }


def with_base(budget: dict[str, Any], base_mm: float, settings: AccuracySettings) -> dict[str, Any]:
    """``budget`` (an :func:`accuracy_record`) with the base's compliance as a term of its own:
    ``base_mm`` (the builder's kit's cheeks, :mod:`qsm.embodiment.kit.base`) added at every
    point to the placing error, and its verdict again."""
    per = {k: v for k, v in budget["per_point"].items() if k != "error_budget_mm"}
    n = len(budget["points_m"])
    per["base_mm"] = [float(base_mm)] * n
    per["error_budget_mm"] = [e + base_mm for e in budget["per_point"]["error_budget_mm"]]
    verdict, ok = _verdict(per, settings)
    would = (
        budget["would_meet"]
        if budget["would_meet"] or ok
        else [
            f"a stiffer base: its {base_mm:.2f} mm at the tool (the builder's kit's cheeks, in "
            f"the plane and from their tilt) is what the budget cannot take"
        ]
    )
    return budget | {
        "per_point": per,
        "worst": _worst(per),
        "worst_point": int(np.argmax(per["error_budget_mm"])) + 1,
        "verdict": verdict,
        "meets_requirements": ok,
        "would_meet": would,
    }


def largest_load_N(budget: dict[str, Any]) -> float | None:
    """The largest peak force (N) of the payload on the tool that keeps ``budget`` (an
    :func:`accuracy_record`) within its tolerance at every point, each point's dynamic sag
    growing in proportion to the force; 0 where its static terms alone miss the tolerance (no
    motion can then meet it), None where no force sags the tool (no limit)."""
    per = {
        k: np.asarray(v if v is not None else 0.0, dtype=float)
        for k, v in budget["per_point"].items()
    }
    room = budget["tolerance_mm"] - per["lost_motion_mm"] - per["tracking_error_mm"]
    room = room - per["creep_mm"]
    room = room - per.get("base_mm", 0.0)
    if (per["sag_mm"] > room).any():
        return 0.0
    per_N = per["dynamic_sag_mm"] / max(budget["dynamic_load_N"].values())
    if not (per_N > 0).any():
        return None
    with np.errstate(divide="ignore"):
        return float(np.min(np.where(per_N > 0, room / per_N, np.inf)))


def serial_record(
    model: ArmModel, angles: NDArray, payload_kg: float, terms: dict[str, NDArray]
) -> dict[str, Any] | None:
    """The design against the serial 2R arm of the same reach, sections, material and drives
    (:mod:`qsm.embodiment.stiffness.serial_arm`), worst over the task points: tool sag under the
    payload, first mode and holding torques, and the verdict (None without drives)."""
    if not np.isfinite(model.drive_stiffness).all():
        return None
    m, (l4, ee_x, ee_y) = model.inertials.mass_kg, model.design[3:6]
    link2 = m[3] * (ee_x + ee_y) / (l4 + ee_x + ee_y)  # the upper arm's L, without its D-B leg
    ref = model.reflected_kgm2
    masses = (m[0], link2, float(model.drive_mass_kg[1]), payload_kg, float(ref[0]), float(ref[1]))
    printed = model.sections._replace(factor=model.factor)
    serial = serial_comparison(model.design, angles, printed, model.drive_stiffness, masses)
    state = loop_state(model.design, angles, np.zeros_like(angles), np.zeros_like(angles))
    quasi_tau = np.abs(joint_loads(model.design, model.inertials, payload_kg, state).tau)
    quasi = {
        "sag_mm": float(np.max(terms["sag_mm"])),
        "first_mode_hz": float(np.min(terms["first_mode_hz"])),
        "holding_torque_Nm": quasi_tau.max(axis=0).tolist(),
    }
    other = {
        "sag_mm": float(serial["sag_mm"].max()),
        "first_mode_hz": float(serial["first_mode_hz"].min()),
        "holding_torque_Nm": serial["holding_torque_Nm"].max(axis=0).tolist(),
    }
    stiffer = quasi["sag_mm"] < other["sag_mm"]
    verdict = (
        f"{'stiffer' if stiffer else 'NOT stiffer'} than the serial 2R arm of the same reach, "
        f"sections and drives: sag {quasi['sag_mm']:.1f} vs {other['sag_mm']:.1f} mm, first mode "
        f"{quasi['first_mode_hz']:.1f} vs {other['first_mode_hz']:.1f} Hz, holding torques "
        f"{quasi['holding_torque_Nm'][0]:.1f} / {quasi['holding_torque_Nm'][1]:.1f} vs "
        f"{other['holding_torque_Nm'][0]:.1f} / {other['holding_torque_Nm'][1]:.1f} N m "
        f"(motor 1 / motor 2, worst over the task points)"
    )
    return {"quasi_serial": quasi, "serial": other, "stiffer": stiffer, "verdict": verdict}
