"""Simulated payload test of a (topology-optimised) design (paper Section 5, Fig. 13).

The paper grips a 3 kg object with a 2 kg gripper (5 kg at the end effector) and drives the arm
through the task with motors geared to 150 N m and 100 N m (NEMA 17 + 50:1 gear and belt). Here the
closed-chain MuJoCo model (:mod:`qsm.physics.mjcf`, optionally with the optimised link mass
properties) is simulated forward:

* reference: the task points in order (at most :data:`qsm.physics.task_points.MAX_VISITED_POINTS`
  of them, chosen by :func:`qsm.physics.task_points.visited_points` when there are more; and back
  to the first when ``return_to_start``), each solved by :mod:`qsm.physics.inverse_kinematics`
  (solution closest to the previous one), joined by rest-to-rest minimum-jerk segments in joint
  space of ``segment_duration_s``, each followed by a ``dwell_s`` hold (the test starts with one
  hold at the first point);
* drives: each motor is the drive chosen for it (:mod:`qsm.embodiment.drives.drive_checks`); the
  model and the plant carry its reflected inertia as joint armature on theta1 / theta2, and the
  torque it can give at the joint is its torque-speed envelope on the output side
  (:class:`qsm.embodiment.drives.envelope.OutputEnvelope`: gear efficiency eta both ways,
  eta N T_m driving and N T_m / eta back-driven, the gearbox's intermittent torque), evaluated
  at the plant's joint speed at every step. The gear losses act through that envelope: the
  controller asks for a joint torque and the motor supplies joint torque / (eta N) when driving.
  ``torque_limits_Nm`` (an override) sets fixed limits instead, e.g. the paper's 150 / 100 N m;
* control: feed-forward torques from the closed-chain inverse dynamics
  (:func:`qsm.physics.dynamics.inverse_dynamics`, same model and properties) plus joint PD feedback
  ``kp (theta_ref - theta) + kd (dtheta_ref - dtheta)``; the *requested* torque is clamped to the
  motor limits before it is applied;
* integration: the PD torque is applied explicitly, which is stable only while ``kd dt / M < 2``
  for the smallest motor-space inertia ``M`` (:func:`motor_inertia`); a small light arm has little
  inertia at the crank, so the step is cut (from the model's ``opt.timestep``) until
  ``kd dt / M <= 0.5`` at every waypoint, while the data are sampled at the model's step;
* pass: the requested torque never exceeds what the drives give (no saturation) and the
  largest tracking error of either motor stays within ``tracking_tolerance_deg``.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any, NamedTuple

import mujoco
import numpy as np
from numpy.typing import ArrayLike, NDArray

from qsm.embodiment.drives.envelope import OutputEnvelope
from qsm.physics.cad import DEFAULT_CAD, CadSettings, MassProperties, mass_properties
from qsm.physics.duty import minimum_jerk
from qsm.physics.dynamics import MIN_SIN_TRANSMISSION, LoopState, inverse_dynamics, loop_state
from qsm.physics.inverse_kinematics import joint_path
from qsm.physics.kinematics import as_design, pose
from qsm.physics.mjcf import model_spec
from qsm.physics.task_points import visited_points
from qsm.physics.workspace import OperatingRange
from qsm.prose import fixed
from qsm.schema.defaults import default


@dataclass(frozen=True)
class PayloadSettings:
    """Payload test settings (SI units unless named otherwise).

    payload_kg: mass at the end effector, gripper included, default 5 kg (the paper's 3 kg object
        and 2 kg gripper); the workflow passes task.payload_kg.
    torque_limits_Nm: fixed motor torque limits at the joints, an explicit override of the
        drives' envelopes (the paper's: (150, 100) N m); default None, the drives'.
    segment_duration_s: duration of each point-to-point move, default 1.5 s.
    dwell_s: hold at each task point (and before the first move), default 0.5 s.
    return_to_start: move back to the first point at the end, default True.
    kp_Nm_rad, kd_Nms_rad: proportional and damping gains per motor, default (2000, 1000) N m/rad
        and (60, 30) N m s/rad (stiff, as geared stepper drives are).
    ki_Nm_rad_s: integral gains per motor, default (20000, 10000) N m/(rad s): the servo's
        integral action, which removes the steady error the plant's model error leaves under PD
        (0: PD). Integration stops while a motor saturates (anti-windup).
    tracking_tolerance_deg: largest allowed motor tracking error, default 0.5 deg.
    plant_mass_error: the simulated links and payload are this fraction heavier than the model
        that gives the feed-forward torques (mass and inertia), default 0.15, so the test checks
        the controller against a model error, not only the integrator.
    operating_range: the motors' ranges for the IK, default theta1 (45, 180) deg, theta2 from
        -37.5 deg.
    """

    payload_kg: float = default("task.payload_kg")
    torque_limits_Nm: tuple[float, float] | None = default("payload_test.torque_limits_Nm")
    segment_duration_s: float = default("payload_test.segment_duration_s")
    dwell_s: float = default("payload_test.dwell_s")
    return_to_start: bool = default("payload_test.return_to_start")
    kp_Nm_rad: tuple[float, float] = default("payload_test.kp_Nm_rad")
    kd_Nms_rad: tuple[float, float] = default("payload_test.kd_Nms_rad")
    ki_Nm_rad_s: tuple[float, float] = default("payload_test.ki_Nm_rad_s")
    tracking_tolerance_deg: float = default("payload_test.tracking_tolerance_deg")
    plant_mass_error: float = default("payload_test.plant_mass_error")
    operating_range: OperatingRange = field(default_factory=OperatingRange)

    def __post_init__(self) -> None:
        if self.segment_duration_s <= 0 or self.dwell_s < 0:
            raise ValueError("need segment_duration_s > 0 and dwell_s >= 0")
        limits = self.torque_limits_Nm
        if (limits is not None and min(limits) <= 0) or self.tracking_tolerance_deg <= 0:
            raise ValueError("torque limits and tracking tolerance must be positive")


DEFAULT_PAYLOAD_TEST = PayloadSettings()
#: Largest kd dt / M the explicit PD loop is stepped with (stability needs < 2).
STABLE_KD_DT_OVER_M = 0.5
#: Keys of a :func:`payload_test` result that hold time series (the rest are scalars).
SERIES_KEYS: tuple[str, ...] = (
    "t_s",
    "theta_ref_deg",
    "theta_deg",
    "torque_requested_Nm",
    "torque_applied_Nm",
    "torque_available_Nm",
)


def reference_trajectory(
    waypoints: ArrayLike, segment_duration_s: float, dwell_s: float, dt: float
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Joint-space reference through ``waypoints`` (n, 2) rad: an initial hold, then for every
    consecutive pair a minimum-jerk move and a hold. Returns t (N,) s and theta, dtheta, ddtheta
    (N, 2) in rad, rad/s, rad/s^2 sampled every ``dt`` s."""
    way = np.asarray(waypoints, dtype=float)
    n_move = max(1, round(segment_duration_s / dt))
    n_hold = round(dwell_s / dt)
    parts_q = [np.repeat(way[:1], n_hold + 1, axis=0)]
    parts_v = [np.zeros((n_hold + 1, 2))]
    parts_a = [np.zeros((n_hold + 1, 2))]
    for q0, q1 in itertools.pairwise(way):
        t = np.arange(1, n_move + 1) * dt
        q, v, a = minimum_jerk(q0, q1, n_move * dt, t)
        parts_q += [q, np.repeat(q1[None], n_hold, axis=0)]
        parts_v += [v, np.zeros((n_hold, 2))]
        parts_a += [a, np.zeros((n_hold, 2))]
    theta = np.concatenate(parts_q)
    return (
        np.arange(len(theta)) * dt,
        theta,
        np.concatenate(parts_v),
        np.concatenate(parts_a),
    )


def _plant(
    design: NDArray[np.float64],
    cad: CadSettings,
    props: dict[str, MassProperties] | None,
    s: PayloadSettings,
    armature: tuple[float, float] = (0.0, 0.0),
) -> mujoco.MjModel:
    """The simulated mechanism: links and payload ``plant_mass_error`` heavier than modelled,
    the drives' reflected inertia as armature (a catalogue value, not scaled)."""
    factor = 1.0 + s.plant_mass_error
    nominal = mass_properties(design, cad) if props is None else props
    heavier = {
        name: MassProperties(p.mass_kg * factor, p.com_m, np.asarray(p.inertia_kg_m2) * factor)
        for name, p in nominal.items()
    }
    return model_spec(design, cad, s.payload_kg * factor, heavier, armature).compile()


def motor_inertia(
    model: mujoco.MjModel, design: NDArray[np.float64], theta: NDArray[np.float64]
) -> NDArray[np.float64]:
    """Motor-space inertia (2, 2) in kg m^2 of the closed chain at motor angles ``theta`` (rad):
    the change of the inverse-dynamics torques per unit motor acceleration at rest."""
    ddth = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    th = np.repeat(np.asarray(theta, dtype=float)[None], 3, axis=0)
    tau = inverse_dynamics(model, design, loop_state(design, th, np.zeros((3, 2)), ddth)).tau
    return (tau[1:] - tau[0]).T


def torque_use(
    requested: NDArray[np.float64], available: NDArray[np.float64]
) -> tuple[list[float | None], list[float]]:
    """Each motor's peak |requested| / available torque over the steps (n, 2), and the share of
    steps at which it ran past its drive's top speed (no torque available). A motor that ran
    past its top speed has no finite peak use: None (``past_top_speed_fraction`` says why)."""
    past = available <= 0
    ratio = np.divide(np.abs(requested), available, out=np.zeros_like(requested), where=~past)
    use = [None if p.any() else float(r) for r, p in zip(ratio.max(axis=0), past.T, strict=True)]
    return use, past.mean(axis=0).tolist()


def _visited(points: ArrayLike, return_to_start: bool) -> NDArray[np.float64]:
    """The task points (n, 2) m the test visits, in order (a bounded subset of many points), and
    the first again at the end when it returns to its start."""
    pts = np.asarray(points, dtype=float).reshape(-1, 2)
    pts = pts[visited_points(pts)]
    if return_to_start and len(pts) > 1:
        pts = np.vstack([pts, pts[:1]])
    return pts


class Reference(NamedTuple):
    """A reference motion: times (N,) s, motor angles (N, 2) rad, speeds rad/s, accelerations
    rad/s^2, and the sample index at which each visited point's hold ends."""

    t: NDArray[np.float64]
    theta: NDArray[np.float64]
    dtheta: NDArray[np.float64]
    ddtheta: NDArray[np.float64]
    hold_ends: NDArray[np.intp]


def raster_reference(way: NDArray[np.float64], s: PayloadSettings, dt: float) -> Reference:
    """The payload test's own reference through ``way`` (n, 2) rad: minimum-jerk moves of
    ``segment_duration_s``, a hold of ``dwell_s`` before the first and after each."""
    t, th, dth, ddth = reference_trajectory(way, s.segment_duration_s, s.dwell_s, dt)
    n_hold, n_move = round(s.dwell_s / dt), max(1, round(s.segment_duration_s / dt))
    ends = np.array([n_hold + i * (n_move + n_hold) for i in range(len(way))])
    return Reference(t, th, dth, ddth, ends)


def _point_errors_mm(
    d: NDArray[np.float64],
    q_act: NDArray[np.float64],
    pts: NDArray[np.float64],
    hold_ends: NDArray[np.intp],
) -> NDArray[np.float64]:
    """The end effector's distance (mm) from each visited point at the end of its hold
    (waypoint reached and held), from the simulated motor angles ``q_act`` (rad)."""
    ee = pose(d, q_act[hold_ends, 0], q_act[hold_ends, 1]).E
    return np.linalg.norm(ee - pts, axis=1) * 1e3


#: The torque series of a payload test's result (N m, per sample and motor).
TORQUE_SERIES = ("torque_requested_Nm", "torque_applied_Nm", "torque_available_Nm")


def _limit_function(
    fixed: NDArray[np.float64] | None, envelopes: Sequence[OutputEnvelope] | None
) -> Callable[[NDArray[np.float64], NDArray[np.float64]], NDArray[np.float64]]:
    """Each motor's torque limit (N m) at a requested torque and speed (rad/s): the ``fixed``
    limits, or else each drive's torque-speed envelope at the joint."""

    def limits(torque: NDArray[np.float64], dq: NDArray[np.float64]) -> NDArray[np.float64]:
        if fixed is not None:
            return fixed
        return np.array([e.limit_at(t, w) for e, t, w in zip(envelopes, torque, dq, strict=True)])

    return limits


def _start(
    model: mujoco.MjModel,
    plant: mujoco.MjModel,
    d: NDArray[np.float64],
    state: LoopState,
    way: NDArray[np.float64],
    kd: NDArray[np.float64],
    dt: float,
) -> tuple[mujoco.MjData, NDArray[np.float64], int]:
    """The plant at the reference's first state, each motor's least inertia (kg m^2) over the
    waypoints, and the substeps per model step (s) that keep the D gain ``kd`` stable; the
    plant's time step is set to match."""
    data = mujoco.MjData(plant)
    data.qpos[:], data.qvel[:] = state.q[0], state.qd[0]
    mujoco.mj_forward(plant, data)
    inertia = np.array([np.diag(motor_inertia(model, d, q)) for q in way]).min(axis=0)
    substeps = max(1, math.ceil(np.max(kd * dt / inertia) / STABLE_KD_DT_OVER_M))
    plant.opt.timestep = dt / substeps
    return data, inertia, substeps


def _reference_state(
    d: NDArray[np.float64],
    t: NDArray[np.float64],
    th: NDArray[np.float64],
    dth: NDArray[np.float64],
    ddth: NDArray[np.float64],
) -> LoopState:
    """The loop's state along the reference (times ``t`` s, motor angles rad and their rates);
    ValueError where it leaves the closing region or nears a transmission singularity."""
    state = loop_state(d, th, dth, ddth)
    if not state.closes.all():
        k = int(np.flatnonzero(~state.closes)[0])
        raise ValueError(
            f"reference leaves the closing region at t={t[k]:.3f} s, "
            f"theta=({math.degrees(th[k, 0]):.2f}, {math.degrees(th[k, 1]):.2f}) deg"
        )
    if state.sin_transmission.min() < MIN_SIN_TRANSMISSION:
        raise ValueError("reference passes through a transmission singularity")
    return state


def _track(
    plant: mujoco.MjModel,
    data: mujoco.MjData,
    tau_ff: NDArray[np.float64],
    th: NDArray[np.float64],
    dth: NDArray[np.float64],
    gains: tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]],
    substeps: int,
    limits: Callable[[NDArray[np.float64], NDArray[np.float64]], NDArray[np.float64]],
) -> tuple[NDArray[np.float64], ...]:
    """Forward-simulate the plant under feedforward ``tau_ff`` (N m) plus PID on the reference
    (``gains`` kp N m/rad, ki N m/(rad s), kd N m s/rad; the error's integral held while a motor
    saturates), each motor's torque clipped to ``limits(torque, speed)``. Returns per sample the
    motor angles (rad), requested, applied and available torques (N m) and whether the request
    exceeded the limit."""
    kp, ki, kd = gains
    h = plant.opt.timestep
    integral = np.zeros(2)
    n = len(th)
    q_act = np.empty((n, 2))
    req, applied, available = (np.zeros((n, 2)) for _ in range(3))
    q_act[0] = data.qpos[[0, 2]]
    over = np.zeros((n, 2), bool)
    for k in range(n - 1):
        for j in range(substeps):  # the PD loop runs at the (sub)step; the reference is held
            q, dq = data.qpos[[0, 2]], data.qvel[[0, 2]]
            torque = tau_ff[k] + kp * (th[k] - q) + ki * integral + kd * (dth[k] - dq)
            lim = limits(torque, dq)
            data.ctrl[:] = np.clip(torque, -lim, lim)
            over[k] |= np.abs(torque) > lim
            integral += np.where(np.abs(torque) > lim, 0.0, (th[k] - q) * h)
            if j == 0:
                req[k], applied[k], available[k] = torque, data.ctrl, lim
            mujoco.mj_step(plant, data)
        q_act[k + 1] = data.qpos[[0, 2]]
    dq = data.qvel[[0, 2]]
    req[-1] = tau_ff[-1] + kp * (th[-1] - q_act[-1]) + ki * integral + kd * (dth[-1] - dq)
    available[-1] = limits(req[-1], dq)
    applied[-1] = np.clip(req[-1], -available[-1], available[-1])
    over[-1] = np.abs(req[-1]) > available[-1]
    return q_act, req, applied, available, over


def _failure_reasons(
    saturated: bool,
    what: str,
    use: Sequence[float | None],
    req: NDArray[np.float64],
    limit: NDArray[np.float64],
    max_err: float,
    tolerance_deg: float,
) -> list[str]:
    """Why the payload test failed: the torque request past ``what`` limited it (with each
    motor's peak use), the tracking error past its tolerance (deg); empty when it passed."""
    reasons = []
    if saturated:
        peaks = np.abs(req).max(axis=0)
        per = "; ".join(
            f"motor {k}: "
            f"{'past its top speed' if u is None else f'{fixed(u, 2)} of what it can give'}"
            f", peak {fixed(p, 1)} N m ({fixed(lim, 1)} N m at standstill)"
            for k, (u, p, lim) in enumerate(zip(use, peaks, limit, strict=True), start=1)
        )
        reasons.append(f"requested torque exceeds the {what} ({per})")
    if not max_err <= tolerance_deg:  # NaN included
        reasons.append(f"tracking error {fixed(max_err, 3)} deg > {tolerance_deg:g} deg")
    return reasons


def _route(
    d: NDArray[np.float64],
    points: ArrayLike,
    s: PayloadSettings,
    reference: Reference | None,
    dt: float,
) -> tuple[NDArray[np.float64], NDArray[np.float64], Reference]:
    """The visited points (n, 2) m, their motor angles (n, 2) rad and the reference through
    them every ``dt`` s: the test's own (the points it visits, :func:`raster_reference`), or
    ``reference`` through ``points`` as given, which must be sampled every ``dt``."""
    pts = _visited(points, s.return_to_start) if reference is None else np.reshape(points, (-1, 2))
    way = joint_path(d, pts, *s.operating_range.degrees)
    ref = raster_reference(way, s, dt) if reference is None else reference
    if not np.allclose(np.diff(ref.t), dt, rtol=1e-9, atol=0):
        raise ValueError(f"the reference is not sampled at the model's time step {dt} s")
    return pts, way, ref


def _drive_limits(
    s: PayloadSettings, drives: Sequence[OutputEnvelope] | None
) -> tuple[NDArray[np.float64] | None, list[OutputEnvelope] | None, tuple[float, float]]:
    """The fixed torque limits (N m) or else the drives' envelopes, and each joint's armature
    (kg m^2: the drives' reflected inertia, 0 with fixed limits and no drives)."""
    if s.torque_limits_Nm is None and drives is None:
        raise ValueError("payload test needs drives or payload_test.torque_limits_Nm")
    fixed = None if s.torque_limits_Nm is None else np.asarray(s.torque_limits_Nm, float)
    envelopes = None if drives is None else list(drives)
    armature = (0.0, 0.0) if envelopes is None else tuple(e.reflected_inertia for e in envelopes)
    return fixed, envelopes, armature


def payload_test(
    design: ArrayLike,
    points: ArrayLike,
    cad: CadSettings = DEFAULT_CAD,
    props: dict[str, MassProperties] | None = None,
    settings: PayloadSettings = DEFAULT_PAYLOAD_TEST,
    drives: Sequence[OutputEnvelope] | None = None,
    reference: Reference | None = None,
) -> dict[str, Any]:
    """Forward-simulate the payload test of ``design`` (6 lengths, m) through task ``points``
    (n, 2) m with link mass properties ``props`` (default: the CAD links), each motor being
    ``drives[j]`` (its envelope and reflected inertia) unless ``settings.torque_limits_Nm``
    overrides the limits (one of the two is needed). With drives the result adds ``drives`` (their
    names) and ``limit_Nm`` is each drive's standstill torque at the joint. ``reference``: the
    motion through the visited points (default :func:`raster_reference`; a time-optimal cycle,
    :mod:`qsm.realization.motion.cycle`), whose ``points`` are then the visited ones in order.

    Returns scalars: ``passed``, ``saturated``, ``max_tracking_error_deg``,
    ``tracking_tolerance_deg``, ``peak_torque_Nm`` (peak |requested| per motor),
    ``peak_torque_over_available`` and ``past_top_speed_fraction`` (:func:`torque_use`),
    ``peak_feedforward_Nm``, ``limit_Nm``, ``saturated_fraction`` (of time steps),
    ``point_error_mm`` (end-effector error at the end of each hold, per waypoint),
    ``waypoints_deg``, ``payload_kg``, ``min_motor_inertia_kg_m2`` (per motor, over the waypoints),
    ``substeps`` (simulation steps per sample), ``duration_s``, ``reason``; and time series ``t_s``
    (N,), ``theta_ref_deg``, ``theta_deg``, ``torque_requested_Nm``, ``torque_applied_Nm`` (N, 2).
    Raises ``ValueError`` when a point is unreachable in the operating range or the reference path
    leaves the region where the loop closes.
    """
    s = settings
    fixed, envelopes, armature = _drive_limits(s, drives)
    limits = _limit_function(fixed, envelopes)
    d = as_design(design)
    run = _simulate(d, points, cad, props, s, armature, limits, reference)
    limit = fixed if fixed is not None else limits(np.ones(2), np.zeros(2))
    saturated = bool(run.over.any())
    max_err = float(np.degrees(np.abs(run.q_act - run.ref.theta)).max())
    use, past_top = torque_use(run.req, run.available)
    what = "fixed limits" if fixed is not None else "drives' torque-speed envelopes"
    reasons = _failure_reasons(
        saturated, what, use, run.req, limit, max_err, s.tracking_tolerance_deg
    )
    return {
        "passed": bool(max_err <= s.tracking_tolerance_deg and not saturated),
        "saturated": saturated,
        "max_tracking_error_deg": max_err,
        "tracking_tolerance_deg": s.tracking_tolerance_deg,
        "peak_torque_Nm": np.abs(run.req).max(axis=0).tolist(),
        "peak_feedforward_Nm": np.abs(run.tau_ff).max(axis=0).tolist(),
        "limit_Nm": limit.tolist(),
        "limits_from": "payload_test.torque_limits_Nm" if fixed is not None else "drives",
        "drives": [e.name for e in envelopes] if envelopes is not None else None,
        "reflected_inertia_kgm2": list(armature),
        "peak_torque_over_available": use,
        "past_top_speed_fraction": past_top,
        "reason": "; ".join(reasons) if reasons else "ok",
        "payload_kg": s.payload_kg,
        **run.fields(d),
    }


class _Run(NamedTuple):
    """One simulated payload test: the reference, its points and waypoints, the feedforward
    and the tracked motion (rad, N m), the least motor inertia and the substeps."""

    ref: Reference
    pts: NDArray[np.float64]
    way: NDArray[np.float64]
    tau_ff: NDArray[np.float64]
    q_act: NDArray[np.float64]
    req: NDArray[np.float64]
    applied: NDArray[np.float64]
    available: NDArray[np.float64]
    over: NDArray[np.bool_]
    inertia: NDArray[np.float64]
    substeps: int

    def fields(self, d: NDArray[np.float64]) -> dict[str, Any]:
        """The result's fields of the motion itself: errors at the holds, waypoints, series."""
        return {
            "saturated_fraction": float(self.over.any(axis=1).mean()),
            "point_error_mm": _point_errors_mm(
                d, self.q_act, self.pts, self.ref.hold_ends
            ).tolist(),
            "waypoints_deg": np.degrees(self.way).tolist(),
            "min_motor_inertia_kg_m2": self.inertia.tolist(),
            "substeps": self.substeps,
            "duration_s": float(self.ref.t[-1]),
            "t_s": self.ref.t,
            "theta_ref_deg": np.degrees(self.ref.theta),
            "theta_deg": np.degrees(self.q_act),
            **dict(zip(TORQUE_SERIES, (self.req, self.applied, self.available), strict=True)),
        }


def _simulate(
    d: NDArray[np.float64],
    points: ArrayLike,
    cad: CadSettings,
    props: dict[str, MassProperties] | None,
    s: PayloadSettings,
    armature: NDArray[np.float64],
    limits: Callable[[NDArray[np.float64], NDArray[np.float64]], NDArray[np.float64]],
    reference: Reference | None,
) -> _Run:
    """The payload test's motion: its reference, the feedforward of the model, and the plant
    tracking it under the controller and ``limits``."""
    model = model_spec(d, cad, s.payload_kg, props, armature).compile()
    dt = float(model.opt.timestep)
    pts, way, ref = _route(d, points, s, reference, dt)
    state = _reference_state(d, ref.t, ref.theta, ref.dtheta, ref.ddtheta)
    tau_ff = inverse_dynamics(model, d, state).tau
    plant = _plant(d, cad, props, s, armature)
    kp, ki, kd = (np.asarray(g, float) for g in (s.kp_Nm_rad, s.ki_Nm_rad_s, s.kd_Nms_rad))
    data, inertia, substeps = _start(model, plant, d, state, way, kd, dt)
    q_act, req, applied, available, over = _track(
        plant, data, tau_ff, ref.theta, ref.dtheta, (kp, ki, kd), substeps, limits
    )
    return _Run(ref, pts, way, tau_ff, q_act, req, applied, available, over, inertia, substeps)
