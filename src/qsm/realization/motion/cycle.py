"""The time-optimal pick-and-place cycle of a design with its chosen drives (TOPP-RA).

The cycle visits task points in order and dwells at each. Each move between two points is a
straight line in joint space between the motor angles of the inverse kinematics at its ends
(linear interpolation), from rest to rest. TOPP-RA (``toppra``) finds the fastest timing along
it under:

* each motor's torque, the closed chain's inverse dynamics by Newton-Euler
  (:mod:`qsm.embodiment.strength.loads`, MuJoCo's to 1e-6) plus the drive's reflected inertia
  times the joint's acceleration (MuJoCo's joint armature), within the drive's torque-speed
  envelope at the joint (:class:`qsm.embodiment.drives.envelope.OutputEnvelope`, the gearbox's
  peak torque included);
* each joint's speed.

The envelope is not linear in TOPP-RA's variables. Each move is planned with a speed bound ``v``
per joint and the least torque of the envelope in the driving direction over [0, ``v``], which
the drive gives at every speed up to ``v`` (back-driving gives more). ``v`` is tried at
:data:`SPEED_FRACTIONS` of the drive's top speed, and the fastest plan is kept. This is the
conservative linearisation, at TOPP-RA's grid points (:data:`GRID` per move; between them the
torque may pass the bound slightly, which MuJoCo's run checks).

TOPP-RA's timing is bang-bang in acceleration: its jerk is unbounded, and each step of the
acceleration rings the arm's modes. Given a jerk time, each move is then retimed along its line
by Ruckig (:func:`jerk_limited`) within a jerk limit: its peak acceleration over the jerk time.
A mode of frequency f driven by an acceleration ramp of duration T is left ringing with the
amplitude of the step's ringing times |sin(pi f T) / (pi f T)|, none when T is one period of the
mode. With a jerk time of one period of the arm's first mode, each ramp to or from the move's
peak acceleration leaves that mode, undamped, no residual vibration; a shorter ramp (a move too
short to reach its peak) leaves some, which the settling check sees.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Sequence
from typing import NamedTuple

import numpy as np
import toppra
import toppra.algorithm
import toppra.constraint
from numpy.typing import ArrayLike, NDArray
from ruckig import InputParameter, Result, Ruckig, Trajectory
from toppra.constraint.linear_constraint import canlinear_colloc_to_interpolate

from qsm.embodiment.drives.envelope import OutputEnvelope
from qsm.embodiment.strength.loads import Inertials, joint_loads
from qsm.physics.dynamics import loop_state
from qsm.prose import point
from qsm.realization.motion.payload import Reference

#: Speed bounds tried per move, as fractions of each drive's top speed at the joint.
SPEED_FRACTIONS: tuple[float, ...] = (0.05, 0.15, 0.3, 0.5, 0.7, 0.85, 0.95)
#: Grid intervals of TOPP-RA along each move.
GRID = 80
#: A plan's peak use of a bound at or above this counts that bound as binding.
BINDING = 0.97
#: At most this many accelerations are tried for a jerk-limited move (:func:`jerk_limited`).
JERK_TRIES = 40

#: TOPP-RA warns of every speed bound at which a move cannot be timed ("Fail to parametrize path
#: ... not controllable"). That is expected: :func:`plan_move` tries several bounds and keeps the
#: fastest that can be timed, and says so itself (ValueError naming the move) when none can.
toppra.setup_logging("ERROR")


class Arm(NamedTuple):
    """What the planner needs of the realised arm: the design (6 lengths, m), its links'
    inertials, the payload (kg) and each motor's drive envelope at the joint."""

    design: NDArray[np.float64]
    inertials: Inertials
    payload_kg: float
    drives: Sequence[OutputEnvelope]

    @property
    def reflected(self) -> NDArray[np.float64]:
        """Each drive's reflected inertia (2,) kg m^2 at the joint."""
        return np.array([e.reflected_inertia for e in self.drives])


class Move(NamedTuple):
    """One planned move: times (N,) s from its start, motor angles (N, 2) rad, speeds rad/s,
    accelerations rad/s^2 and torques (N, 2) N m; the speed bound (2,) rad/s and torque bound
    (2,) N m it was planned with, and what binds (``torque``, ``speed`` or both)."""

    t: NDArray[np.float64]
    q: NDArray[np.float64]
    qd: NDArray[np.float64]
    qdd: NDArray[np.float64]
    tau: NDArray[np.float64]
    speed_bound: NDArray[np.float64]
    torque_bound: NDArray[np.float64]
    binding: str

    @property
    def duration_s(self) -> float:
        """The move's duration (s)."""
        return float(self.t[-1])


def top_speed(envelope: OutputEnvelope) -> float:
    """The joint speed (rad/s) beyond which the drive gives no torque."""
    motor = envelope.int_speed
    if envelope.table is not None:
        motor = min(motor, float(envelope.table[0][-1]))
    else:
        motor = min(motor, envelope.no_load_speed)
    return motor / envelope.ratio


def torque_bound(envelope: OutputEnvelope, speed: float) -> float:
    """The torque (N m) the drive gives at the joint at every speed up to ``speed`` (rad/s): the
    least of its envelope in the driving direction (back-driving gives more) over [0, speed],
    at 64 speeds and its torque-speed table's own."""
    speeds = np.linspace(0.0, speed, 64)
    if envelope.table is not None:
        table = envelope.table[0] / envelope.ratio
        speeds = np.concatenate([speeds, table[table <= speed]])
    return float(envelope.limit(np.ones_like(speeds), speeds).min())


def motor_torques(arm: Arm, q: ArrayLike, qd: ArrayLike, qdd: ArrayLike) -> NDArray[np.float64]:
    """The motors' torques (N, 2) N m at motor angles, speeds and accelerations (N, 2): the
    closed chain's inverse dynamics with the payload, plus each drive's reflected inertia."""
    q, qd, qdd = (np.atleast_2d(np.asarray(x, dtype=float)) for x in (q, qd, qdd))
    state = loop_state(arm.design, q, qd, qdd)
    return joint_loads(arm.design, arm.inertials, arm.payload_kg, state).tau + arm.reflected * qdd


#: Inverse dynamics of a batch: torques (N, dof) at positions, speeds, accelerations (N, dof).
InverseDynamics = Callable[[NDArray, NDArray, NDArray], NDArray]


class TorqueTerms(NamedTuple):
    """The torques along a path at TOPP-RA's grid points (GRID + 1, dof) N m, as
    tau = a s'' + b s'^2 + c in the path coordinate s."""

    a: NDArray[np.float64]
    b: NDArray[np.float64]
    c: NDArray[np.float64]


def straight_path(q0: ArrayLike, q1: ArrayLike) -> toppra.SplineInterpolator:
    """The straight joint-space path q0 -> q1 (dof,) rad over s in [0, 1]."""
    return toppra.SplineInterpolator([0.0, 1.0], np.vstack([q0, q1]), bc_type="natural")


def torque_terms(inverse: InverseDynamics, path: toppra.SplineInterpolator) -> TorqueTerms:
    """:class:`TorqueTerms` of ``path`` at the :data:`GRID` points, ``inverse`` giving the
    torques of every point at once: one evaluation serves every speed bound of a move."""
    grid = np.linspace(0.0, 1.0, GRID + 1)
    p, ps, pss = path(grid), path(grid, 1), path(grid, 2)
    zero = np.zeros_like(p)
    c = inverse(p, zero, zero)
    return TorqueTerms(inverse(p, zero, ps) - c, inverse(p, ps, pss) - c, c)


class _BatchTorque(toppra.constraint.JointTorqueConstraint):
    """TOPP-RA's joint torque constraint from the path's :class:`TorqueTerms` (the parent
    evaluates the inverse dynamics point by point), in TOPP-RA's interpolation scheme."""

    def __init__(self, terms: TorqueTerms, torque: NDArray[np.float64]) -> None:
        super().__init__(
            None, np.column_stack([-torque, torque]), np.zeros(len(torque)),
            discretization_scheme=toppra.constraint.DiscretizationType.Interpolation,
        )  # fmt: skip
        self.terms = terms

    def compute_constraint_params(self, path, gridpoints):
        """TOPP-RA's a, b, c, F, g of the torque bounds at ``gridpoints`` (those of the
        terms)."""
        eye = np.eye(self.terms.c.shape[1])
        f = np.vstack([eye, -eye])
        g = np.concatenate([self.tau_lim[:, 1], -self.tau_lim[:, 0]])
        return canlinear_colloc_to_interpolate(
            *self.terms, f, g, None, None, gridpoints, identical=True
        )


def time_optimal_timing(
    path: toppra.SplineInterpolator, terms: TorqueTerms, speed: ArrayLike, torque: ArrayLike
) -> toppra.interpolator.AbstractGeometricPath | None:
    """TOPP-RA's fastest rest-to-rest timing along ``path`` (:func:`straight_path`) with every
    joint's |speed| (rad/s) and |torque| (N m) bounded, the torques given by ``terms``
    (:func:`torque_terms`); None where no timing is feasible."""
    speed, torque = np.asarray(speed, dtype=float), np.asarray(torque, dtype=float)
    limits = [
        toppra.constraint.JointVelocityConstraint(np.column_stack([-speed, speed])),
        _BatchTorque(terms, torque),
    ]
    grid = np.linspace(0.0, 1.0, GRID + 1)
    algorithm = toppra.algorithm.TOPPRA(
        limits, path, gridpoints=grid, parametrizer="ParametrizeConstAccel"
    )
    return algorithm.compute_trajectory(0.0, 0.0)


def sampled_end_s(timing: toppra.interpolator.AbstractGeometricPath, dt: float) -> float:
    """The last sample time (s) of ``timing`` sampled every ``dt`` s, its end held to the next
    step (:func:`sampled`)."""
    return math.ceil(timing.duration / dt) * dt


def sampled(
    timing: toppra.interpolator.AbstractGeometricPath, dt: float
) -> tuple[NDArray, NDArray, NDArray, NDArray]:
    """``timing`` every ``dt`` s, the end held to the next step: times (N,) s, positions,
    speeds and accelerations (N, dof)."""
    t = np.arange(math.ceil(timing.duration / dt) + 1) * dt
    at = np.minimum(t, timing.duration)
    return t, timing(at), timing(at, 1), timing(at, 2)


def plan_move(
    arm: Arm,
    q0: ArrayLike,
    q1: ArrayLike,
    dt: float,
    fractions: Sequence[float] = SPEED_FRACTIONS,
    jerk_time_s: float | None = None,
) -> Move:
    """The fastest of the moves q0 -> q1 (motor angles (2,) rad) planned at each speed bound of
    ``fractions`` (of each drive's top speed; the first of equally fast ones), sampled every
    ``dt`` s, then retimed with its acceleration ramped over ``jerk_time_s`` (s; None: TOPP-RA's
    timing, :func:`jerk_limited`); ValueError when none is feasible (a drive that cannot hold
    the arm). Only the fastest timing is sampled: a slow bound's is the longest."""
    q0, q1 = np.asarray(q0, dtype=float), np.asarray(q1, dtype=float)
    top = np.array([top_speed(e) for e in arm.drives])
    path = straight_path(q0, q1)
    terms = torque_terms(lambda q, qd, qdd: motor_torques(arm, q, qd, qdd), path)
    timings = []
    for fraction in fractions:
        speed = fraction * top
        torque = np.array([torque_bound(e, v) for e, v in zip(arm.drives, speed, strict=True)])
        timing = time_optimal_timing(path, terms, speed, torque)
        if timing is not None:
            timings.append((sampled_end_s(timing, dt), timing, speed, torque))
    if not timings:
        raise ValueError(
            f"no timing of the move from motor angles {point(np.degrees(q0), 1, 'deg')} to "
            f"{point(np.degrees(q1), 1, 'deg')} keeps the torques within the drives'"
        )
    _, timing, speed, torque = min(timings, key=lambda planned: planned[0])
    t, q, qd, qdd = sampled(timing, dt)
    tau = motor_torques(arm, q, qd, qdd)
    best = Move(t, q, qd, qdd, tau, speed, torque, _binding(qd, tau, speed, torque))
    return best if jerk_time_s is None else jerk_limited(best, arm, jerk_time_s, dt)


def _ruckig(
    speed: float, accel: float, jerk: float, dt: float
) -> tuple[NDArray, NDArray, NDArray, NDArray]:
    """Ruckig's rest-to-rest timing of a path coordinate from 0 to 1 within ``speed`` (1/s),
    ``accel`` (1/s^2) and ``jerk`` (1/s^3): times (N,) s every ``dt`` s (the end held to the
    next step), the coordinate, its speed and its acceleration (N,)."""
    inp = InputParameter(1)
    inp.current_position, inp.target_position = [0.0], [1.0]
    inp.max_velocity, inp.max_acceleration, inp.max_jerk = [speed], [accel], [jerk]
    traj = Trajectory(1)
    if Ruckig(1).calculate(inp, traj) not in (Result.Working, Result.Finished):
        raise ValueError(f"Ruckig found no timing within {speed}, {accel}, {jerk}")
    t = np.arange(math.ceil(traj.duration / dt) + 1) * dt
    at = np.minimum(t, traj.duration)
    s, sd, sdd = (
        np.array(v)[:, 0] for v in zip(*(traj.at_time(float(x)) for x in at), strict=True)
    )
    return t, s, sd, sdd


def jerk_limited(move: Move, arm: Arm, jerk_time_s: float, dt: float) -> Move:
    """``move`` retimed by Ruckig along its straight line (rest to rest), its path acceleration
    ramped over ``jerk_time_s`` (s): the path speed at most the TOPP-RA move's peak (so each
    joint within its speed bound), the path acceleration from the TOPP-RA move's peak, lowered
    (and the jerk, its acceleration over ``jerk_time_s``, with it) until the torques stay within
    the move's torque bounds at every sample, at most :data:`JERK_TRIES` times (then the last,
    which MuJoCo's run checks). Each joint's jerk is its change times the path's."""
    q0, dq = move.q[0], move.q[-1] - move.q[0]
    norm = float(dq @ dq)
    if norm == 0.0:
        return move
    speed = float(np.abs(move.qd @ dq).max() / norm)
    accel = float(np.abs(move.qdd @ dq).max() / norm)
    for _ in range(JERK_TRIES):
        t, s, sd, sdd = _ruckig(speed, accel, accel / jerk_time_s, dt)
        q, qd, qdd = (q0 + s[:, None] * dq, sd[:, None] * dq, sdd[:, None] * dq)
        tau = motor_torques(arm, q, qd, qdd)
        use = float((np.abs(tau) / move.torque_bound).max())
        if use <= 1.0:
            break
        accel *= min(0.97, 1.0 / use)
    binding = f"{move.binding}, then the jerk limit"
    return move._replace(t=t, q=q, qd=qd, qdd=qdd, tau=tau, binding=binding)


def _binding(qd: NDArray, tau: NDArray, speed: NDArray, torque: NDArray) -> str:
    """Which bounds the move reaches (their peak use >= :data:`BINDING`)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        torque_use = float(np.nanmax(np.abs(tau) / torque))
    speed_use = float(np.max(np.abs(qd) / speed))
    found = [n for n, u in (("torque", torque_use), ("speed", speed_use)) if u >= BINDING]
    return " and ".join(found) or "neither (the grid)"


def time_scaled(move: Move, arm: Arm, factor: float, dt: float) -> Move:
    """``move`` run ``factor`` (>= 1) times slower, resampled every ``dt`` s: speeds / factor,
    accelerations / factor^2 at the same positions, the torques recomputed."""
    if factor == 1.0:
        return move
    t = np.arange(math.ceil(move.t[-1] * factor / dt) + 1) * dt
    at = np.minimum(t / factor, move.t[-1])
    q, qd, qdd = (
        np.column_stack([np.interp(at, move.t, x[:, j]) for j in range(x.shape[1])])
        for x in (move.q, move.qd / factor, move.qdd / factor**2)
    )
    tau = motor_torques(arm, q, qd, qdd)
    return move._replace(t=t, q=q, qd=qd, qdd=qdd, tau=tau, binding=f"slowed {factor:g}x")


class Cycle(NamedTuple):
    """A cycle: its moves, in order, the dwell (s) at each visited point, the sample step (s),
    whether it ``returns`` to its first point, how many times slower than the time-optimal
    timing it runs, the time (s) its moves ramp their acceleration over as run (None: they do
    not), and the dwell
    (s) after each move where it differs from ``dwell_s`` (None: none does; a returning cycle
    starts with its last)."""

    moves: tuple[Move, ...]
    dwell_s: float
    dt: float
    returns: bool
    factor: float = 1.0
    jerk_time_s: float | None = None
    dwells_s: tuple[float, ...] | None = None

    @property
    def stops_s(self) -> tuple[float, ...]:
        """The dwell (s) at the first point, then after each move."""
        after = self.dwells_s or (self.dwell_s,) * len(self.moves)
        return ((after[-1] if self.returns else self.dwell_s), *after)

    def period(self) -> slice:
        """The samples of :meth:`samples` that make one period of the repeated cycle: all but
        the first dwell when the cycle returns (its last dwell is at the same point)."""
        return slice(round(self.stops_s[0] / self.dt) + 1 if self.returns else 0, None)

    @property
    def time_s(self) -> float:
        """The cycle's time (s): every move and a dwell at each point it visits (the start and
        the end once when it returns there)."""
        stops = self.stops_s[1:] if self.returns else self.stops_s
        return float(sum(m.duration_s for m in self.moves) + sum(stops))

    def samples(self) -> Reference:
        """The cycle as a reference motion from rest at its first point: a dwell, then each move
        and a dwell at its end, every ``dt`` s, with the sample at which each dwell ends."""
        holds = [round(d / self.dt) for d in self.stops_s]
        first = self.moves[0]
        q = [np.repeat(first.q[:1], holds[0] + 1, axis=0)]
        qd = [np.zeros((holds[0] + 1, 2))]
        qdd = [np.zeros((holds[0] + 1, 2))]
        ends = [holds[0]]
        for m, hold in zip(self.moves, holds[1:], strict=True):
            q += [m.q[1:], np.repeat(m.q[-1:], hold, axis=0)]
            qd += [m.qd[1:], np.zeros((hold, 2))]
            qdd += [m.qdd[1:], np.zeros((hold, 2))]
            ends.append(ends[-1] + len(m.t) - 1 + hold)
        theta = np.concatenate(q)
        t = np.arange(len(theta)) * self.dt
        return Reference(t, theta, np.concatenate(qd), np.concatenate(qdd), np.array(ends))


def plan_cycle(
    arm: Arm,
    angles: ArrayLike,
    dwell_s: float,
    dt: float,
    returns: bool,
    fractions: Sequence[float] = SPEED_FRACTIONS,
) -> Cycle:
    """The time-optimal cycle through the visited points' motor ``angles`` (n, 2) rad, in order
    (the start again at the end when it ``returns``), with ``dwell_s`` at each, sampled every
    ``dt`` s, each move planned at the speed bounds ``fractions`` (TOPP-RA's timing,
    :func:`plan_move`)."""
    way = np.asarray(angles, dtype=float)
    moves = tuple(plan_move(arm, a, b, dt, fractions) for a, b in itertools.pairwise(way))
    return Cycle(moves, dwell_s, dt, returns)


def jerk_limited_cycle(cycle: Cycle, arm: Arm, jerk_time_s: float | None) -> Cycle:
    """``cycle`` (as planned, not slowed) with each move retimed, its acceleration ramped over
    ``jerk_time_s`` (s; None: ``cycle`` as it is, :func:`jerk_limited`)."""
    if jerk_time_s is None:
        return cycle
    moves = tuple(jerk_limited(m, arm, jerk_time_s, cycle.dt) for m in cycle.moves)
    return cycle._replace(moves=moves, jerk_time_s=jerk_time_s)


def slowed(cycle: Cycle, arm: Arm, factor: float) -> Cycle:
    """``cycle`` (as planned) run ``factor`` times slower, its ramps (the jerk time) as long;
    its dwells unchanged."""
    moves = tuple(time_scaled(m, arm, factor, cycle.dt) for m in cycle.moves)
    jerk = None if cycle.jerk_time_s is None else cycle.jerk_time_s * factor
    return cycle._replace(moves=moves, factor=factor, jerk_time_s=jerk)


#: A minimum-jerk move's duration over (its change / its peak speed).
MIN_JERK_DURATION = 1.875


def move_jerk(move: Move, jerk_time_s: float | None, dt: float) -> dict[str, list[float] | None]:
    """A move's jerk as run: each joint's peak (rad/s^3, from its sampled accelerations) and its
    limit (its change times the move's peak path acceleration over ``jerk_time_s``; None
    without a jerk time)."""
    dq = move.q[-1] - move.q[0]
    peak = np.abs(np.diff(move.qdd, axis=0)).max(axis=0) / dt if len(move.t) > 1 else np.zeros(2)
    if jerk_time_s is None or not float(dq @ dq):
        return {"peak_jerk_rad_s3": peak.tolist(), "jerk_limit_rad_s3": None}
    path_accel = float(np.abs(move.qdd @ dq).max() / (dq @ dq))
    limit = np.abs(dq) * path_accel / jerk_time_s
    return {"peak_jerk_rad_s3": peak.tolist(), "jerk_limit_rad_s3": limit.tolist()}


def raster_time_s(angles: NDArray[np.float64], peak_speed_rad_s: float) -> float:
    """The moves' time (s) between consecutive motor ``angles`` (n, 2) rad at the duty's raster
    speed: minimum-jerk moves whose faster joint peaks at ``peak_speed_rad_s`` (rad/s)."""
    change = np.abs(np.diff(angles, axis=0)).max(axis=1)
    return float(MIN_JERK_DURATION * change.sum() / peak_speed_rad_s)
