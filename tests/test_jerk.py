"""Jerk-limited moves (qsm.realization.motion.cycle.jerk_limited): within their stated jerk,
on their line from rest to rest within the drives' bounds, and a ramp of one period of a mode
leaving that mode no residual vibration (an undamped oscillator integrated in closed form)."""

import numpy as np
import pytest

from qsm.embodiment.drives.drive_checks import DriveCheck
from qsm.embodiment.drives.envelope import OutputEnvelope
from qsm.embodiment.strength.loads import Inertials
from qsm.physics.batch_mass import batch_mass_properties
from qsm.physics.cad import DEFAULT_CAD
from qsm.realization.motion.cycle import Arm, _ruckig, plan_move

DESIGN = np.array([0.5, 0.15, 0.55, 0.22, 0.6, 0.2])
DT = 5e-4


@pytest.fixture(scope="module")
def arm() -> Arm:
    """The test design with the lightest drives for its duty, its solid links, 5 kg."""
    check = DriveCheck()
    report = check.report(DESIGN)
    drives = [
        OutputEnvelope.of(check.catalogue, m.drive.motor_key, m.drive.gearbox_key)
        for m in report.motors.values()
    ]
    return Arm(DESIGN, Inertials(*batch_mass_properties(DESIGN, DEFAULT_CAD)), 5.0, drives)


def test_a_jerk_limited_move_keeps_its_jerk_its_line_and_its_bounds(arm):
    """Each joint's jerk (the sampled accelerations' differences) stays within its change times
    the path's limit, the path's peak acceleration over the jerk time; the move stays on the
    straight line, starts and ends at rest, and takes longer than TOPP-RA's."""
    q0, q1 = np.radians([95.0, 20.0]), np.radians([140.0, 60.0])
    optimal = plan_move(arm, q0, q1, DT)
    limited = plan_move(arm, q0, q1, DT, jerk_time_s=0.1)
    dq = q1 - q0
    path_accel = np.abs(limited.qdd @ dq).max() / (dq @ dq)
    jerk = np.abs(np.diff(limited.qdd, axis=0)).max(axis=0) / DT
    assert (jerk <= np.abs(dq) * path_accel / 0.1 * (1 + 1e-6)).all()
    assert np.abs(np.diff(optimal.qdd, axis=0)).max() / DT > 10 * jerk.max()  # bang-bang
    off_line = (limited.q - q0) - np.outer((limited.q - q0) @ dq / (dq @ dq), dq)
    assert np.abs(off_line).max() < 1e-12
    np.testing.assert_allclose(limited.q[-1], q1, atol=1e-9)
    assert np.abs(limited.qd[[0, -1]]).max() < 1e-9
    assert (np.abs(limited.tau) <= limited.torque_bound).all()
    assert (np.abs(limited.qd) <= limited.speed_bound * (1 + 1e-9)).all()
    assert limited.duration_s > optimal.duration_s


def _residual(accel: np.ndarray, omega: float, dt: float) -> float:
    """The residual amplitude of an undamped oscillator x'' + omega^2 x = -a(t) from rest,
    after ``accel`` (piecewise constant over each step, then zero): the exact solution
    stepped sample by sample."""
    c, s = np.cos(omega * dt), np.sin(omega * dt)
    x = v = 0.0
    for a in accel:
        xs = -a / omega**2  # the static deflection under this step's acceleration
        x, v = xs + (x - xs) * c + v / omega * s, -(x - xs) * omega * s + v * c
    return float(np.hypot(x, v / omega))


@pytest.mark.parametrize(("periods", "residual"), [(1.0, 0.01), (0.5, None)])
def test_a_ramp_of_one_period_leaves_the_mode_still(periods, residual):
    """A move whose acceleration ramps over one period of a 5 Hz mode leaves it within 1 % of
    the static deflection a bang-bang step would ring with; over half a period, it rings."""
    f = 5.0
    omega = 2 * np.pi * f
    dt = 1e-5
    accel, jerk = 4.0, 4.0 * f / periods
    _, _, _, sdd = _ruckig(speed=1.5, accel=accel, jerk=jerk, dt=dt)
    assert np.abs(sdd).max() == pytest.approx(accel, rel=1e-6)  # the ramps reach the peak
    left = _residual(sdd, omega, dt) / (accel / omega**2)
    if residual is None:
        assert left > 0.1
    else:
        assert left < residual
