"""ISO 9283 pose accuracy and repeatability, and the standard pick-and-place cycle's route:
the standard's geometry and definitions by hand, the Monte Carlo's terms against closed forms
and the catalogue's numbers, the test plane and the stroke against an independent IK."""

import itertools
import json
import math
from dataclasses import replace

import numpy as np
import pytest

from qsm.config.reading import load_config
from qsm.config.settings.realization import realization_of
from qsm.embodiment.drives.catalogue import (
    CatalogueError,
    default_catalogue_folder,
    read_catalogue,
)
from qsm.embodiment.stiffness.error_terms import payload_force_N
from qsm.embodiment.stiffness.frame import tool_compliance
from qsm.embodiment.strength.loads import joint_loads
from qsm.physics.dynamics import loop_state
from qsm.physics.inverse_kinematics import joint_angles, joint_path
from qsm.physics.kinematics import end_effector
from qsm.realization.accuracy.accuracy_budget import AccuracySettings, creep_drift_m
from qsm.realization.accuracy.iso9283 import (
    RandomTerms,
    ap_rp_mm,
    largest_plane,
    plane_points,
    play_opens,
    pose_characteristics,
)
from qsm.realization.accuracy.iso_record import IsoSettings, iso_record, random_terms
from qsm.realization.final.standard_cycle import STROKE_M, StandardRoute, standard_route
from qsm.realization.selection.pipeline import arm_model, realize

DESIGN = np.array([0.5, 0.15, 0.55, 0.22, 0.6, 0.2])
OP = ((45.0, 180.0), -37.5)
NONE = RandomTerms(np.zeros(2), np.zeros(2), np.zeros(2), 0.0)


@pytest.fixture(scope="module")
def settings():
    return replace(realization_of(load_config()), accuracy=AccuracySettings())


@pytest.fixture(scope="module")
def realized(settings):
    return realize(DESIGN, settings)


@pytest.fixture(scope="module")
def plane():
    centre = end_effector(DESIGN, math.radians(120.0), math.radians(30.0))
    return largest_plane(DESIGN, centre, *OP)


def test_p2_to_p5_stand_a_tenth_of_the_diagonal_in_from_the_corners():
    side = 0.2
    pts = plane_points([1.0, 2.0], side)
    corners = np.array([1.0, 2.0]) + side / 2 * np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]])
    in_from_corner = np.linalg.norm(pts[1:] - corners, axis=1)
    np.testing.assert_allclose(in_from_corner, 0.1 * side * math.sqrt(2), rtol=1e-12)
    np.testing.assert_allclose(pts[0], [1.0, 2.0])


def test_ap_and_rp_follow_the_standards_definitions():
    # poses on a circle of radius r about a point a off the command: barycentre a, l = r, S = 0
    r, a = 0.3e-3, 1.2e-3
    phi = np.linspace(0, 2 * np.pi, 30, endpoint=False)
    attained = np.stack([a + r * np.cos(phi), r * np.sin(phi)], axis=-1)[:, None, :]
    ap, rp = ap_rp_mm(attained, [[0.0, 0.0]])
    assert ap[0] == pytest.approx(1.2, abs=1e-9) and rp[0] == pytest.approx(0.3, abs=1e-9)
    # two radii: l-bar + 3 S_l with n - 1 degrees of freedom, by hand
    radii = np.where(np.arange(30) % 2, 1e-3, 3e-3)
    attained = np.stack([radii * np.cos(phi), radii * np.sin(phi)], axis=-1)[:, None, :]
    s = math.sqrt(30 * 1.0**2 / 29)  # each distance 1 mm off the mean of 2 mm
    assert ap_rp_mm(attained, [[0.0, 0.0]])[1][0] == pytest.approx(2.0 + 3 * s, rel=1e-9)


def test_the_plane_is_the_largest_square_an_independent_ik_reaches(plane):
    def reached(side):
        u = np.linspace(-side / 2, side / 2, 15)
        for x in u:
            for y in u:
                try:
                    joint_angles(DESIGN, np.add(plane.centre_m, [x, y]), *OP)
                except ValueError:
                    return False
        return True

    assert plane.side_m > 0.05 and reached(plane.side_m)
    assert not reached(plane.side_m * 1.03)


def test_without_random_terms_ap_is_the_sag_and_base_and_rp_is_zero(realized, settings, plane):
    model = arm_model(realized, settings)
    angles = joint_path(DESIGN, plane.points_m, *OP)
    pc = pose_characteristics(model, plane, angles, 5.0, NONE, base_mm=0.4)
    k = model.drive_stiffness
    c = tool_compliance(DESIGN, angles[:, 0], angles[:, 1], model.sections, k)
    sag_mm = 1e3 * np.linalg.norm(c @ payload_force_N(5.0, np.zeros(2)), axis=-1)
    np.testing.assert_allclose(pc.ap_mm, sag_mm + 0.4, rtol=1e-9)  # the base along the sag
    np.testing.assert_allclose(pc.compensated_ap_mm, 0.4, rtol=1e-9)
    np.testing.assert_allclose(pc.rp_mm, 0.0, atol=1e-12)


def test_the_aged_ap_adds_the_creeps_drift_to_the_systematic_terms(realized, settings, plane):
    """Without random terms the AP after the service time is |sag + base along it + drift|,
    the drift the budget's creep at the plane's points; without a creep law it is the AP."""
    model = arm_model(realized, settings)
    assert model.printed is not None and model.printed.creep_coefficient > 0
    angles = joint_path(DESIGN, plane.points_m, *OP)
    pc = pose_characteristics(model, plane, angles, 5.0, NONE, base_mm=0.4)
    c = tool_compliance(DESIGN, angles[:, 0], angles[:, 1], model.sections, model.drive_stiffness)
    sag = c @ payload_force_N(5.0, np.zeros(2))
    drift = creep_drift_m(model, angles[:, 0], angles[:, 1], 5.0)
    along = sag / np.linalg.norm(sag, axis=-1, keepdims=True)
    aged = 1e3 * np.linalg.norm(sag + 4e-4 * along + drift, axis=-1)
    np.testing.assert_allclose(pc.service_ap_mm, aged, rtol=1e-9)
    np.testing.assert_allclose(pc.creep_mm, 1e3 * np.linalg.norm(drift, axis=-1), rtol=1e-12)
    assert pc.service_time_h == model.printed.service_time_h
    fresh = pose_characteristics(model._replace(printed=None), plane, angles, 5.0, NONE, 0.4)
    np.testing.assert_array_equal(fresh.service_ap_mm, fresh.ap_mm)
    assert not fresh.creep_mm.any()


def test_a_joints_play_moves_the_tool_by_its_jacobian(realized, settings, plane):
    """Backlash b at motor 1 alone: attained poses spread along the Jacobian's first column,
    uniformly over +-b/2, so RP is at most |J1| b / 2 + 3 S and grows in proportion to b."""
    model = arm_model(realized, settings)
    angles = joint_path(DESIGN, plane.points_m, *OP)
    play = RandomTerms(np.array([1e-3, 0.0]), np.zeros(2), np.zeros(2), 0.0)
    one = pose_characteristics(model, plane, angles, 5.0, play)
    two = pose_characteristics(
        model, plane, angles, 5.0, replace(play, backlash_rad=2 * play.backlash_rad)
    )
    np.testing.assert_allclose(two.rp_mm, 2 * one.rp_mm, rtol=1e-9)
    h = 1e-7
    t1, t2 = angles[:, 0], angles[:, 1]
    j1 = (end_effector(DESIGN, t1 + h, t2) - end_effector(DESIGN, t1 - h, t2)) / (2 * h)
    reach_mm = 1e3 * np.linalg.norm(j1, axis=1) * 1e-3  # |J1| b: the whole spread
    # a uniform spread of width w: l-bar about w / 4, S_l about w / (4 sqrt 3)
    np.testing.assert_allclose(one.rp_mm, reach_mm * (0.25 + 0.75 / math.sqrt(3)), rtol=0.3)
    assert one.main_random_term == "backlash"


def test_friction_holds_the_joint_anywhere_within_plus_or_minus_its_deflection(
    realized, settings, plane
):
    """Friction f at motor 1 alone: the joint rests anywhere in [-f, f], a spread of 2 f along
    the Jacobian's first column, as a backlash of 2 f would give."""
    model = arm_model(realized, settings)
    angles = joint_path(DESIGN, plane.points_m, *OP)
    f = 5e-4
    friction = RandomTerms(np.zeros(2), np.zeros(2), np.array([f, 0.0]), 0.0)
    pc = pose_characteristics(model, plane, angles, 5.0, friction)
    h = 1e-7
    t1, t2 = angles[:, 0], angles[:, 1]
    j1 = (end_effector(DESIGN, t1 + h, t2) - end_effector(DESIGN, t1 - h, t2)) / (2 * h)
    width_mm = 1e3 * np.linalg.norm(j1, axis=1) * 2 * f
    np.testing.assert_allclose(pc.rp_mm, width_mm * (0.25 + 0.75 / math.sqrt(3)), rtol=0.3)
    assert pc.main_random_term == "friction"


def test_the_monte_carlo_repeats_with_its_seed(realized, settings, plane):
    model = arm_model(realized, settings)
    angles = joint_path(DESIGN, plane.points_m, *OP)
    terms = RandomTerms(np.full(2, 3e-4), np.full(2, 1e-5), np.full(2, 2e-4), 0.01)
    a, b = (pose_characteristics(model, plane, angles, 5.0, terms, seed=7) for _ in range(2))
    np.testing.assert_array_equal(a.rp_mm, b.rp_mm)
    other = pose_characteristics(model, plane, angles, 5.0, terms, seed=8)
    assert not np.array_equal(a.rp_mm, other.rp_mm)


def test_the_random_terms_are_the_catalogues_numbers(realized, settings):
    payload = {"point_error_mm": [0.002, 0.011, 0.004]}
    iso = IsoSettings(30, 1, 4096.0, (2000.0, 1000.0))
    terms, sources = random_terms(realized.drives, settings.drives.catalogue, payload, iso)
    cat = read_catalogue(default_catalogue_folder())
    for j, motor in enumerate(realized.drives.motors.values()):
        drive = motor.drive
        row = cat.motors.loc[drive.motor_key]
        n = drive.ratio
        assert terms.friction_rad[j] == pytest.approx(row.I_nl * row.k_t * n / iso.kp_Nm_rad[j])
        assert terms.encoder_rad[j] == pytest.approx(2 * math.pi / (4096 * n))
        assert terms.backlash_rad[j] == pytest.approx(math.radians(drive.backlash_arcmin / 60))
    assert terms.settling_mm == 0.011
    assert all("assumed: iso9283.encoder_counts" in s for s in sources["encoder"])


def test_a_repeatability_past_the_tasks_fails_with_its_numbers(realized, settings, plane):
    model = arm_model(realized, settings)
    angles = joint_path(DESIGN, plane.points_m, *OP)
    terms = RandomTerms(np.full(2, 3e-4), np.zeros(2), np.zeros(2), 0.0)
    pc = pose_characteristics(model, plane, angles, 5.0, terms)
    sources = {"backlash": ["b"], "encoder": ["e"], "friction": ["f"], "settling": ["s"]}
    low, high = 0.5 * pc.rp_mm.max(), 2 * pc.rp_mm.max()
    failing = {"simulated": True} | iso_record(pc, sources, 5.0, low, mirrored=True)
    assert failing["meets_repeatability"] is False
    assert iso_record(pc, sources, 5.0, high, False)["meets_repeatability"] is True
    assert failing["plane_centre_m"][0] == pytest.approx(-plane.centre_m[0])  # the user's frame
    json.dumps(failing, allow_nan=False)
    from qsm.report.accuracy_report import repeatability_problem

    text = repeatability_problem(failing)
    assert f"{pc.rp_mm.max():.3f} mm" in text and f"{low:g} mm required" in text


def test_an_encoder_count_column_is_read_and_a_negative_one_refused(tmp_path):
    for f in default_catalogue_folder().glob("*.csv"):
        (tmp_path / f.name).write_text(f.read_text())
    motors = tmp_path / "motors.csv"
    text = motors.read_text().replace("0.0884,4.58,,994.8,,,,", "0.0884,4.58,,994.8,,,2048,", 1)
    motors.write_text(text)
    assert read_catalogue(tmp_path).motors.loc["MM_578298", "encoder_counts"] == 2048
    motors.write_text(text.replace(",2048,", ",-2048,"))
    with pytest.raises(CatalogueError, match="encoder_counts"):
        read_catalogue(tmp_path)


def test_the_standard_stroke_is_the_longest_an_independent_ik_reaches(plane):
    route = standard_route(DESIGN, plane.centre_m, *OP)

    def reached(stroke):
        corners = StandardRoute(plane.centre_m, stroke).corners()
        edges = [
            a + s * (b - a) for a, b in itertools.pairwise(corners) for s in np.linspace(0, 1, 25)
        ]
        try:
            joint_path(DESIGN, edges, *OP)
        except ValueError:
            return False
        return True

    visits = route.visits()
    assert np.allclose(visits[0], visits[-1]) and np.allclose(
        np.diff(visits[:4, 1]), [0.025, 0, -0.025]
    )
    assert reached(route.stroke_m)
    if route.scaled:
        assert not reached(route.stroke_m * 1.03)
    else:
        assert route.stroke_m == STROKE_M


def test_a_play_held_closed_by_gravity_scatters_nothing(realized, settings, plane):
    model = arm_model(realized, settings)
    angles = joint_path(DESIGN, plane.points_m, *OP)
    opens = play_opens(model, angles, 5.0, (False, False))
    # the holding torques at rest: the sign test by hand
    zero = np.zeros_like(angles)
    state = loop_state(DESIGN, angles, zero, zero)
    tau = joint_loads(DESIGN, model.inertials, 5.0, state).tau
    np.testing.assert_array_equal(opens, (tau.max(axis=0) > 0) & (tau.min(axis=0) < 0))
    assert play_opens(model, angles, 5.0, (True, False))[0]
    payload = {"point_error_mm": [0.01]}
    iso = IsoSettings(30, 1, 4096.0, (2000.0, 1000.0))
    cat = settings.drives.catalogue
    terms, sources = random_terms(realized.drives, cat, payload, iso, (False, True))
    assert terms.backlash_rad[0] == 0.0 and terms.backlash_rad[1] > 0.0
    assert "gravity holds its" in sources["backlash"][0]
