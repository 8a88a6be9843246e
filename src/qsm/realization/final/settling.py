"""Settling at each stop of a cycle: how long the tool rings after it arrives, and the dwell it
needs before it is placed within the tolerance.

The arm's first mode as the tool sees it (:func:`qsm.embodiment.stiffness.modes.tool_mode`: its
frequency and the direction it moves the tool, by the accuracy budget's frame with the printed
plates, the gearboxes' springs and the moving masses) is a single-mode oscillator at each stop's
pose,

    x'' + 2 zeta omega x' + omega^2 x = omega^2 c F(t),

x the tool's elastic displacement (m) along the mode's direction about its rest under gravity,
c the tool's compliance along it (m/N) and F the payload's inertial force along it (N, the
payload times the tool's acceleration, :func:`qsm.embodiment.stiffness.error_terms
.tool_acceleration`), so that a steady acceleration deflects the tool as the budget's dynamic
sag does. It is stepped exactly over the move, the force held over each sample (zero-order hold,
:func:`response`). After the arrival the ringing decays with the envelope A e^(-zeta omega t);
the stop is settled once the static terms of the placing error (the budget's, all but the
dynamic sag) plus that envelope stay within the tolerance (:func:`settling_s`). Each stop's dwell
is the longer of the configured one (the gripper's time) and that.

The elastic MuJoCo model of :mod:`qsm.realization.final.elastic_arm` (beam segments with
torsional springs, gearboxes as springs, the links' own inertia) runs each move of the cycle kept
from rest at its start and holds its end: the stop's dwell is also at least the time after which
the tool's ringing about its rest there stays within what the static terms leave
(:func:`settled`). It is not run for each trial of the slow-down, only for the cycles checked.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
import scipy.linalg
from numpy.typing import ArrayLike, NDArray

from qsm.embodiment.stiffness.error_terms import tool_acceleration
from qsm.embodiment.stiffness.frame import tool_compliance
from qsm.embodiment.stiffness.modes import tool_mode
from qsm.realization.accuracy.accuracy_budget import ArmModel
from qsm.realization.final.elastic_arm import ElasticArm, ElasticStop
from qsm.realization.final.elastic_arm import stops as elastic_stops
from qsm.realization.motion.cycle import Cycle, Move


@dataclass(frozen=True)
class ToolMode:
    """The first mode at a pose as the tool sees it: ``frequency_hz`` (Hz), the unit
    ``direction`` (2,) it moves the tool in, and the tool's ``compliance_m_N`` (m/N) along it."""

    frequency_hz: float
    direction: tuple[float, float]
    compliance_m_N: float

    @property
    def omega(self) -> float:
        """The mode's angular frequency (rad/s)."""
        return 2 * math.pi * self.frequency_hz


@dataclass(frozen=True)
class Settling:
    """What the settling check needs: the arm's frame ``model``, the payload (kg, tool flange
    included), the ``damping_ratio`` (1) of its first mode, the ``tolerance_mm`` (mm) and the
    largest static part of the placing error over the task points (``static_mm``, mm: the
    budget's terms but the dynamic sag), and the arm's ``elastic`` model
    (:mod:`qsm.realization.final.elastic_arm`; None: the single mode alone)."""

    model: ArmModel
    payload_kg: float
    damping_ratio: float
    tolerance_mm: float
    static_mm: float
    elastic: ElasticArm | None = None

    @property
    def allowed_m(self) -> float:
        """The ringing (m) the tolerance leaves once the static terms are placed."""
        return 1e-3 * (self.tolerance_mm - self.static_mm)


@dataclass(frozen=True)
class Arrival:
    """One stop: the first mode there (Hz), the ringing amplitude on arrival (mm), the time
    after which the tool stays within the tolerance (``settling_s``, s; None: never, its static
    terms alone miss it), the same in the elastic model (``elastic``, None: not run; its
    ``settling_s`` None: not within its hold) and the ``dwell_s`` kept (s: the configured dwell,
    or the longer settling time)."""

    frequency_hz: float
    ringing_mm: float
    settling_s: float | None
    dwell_s: float
    elastic: ElasticStop | None = None

    def record(self, point: int) -> dict[str, Any]:
        """JSON, at task point number ``point``."""
        e = self.elastic
        return {"point": point, "first_mode_hz": self.frequency_hz,
                "ringing_mm": self.ringing_mm, "settling_s": self.settling_s,
                "elastic_ringing_mm": None if e is None else e.ringing_mm,
                "elastic_settling_s": None if e is None else e.settling_s,
                "dwell_s": self.dwell_s}  # fmt: skip


def mode_at(model: ArmModel, angles: ArrayLike, payload_kg: float) -> ToolMode:
    """The first mode at motor ``angles`` (2,) rad of the arm ``model`` carrying ``payload_kg``
    at the tool (kg), and the tool's compliance along its direction."""
    t1, t2 = (float(a) for a in np.asarray(angles, dtype=float))
    printed = model.sections._replace(factor=model.factor)
    rigid = not np.isfinite(model.drive_stiffness).all()
    k = None if rigid else model.drive_stiffness
    reflected = None if rigid else model.reflected_kgm2
    f, u = tool_mode(model.design, t1, t2, printed, model.inertials.mass_kg, payload_kg, k,
                     reflected)  # fmt: skip
    c = tool_compliance(model.design, t1, t2, printed, k)
    return ToolMode(f, (float(u[0]), float(u[1])), float(u @ c @ u))


def response(
    force_N: NDArray[np.float64],
    mode: ToolMode,
    damping_ratio: float,
    dt: float,
    start: tuple[float, float] = (0.0, 0.0),
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The oscillator's displacement (N,) m and speed (N,) m/s from ``start`` (m, m/s; rest)
    under ``force_N`` (N,) N along the mode, each held over its step of ``dt`` s, stepped
    exactly (the matrix exponential of the state and the held force together)."""
    w, z = mode.omega, damping_ratio
    a = np.array([[0.0, 1.0, 0.0], [-(w**2), -2 * z * w, w**2 * mode.compliance_m_N], [0, 0, 0]])
    step = scipy.linalg.expm(a * dt)
    x = np.zeros((len(force_N), 2))
    state = np.asarray(start, dtype=float)
    for i, f in enumerate(force_N):
        x[i] = state
        state = step[:2, :2] @ state + step[:2, 2] * f
    return x[:, 0], x[:, 1]


def amplitude_m(x: float, v: float, mode: ToolMode, damping_ratio: float) -> float:
    """The envelope (m) of the free decay from displacement ``x`` (m) and speed ``v`` (m/s)."""
    w, z = mode.omega, damping_ratio
    wd = w * math.sqrt(1.0 - z * z)
    return math.hypot(x, (v + z * w * x) / wd)


def settling_s(
    amplitude: float, mode: ToolMode, damping_ratio: float, allowed_m: float
) -> float | None:
    """The time (s) after which a free decay of envelope ``amplitude`` (m) stays within
    ``allowed_m`` (m): 0 where it starts within it, None where nothing is allowed."""
    if allowed_m <= 0.0:
        return None
    if amplitude <= allowed_m:
        return 0.0
    return math.log(amplitude / allowed_m) / (damping_ratio * mode.omega)


def arrival(move: Move, check: Settling, dwell_s: float, dt: float) -> Arrival:
    """The stop at the end of ``move``, its ringing and its dwell: at least ``dwell_s`` (s),
    the settling time where longer."""
    mode = mode_at(check.model, move.q[-1], check.payload_kg)
    accel = tool_acceleration(check.model.design, move.q, move.qd, move.qdd)
    force = -check.payload_kg * accel @ np.asarray(mode.direction)
    x, v = response(force, mode, check.damping_ratio, dt)
    # the last sample is the arrival's: the force is off from there on
    amp = amplitude_m(float(x[-1]), float(v[-1]), mode, check.damping_ratio)
    settle = settling_s(amp, mode, check.damping_ratio, check.allowed_m)
    dwell = dwell_s if settle is None else max(dwell_s, settle)
    return Arrival(mode.frequency_hz, 1e3 * amp, settle, dwell)


def settled(
    cycle: Cycle, check: Settling, elastic: bool = True
) -> tuple[Cycle, tuple[Arrival, ...]]:
    """``cycle`` with each stop's dwell lengthened to its settling time (:func:`arrival`; the
    configured dwell the least), in the elastic model too where ``check`` has one and
    ``elastic``, and the stops after its moves."""
    stops = tuple(arrival(m, check, cycle.dwell_s, cycle.dt) for m in cycle.moves)
    if elastic and check.elastic is not None:
        moves = [(m.t, m.q) for m in cycle.moves]
        omegas = [2 * math.pi * a.frequency_hz for a in stops]
        found = elastic_stops(check.elastic, moves, omegas, check.allowed_m)
        stops = tuple(
            replace(a, elastic=e, dwell_s=max(a.dwell_s, e.settling_s or 0.0))
            for a, e in zip(stops, found, strict=True)
        )
    return cycle._replace(dwells_s=tuple(a.dwell_s for a in stops)), stops


def elastic_error(cycle: Cycle, check: Settling) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The tool's elastic displacement along the first mode (mm) over ``cycle``'s samples from
    rest at its first point (times s, :meth:`~qsm.realization.motion.cycle.Cycle.samples`), each
    move and the dwell after it in the mode at the move's end, the state carried on."""
    state, out = (0.0, 0.0), [np.zeros(round(cycle.stops_s[0] / cycle.dt) + 1)]
    for move, dwell in zip(cycle.moves, cycle.stops_s[1:], strict=True):
        mode = mode_at(check.model, move.q[-1], check.payload_kg)
        accel = tool_acceleration(check.model.design, move.q[1:], move.qd[1:], move.qdd[1:])
        force = -check.payload_kg * accel @ np.asarray(mode.direction)
        force = np.concatenate([force, np.zeros(round(dwell / cycle.dt))])
        x, v = response(force, mode, check.damping_ratio, cycle.dt, state)
        state = (float(x[-1]), float(v[-1]))
        out.append(1e3 * x)
    x_mm = np.concatenate(out)
    return np.arange(len(x_mm)) * cycle.dt, x_mm
