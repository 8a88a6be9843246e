"""The time-optimal cycle of a realised design, checked: the tool's placing error under the
payload's peak force, its links' strength at the cycle's loads, its drives' RMS (thermal) use
over the repeated cycle, and MuJoCo's run of it with the chosen drives' envelopes (the payload
test's plant and controller).

:func:`checked_cycle` plans the cycle (:mod:`qsm.realization.motion.cycle`), slows it first until
the payload's peak force keeps the accuracy budget within the tolerance (the least such factor, by
bisection: the peak force never grows as the cycle slows), then runs it :data:`SLOWER` times slower
in turn until the links hold (g13's check on one period of its samples), each drive's
RMS use is within its continuous ratings (the drive check's own model,
:mod:`qsm.embodiment.drives.utilization`) and MuJoCo's run passes; what even the slowest cannot
meet does not slow it, and the result says by how much it was slowed and why
(:func:`qsm.realization.final.cycle_run.cycle_record` gives its figures).

The slow-down and the jerk time are chosen together where the stops' settling is checked: from
the least slow-down that holds, every slower one and every jerk time offered is weighed by its
cycle time with each stop dwelling until the tool settles (:func:`fastest`). Slowing more or
ramping longer rings the arm less, so a stop may need less dwell than the moves gain. The
fastest pair is run (the elastic model, MuJoCo); where MuJoCo's run fails, the fastest of the
slower ones.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import NDArray

from qsm.embodiment.drives.utilization import CHECKS, DriveArrays, utilization
from qsm.physics.cad import MassProperties
from qsm.physics.duty import Duty
from qsm.physics.mjcf import TIMESTEP_S
from qsm.prose import per_motor
from qsm.realization.accuracy.accuracy_budget import peak_payload_force_N
from qsm.realization.final.settling import Arrival, Settling, settled
from qsm.realization.motion.cycle import (
    Arm,
    Cycle,
    jerk_limited_cycle,
    motor_torques,
    plan_cycle,
    slowed,
)
from qsm.realization.motion.payload import PayloadSettings, payload_test
from qsm.realization.selection.pipeline import Realization

#: How many times slower than time-optimal a cycle is tried, in turn, until it passes.
SLOWER: tuple[float, ...] = (1.0, 1.1, 1.25, 1.5, 2.0, 2.5, 3.0, 4.0)
#: The slowest a cycle is run to keep the tool within the tolerance.
SLOWEST_FOR_TOLERANCE = 8.0
#: The drive ratings the thermal check reads.
THERMAL = (CHECKS.index("motor_rms"), CHECKS.index("gear_rms"))


@dataclass(frozen=True)
class SpeedChoice:
    """One timing of the cycle weighed by :func:`fastest`: its slow-down ``factor`` (1), the
    ``jerk_time_s`` its moves were planned with before it (s; None: TOPP-RA's timing) and its
    ``time_s`` (s), each stop's dwell its settling time by the single-mode check."""

    factor: float
    jerk_time_s: float | None
    time_s: float

    def record(self) -> dict[str, Any]:
        """JSON, with the ramps as run (the jerk time times the slow-down)."""
        ramp = None if self.jerk_time_s is None else self.jerk_time_s * self.factor
        return {"slowed_by": self.factor, "jerk_time_s": ramp, "cycle_time_s": self.time_s}


class CheckedCycle(NamedTuple):
    """The cycle as run, the time-optimal one (at its jerk time), its links' largest
    utilisation over it, the MuJoCo run's result, why it was slowed (empty: it was not), its
    stops, and the timings weighed for it, fastest first (:func:`fastest`)."""

    cycle: Cycle
    optimal: Cycle
    utilisation: float
    simulation: dict[str, Any]
    slowed_for: list[str]
    arrivals: tuple[Arrival, ...] = ()
    choices: tuple[SpeedChoice, ...] = ()

    @property
    def jerk_chosen(self) -> bool:
        """Whether its jerk time was chosen with its slow-down: several were weighed and the
        fastest pair was kept (not a slower one that MuJoCo's run asked for)."""
        weighed = len({c.jerk_time_s for c in self.choices}) > 1
        return weighed and self.choices[0].factor == self.cycle.factor


def cycle_duty(cycle: Cycle) -> Duty:
    """One period of the cycle's samples as a duty for the strength check, each weighted by
    its time step."""
    ref = cycle.samples()
    k = cycle.period()
    moving = (np.abs(ref.dtheta[k]) + np.abs(ref.ddtheta[k])).max(axis=1) > 0
    return Duty(
        theta=ref.theta[k],
        dtheta=ref.dtheta[k],
        ddtheta=ref.ddtheta[k],
        static=~moving,
        time_s=ref.t[k],
        weight_s=np.full(len(ref.t[k]), cycle.dt),
    )


def link_utilisation(cycle: Cycle, done: Realization, payload_kg: float) -> float:
    """The links' and bearings' largest utilisation (<= 1 holds) over ``cycle``'s loads, at the
    realised sections (solid links: they bound the bored parts' loads)."""
    check = replace(done.strength_check, duty=cycle_duty(cycle), payload_kg=payload_kg)
    table = check.evaluate_with_torques(done.design[None], done.sections)[0]
    return float(table["strength_utilisation"].iloc[0])


def cycle_torques(
    cycle: Cycle, arm: Arm, one_period: bool = True
) -> tuple[NDArray, NDArray, NDArray, NDArray]:
    """Times (N,) s, motor angles (N, 2) rad, speeds rad/s and torques N m (the drives'
    reflected inertia included) over one period of the repeated cycle, or (``one_period``
    False) over all its samples from rest at its first point."""
    ref = cycle.samples()
    k = cycle.period() if one_period else slice(None)
    tau = motor_torques(arm, ref.theta[k], ref.dtheta[k], ref.ddtheta[k])
    return ref.t[k], ref.theta[k], ref.dtheta[k], tau


def rms_torque_Nm(cycle: Cycle, arm: Arm) -> NDArray[np.float64]:
    """Each motor's RMS torque (2,) N m over one period of the repeated cycle."""
    return np.sqrt((cycle_torques(cycle, arm)[3] ** 2).mean(axis=0))


def thermal_use(cycle: Cycle, arm: Arm, drives: DriveArrays) -> NDArray[np.float64]:
    """Each motor's thermal use (2,) over one period of the repeated cycle: the larger of its
    motor's and its gearbox's RMS torque over their continuous ratings, gear losses by the
    torque's direction, as the drive check counts them (<= 1 holds; NaN where the catalogue
    lacks a rating). ``drives``: the two motors' drives, in order."""
    _, _, dq, tau = cycle_torques(cycle, arm)
    w = np.full((1, len(tau)), cycle.dt)
    use = [
        utilization(drives.take(np.array([j])), tau[None, :, j], dq[None, :, j], w)[0, 0]
        for j in range(2)
    ]
    out = np.array([u[list(THERMAL)].max() for u in use])
    return np.where(np.isfinite(out), out, np.nan)


def peak_load_N(cycle: Cycle, arm: Arm) -> float:
    """The payload's peak force (N) on the tool over the cycle, its weight and inertia."""
    ref = cycle.samples()
    return peak_payload_force_N(arm.design, arm.payload_kg, ref.theta, ref.dtheta, ref.ddtheta)


def tolerance_factor(optimal: Cycle, arm: Arm, max_load_N: float | None) -> float | None:
    """The least slow-down (>= 1) of the ``optimal`` cycle whose payload's peak force is at most
    ``max_load_N`` (N; None: no limit), to 0.01; None where even
    :data:`SLOWEST_FOR_TOLERANCE` does not bring it there."""
    if max_load_N is None or peak_load_N(optimal, arm) <= max_load_N:
        return 1.0
    hi = SLOWEST_FOR_TOLERANCE
    if peak_load_N(slowed(optimal, arm, hi), arm) > max_load_N:
        return None
    lo = 1.0
    while hi - lo > 0.01:
        mid = 0.5 * (lo + hi)
        lo, hi = (
            (mid, hi) if peak_load_N(slowed(optimal, arm, mid), arm) > max_load_N else (lo, mid)
        )
    return math.ceil(hi * 100.0) / 100.0  # rounded up: still within the load


def _problems(cycle: Cycle, arm: Arm, done: Realization, drives: DriveArrays) -> dict[str, str]:
    """Why ``cycle`` cannot run as it is, before MuJoCo, by kind: the links' ``strength``, the
    drives' RMS (``thermal``) use over repeated cycles."""
    out = {}
    util = link_utilisation(cycle, done, arm.payload_kg)
    if util > 1.0:
        out["strength"] = f"the links reach {util:.2f} of their strength at {cycle.factor:g}x"
    use = thermal_use(cycle, arm, drives)
    if (use > 1.0).any():  # NaN: a rating the catalogue does not give
        out["thermal"] = (
            f"RMS torque {per_motor(rms_torque_Nm(cycle, arm), 1, 'N m')} uses "
            f"{per_motor(use, 2, '')} of the drives' continuous ratings at {cycle.factor:g}x"
        )
    return out


def fastest(
    timed: Callable[[float, float | None], Cycle],
    factors: Sequence[float],
    jerk_times_s: Sequence[float | None],
    settling: Settling | None,
    within: Callable[[Cycle], bool] = lambda cycle: True,
) -> tuple[SpeedChoice, ...]:
    """The timings (slow-down in ``factors``, jerk time in ``jerk_times_s``; ``timed`` gives
    each cycle) by their cycle time, fastest first, each stop dwelling until it settles by the
    single-mode check: more slowing rings less, a longer ramp rings less, and both lengthen the
    moves. A timing at another jerk time than the first is left out where not ``within`` what
    the cycle must meet (the first is, at every factor). Where the ``settling`` check
    cannot weigh them (none, or static terms that alone miss the tolerance): the first jerk
    time only, at each slow-down, least first."""
    weighs = settling is not None and settling.allowed_m > 0.0
    choices = []
    for factor in factors:
        for k, jerk in enumerate(jerk_times_s if weighs else jerk_times_s[:1]):
            cycle = timed(factor, jerk)
            if k and not within(cycle):
                continue
            if settling is not None:
                cycle = settled(cycle, settling, elastic=False)[0]
            choices.append(SpeedChoice(factor, jerk, cycle.time_s))
    return tuple(sorted(choices, key=lambda c: c.time_s if weighs else c.factor))


def checked_cycle(
    done: Realization,
    props: dict[str, MassProperties],
    arm: Arm,
    route: tuple[NDArray[np.float64], NDArray[np.float64]],
    test: PayloadSettings,
    task: tuple[float, bool],
    drives: DriveArrays,
    max_load_N: float | None = None,
    jerk_times_s: Sequence[float | None] = (None,),
    settling: Settling | None = None,
) -> CheckedCycle:
    """The fastest of the time-optimal cycle through the visited points (``route``: the points
    (n, 2) m and their motor angles rad; ``task``: the dwell s and whether it returns), slowed
    until the payload's peak force is at most ``max_load_N`` (N, what keeps the tool within the
    tolerance; None: no limit) and then :data:`SLOWER` times slower, that the links hold,
    whose RMS use of the ``drives`` (the two motors', :func:`thermal_use`) stays within 1, and
    that MuJoCo runs within the drives' envelopes and the tracking tolerance. What even the
    slowest cannot meet (a holding torque past a drive's rating, say) does not slow it, and
    ``slowed_for`` says so; when MuJoCo's run never passes, the slowest is kept. Each move's
    acceleration ramps over one of ``jerk_times_s`` (s; None: TOPP-RA's bang-bang timing; the
    first where the settling check cannot weigh them) and each stop's dwell is lengthened to
    its ``settling`` time (:mod:`qsm.realization.final.settling`; None: not): of the slow-downs
    from the least that holds and the jerk times, the pair whose cycle, dwells included, is
    the shortest (:func:`fastest`)."""
    points, angles = route
    topp = plan_cycle(arm, angles, task[0], TIMESTEP_S, task[1])
    plan = functools.cache(lambda jerk: jerk_limited_cycle(topp, arm, jerk))  # those weighed
    start, first = _for_tolerance(plan(jerk_times_s[0]), arm, max_load_N)
    factors = [start, *(f for f in SLOWER if f > start)]

    def timed(factor: float, jerk: float | None = jerk_times_s[0]) -> Cycle:
        """The cycle ramped over ``jerk`` s, then slowed ``factor`` times."""
        return slowed(plan(jerk), arm, factor)

    slowest = _problems(timed(factors[-1]), arm, done, drives)
    last, slowest_factor = "", factors[-1]
    while fixable := _fixable(timed(factors[0]), arm, done, drives, slowest):  # never the last
        last = fixable[0]
        factors.pop(0)
    meets = _meets(max_load_N, arm, (done, drives), slowest)
    choices = left = fastest(timed, factors, jerk_times_s, settling, meets)
    while True:
        cycle = timed(left[0].factor, left[0].jerk_time_s)
        cycle, arrivals = (cycle, ()) if settling is None else settled(cycle, settling)
        sim = _simulated(done, props, arm, points, test, cycle)
        if sim["passed"]:
            break
        last = f"MuJoCo's run at {cycle.factor:g}x: {sim['reason']}"
        if not (slower := _slower(left, left[0])):
            break  # the slowest failed too: kept
        left = slower
    util = link_utilisation(cycle, done, arm.payload_kg)
    problems = _problems(cycle, arm, done, drives)  # what stands: what even the slowest fails
    unfixable = [f"{p} (not met at {slowest_factor:g}x either)" for k, p in problems.items()
                 if k in slowest]  # fmt: skip
    slower = [last] if cycle.factor > start and last else []
    notes = first + slower + _settling_note(choices, left[0]) + unfixable
    optimal = timed(1.0, left[0].jerk_time_s)
    return CheckedCycle(cycle, optimal, util, sim, notes, arrivals, choices)


def _meets(
    max_load_N: float | None,
    arm: Arm,
    checked: tuple[Realization, DriveArrays],
    slowest: dict[str, str],
) -> Callable[[Cycle], bool]:
    """Whether a timing is within the tolerance's load (``max_load_N``, N; None: any) and fails
    nothing (strength, heat; ``checked``: the realisation and its drives) that the ``slowest``
    cycle meets."""
    done, drives = checked

    def meets(cycle: Cycle) -> bool:
        load = max_load_N is None or peak_load_N(cycle, arm) <= max_load_N
        return load and not _fixable(cycle, arm, done, drives, slowest)

    return meets


def _fixable(
    cycle: Cycle, arm: Arm, done: Realization, drives: DriveArrays, slowest: dict[str, str]
) -> list[str]:
    """What ``cycle`` fails (:func:`_problems`) that the ``slowest`` cycle meets."""
    return [p for kind, p in _problems(cycle, arm, done, drives).items() if kind not in slowest]


def _slower(choices: Sequence[SpeedChoice], failed: SpeedChoice) -> list[SpeedChoice]:
    """The ``choices`` slower than one that ``failed`` MuJoCo's run (its envelope's torques
    fall as the cycle slows; the jerk time barely moves them)."""
    return [c for c in choices if c.factor > failed.factor]


def _settling_note(choices: Sequence[SpeedChoice], kept: SpeedChoice) -> list[str]:
    """Why the ``kept`` timing is slower than the least slow-down weighed (``choices``,
    fastest first) where the settling chose it: the two cycle times."""
    least = min(c.factor for c in choices)
    if kept.factor == least or kept is not choices[0]:
        return []
    quickest = next(c for c in choices if c.factor == least)
    return [
        f"the settling: at {kept.factor:g}x the tool rings less, and the cycle, its dwells "
        f"included, takes {kept.time_s:.2f} s against {quickest.time_s:.2f} s at {least:g}x"
    ]


def _for_tolerance(optimal: Cycle, arm: Arm, max_load_N: float | None) -> tuple[float, list[str]]:
    """The slow-down the tolerance asks of the ``optimal`` cycle (:func:`tolerance_factor`; 1
    where slowing cannot meet it) and why, with the forces."""
    factor = tolerance_factor(optimal, arm, max_load_N)
    peak = peak_load_N(optimal, arm)
    if factor is None and not max_load_N:
        return 1.0, [
            "the tolerance: its static terms (the sag under the payload's weight, creep, lost "
            "motion, tracking and base) alone exceed it, so no speed meets it"
        ]
    if factor is None:
        return 1.0, [
            f"the tolerance: the payload's peak force would have to stay within "
            f"{max_load_N:.1f} N, which even {SLOWEST_FOR_TOLERANCE:g}x slower does not give"
        ]
    if factor == 1.0:
        return 1.0, []
    return factor, [
        f"the tolerance: the payload's peak force {peak:.1f} N at 1x, at most "
        f"{max_load_N:.1f} N to keep the tool within it, at {factor:g}x"
    ]


def _simulated(
    done: Realization,
    props: dict[str, MassProperties],
    arm: Arm,
    points: NDArray[np.float64],
    test: PayloadSettings,
    cycle: Cycle,
) -> dict[str, Any]:
    """MuJoCo's run of ``cycle`` (the payload test's plant and controller) within the drives'
    envelopes, the ones it was planned with (``payload_test.torque_limits_Nm`` set aside)."""
    return payload_test(
        done.design, points, props=props, settings=replace(test, torque_limits_Nm=None),
        drives=arm.drives, reference=cycle.samples(),
    )  # fmt: skip
