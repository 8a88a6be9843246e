"""The realised design's accuracy budget (qsm.realization.accuracy.accuracy_budget) and the
gearboxes' stiffness and play (qsm.embodiment.drives.compliance)."""

import json
import math
from dataclasses import replace

import numpy as np
import pandas as pd
import pytest

from qsm.config.reading import load_config
from qsm.config.settings.realization import realization_of
from qsm.embodiment.drives.catalogue import (
    CatalogueError,
    default_catalogue_folder,
    read_catalogue,
)
from qsm.embodiment.drives.compliance import (
    DEFAULT_BACKLASH_ARCMIN,
    DEFAULT_STIFFNESS_NM_RAD,
    gear_compliance,
)
from qsm.embodiment.drives.report import (
    CatalogueDrive,
    DriveReport,
    DriveRequirement,
    MotorReport,
)
from qsm.embodiment.stiffness.error_terms import payload_force_N, sag_m, torque_reverses
from qsm.embodiment.stiffness.frame import tool_compliance
from qsm.physics.dynamics import inverse_dynamics, loop_state
from qsm.physics.inverse_kinematics import joint_path
from qsm.physics.kinematics import end_effector
from qsm.physics.mjcf import model_spec
from qsm.prose import fixed
from qsm.realization.accuracy.accuracy_budget import (
    MOTION_STEP_S,
    AccuracySettings,
    budget_mm,
    largest_load_N,
    task_motion_torques,
)
from qsm.realization.final.final_budget import plate_factors, tracking_per_point
from qsm.realization.motion.payload import reference_trajectory
from qsm.realization.selection.pipeline import arm_model, budget_of, realize

DESIGN = np.array([0.5, 0.15, 0.55, 0.22, 0.6, 0.2])
ANGLES = np.radians([[95.0, 20.0], [120.0, 30.0], [140.0, 60.0]])


@pytest.fixture(scope="module")
def settings():
    """The default config's realisation, without growing the design for its task (the budget's
    own tests; growing: tests/test_accuracy_sizing.py)."""
    return replace(realization_of(load_config()), accuracy=AccuracySettings())


@pytest.fixture(scope="module")
def points():
    return end_effector(DESIGN, ANGLES[:, 0], ANGLES[:, 1])


@pytest.fixture(scope="module")
def realized(settings):
    return realize(DESIGN, settings)


def budget_at(done, settings, points):
    """The budget of ``done`` at ``points`` under ``settings`` (what the workflow's rule and
    ``qsm export`` call)."""
    return budget_of(done, settings, points)


def test_the_record_is_strict_json_with_every_term_per_point(realized, settings, points):
    budget = budget_at(realized, settings, points)
    text = json.dumps(budget, allow_nan=False)
    assert json.loads(text) == budget
    for key, values in budget["per_point"].items():
        assert values is None or len(values) == len(points), key
    assert budget["per_point"]["tracking_error_mm"] is None  # no payload test yet


def test_the_budget_is_the_worst_case_sum_of_its_terms():
    terms = {
        "sag_mm": np.array([1.0, 4.0]),
        "dynamic_sag_mm": np.array([2.0, 3.0]),
        "creep_mm": np.array([0.125, 0.5]),
        "lost_motion_mm": np.array([0.5, 0.0]),
    }
    np.testing.assert_allclose(budget_mm(terms, [0.25, 1.0]), [2.875, 5.5])
    np.testing.assert_allclose(budget_mm(terms, None), [2.625, 4.5])


def test_the_static_sag_is_the_frames_response_to_the_payloads_weight(realized, settings, points):
    """sag_rigid_drives_mm against the frame solved here: the payload's weight m g at E."""
    model = arm_model(realized, settings)
    c = tool_compliance(DESIGN, ANGLES[:, 0], ANGLES[:, 1], model.sections)
    m = settings.motion.payload_kg
    expected = 1e3 * np.hypot(c[:, 0, 1], c[:, 1, 1]) * m * 9.80665
    np.testing.assert_allclose(
        budget_at(realized, settings, points)["per_point"]["sag_rigid_drives_mm"], expected
    )
    assert (
        np.array(budget_at(realized, settings, points)["per_point"]["sag_mm"]) >= expected
    ).all()


@pytest.mark.parametrize("tolerance_mm", [1e3, 1e-2])
def test_the_tolerance_decides_the_verdict_and_its_numbers(settings, points, tolerance_mm):
    tight = replace(settings, accuracy=AccuracySettings(tolerance_mm=tolerance_mm))
    budget = budget_at(realize(DESIGN, tight), tight, points)
    worst = budget["worst"]["error_budget_mm"]
    assert budget["meets_requirements"] is (worst <= tolerance_mm)
    assert f"{fixed(worst, 2)} mm" in budget["verdict"]  # 2 decimals, 4 significant digits
    assert f"tolerance {tolerance_mm:g} mm" in budget["verdict"]
    if budget["meets_requirements"]:
        assert budget["would_meet"] == []
    else:
        assert budget["verdict"].startswith(("NOT STIFF ENOUGH", "TOO MUCH PLAY", "TRACKS"))
        assert budget["would_meet"]


def test_a_first_mode_requirement_above_the_arms_is_reported(settings, points):
    lowest = budget_at(realize(DESIGN, settings), settings, points)["worst"]["first_mode_hz"]
    need = replace(settings, accuracy=AccuracySettings(1e3, min_first_mode_hz=2 * lowest))
    budget = budget_at(realize(DESIGN, need), need, points)
    assert not budget["meets_requirements"]
    assert f"first mode {lowest:.1f} Hz" in budget["verdict"]
    (only,) = budget["would_meet"]  # the tolerance is met: no advice for it
    assert only.startswith(f"for a first mode of {2 * lowest:g} Hz: an arm 4.0x as stiff")


def test_torque_reversals_agree_with_mujocos_inverse_dynamics(realized, settings, points):
    """The Newton-Euler torques along the task's motion change sign where MuJoCo's do."""
    model = arm_model(realized, settings)
    angles = joint_path(DESIGN, points, settings.motion.operating_range.theta1_deg)
    ne = task_motion_torques(model, angles, settings.motion)
    way = angles[[*range(len(angles)), 0]] if settings.motion.return_to_start else angles
    _, th, dth, ddth = reference_trajectory(
        way, settings.motion.segment_duration_s, settings.motion.dwell_s, MOTION_STEP_S
    )
    from qsm.embodiment.parts.part_mass import part_mass_properties

    props = part_mass_properties(realized.parts)
    mj = model_spec(DESIGN, settings.strength.cad, settings.motion.payload_kg, props).compile()
    tau = inverse_dynamics(mj, DESIGN, loop_state(DESIGN, th, dth, ddth)).tau
    np.testing.assert_allclose(ne, tau, atol=1e-6 * np.abs(tau).max())
    assert (torque_reverses(ne) == torque_reverses(tau)).all()


def test_play_moves_the_tool_only_where_a_torque_reverses(realized, settings, points):
    budget = budget_at(realized, settings, points)
    lost = np.asarray(budget["per_point"]["lost_motion_mm"])
    counted = [j["backlash_counted"] for j in budget["joints"].values()]
    assert (lost > 0).all() == any(counted)
    assert (lost == 0).all() == (not any(counted))


def test_plate_factors_are_the_fe_compliance_ratios():
    topology = {
        "links": {
            "lower_arm": {"compliance_before_J": 1.0, "compliance_after_J": 1.25},
            "upper_arm": {
                "compliance_before_J": 2.0,
                "compliance_after_J": 2.0,
                "kept_solid": True,
            },
        }
    }
    np.testing.assert_allclose(plate_factors(topology), [0.8, 1.0, 1.0, 1.0])


def test_tracking_error_of_the_first_point_is_its_worse_hold():
    """The test holds at the first point before it moves and again when it returns."""
    pts = np.array([[0.0, 0.5], [0.1, 0.5]])
    np.testing.assert_allclose(tracking_per_point(pts, [0.2, 0.3, 0.5]), [0.5, 0.3])
    np.testing.assert_allclose(tracking_per_point(pts, [0.2, 0.3]), [0.2, 0.3])


def test_a_drive_without_a_stiffness_keeps_the_others():
    from qsm.realization.accuracy.accuracy_budget import RIGID_FACTOR, drive_terms

    def motor(stiffness: float) -> MotorReport:
        drive = CatalogueDrive("m", "g", "M", "G", 10.0, 1.0, 0.0, 0.0, stiffness, "", "")
        return MotorReport(True, -0.5, DriveRequirement(1.0, 1.0, 1.0, 1.0), drive, {})

    motors = {"motor1": motor(2.0e3), "motor2": motor(math.inf)}  # no stiffness known
    k = drive_terms(DriveReport(True, "lightest", motors))[0]
    np.testing.assert_allclose(k, [2.0e3, RIGID_FACTOR * 2.0e3])


def test_a_gearbox_without_values_gets_stated_assumptions():
    row = pd.Series({"key": "X", "type": "planetary"})
    got = gear_compliance(row)
    assert got["backlash_arcmin"] == DEFAULT_BACKLASH_ARCMIN
    assert got["torsional_stiffness_Nm_rad"] == DEFAULT_STIFFNESS_NM_RAD
    assert got["backlash_from"].startswith("assumed") and got["stiffness_from"].startswith(
        "assumed"
    )
    given = gear_compliance(
        pd.Series(
            {"type": "harmonic", "backlash_arcmin": 1.0, "torsional_stiffness_Nm_rad": 6.7e4,
             "stiffness_status": "published", "stiffness_source": "HD catalogue"}
        )
    )  # fmt: skip
    assert given["torsional_stiffness_Nm_rad"] == 6.7e4
    assert given["stiffness_from"] == "published: HD catalogue"


def test_the_shipped_catalogue_gives_every_gearbox_its_values_and_status():
    gearboxes = read_catalogue(default_catalogue_folder()).gearboxes
    assert gearboxes["backlash_arcmin"].gt(0).all()
    assert gearboxes["torsional_stiffness_Nm_rad"].gt(0).all()
    assert set(gearboxes["backlash_status"]) | set(gearboxes["stiffness_status"]) <= {
        "published",
        "assumed",
    }
    assert gearboxes["stiffness_source"].str.len().gt(20).all()


def test_a_zero_stiffness_is_refused_naming_the_column(tmp_path):
    for f in default_catalogue_folder().glob("*.csv"):
        text = f.read_text()
        if f.name == "gearboxes.csv":
            text = text.replace(",60,2400,", ",60,0,", 1)
        (tmp_path / f.name).write_text(text)
    with pytest.raises(CatalogueError, match="torsional_stiffness_Nm_rad"):
        read_catalogue(tmp_path)


def test_sag_of_a_pure_weight_is_linear_in_the_payload():
    c = np.array([[3e-4, 1e-4], [1e-4, 2e-4]])
    one, two = (sag_m(c, payload_force_N(m, np.zeros(2))) for m in (1.0, 2.0))
    assert two == pytest.approx(2 * one) and math.isfinite(one)


def test_g15s_sag_is_the_budgets_rigid_sag_at_the_configured_section(realized, settings, points):
    """The loop's check (batch inverse kinematics, solid links, rigid drives) gives the budget's
    sag_rigid_drives_mm of a fixed-section design, worst over the points."""
    from qsm.embodiment.stiffness.sag_check import SagCheck

    check = SagCheck(points=tuple(map(tuple, points)), cad=settings.strength.cad)
    worst = budget_at(realized, settings, points)["worst"]["sag_rigid_drives_mm"]
    assert check.sag_mm(DESIGN)[0] == pytest.approx(worst, rel=1e-9)
    assert check.violation(DESIGN)[0] == pytest.approx(worst - check.tolerance_mm, rel=1e-9)
    far = SagCheck(points=((5.0, 5.0),))
    assert far.violation(DESIGN)[0] > 1e5  # out of reach: a large violation, not NaN


def test_g15_is_a_column_of_the_extra_constraints(settings, points):
    from qsm.embodiment.stiffness.sag_check import SagCheck
    from qsm.optimization.constraint_set import G15, ExtraConstraints
    from qsm.physics.cad import DEFAULT_CAD

    check = SagCheck(points=tuple(map(tuple, points)), tolerance_mm=10.0)
    extra = ExtraConstraints(False, False, None, DEFAULT_CAD, (600, 350, 350), sag=check)
    assert extra.names("paper")[-1] == G15 and "g15 tool sag within 10 mm" in extra.label("paper")
    designs = np.stack([DESIGN, DESIGN * 1.1])
    (g15,) = extra.columns("paper", designs)
    np.testing.assert_allclose(g15, check.violation(designs))


def test_the_dynamic_sag_takes_the_larger_of_the_dutys_and_the_cycles_load(
    realized, settings, points
):
    plain = budget_of(realized, settings, points)
    duty_N = plain["dynamic_load_N"]["duty"]
    gentle = budget_of(realized, settings, points, cycle_load_N=0.5 * duty_N)
    assert gentle["dynamic_load_from"] == "duty"
    assert gentle["per_point"]["dynamic_sag_mm"] == plain["per_point"]["dynamic_sag_mm"]
    hard = budget_of(realized, settings, points, cycle_load_N=2.0 * duty_N)
    assert hard["dynamic_load_from"] == "cycle"
    # the sag under a force of the worst direction is linear in its magnitude
    np.testing.assert_allclose(
        hard["per_point"]["dynamic_sag_mm"],
        2.0 * np.array(plain["per_point"]["dynamic_sag_mm"]),
        rtol=1e-12,
    )


def test_the_largest_load_keeps_every_point_within_the_tolerance():
    """By hand: at each point the dynamic sag grows with the force, so the largest force is the
    least of (tolerance - creep - lost motion - tracking) / (dynamic sag per newton)."""
    budget = {
        "tolerance_mm": 5.0,
        "dynamic_load_N": {"duty": 60.0, "cycle": 50.0},
        "per_point": {
            "sag_mm": [2.0, 3.0],
            "dynamic_sag_mm": [3.0, 4.0],  # at 60 N: 0.05 and 0.0667 mm/N
            "creep_mm": [0.2, 0.4],
            "lost_motion_mm": [0.5, 0.0],
            "tracking_error_mm": [0.1, 0.2],
        },
    }
    expected = min(4.2 / (3.0 / 60.0), 4.4 / (4.0 / 60.0))  # 84 and 66 N
    assert largest_load_N(budget) == pytest.approx(expected)
    assert largest_load_N(budget) == pytest.approx(66.0)
    budget["per_point"]["tracking_error_mm"] = None  # before the payload test
    assert largest_load_N(budget) == pytest.approx(69.0)
    budget["per_point"]["sag_mm"] = [2.0, 4.8]  # the weight and creep alone are past it
    assert largest_load_N(budget) == 0.0
    budget["per_point"]["sag_mm"] = [2.0, 3.0]
    budget["per_point"]["dynamic_sag_mm"] = [0.0, 0.0]  # no force sags the tool: no limit
    assert largest_load_N(budget) is None


def test_a_missed_tolerance_says_what_the_sizing_did():
    """The final budget's advice starts from the sizing: the limits it stopped at, or (when it
    met its own target) its figure against the arm's as printed; nothing where the budget meets
    the tolerance or the arm was not sized for it."""
    from qsm.realization.accuracy.accuracy_sizing import AccuracyChoice
    from qsm.realization.final.final_budget import sizing_note

    missed = {"meets_requirements": False, "worst": {"error_budget_mm": 6.2}}
    met = AccuracyChoice(np.ones(4), (0.0, 0.0), 3.4, 3.5, True)
    (note,) = sizing_note(met, missed)
    assert "3.40 mm" in note and "3.50 mm" in note and "errs 6.20 mm" in note
    held = replace(met, meets=False, structure_mm=4.1, stopped_at=("the crank at 1.30x", "x"))
    assert sizing_note(held, missed) == [
        "more than the sizing may give: it stopped at the crank at 1.30x; x"
    ]
    assert sizing_note(met, missed | {"meets_requirements": True}) == []
    assert sizing_note(replace(met, meets=None), missed) == []
