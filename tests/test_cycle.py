"""The time-optimal moves (qsm.realization.motion.cycle) against hand cases: a single link's
bang-bang motion in closed form, with a speed bound, and under gravity against a phase-plane
reference."""

import contextlib
import itertools

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import brentq

from qsm.embodiment.drives.drive_checks import DriveCheck
from qsm.embodiment.drives.envelope import OutputEnvelope
from qsm.embodiment.strength.loads import Inertials
from qsm.physics.batch_mass import batch_mass_properties
from qsm.physics.cad import DEFAULT_CAD
from qsm.realization.final.cycle_check import (
    cycle_torques,
    peak_load_N,
    thermal_use,
    tolerance_factor,
)
from qsm.realization.motion.cycle import (
    Arm,
    plan_cycle,
    sampled,
    slowed,
    straight_path,
    time_optimal_timing,
    top_speed,
    torque_terms,
)
from qsm.realization.motion.front_cycles import FRONT_FRACTIONS

INERTIA = 0.5  # kg m^2 about the joint
DESIGN = np.array([0.5, 0.15, 0.55, 0.22, 0.6, 0.2])
DT = 1e-4  # s; a move ends at the next step


def time_optimal_move(inverse, q0, q1, speed, torque, dt):
    """TOPP-RA's timing of the straight move q0 -> q1 under the bounds, sampled every ``dt`` s;
    None where none is feasible."""
    path = straight_path(q0, q1)
    timing = time_optimal_timing(path, torque_terms(inverse, path), speed, torque)
    return None if timing is None else sampled(timing, dt)


def _link(gravity_Nm: float = 0.0):
    """One link turning about a horizontal (gravity_Nm > 0) or vertical axis: tau = I qdd +
    G cos q."""
    return lambda q, qd, qdd: INERTIA * qdd + gravity_Nm * np.cos(q)


@pytest.mark.parametrize(("angle", "torque"), [(1.0, 2.0), (0.4, 5.0), (2.0, 1.0)])
def test_a_torque_bound_gives_the_bang_bang_time(angle, torque):
    t, q, qd, _ = time_optimal_move(_link(), [0.0], [angle], [1e3], [torque], DT)
    expected = 2.0 * np.sqrt(angle * INERTIA / torque)  # half accelerating, half braking
    assert t[-1] == pytest.approx(expected, rel=2e-3)
    assert q[-1, 0] == pytest.approx(angle, abs=1e-9)
    assert abs(qd[-1, 0]) < 1e-6 and abs(qd[0, 0]) < 1e-6


def test_a_speed_bound_gives_the_trapezoid_time():
    angle, torque, speed = 1.0, 2.0, 1.5  # bang-bang would peak at 2 rad/s
    t, _, qd, _ = time_optimal_move(_link(), [0.0], [angle], [speed], [torque], DT)
    accel = torque / INERTIA
    assert t[-1] == pytest.approx(angle / speed + speed / accel, rel=2e-3)
    assert np.abs(qd).max() <= speed * (1 + 1e-9)


def test_a_lower_torque_bound_takes_longer():
    times = [time_optimal_move(_link(), [0.0], [1.0], [1e3], [t], DT)[0][-1] for t in (4, 2, 1)]
    assert times[0] < times[1] < times[2]


def _phase_plane_time(q0: float, q1: float, torque: float, gravity: float) -> float:
    """Rest-to-rest time under |tau| <= torque with tau = I qdd + G cos q: full torque forward
    from q0, full braking into q1, switching where the two speed curves meet."""

    def forward(q: float) -> float:  # v^2 accelerating from rest at q0
        return 2 * (torque * (q - q0) - gravity * (np.sin(q) - np.sin(q0))) / INERTIA

    def backward(q: float) -> float:  # v^2 braking to rest at q1
        return 2 * (torque * (q1 - q) + gravity * (np.sin(q1) - np.sin(q))) / INERTIA

    switch = brentq(lambda q: forward(q) - backward(q), q0, q1)
    t1 = quad(lambda q: 1 / np.sqrt(forward(q)), q0, switch, limit=200)[0]
    t2 = quad(lambda q: 1 / np.sqrt(backward(q)), switch, q1, limit=200)[0]
    return t1 + t2


def test_under_gravity_the_time_is_the_phase_plane_references():
    q0, q1, torque, gravity = -0.3, 1.2, 6.0, 3.0
    t, q, _, qdd = time_optimal_move(_link(gravity), [q0], [q1], [1e3], [torque], DT)
    assert t[-1] == pytest.approx(_phase_plane_time(q0, q1, torque, gravity), rel=5e-3)
    tau = INERTIA * qdd[:, 0] + gravity * np.cos(q[:, 0])
    assert np.abs(tau).max() <= torque * 1.02  # TOPP-RA's grid: within 2 %


def test_an_infeasible_bound_gives_no_timing():
    """A torque below gravity's cannot hold the link: no timing."""
    assert time_optimal_move(_link(5.0), [0.0], [0.5], [1e3], [1.0], DT) is None


@pytest.fixture(scope="module")
def arm():
    """The test design with the lightest drives for its duty, its solid links, 5 kg."""
    check = DriveCheck()
    report = check.report(DESIGN)
    drives = [
        OutputEnvelope.of(check.catalogue, m.drive.motor_key, m.drive.gearbox_key)
        for m in report.motors.values()
    ]
    inertials = Inertials(*batch_mass_properties(DESIGN, DEFAULT_CAD))
    return Arm(DESIGN, inertials, 5.0, drives)


def test_a_cycle_holds_at_its_points_and_its_time_adds_up(arm):
    angles = np.radians([[95.0, 20.0], [120.0, 30.0], [140.0, 60.0], [95.0, 20.0]])
    cycle = plan_cycle(arm, angles, 0.5, 1e-3, returns=True)
    ref = cycle.samples()
    np.testing.assert_allclose(ref.theta[ref.hold_ends], angles, atol=1e-9)
    assert np.abs(ref.dtheta[ref.hold_ends]).max() < 1e-9
    # the samples start at rest with a dwell at the first point, which a repeated cycle shares
    # with its last: one period is the rest, one dwell per point
    assert ref.t[-1] == pytest.approx(cycle.time_s + cycle.dwell_s, abs=1e-9)
    period = ref.t[cycle.period()]
    assert period[-1] - period[0] + cycle.dt == pytest.approx(cycle.time_s, abs=1e-9)
    moves = sum(m.duration_s for m in cycle.moves)
    assert cycle.time_s == pytest.approx(moves + 3 * 0.5)
    open_cycle = plan_cycle(arm, angles[:3], 0.5, 1e-3, returns=False)  # three stops, two moves
    assert open_cycle.time_s == pytest.approx(sum(m.duration_s for m in open_cycle.moves) + 1.5)
    for move in cycle.moves:
        top = np.array([top_speed(e) for e in arm.drives])
        assert (np.abs(move.qd) <= top).all()
        limit = np.array([e.limit(t, w) for e, t, w in zip(arm.drives, move.tau.T, move.qd.T,
                                                          strict=True)]).T  # fmt: skip
        assert (np.abs(move.tau) <= limit * 1.02).all()  # TOPP-RA's grid: within 2 %


def test_a_slowed_cycle_takes_the_same_path_longer_and_gentler(arm):
    angles = np.radians([[95.0, 20.0], [140.0, 60.0]])
    cycle = plan_cycle(arm, angles, 0.0, 1e-3, returns=False)
    twice = slowed(cycle, arm, 2.0)
    (move,), (slow,) = cycle.moves, twice.moves
    assert slow.duration_s == pytest.approx(2 * move.duration_s, abs=2e-3)
    assert np.abs(slow.qd).max() == pytest.approx(np.abs(move.qd).max() / 2, rel=1e-2)
    path = np.interp(np.linspace(0, 1, 50), slow.t / slow.t[-1], slow.q[:, 0])
    np.testing.assert_allclose(path, np.interp(np.linspace(0, 1, 50), move.t / move.t[-1],
                                               move.q[:, 0]), atol=1e-3)  # fmt: skip


def test_the_tolerance_slows_the_cycle_to_the_least_factor_within_the_load(arm):
    """The payload's peak force never grows as the cycle slows (weight plus inertia / k^2);
    the factor found is the least, to 0.01, that brings it within the limit."""
    angles = np.radians([[95.0, 20.0], [140.0, 60.0], [95.0, 20.0]])
    optimal = plan_cycle(arm, angles, 0.2, 1e-3, returns=True)
    peaks = [peak_load_N(slowed(optimal, arm, k), arm) for k in (1.0, 1.5, 2.0, 3.0, 8.0)]
    assert all(a >= b - 1e-9 for a, b in itertools.pairwise(peaks))
    weight = 5.0 * 9.81
    assert peaks[-1] >= weight and peaks[0] > 1.2 * weight
    limit = 0.5 * (peaks[0] + peaks[-1])
    k = tolerance_factor(optimal, arm, limit)
    assert 1.0 < k < 8.0
    assert peak_load_N(slowed(optimal, arm, k), arm) <= limit
    assert peak_load_N(slowed(optimal, arm, k - 0.02), arm) > limit
    assert tolerance_factor(optimal, arm, None) == 1.0
    assert tolerance_factor(optimal, arm, 2 * peaks[0]) == 1.0
    assert tolerance_factor(optimal, arm, 0.99 * weight) is None  # the weight alone is past it


def test_the_thermal_use_counts_gear_losses_by_direction(arm):
    """A cycle's thermal use equals the drive check's motor RMS rating by hand: the motor's
    torque is tau / (N eta) where the drive drives and tau eta / N where it is back-driven."""
    angles = np.radians([[95.0, 20.0], [140.0, 60.0], [95.0, 20.0]])
    cycle = slowed(plan_cycle(arm, angles, 0.3, 1e-3, returns=True), arm, 2.0)
    check = DriveCheck()
    drives = check.catalogue.drives
    rows = [  # the fixture's drives
        int(np.flatnonzero((drives["motor"] == m.drive.motor_key).to_numpy()
                           & (drives["gearbox"] == m.drive.gearbox_key).to_numpy())[0])
        for m in check.report(DESIGN).motors.values()
    ]  # fmt: skip
    arrays = check.arrays.take(np.array(rows))
    use = thermal_use(cycle, arm, arrays)
    _, _, dq, tau = cycle_torques(cycle, arm)
    for j in range(2):
        n, eta, cont = arrays.ratio[j], arrays.efficiency[j], arrays.cont_torque[j]
        driving = tau[:, j] * dq[:, j] >= 0
        motor = np.where(driving, tau[:, j] / (n * eta), tau[:, j] * eta / n)
        motor_use = np.sqrt((motor**2).mean()) / cont
        gear_use = np.sqrt((tau[:, j] ** 2).mean()) / arrays.gear_cont_torque[j]
        assert use[j] == pytest.approx(max(motor_use, gear_use), rel=1e-6)


def test_the_fronts_three_speed_bounds_plan_no_faster_and_nearly_as_fast(arm):
    """The fronts' plans (four speed bounds) against the realised design's (seven): never
    faster than 0.1 % (the bounds differ, the grid is the same), and within 1 %."""
    angles = np.radians([[95.0, 20.0], [140.0, 60.0], [120.0, 30.0], [95.0, 20.0]])
    full = plan_cycle(arm, angles, 0.5, 1e-3, returns=True).time_s
    front = plan_cycle(arm, angles, 0.5, 1e-3, returns=True, fractions=FRONT_FRACTIONS).time_s
    assert full * 0.999 <= front <= full * 1.01


def test_a_move_is_the_fastest_of_its_speed_bounds_each_planned_alone(arm):
    """plan_move times the move at every speed bound and samples the fastest only: the move is
    the one its bound gives planned alone, sample for sample, and no bound alone is faster
    (the first of equally fast bounds is kept)."""
    from qsm.realization.motion.cycle import plan_move

    q0, q1 = np.radians([95.0, 20.0]), np.radians([140.0, 60.0])
    fractions = (0.15, 0.95, 0.5, 0.3)
    move = plan_move(arm, q0, q1, 1e-3, fractions)
    alone = {}
    for f in fractions:
        with contextlib.suppress(ValueError):  # a bound too fast for the drives' torque
            alone[f] = plan_move(arm, q0, q1, 1e-3, (f,))
    assert len(alone) >= 3
    assert move.duration_s == min(m.duration_s for m in alone.values())
    fastest = next(f for f in alone if alone[f].duration_s == move.duration_s)
    for got, expected in zip(move, alone[fastest], strict=True):
        np.testing.assert_array_equal(got, expected)
    assert alone[0.15].duration_s > 2 * move.duration_s  # the slow bound's move is the longest
