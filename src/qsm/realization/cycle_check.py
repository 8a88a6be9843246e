"""The time-optimal cycle of a realised design, checked: its links' strength at the cycle's loads,
its drives' RMS (thermal) torque over the repeated cycle, and MuJoCo's run of it with the chosen
drives' envelopes (the payload test's plant and controller).

:func:`checked_cycle` plans the cycle (:mod:`qsm.realization.cycle`) and runs it :data:`SLOWER`
times slower in turn until the links hold (g13's check on one period of its samples), each
motor's RMS torque is within its drive's continuous torque at the joint, and MuJoCo's run passes;
what even the slowest cannot meet does not slow it, and the result says by how much it was
slowed and why (:func:`qsm.report.cycle_report.cycle_record` gives its figures).
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import NDArray

from qsm.physics.cad import MassProperties
from qsm.physics.duty import Duty
from qsm.physics.mjcf import TIMESTEP_S
from qsm.realization.cycle import Arm, Cycle, motor_torques, plan_cycle, slowed
from qsm.realization.payload import PayloadSettings, payload_test
from qsm.realization.pipeline import Realization

#: How many times slower than time-optimal a cycle is tried, in turn, until it passes.
SLOWER: tuple[float, ...] = (1.0, 1.1, 1.25, 1.5, 2.0, 2.5, 3.0, 4.0)


class CheckedCycle(NamedTuple):
    """The cycle as run, the time-optimal one, its links' largest utilisation over it, the
    MuJoCo run's result, and why it was slowed (empty: it was not)."""

    cycle: Cycle
    optimal: Cycle
    utilisation: float
    simulation: dict[str, Any]
    slowed_for: list[str]


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


def _problems(cycle: Cycle, arm: Arm, done: Realization, continuous_Nm: NDArray) -> dict[str, str]:
    """Why ``cycle`` cannot run as it is, before MuJoCo, by kind: the links' ``strength``, the
    drives' RMS (``thermal``) torque over repeated cycles."""
    out = {}
    util = link_utilisation(cycle, done, arm.payload_kg)
    if util > 1.0:
        out["strength"] = f"the links reach {util:.2f} of their strength at {cycle.factor:g}x"
    rms = rms_torque_Nm(cycle, arm)
    if (rms > continuous_Nm).any():  # NaN: a continuous torque the catalogue does not give
        out["thermal"] = (
            f"RMS torque {np.round(rms, 1).tolist()} N m over the drives' continuous "
            f"{np.round(continuous_Nm, 1).tolist()} N m at {cycle.factor:g}x"
        )
    return out


def checked_cycle(
    done: Realization,
    props: dict[str, MassProperties],
    arm: Arm,
    angles: NDArray[np.float64],
    points: NDArray[np.float64],
    test: PayloadSettings,
    dwell_s: float,
    returns: bool,
    continuous_Nm: NDArray[np.float64],
) -> CheckedCycle:
    """The fastest of the time-optimal cycle through the visited ``points`` (n, 2) m (motor
    ``angles``), run :data:`SLOWER` times slower in turn, that the links hold, whose RMS torques
    stay within the drives' ``continuous_Nm`` (2,) at the joint, and that MuJoCo runs within the
    drives' envelopes and the tracking tolerance. What even the slowest cannot meet (a holding
    torque past a drive's continuous torque, say) does not slow it, and ``slowed_for`` says so;
    when MuJoCo's run never passes, the slowest is kept."""
    optimal = plan_cycle(arm, angles, dwell_s, TIMESTEP_S, returns)
    slowest = _problems(slowed(optimal, arm, SLOWER[-1]), arm, done, continuous_Nm)
    last = ""
    for factor in SLOWER:
        cycle = slowed(optimal, arm, factor)
        problems = _problems(cycle, arm, done, continuous_Nm)
        if fixable := [p for kind, p in problems.items() if kind not in slowest]:
            last = fixable[0]
            continue
        sim = _simulated(done, props, arm, points, test, cycle)
        if sim["passed"]:
            break
        last = f"MuJoCo's run at {factor:g}x: {sim['reason']}"
    util = link_utilisation(cycle, done, arm.payload_kg)
    # what stands at the speed kept: the kinds that even the slowest does not meet
    unfixable = [f"{p} (not met at {SLOWER[-1]:g}x either)" for p in problems.values()]
    reasons = ([last] if cycle.factor > 1.0 and last else []) + unfixable
    return CheckedCycle(cycle, optimal, util, sim, reasons)


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
