"""The masses that move with the arm: the tool flange at E enters the realisation's dynamics
(torques, drives, strength, sag), found by a bounded loop to its fixed point
(qsm.realization.selection.pipeline.realize)."""

import math
from dataclasses import replace

import mujoco
import numpy as np
import pytest

from qsm import load_config
from qsm.config.settings.realization import realization_of
from qsm.embodiment.drives.envelope import OutputEnvelope
from qsm.embodiment.drives.torque_limits import checked_peaks_Nm, limited
from qsm.embodiment.kit import fasteners as fs
from qsm.embodiment.kit import joints as jt
from qsm.physics.kinematics import end_effector
from qsm.physics.mjcf import mjcf_xml
from qsm.realization.accuracy.accuracy_budget import (
    AccuracySettings,
    peak_payload_force_N,
    task_motion_duty,
)
from qsm.realization.selection.pipeline import (
    budget_of,
    carrying,
    realize,
    realize_once,
)

DESIGN = np.array([0.5, 0.15, 0.55, 0.22, 0.6, 0.2])
POINTS = end_effector(DESIGN, *np.radians([[95.0, 120.0, 140.0], [20.0, 30.0, 60.0]]))


def _settings(**loop):
    points = tuple(map(tuple, POINTS.tolist()))
    accuracy = AccuracySettings(3.0, points_m=points, max_section_scale=2.0)
    settings = replace(realization_of(load_config()), accuracy=accuracy)
    return replace(settings, kit_sizing=replace(settings.kit_sizing, **loop))


def test_the_tool_flange_mass_by_hand():
    """ISO 9409-1-31.5-4-M5's 40 mm face, 16 mm thick, in steel (7850 kg/m^3): 0.158 kg; its M8
    centre screw (ISO 4762: head 13 x 8 mm) of 30 mm and the ISO 7089 washer (8.4 / 16 x
    1.6 mm) add theirs."""
    screw = fs.Fastener("ISO 4762", "M8 x 30", "M8", 8.0, 30.0, "tool flange")
    disc = math.pi / 4 * 40.0**2 * 16.0 * 7850e-9
    assert disc == pytest.approx(0.158, abs=5e-4)  # the figure the kit's BOM gives the disc
    head = math.pi / 4 * 13.0**2 * 8.0 * 7850e-9
    shank = math.pi / 4 * 8.0**2 * 30.0 * 7850e-9
    washer = math.pi / 4 * (16.0**2 - 8.4**2) * 1.6 * 7850e-9
    assert jt.flange_mass_kg(40.0, screw) == pytest.approx(disc + head + shank + washer, rel=1e-9)


def test_the_realisation_carries_its_tool_flange():
    """The drives and the strength were checked with the flange's mass at E beside the payload:
    the drive check run again with it gives the report's torques, and without it less."""
    settings = _settings()
    done = realize(DESIGN, settings)
    tool = done.tool_kg
    assert tool > 0.1 and done.tool_flange.holds
    assert done.strength.tool_flange_kg == tool
    assert done.strength.payload_kg == settings.motion.payload_kg
    scale = None if done.scale is None else np.asarray(done.scale)[None]
    drives = replace(settings.drives, min_stiffness_Nm_rad=done.accuracy.min_stiffness_Nm_rad)
    drives = replace(drives, task_duty=None)

    def peak(extra_kg):
        report = carrying(replace(settings, drives=drives), extra_kg).drives.report(DESIGN, scale)
        return report.motors["motor1"].required.peak_torque_Nm

    required = done.drives.motors["motor1"].required.peak_torque_Nm
    assert peak(tool) == pytest.approx(required, rel=1e-12)
    assert peak(0.0) < required - 0.5 * tool * 9.81 * DESIGN[0] * 0.1  # it weighs on motor 1
    # the budget's payload force is that of the payload and the flange
    du = settings.strength.duty
    force = peak_payload_force_N(
        DESIGN, settings.motion.payload_kg + tool, du.theta, du.dtheta, du.ddtheta
    )
    budget = budget_of(done, carrying(settings, tool), POINTS)
    assert budget["dynamic_load_N"]["duty"] == pytest.approx(force, rel=1e-12)


def test_the_loop_stops_at_its_fixed_point():
    """With a tolerance of nothing the loop runs until the flange it chooses is the one it
    carried (the sizes are discrete: the second realisation repeats the first's flange); with one
    realisation allowed it stops unsettled, and says so."""
    settled = realize(DESIGN, _settings(tolerance=1e-12, max_iterations=4))
    point = settled.fixed_point
    assert point.converged and 2 <= point.iterations <= 4
    payload = _settings().motion.payload_kg  # the loop's tolerance is a share of it
    assert point.tool_kg[-1] == pytest.approx(
        settled.tool_flange.moving_mass_kg, abs=1e-12 * payload
    )
    once = realize(DESIGN, _settings(tolerance=1e-12, max_iterations=1))
    assert once.fixed_point.iterations == 1 and not once.fixed_point.converged
    # a single realisation carrying the settled flange is the settled realisation
    again = realize_once(DESIGN, carrying(_settings(), point.tool_kg[-1]))
    assert again.drives == settled.drives  # the same inputs, the same code path


def test_each_drive_gets_a_torque_limit_above_its_checked_torque():
    """The limit is the margin times the largest torque the checks found on the motor (over the
    duty and the task motion, the drive's reflected inertia included), at most the drive's
    standstill torque; the cycle's and the payload test's drives are capped at it, and the
    export's MJCF holds each motor to it."""
    settings = _settings(torque_margin=1.2)
    done = realize(DESIGN, settings)
    check = carrying(settings, done.tool_kg).drives
    check = replace(check, task_duty=task_motion_duty(_angles(), settings.motion))
    scales = None if done.scale is None else np.asarray(done.scale)[None]
    drives = [done.drives.motors[f"motor{k}"].drive for k in (1, 2)]
    envs = [OutputEnvelope.of(check.catalogue, d.motor_key, d.gearbox_key) for d in drives]
    rotors = [e.reflected_inertia for e in envs]
    duty_only = checked_peaks_Nm(replace(check, task_duty=None), DESIGN, scales, rotors)
    peaks = checked_peaks_Nm(check, DESIGN, scales, rotors)
    for k, (limit, env) in enumerate(zip(done.torque_limits_Nm, envs, strict=True), start=1):
        required = done.drives.motors[f"motor{k}"].required.peak_torque_Nm
        assert duty_only[k - 1] == pytest.approx(required, rel=1e-9)  # the drive check's figure
        task = done.drives.task_motion.peak_torque_Nm[k - 1]  # without the rotor
        assert peaks[k - 1] >= max(required, task) - 1e-9
        standstill = float(env.limit(1.0, 0.0))
        assert limit == pytest.approx(min(1.2 * peaks[k - 1], standstill), rel=1e-12)
        capped = limited(env, limit)
        speeds = np.linspace(0.0, 1.0, 11)
        assert np.all(capped.limit(np.ones(11), speeds) <= limit + 1e-12)
        assert np.all(capped.limit(np.ones(11), speeds) <= env.limit(np.ones(11), speeds))
    model = mujoco.MjModel.from_xml_string(mjcf_xml(DESIGN, torque_limits_Nm=done.torque_limits_Nm))
    ranges = [model.joint(name).id for name in ("theta1", "theta2")]
    np.testing.assert_allclose(  # MJCF holds 6 significant digits
        model.jnt_actfrcrange[ranges][:, 1], np.asarray(done.torque_limits_Nm), rtol=1e-5
    )


def _angles():
    """The motor angles (n, 2) rad at the test's task points."""
    return np.radians([[95.0, 20.0], [120.0, 30.0], [140.0, 60.0]])
