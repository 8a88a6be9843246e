"""The cycle's slow-down and jerk time chosen together (qsm.realization.final.cycle_check
.fastest): the shortest cycle once each stop has settled, against the cycle that only slows as
little as it may; and a slowed cycle's ramps as run against its sampled jerk."""

import numpy as np
import pytest

from qsm.embodiment.drives.drive_checks import DriveCheck
from qsm.embodiment.drives.envelope import OutputEnvelope
from qsm.embodiment.stiffness.error_terms import tool_acceleration
from qsm.embodiment.stiffness.frame import FrameSections
from qsm.embodiment.strength.loads import Inertials
from qsm.physics.batch_mass import batch_mass_properties
from qsm.physics.cad import DEFAULT_CAD
from qsm.realization.accuracy.accuracy_budget import ArmModel
from qsm.realization.final.cycle_check import CheckedCycle, SpeedChoice, fastest
from qsm.realization.final.settling import Settling, amplitude_m, mode_at, response, settled
from qsm.realization.motion.cycle import (
    Arm,
    Cycle,
    jerk_limited_cycle,
    move_jerk,
    plan_cycle,
    slowed,
)

DESIGN = np.array([0.5, 0.15, 0.55, 0.22, 0.6, 0.2])  # m
ANGLES = np.radians([[95.0, 20.0], [140.0, 60.0], [95.0, 20.0]])  # there and back
FACTORS = (1.0, 1.1, 1.25, 1.5, 2.0, 2.5, 3.0, 4.0)
PAYLOAD_KG, ZETA, DT = 5.0, 0.02, 1e-3


@pytest.fixture(scope="module")
def case():
    """The test design with the lightest drives for its duty, 5 kg; its frame of 100 x 50 mm
    printed links (a first mode near 11 Hz); its time-optimal cycle with no dwell."""
    check = DriveCheck()
    drives = [
        OutputEnvelope.of(check.catalogue, m.drive.motor_key, m.drive.gearbox_key)
        for m in check.report(DESIGN).motors.values()
    ]
    inertials = Inertials(*batch_mass_properties(DESIGN, DEFAULT_CAD))
    arm = Arm(DESIGN, inertials, PAYLOAD_KG, drives)
    sections = FrameSections(np.full(4, 0.1), np.full(4, 0.05), 2.2e9, 0.35)
    model = ArmModel(DESIGN, sections, np.ones(4), inertials, np.array([2e4, 1e4]),
                     np.zeros(2), np.zeros(2), np.zeros(2))  # fmt: skip
    period = 1.0 / min(mode_at(model, a, PAYLOAD_KG).frequency_hz for a in ANGLES)
    return arm, model, plan_cycle(arm, ANGLES, 0.0, DT, returns=True), period


def _timed(arm, topp, jerks):
    plans = {j: jerk_limited_cycle(topp, arm, j) for j in jerks}
    return lambda factor, jerk=jerks[0]: slowed(plans[jerk], arm, factor)


def _by_hand(cycle, model, allowed_m):
    """The cycle's time with each stop dwelling until its free decay stays within
    ``allowed_m``: the single-mode oscillator stepped over each move, then its envelope's
    decay solved for the time (independently of settling.arrival and settled)."""
    total = 0.0
    for move in cycle.moves:
        mode = mode_at(model, move.q[-1], PAYLOAD_KG)
        force = -PAYLOAD_KG * tool_acceleration(DESIGN, move.q, move.qd, move.qdd) @ mode.direction
        x, v = response(force, mode, ZETA, cycle.dt)
        amp = amplitude_m(float(x[-1]), float(v[-1]), mode, ZETA)
        times = np.arange(0.0, 20.0, 1e-4)  # the first time the envelope is within
        within = amp * np.exp(-ZETA * mode.omega * times) <= allowed_m
        total += move.duration_s + float(times[np.argmax(within)])
    return total


def test_the_shortest_settled_cycle_may_slow_more_and_ramp_longer(case):
    """With 0.05 mm left for ringing, the fastest pair is not the least slow-down with a ramp
    of one period: slowing and ramping longer ring the arm so much less that the stops'
    dwells shrink more than the moves grow. Each pair's time is the moves plus each stop's
    settling time, found by hand to the 0.1 ms step."""
    arm, model, topp, period = case
    jerks = (period, 0.5 * period, 2.0 * period)
    check = Settling(model, PAYLOAD_KG, ZETA, tolerance_mm=1.0, static_mm=0.95)
    choices = fastest(_timed(arm, topp, jerks), FACTORS, jerks, check)
    assert len(choices) == len(FACTORS) * len(jerks)
    times = [c.time_s for c in choices]
    assert times == sorted(times)
    least = next(c for c in choices if c.factor == 1.0 and c.jerk_time_s == period)
    assert (choices[0].factor, choices[0].jerk_time_s) != (1.0, period)
    assert choices[0].time_s < 0.6 * least.time_s  # a much shorter cycle
    for c in (choices[0], least):
        cycle = _timed(arm, topp, jerks)(c.factor, c.jerk_time_s)
        assert c.time_s == pytest.approx(_by_hand(cycle, model, check.allowed_m), abs=2e-3)
        assert settled(cycle, check, elastic=False)[0].time_s == pytest.approx(c.time_s)


def test_without_a_settling_check_the_slow_downs_come_in_order_at_the_first_jerk_time(case):
    """No settling check (or static terms that leave nothing for ringing): nothing to weigh,
    so the first jerk time at each slow-down, the least first."""
    arm, model, topp, period = case
    jerks = (period, 0.5 * period)
    timed = _timed(arm, topp, jerks)
    for check in (None, Settling(model, PAYLOAD_KG, ZETA, tolerance_mm=1.0, static_mm=1.2)):
        choices = fastest(timed, FACTORS, jerks, check)
        assert [c.factor for c in choices] == list(FACTORS)
        assert {c.jerk_time_s for c in choices} == {period}


@pytest.mark.parametrize("factor", [1.0, 2.0, 3.0])
def test_a_slowed_cycle_ramps_as_long_as_it_states(case, factor):
    """Slowed ``factor`` times, a move ramped over T ramps over factor T: its sampled peak
    jerk is its stated limit (the change times its peak path acceleration over factor T)."""
    arm, _, topp, _ = case
    cycle = slowed(jerk_limited_cycle(topp, arm, 0.1), arm, factor)
    assert cycle.jerk_time_s == pytest.approx(0.1 * factor)
    for move in cycle.moves:
        jerk = move_jerk(move, cycle.jerk_time_s, cycle.dt)
        peak, limit = np.array(jerk["peak_jerk_rad_s3"]), np.array(jerk["jerk_limit_rad_s3"])
        np.testing.assert_allclose(peak, limit, rtol=0.02)


def test_the_jerk_time_is_said_to_be_chosen_only_where_the_fastest_pair_was_kept():
    """Several jerk times weighed and the fastest pair run: chosen. A slower pair kept because
    MuJoCo's run failed the fastest, or one jerk time only: not chosen."""
    pairs = (SpeedChoice(1.0, 0.05, 1.6), SpeedChoice(1.0, 0.1, 1.7), SpeedChoice(2.0, 0.05, 2.1))

    def kept(factor, choices=pairs):
        cycle = Cycle((), 0.5, DT, True, factor=factor)
        return CheckedCycle(cycle, cycle, 0.5, {}, [], (), choices)

    assert kept(1.0).jerk_chosen
    assert not kept(2.0).jerk_chosen
    assert not kept(1.0, (pairs[0], pairs[2])).jerk_chosen
