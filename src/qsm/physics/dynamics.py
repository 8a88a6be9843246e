"""Closed-chain inverse dynamics of the mechanism with MuJoCo: motor torques over a duty.

``mj_inverse`` with the loop equality active does not give a closed chain's motor torques (its
soft constraint force is zero on a consistent trajectory), so (docs/stages.md, Stage 2):

1. the passive joint angles, velocities and accelerations follow analytically from the loop
   closure B - l4 dir(phi) = C + l3 dir(psi) (phi: upper arm, psi: coupler CD) and its first and
   second time derivatives, including the velocity-product (Jdot v) terms;
2. ``mj_inverse`` on the open tree (equality disabled through ``opt.disableflags``) gives the
   generalized force ``qfrc`` the tree needs on that state, for all of a design's states in one
   call on a model of many tree copies (:mod:`qsm.physics.tiled`: the design's own numbers);
3. with G = dq/dtheta (4 x 2) the motor torques are tau = G^T qfrc, and the coupler force lambda
   (force on the coupler at D from the upper arm, the D bearing load) solves the passive rows of
   qfrc = S^T tau + Jc^T lambda.

Sign: tau_i is the torque motor i applies to its own link (lower arm, crank) about +z
(counter-clockwise positive); both motor joints are absolute angles (see :mod:`qsm.physics.mjcf`).
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any, NamedTuple

import mujoco
import numpy as np
from numpy.typing import ArrayLike, NDArray

from qsm.physics.cad import DEFAULT_CAD, CadError, CadSettings, mass_properties
from qsm.physics.duty import Duty
from qsm.physics.kinematics import as_design, cross, perp, relative_arm_angle
from qsm.physics.mjcf import JOINT_NAMES, body_inertials
from qsm.physics.results import DYNAMICS_COLUMNS
from qsm.physics.tiled import tree_forces

# |sin| of the transmission angle at D below which a mechanism is reported as singular
MIN_SIN_TRANSMISSION = 1e-3
#: Designs whose loop states :func:`loop_states` solves in one call (small enough to stay in cache)
LOOP_BATCH = 64


class LoopState(NamedTuple):
    """Loop-consistent joint state for motor samples (N of them).

    q, qd, qdd: (N, 4) positions (rad), velocities (rad/s), accelerations (rad/s^2) of the joints in
    :data:`qsm.physics.mjcf.JOINT_NAMES` order; G: (N, 4, 2) dq/dtheta; rocker_dir, coupler_dir:
    (N, 2) unit vectors dir(phi) and dir(psi); sin_transmission: (N,) |sin| of the transmission
    angle at D; closes: (N,) whether the loop closes (other fields are NaN where it does not).
    """

    q: NDArray[np.float64]
    qd: NDArray[np.float64]
    qdd: NDArray[np.float64]
    G: NDArray[np.float64]
    rocker_dir: NDArray[np.float64]
    coupler_dir: NDArray[np.float64]
    sin_transmission: NDArray[np.float64]
    closes: NDArray[np.bool_]


def loop_state(
    design: ArrayLike, theta: ArrayLike, dtheta: ArrayLike, ddtheta: ArrayLike
) -> LoopState:
    """Solve the loop for motor angles/rates/accelerations (N, 2) of one design (6 lengths, m), or
    of a batch of designs (P, 6); the fields then carry a leading design axis (P, N, ...)."""
    d = as_design(design)
    th, dth, ddth = (np.atleast_2d(np.asarray(a, dtype=float)) for a in (theta, dtheta, ddtheta))
    if d.ndim > 1:  # a batch of designs (P, 6): states (N, 2) shared or (P, N, 2) per design
        # shared states keep a length-1 design axis: what depends on them alone is computed once
        th, dth, ddth = (a.reshape((1,) * (d.ndim + 1 - a.ndim) + a.shape) for a in (th, dth, ddth))
    with np.errstate(invalid="ignore", divide="ignore"):
        return _loop_state(d, th, dth, ddth)


def loop_states(designs: ArrayLike, duty: Duty) -> Iterator[LoopState]:
    """:func:`loop_state` over ``duty`` of each design of ``designs`` (M, 6) m, in order, solved
    :data:`LOOP_BATCH` designs at a time: each design's numbers are those of its own call, bit
    for bit, in a fifth of the time."""
    d = np.asarray(designs, dtype=float)
    for first in range(0, len(d), LOOP_BATCH):
        batch = loop_state(d[first : first + LOOP_BATCH], duty.theta, duty.dtheta, duty.ddtheta)
        for i in range(len(batch.q)):
            yield LoopState(*(field[i] for field in batch))


def components_first(*lead: int, last: tuple[int, ...]) -> NDArray[np.float64]:
    """An empty array of shape (*lead, *last) stored with the ``last`` axes first, so that each
    of their entries (a joint's angle, a vector's x) is one contiguous block."""
    k = len(last)
    return np.empty((*last, *lead)).transpose((*range(k, k + len(lead)), *range(k)))


def _loop_state(d: NDArray, th: NDArray, dth: NDArray, ddth: NDArray) -> LoopState:
    """:func:`loop_state` of designs ``d`` (..., 6) at motor states (..., N, 2), each plane
    vector by its components."""
    l1, l2, l3, l4 = (d[..., i, None] for i in range(4))
    t1, t2 = th[..., 0], th[..., 1]
    # the pose (qsm.physics.kinematics.pose): B = l1 e1, C = l2 e2, D = B - l4 u
    rel, closes = relative_arm_angle(np.stack([l2 / l1, l3 / l1, l4 / l1], axis=-1), t1 - t2)
    phi = t1 + rel
    e1x, e1y, e2x, e2y = np.cos(t1), np.sin(t1), np.cos(t2), np.sin(t2)
    ux, uy = np.cos(phi), np.sin(phi)
    psi = np.arctan2((l1 * e1y - l4 * uy) - l2 * e2y, (l1 * e1x - l4 * ux) - l2 * e2x)
    vx, vy = np.cos(psi), np.sin(psi)
    # M [phi_dot, psi_dot] = C_dot - B_dot with columns a = -l4 perp(u), b = -l3 perp(v)
    ax, ay, bx, by = -l4 * -uy, -l4 * ux, -l3 * -vy, -l3 * vx
    det = ax * by - ay * bx

    def solve(rx: NDArray, ry: NDArray) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        return (rx * by - ry * bx) / det, (ax * ry - ay * rx) / det

    phi_1, psi_1 = solve(-l1 * -e1y, -l1 * e1x)  # d/dtheta1
    phi_2, psi_2 = solve(l2 * -e2y, l2 * e2x)  # d/dtheta2
    w1, w2, a1, a2 = dth[..., 0], dth[..., 1], ddth[..., 0], ddth[..., 1]
    phi_d, psi_d = phi_1 * w1 + phi_2 * w2, psi_1 * w1 + psi_2 * w2
    b_ddx, b_ddy = l1 * (a1 * -e1y - w1**2 * e1x), l1 * (a1 * e1x - w1**2 * e1y)
    c_ddx, c_ddy = l2 * (a2 * -e2y - w2**2 * e2x), l2 * (a2 * e2x - w2**2 * e2y)
    pd2, sd2 = l4 * phi_d**2, l3 * psi_d**2
    phi_dd, psi_dd = solve(c_ddx - b_ddx - pd2 * ux - sd2 * vx, c_ddy - b_ddy - pd2 * uy - sd2 * vy)
    lead = phi.shape
    q, qd, qdd = (components_first(*lead, last=(4,)) for _ in range(3))
    states = ((t1, phi, t2, psi), (w1, phi_d, w2, psi_d), (a1, phi_dd, a2, psi_dd))
    for o, (x, y, z, w) in zip((q, qd, qdd), states, strict=True):
        o[..., 0], o[..., 2] = x, z
        np.subtract(y, x, out=o[..., 1])
        np.subtract(w, z, out=o[..., 3])
    G = components_first(*lead, last=(4, 2))  # dq_i/dtheta
    G[..., 0, :], G[..., 2, :] = (1.0, 0.0), (0.0, 1.0)
    G[..., 1, 0], G[..., 1, 1], G[..., 3, 0], G[..., 3, 1] = phi_1 - 1.0, phi_2, psi_1, psi_2 - 1.0
    u, v = components_first(*lead, last=(2,)), components_first(*lead, last=(2,))
    u[..., 0], u[..., 1], v[..., 0], v[..., 1] = ux, uy, vx, vy
    return LoopState(q, qd, qdd, G, u, v, np.abs(ux * vy - uy * vx), np.broadcast_to(closes, lead))


class InverseResult(NamedTuple):
    """tau: (N, 2) motor torques (N m); coupler_force: (N, 2) force on the coupler at D from the
    upper arm (N), the D bearing load. NaN rows where the loop does not close."""

    tau: NDArray[np.float64]
    coupler_force: NDArray[np.float64]


def inverse_dynamics(model: mujoco.MjModel, design: ArrayLike, state: LoopState) -> InverseResult:
    """Closed-chain inverse dynamics of ``model`` (from :func:`qsm.physics.mjcf.build_model` for
    ``design``) on the loop-consistent ``state`` (:func:`loop_state`).

    Runs ``mj_inverse`` on the open tree (the loop equality is disabled during the call and the
    model's flags restored afterwards), then tau = G^T qfrc and the coupler force from the
    passive-joint rows of qfrc = S^T tau + Jc^T lambda.
    """
    dof = np.array([model.jnt_dofadr[model.joint(n).id] for n in JOINT_NAMES])
    if not np.array_equal(dof, np.arange(4)):
        raise RuntimeError(f"unexpected dof order {dof} for joints {JOINT_NAMES}")
    data = mujoco.MjData(model)
    qpos, qvel, qacc, qfrc_inv = data.qpos, data.qvel, data.qacc, data.qfrc_inverse
    n = len(state.q)
    qfrc = np.full((n, 4), np.nan)
    flags = model.opt.disableflags
    model.opt.disableflags = flags | mujoco.mjtDisableBit.mjDSBL_EQUALITY
    try:
        for k in np.flatnonzero(state.closes):
            qpos[:] = state.q[k]
            qvel[:] = state.qd[k]
            qacc[:] = state.qdd[k]
            mujoco.mj_inverse(model, data)
            qfrc[k] = qfrc_inv
    finally:
        model.opt.disableflags = flags
    return _motor_forces(design, state, qfrc)


def tree_inverse_dynamics(
    design: ArrayLike,
    bodies: dict[str, Any],
    state: LoopState,
    armature: tuple[float, float] = (0.0, 0.0),
) -> InverseResult:
    """:func:`inverse_dynamics` without a model of the design: the open tree's generalized
    forces come from :func:`qsm.physics.tiled.tree_forces` with ``bodies``
    (:func:`qsm.physics.mjcf.body_inertials`), all states in one ``mj_inverse`` call;
    ``armature`` (kg m^2) on theta1 and theta2 (the drives' reflected inertia)."""
    qfrc = np.full((len(state.q), 4), np.nan)
    rows = np.flatnonzero(state.closes)
    qfrc[rows] = tree_forces(bodies, state.q[rows], state.qd[rows], state.qdd[rows], armature)
    return _motor_forces(design, state, qfrc)


def _motor_forces(design: ArrayLike, state: LoopState, qfrc: NDArray[np.float64]) -> InverseResult:
    """Motor torques tau = G^T qfrc and the coupler force from the passive-joint rows of qfrc."""
    tau = np.einsum("nij,ni->nj", state.G, qfrc)
    d = as_design(design)
    a, b = d[3] * perp(state.rocker_dir), d[2] * perp(state.coupler_dir)
    det = cross(a, b)
    f1, f2 = qfrc[:, 1], qfrc[:, 3]  # rows of the passive joints: a . lambda = f1, b . lambda = f2
    lam = np.column_stack(
        [(f1 * b[:, 1] - f2 * a[:, 1]) / det, (a[:, 0] * f2 - b[:, 0] * f1) / det]
    )
    return InverseResult(tau, lam)


def joint_torques(
    design: ArrayLike,
    theta: ArrayLike,
    dtheta: ArrayLike,
    ddtheta: ArrayLike,
    *,
    payload_kg: float,
    link_density: float | None = None,
) -> NDArray[np.float64]:
    """Motor torques (N, 2) in N m for motor angles, rates, accelerations (N, 2) in rad, rad/s,
    rad/s^2 of one design (6 lengths, m) with a payload (kg) at E.

    Links use the default :class:`qsm.physics.cad.CadSettings` section, with ``link_density``
    (kg/m^3) replacing the default material when given. Rows where the loop does not close are NaN;
    raises :class:`qsm.physics.cad.CadError` when the section does not fit the design.
    """
    settings = DEFAULT_CAD if link_density is None else CadSettings(density_kg_m3=link_density)
    state = loop_state(design, theta, dtheta, ddtheta)
    bodies = body_inertials(design, mass_properties(design, settings), payload_kg)
    return tree_inverse_dynamics(design, bodies, state).tau


def _failure(status: str, reason: str, masses: dict[str, float]) -> dict[str, Any]:
    """The result of a design whose dynamics failed: NaN but its masses, and why."""
    out: dict[str, Any] = dict.fromkeys(DYNAMICS_COLUMNS, np.nan)
    out.update(masses, status=status, status_reason=reason)
    return out


def _peaks(
    tau: NDArray[np.float64],
    coupler_force: NDArray[np.float64],
    sin_mu: NDArray[np.float64],
    duty: Duty,
) -> dict[str, float]:
    """The torque columns of :func:`evaluate_mechanism` from its motor torques (N, 2) N m, the
    coupler force (N, 2) N and |sin| of the transmission angle (N,) over ``duty``."""
    mag = np.abs(tau)
    k1, k2 = int(np.argmax(mag[:, 0])), int(np.argmax(mag[:, 1]))
    w = duty.weight_s
    rms = np.sqrt((w[:, None] * tau**2).sum(axis=0) / w.sum())
    deg = np.degrees(duty.theta)
    return {
        "tau1_Nm": float(mag[k1, 0]),
        "tau2_Nm": float(mag[k2, 1]),
        "theta1_at_tau1_peak_deg": float(deg[k1, 0]),
        "theta2_at_tau1_peak_deg": float(deg[k1, 1]),
        "theta1_at_tau2_peak_deg": float(deg[k2, 0]),
        "theta2_at_tau2_peak_deg": float(deg[k2, 1]),
        "tau1_rms_Nm": float(rms[0]),
        "tau2_rms_Nm": float(rms[1]),
        "coupler_force_peak_N": float(np.hypot(*coupler_force.T).max()),
        "transmission_angle_min_deg": float(np.degrees(np.arcsin(min(sin_mu.min(), 1.0)))),
    }


def evaluate_mechanism(
    design: ArrayLike,
    duty: Duty,
    settings: CadSettings = DEFAULT_CAD,
    payload_kg: float = 5.0,
    scale: ArrayLike | None = None,
    state: LoopState | None = None,
) -> dict[str, Any]:
    """Peak and RMS motor torques of one design (6 lengths, m) over ``duty``, each link of the
    section ``settings`` scaled by its entry of ``scale`` (4,) (None: ``settings`` for all);
    ``state``: the design's loop state over ``duty`` when solved already (:func:`loop_states`).

    Returns a dict with the keys of :data:`qsm.physics.results.DYNAMICS_COLUMNS`: peak |tau|
    (N m) of each motor and the motor angles (deg) where it occurs, time-weighted RMS torques
    over the moving part of the duty,
    peak coupler (D bearing) force (N), smallest transmission angle at D (deg, folded into
    [0, 90]), link masses (kg, without the payload), and ``status``: 'ok', 'cad_invalid' (the
    section does not fit), 'loop_open' (the loop does not close at some duty pose), 'singular'
    (|sin| of the transmission angle below :data:`MIN_SIN_TRANSMISSION`), 'nonfinite' or 'error'
    (unexpected exception), with a human-readable ``status_reason``. Never raises.
    """
    masses: dict[str, float] = {}
    try:
        props = mass_properties(design, settings, scale)
        masses = {f"mass_{k}_kg": v.mass_kg for k, v in props.items()}
        if state is None:
            state = loop_state(design, duty.theta, duty.dtheta, duty.ddtheta)
        if not state.closes.all():
            bad = np.flatnonzero(~state.closes)
            t1, t2 = np.degrees(duty.theta[bad[0]])
            return _failure(
                "loop_open",
                f"loop does not close at {len(bad)} of {len(bad) + state.closes.sum()} duty poses,"
                f" first at theta1={t1:.2f} deg, theta2={t2:.2f} deg",
                masses,
            )
        sin_mu = state.sin_transmission
        if sin_mu.min() < MIN_SIN_TRANSMISSION:
            return _failure(
                "singular",
                f"|sin transmission angle| = {sin_mu.min():.3g} < {MIN_SIN_TRANSMISSION}",
                masses,
            )
        inv = tree_inverse_dynamics(design, body_inertials(design, props, payload_kg), state)
        if not (np.isfinite(inv.tau).all() and np.isfinite(inv.coupler_force).all()):
            return _failure("nonfinite", "non-finite torque or coupler force", masses)
    except CadError as exc:
        return _failure("cad_invalid", str(exc), masses)
    except Exception as exc:  # one bad mechanism must not stop a table
        return _failure("error", f"{type(exc).__name__}: {exc}", masses)
    return {**_peaks(inv.tau, inv.coupler_force, sin_mu, duty), **masses, "status": "ok",
            "status_reason": ""}  # fmt: skip
