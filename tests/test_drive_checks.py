"""Drives in the loop (qsm.embodiment.drives.drive_checks): reflected inertia against MuJoCo
armature, the per-candidate choice, g14 and the dataset columns."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from test_drives import write_catalogue

from qsm.dataset.columns import DRIVE_COLUMNS
from qsm.embodiment.drives.catalogue import read_catalogue
from qsm.embodiment.drives.drive_checks import DriveCheck
from qsm.embodiment.drives.report import CatalogueDrive, report_json
from qsm.embodiment.drives.selection import offer, select_drives
from qsm.embodiment.strength.loads import Inertials, joint_loads
from qsm.physics.cad import mass_properties
from qsm.physics.duty import Duty, duty_cycle
from qsm.physics.dynamics import inverse_dynamics, loop_state, tree_inverse_dynamics
from qsm.physics.mjcf import body_inertials, model_spec
from qsm.report.drive_text import drive_sentences
from qsm.report.headline_tables import drive_failures

DESIGN = np.array([0.5, 0.15, 0.5, 0.22, 0.6, 0.2])


def test_armature_on_theta1_theta2_is_tau_plus_j_theta_ddot():
    """MuJoCo's armature J on the motor joints adds exactly J theta'' to each motor torque."""
    duty = duty_cycle()
    arm = (0.7, 0.25)  # kg m^2
    props = mass_properties(DESIGN)
    state = loop_state(DESIGN, duty.theta, duty.dtheta, duty.ddtheta)
    bodies = body_inertials(DESIGN, props, 5.0)
    bare = joint_loads(DESIGN, Inertials.of(props), 5.0, state).tau
    expected = bare + np.asarray(arm) * duty.ddtheta
    assert np.abs(np.asarray(arm) * duty.ddtheta).max() > 0.1  # the term is not negligible
    tiled = tree_inverse_dynamics(DESIGN, bodies, state, arm).tau
    np.testing.assert_allclose(tiled, expected, atol=1e-6)
    model = model_spec(DESIGN, payload_kg=5.0, armature=arm).compile()
    rows = np.arange(0, len(duty.theta), 25)
    sub = loop_state(DESIGN, duty.theta[rows], duty.dtheta[rows], duty.ddtheta[rows])
    np.testing.assert_allclose(inverse_dynamics(model, DESIGN, sub).tau, expected[rows], atol=1e-6)


@pytest.fixture
def three(tmp_path):
    """(A, G10) 0.7 kg, J 1.1e-3; (A, G50) 0.9 kg, J 3e-2; (B, G10) 2.2 kg, J 1.01e-2 kg m^2."""
    return read_catalogue(write_catalogue(tmp_path / "cat"))


def test_each_candidate_is_checked_with_its_own_reflected_inertia(three):
    # 1 N m at 0.1 rad/s for 1 s, then 0.1 N m at 0.1 rad/s with 100 rad/s^2 for 1 s
    tau, omega, w = [1.0, 0.1], [0.1, 0.1], [1.0, 1.0]
    accel = [0.0, 100.0]
    # without inertia (A, G10) is the lightest that meets it: motor RMS
    # sqrt((1^2 + 0.1^2) / 2) / 8 / 0.2 = 0.44, envelope 1 / 8 / 2.4 + 1 / 200 = 0.057
    assert select_drives(three, tau, omega, w).choice.tolist() == [0]
    sel = select_drives(three, tau, omega, w, accel=accel)
    # with it: (A, G10) sees 0.1 + 1.1e-3 x 100 = 0.21 N m, (A, G50) 0.1 + 3 = 3.1 N m: the
    # second sample is back-driven for neither (0.1 rad/s, torque > 0); (A, G10) still meets
    # everything, so the same choice, with 0.21 N m in the second sample's requirement
    assert sel.choice.tolist() == [0]
    assert sel.rms_torque[0] == pytest.approx(np.sqrt((1.0 + 0.21**2) / 2))
    # a larger acceleration: (A, G10) needs 0.1 + 1.1e-3 x 2e4 = 22.1 N m > its gearbox's 20;
    # (A, G50) 0.1 + 600 N m > 60; (B, G10) 0.1 + 202 > 20: none, and g14 is the least excess
    sel = select_drives(three, tau, omega, w, accel=[0.0, 2e4])
    assert sel.choice.tolist() == [-1]
    assert sel.best.tolist() == [0]
    u = sel.utilization[0]
    assert u[3] == pytest.approx(22.1 / 20)  # gearbox peak
    assert sel.violation[0] == pytest.approx(u.max() - 1)


def _duty(n: int, dtheta: float, ddtheta: float) -> Duty:
    ones = np.ones(n)
    return Duty(
        theta=np.column_stack([np.full(n, 1.5), np.full(n, 0.5)]),
        dtheta=np.column_stack([ones * dtheta, ones * dtheta]),
        ddtheta=np.column_stack([ones * ddtheta, ones * ddtheta]),
        static=np.zeros(n, bool),
        time_s=np.arange(n, dtype=float),
        weight_s=ones,
    )


def test_select_takes_speeds_and_accelerations_from_the_duty(three):
    check = DriveCheck(catalogue=three, duty=_duty(3, 5.0, 0.0))
    # 8 N m at 5 rad/s: only (B, G10) (test_drives: 8 / 10 = 0.8 at its gearbox's RMS rating)
    tau = np.stack([np.full((1, 3), 8.0), np.full((1, 3), 3.0)], -1)
    one, two = check.select(tau)
    assert one.choice.tolist() == [2]
    assert one.violation[0] == pytest.approx(0.8 - 1)
    assert one.peak_power[0] == pytest.approx(40.0)
    # 3 N m at 5 rad/s: (A, G10) fails RMS 3 / 8 / 0.2; (A, G50) at 250 rad/s exceeds the
    # no-load speed 200; (B, G10): 3 / 8 / 1.5 = 0.25, 3 / 8 / 2 = 0.19, 50 / 240 < 1
    assert two.choice.tolist() == [2]


def test_g14_and_the_dataset_columns_on_a_real_design(three):
    check = DriveCheck(catalogue=three)
    table = check.evaluate(DESIGN[None])
    assert list(table.columns) == list(DRIVE_COLUMNS)
    # this 0.5 m arm with 5 kg needs tens of N m at the lower arm, far beyond these small drives
    # (at most 60 N m peak and 30 N m continuous at the output): g14 > 0, no drives
    row = table.iloc[0]
    assert not row["has_drives"] and row["drive_violation"] > 0
    assert check.violation(DESIGN[None])[0] == pytest.approx(row["drive_violation"])
    assert row["drive_violation"] == pytest.approx(
        max(row["drive1_violation"], row["drive2_violation"])
    )
    # the requirement includes the reflected inertia of the reported drive
    no_j = DriveCheck(catalogue=three, reflected_inertia=False).evaluate(DESIGN[None]).iloc[0]
    tau, _ = check.torques(DESIGN[None])
    j1 = row["drive1_reflected_inertia_kgm2"]
    torque = tau[0, :, 0] + j1 * check.duty.ddtheta[:, 0]
    assert row["drive1_peak_torque_Nm"] == pytest.approx(np.abs(torque).max())
    assert no_j["drive1_peak_torque_Nm"] == pytest.approx(np.abs(tau[0, :, 0]).max())
    report = report_json(check.report(DESIGN))  # the record the outputs read
    text = " ".join(drive_sentences(report))
    assert "NO DRIVE" in text and "the strongest drive" in text
    # summary.md's bullets: one per motor without a drive, with what the strongest offers
    bullets = drive_failures(report)
    failing = [m for m in report["motors"].values() if not m["has_drive"]]
    assert len(bullets) == len(failing) > 0
    for line, m in zip(bullets, failing, strict=True):
        assert (
            line.startswith("- motor ")
            and f"{m['strongest_drive']['peak_torque_Nm']:.0f} N m" in line
        )
    assert drive_failures({}) == []
    # an undefined design (the loop does not close): NaN columns and the fixed g14
    bad = np.array([[0.5, 0.45, 0.2, 0.1, 0.6, 0.2]])
    assert check.violation(bad)[0] == pytest.approx(10.0)


def test_g14_from_the_strength_checks_torques_equals_its_own():
    """The optimisation computes the loads once: g14 from the strength check's torques is the
    drive check's own g14 (the same section, payload and duty)."""
    from qsm.embodiment.strength.link_checks import StrengthCheck
    from qsm.physics.duty import DutySettings, duty_cycle

    duty = duty_cycle(DutySettings(samples_per_segment=6))
    designs = np.array([[0.5, 0.15, 0.5, 0.22, 0.6, 0.2], [0.35, 0.1, 0.38, 0.14, 0.42, 0.2]])
    _, tau, good = StrengthCheck(duty=duty).violation_and_torques(designs)
    drives = DriveCheck(duty=duty)
    np.testing.assert_array_equal(
        drives.violation_from_torques(designs, tau, good), drives.violation(designs)
    )


def test_a_realised_design_s_drives_hold_the_task_as_well_as_the_duty():
    """A task that holds the arm stretched out (170, -30 deg) asks motor 1 for more continuous
    torque than the duty's raster: the drive chosen meets both, the duty's own choice would
    overheat on the task, and the hold's torque is within the chosen drive's continuous rating
    at the joint (a hold drives the gear, so the rating is k_t I_nom N eta)."""
    plain = DriveCheck()
    theta = np.radians([[170.0, -30.0]] * 3)
    still = np.zeros_like(theta)
    hold = Duty(theta, still, still, np.ones(3, bool), np.zeros(3), np.ones(3))
    check = replace(plain, task_duty=hold)
    report = check.report(DESIGN)
    also, need = check.task_violations(DESIGN[None])
    drives = plain.catalogue.drives
    chosen, before = (r.motors["motor1"].drive for r in (report, plain.report(DESIGN)))

    def row(drive: CatalogueDrive) -> int:
        match = (drives["motor"] == drive.motor_key) & (drives["gearbox"] == drive.gearbox_key)
        return int(np.flatnonzero(match.to_numpy())[0])

    assert also[0][row(chosen)] <= 0 < also[0][row(before)]
    assert chosen.mass_kg > before.mass_kg  # the lightest that meets both is heavier
    assert need.rms_torque_Nm[0] <= offer(plain.catalogue)[row(chosen)]["cont_torque_Nm"]
    assert need.rms_torque_Nm[0] > offer(plain.catalogue)[row(before)]["cont_torque_Nm"]
