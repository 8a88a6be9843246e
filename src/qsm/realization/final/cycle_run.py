"""The realised design's time-optimal cycle as run: planned and checked
(:mod:`qsm.realization.final.cycle_check`) with its drives, and its record for JSON
(``selected.json``'s ``cycle``: times, power, torque, energy, thermal use, MuJoCo's run) and its
trajectory as a table. :mod:`qsm.report.cycle_report` states it."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from qsm.embodiment.drives.catalogue import Catalogue
from qsm.embodiment.drives.envelope import OutputEnvelope
from qsm.embodiment.drives.selection import offer
from qsm.embodiment.drives.torque_limits import limited
from qsm.embodiment.drives.utilization import DriveArrays
from qsm.embodiment.strength.loads import Inertials
from qsm.physics.cad import MassProperties
from qsm.physics.inverse_kinematics import joint_path
from qsm.physics.task_points import TaskCycle
from qsm.realization.final.cycle_check import (
    CheckedCycle,
    checked_cycle,
    cycle_torques,
    peak_load_N,
    thermal_use,
)
from qsm.realization.final.settling import Settling
from qsm.realization.motion.cycle import Arm, Cycle, move_jerk, raster_time_s
from qsm.realization.motion.payload import PayloadSettings
from qsm.realization.selection.pipeline import Realization, RealizationSettings

#: Columns of :func:`trajectory_table`, one row per sample of the cycle as run.
TRAJECTORY_COLUMNS: dict[str, str] = {
    "t_s": "time from the cycle's start (s)",
    **{f"theta{j}_deg": f"motor {j} angle (deg)" for j in (1, 2)},
    **{f"omega{j}_deg_s": f"motor {j} speed (deg/s)" for j in (1, 2)},
    **{
        f"tau{j}_Nm": f"motor {j} torque at the joint, reflected inertia included (N m)"
        for j in (1, 2)
    },
}


def trajectory_table(cycle: Cycle | None, arm: Arm) -> pd.DataFrame:
    """The cycle as run from rest at its first point, one row per sample
    (:data:`TRAJECTORY_COLUMNS`; no rows without a cycle)."""
    if cycle is None:
        return pd.DataFrame(columns=list(TRAJECTORY_COLUMNS))
    t, q, qd, tau = cycle_torques(cycle, arm, one_period=False)
    out = {"t_s": t}
    for j in (0, 1):
        out[f"theta{j + 1}_deg"] = np.degrees(q[:, j])
        out[f"omega{j + 1}_deg_s"] = np.degrees(qd[:, j])
        out[f"tau{j + 1}_Nm"] = tau[:, j]
    return pd.DataFrame(out)[list(TRAJECTORY_COLUMNS)]


def _power(cycle: Cycle, arm: Arm) -> dict[str, Any]:
    """Over one period of the repeated cycle: each motor's peak and RMS mechanical power (W) at
    the joint, its peak and RMS torque (N m), and the energy per cycle (J): the motors' positive
    work, braking not recovered."""
    t, _, qd, tau = cycle_torques(cycle, arm)
    power = tau * qd
    dt = cycle.dt
    return {
        "peak_power_W": np.abs(power).max(axis=0).tolist(),
        "rms_power_W": np.sqrt((power**2).mean(axis=0)).tolist(),
        "rms_torque_Nm": np.sqrt((tau**2).mean(axis=0)).tolist(),
        "peak_torque_Nm": np.abs(tau).max(axis=0).tolist(),
        "energy_per_cycle_J": float(np.clip(power, 0.0, None).sum() * dt),
        "samples": len(t),
    }


#: Motor types whose torque constant and resistance give the input power.
DC_TYPES = ("DC", "BLDC")


def electrical_power(
    cycle: Cycle, arm: Arm, motors: Sequence[Mapping[str, Any]]
) -> list[dict[str, Any] | str]:
    """Each motor's electrical power over the cycle where its catalogue row gives its torque
    constant and resistance (DC and brushless DC motors): peak and RMS input power (W) and the
    energy drawn per cycle (J, regeneration not recovered), from P = tau_m omega_m + R (tau_m /
    k_t)^2 with tau_m the joint torque over ratio x efficiency when driving (x efficiency / ratio
    when back-driven); "unknown" otherwise. Over one period of the repeated cycle."""
    _, _, qd, tau = cycle_torques(cycle, arm)
    out: list[dict[str, Any] | str] = []
    for j, (env, motor) in enumerate(zip(arm.drives, motors, strict=True)):
        kt, r = float(motor.get("k_t", np.nan)), float(motor.get("R", np.nan))
        dc = str(motor.get("type", "")).upper() in DC_TYPES
        if not (dc and np.isfinite(kt) and np.isfinite(r) and kt > 0):
            out.append("unknown")
            continue
        driving = tau[:, j] * qd[:, j] >= 0
        n, eta = env.ratio, env.efficiency
        tau_m = np.where(driving, tau[:, j] / (n * eta), tau[:, j] * eta / n)
        power = tau_m * qd[:, j] * n + r * (tau_m / kt) ** 2
        out.append({
            "peak_W": float(np.abs(power).max()),
            "rms_W": float(np.sqrt((power**2).mean())),
            "energy_per_cycle_J": float(np.clip(power, 0.0, None).sum() * cycle.dt),
        })  # fmt: skip
    return out


def cycle_record(
    checked: CheckedCycle,
    arm: Arm,
    visits: Sequence[int],
    angles: NDArray[np.float64],
    raster_s: float,
    ratings: tuple[Sequence[float], DriveArrays],
    motors: Sequence[Mapping[str, Any]],
) -> dict[str, Any]:
    """JSON-ready ``cycle``: its time and rate, each move's time and what binds it, the power,
    torque and energy figures, the thermal check (``ratings``: each drive's continuous torque N m
    at the joint, and the two drives, :func:`~qsm.realization.final.cycle_check.thermal_use`), the
    links' utilisation, MuJoCo's run, the motor ``angles`` (n, 2) rad at the visited
    points, how much faster than the raster's speed (``raster_s``: the same moves at the duty's
    raster speed, the same dwells), and each motor's electrical power where its catalogue row
    (``motors``) allows (:func:`electrical_power`)."""
    c, sim = checked.cycle, checked.simulation
    power = _power(c, arm)
    raster = raster_s + c.time_s - sum(m.duration_s for m in c.moves)  # the same dwells
    continuous_Nm, drives = ratings
    use = thermal_use(c, arm, drives)
    thermal = [float(u) if np.isfinite(u) else None for u in use]
    thermal_ok = None if None in thermal else bool(max(thermal) <= 1.0)
    return {
        "planned": True,
        "cycle_time_s": c.time_s,
        "cycles_per_hour": 3600.0 / c.time_s,
        "time_optimal_s": checked.optimal.time_s,
        "slowed_by": c.factor,
        "slowed_for": checked.slowed_for,
        "speed_choices": [choice.record() for choice in checked.choices],
        **_stops(checked, visits),
        "waypoints_deg": np.degrees(angles).tolist(),
        **power,
        "peak_payload_force_N": peak_load_N(c, arm),
        "electrical": electrical_power(c, arm, motors),
        "continuous_torque_Nm": [float(k) if np.isfinite(k) else None for k in continuous_Nm],
        "thermal_use": thermal,
        "thermal_ok": thermal_ok,
        "strength_utilisation": checked.utilisation,
        "links_hold": bool(checked.utilisation <= 1.0),
        "simulation": {k: sim[k] for k in _SIMULATION_KEYS},
        "raster_cycle_s": raster,
        "faster_than_raster": raster / c.time_s,
        "ok": bool(sim["passed"] and checked.utilisation <= 1.0 and thermal_ok is not False),
        "interpolation": "straight lines in joint space between the points, rest to rest",
        "linearisation": "each move's torque bound is the least of the envelope up to its speed "
        "bound, at TOPP-RA's grid points; the fastest of several speed bounds kept",
        "bounds": [
            {"speed_rad_s": m.speed_bound.tolist(), "torque_Nm": m.torque_bound.tolist()}
            for m in checked.optimal.moves
        ],
    }


def _stops(checked: CheckedCycle, visits: Sequence[int]) -> dict[str, Any]:
    """The cycle's visits, its moves (time, what binds them, their jerk) and its stops (the
    configured dwell, each stop's dwell and settling)."""
    c = checked.cycle
    moves = [
        {"from": a, "to": b, "time_s": m.duration_s, "binding": m.binding,
         "optimal_binding": o.binding, **move_jerk(m, c.jerk_time_s, c.dt)}
        for a, b, m, o in zip(visits[:-1], visits[1:], c.moves, checked.optimal.moves, strict=True)
    ]  # fmt: skip
    return {
        "dwell_s": c.dwell_s,
        "dwells_s": list(c.stops_s[1:]),
        "settling": [a.record(p) for a, p in zip(checked.arrivals, visits[1:], strict=False)],
        "visits": list(visits),
        "moves": moves,
    }


_SIMULATION_KEYS = (
    "passed",
    "reason",
    "max_tracking_error_deg",
    "tracking_tolerance_deg",
    "point_error_mm",
    "peak_torque_over_available",
    "saturated_fraction",
)


def run_cycle(
    done: Realization,
    props: dict[str, MassProperties],
    settings: RealizationSettings,
    test: PayloadSettings,
    task: TaskCycle,
    raster_speed_deg_s: float,
    max_load_N: float | None = None,
    jerk_times_s: Sequence[float | None] = (None,),
    settling: Settling | None = None,
) -> tuple[dict[str, Any], CheckedCycle | None, Arm]:
    """The realised design's time-optimal ``task`` cycle with its drives (the chosen ones, or
    the nearest), checked (:func:`qsm.realization.final.cycle_check.checked_cycle`, MuJoCo's
    run with the payload ``test``'s plant and controller; ``max_load_N`` the payload's largest
    peak force that keeps the tool within the tolerance; each move's acceleration ramped over
    one of ``jerk_times_s``, s, chosen with the slow-down; each stop's dwell lengthened to its
    ``settling`` time, None: not): its
    record, the checked cycle (None, and the record says why, where no
    cycle can be planned) and the arm it was planned for."""
    catalogue = settings.drives.catalogue
    keys = [m.drive for m in done.drives.motors.values()]
    drives = [  # within each drive's torque limit, which the controller keeps
        limited(OutputEnvelope.of(catalogue, k.motor_key, k.gearbox_key), limit)
        for k, limit in zip(keys, done.torque_limits_Nm, strict=True)
    ]
    rows = np.array([_drive_row(catalogue, k.motor_key, k.gearbox_key) for k in keys])
    continuous = np.array([offer(catalogue)[i]["cont_torque_Nm"] for i in rows])
    ratings = (continuous, settings.drives.arrays.take(rows))
    arm = Arm(done.design, Inertials.of(props), test.payload_kg, drives)
    points = np.asarray(task.points, dtype=float)
    try:
        angles = joint_path(done.design, points, *test.operating_range.degrees)
        checked = checked_cycle(
            done, props, arm, (points, angles), test, (task.dwell_s, task.returns), ratings[1],
            max_load_N, jerk_times_s, settling,
        )  # fmt: skip
    except ValueError as exc:  # a point out of reach, or drives that cannot hold the arm
        return unplanned_record(task, str(exc)), None, arm
    raster = raster_time_s(angles, np.radians(raster_speed_deg_s))
    motors = [catalogue.motors.loc[k.motor_key].to_dict() for k in keys]
    record = cycle_record(checked, arm, task.visits, angles, raster, ratings, motors)
    return record, checked, arm


def unplanned_record(task: TaskCycle, reason: str) -> dict[str, Any]:
    """The ``cycle`` record of a cycle that could not be planned, and why."""
    return {"planned": False, "ok": False, "reason": reason, "visits": list(task.visits),
            "dwell_s": task.dwell_s}  # fmt: skip


def _drive_row(catalogue: Catalogue, motor_key: str, gearbox_key: str) -> int:
    """The row of the catalogue's drive (motor_key, gearbox_key)."""
    drives = catalogue.drives
    match = (drives["motor"] == motor_key).to_numpy() & (
        drives["gearbox"] == gearbox_key
    ).to_numpy()
    return int(np.flatnonzero(np.asarray(match))[0])
