"""Tasks at x > 0 are designed as their mirror image (qsm.physics.mirror)."""

import copy

import mujoco
import numpy as np
import pytest

from qsm.app.evaluate import evaluate_ratios
from qsm.config.reading import load_config, validate_config
from qsm.config.settings import physics
from qsm.physics.dynamics import inverse_dynamics, loop_state
from qsm.physics.inverse_kinematics import joint_angles
from qsm.physics.mirror import design_points, is_mirrored, mirror_points, mirror_spec, task_record
from qsm.physics.mjcf import mjcf_xml, model_spec
from qsm.physics.task import min_enclosing_circle

#: A unit design (l2, l3, l4, ee_x, ee_y) that holds the default task (asserted below).
RATIOS = (0.4, 1.0, 0.45, 1.2, 0.45)


@pytest.fixture(scope="module")
def configs():
    """The default config and the same with its task mirrored to x > 0."""
    config = load_config()
    mirrored = copy.deepcopy(config)
    mirrored["task"]["points"] = mirror_points(config["task"]["points"]).tolist()
    return config, validate_config(mirrored)


def test_the_default_task_is_kept_and_its_mirror_designed_as_it(configs):
    config, mirrored = configs
    points = config["task"]["points"]
    assert not is_mirrored(points)
    assert design_points(points) == points
    assert all(x > 0 for x, _ in mirrored["task"]["points"])
    assert is_mirrored(mirrored["task"]["points"])
    assert design_points(mirrored["task"]["points"]) == points
    assert design_points(design_points(mirrored["task"]["points"])) == points
    record = task_record(mirrored["task"]["points"])
    assert record["mirrored"] and record["points_m"] == mirrored["task"]["points"]
    assert "mirror image" in record["note"]


@pytest.mark.parametrize(("xs", "mirrored"), [((-0.1, 0.5), True), ((-0.5, 0.1), False)])
def test_a_task_on_both_sides_is_designed_on_the_side_of_its_disk_centre(xs, mirrored):
    points = [[xs[0], 0.3], [xs[1], 0.3]]
    assert is_mirrored(points) == mirrored
    assert min_enclosing_circle(design_points(points)).centre[0] < 0


def test_the_mirrored_task_gets_the_same_design_and_torques(configs):
    config, mirrored = configs
    plain, mirror = (evaluate_ratios(RATIOS, c) for c in (config, mirrored))
    assert plain["feasible"]
    assert mirror["feasible"]
    assert mirror["mirrored"] and not plain["mirrored"]
    for key in ("scale", "eta", "tau1_Nm", "tau2_Nm"):
        assert mirror[key] == pytest.approx(plain[key], rel=1e-9)
    assert list(mirror["design_m"].values()) == pytest.approx(
        list(plain["design_m"].values()), rel=1e-9
    )


def test_the_mirrored_mjcf_visits_the_users_points_with_the_same_torques(configs):
    """The mirrored model's end effector (site payload, MuJoCo's forward kinematics of the XML)
    lands on the user's x > 0 points at the design's joint angles for the mirrored points; its
    inverse dynamics there (moving, so inertia counts) equals the design's: gravity is along -y,
    which the mirror keeps."""
    config, mirrored = configs
    design = list(evaluate_ratios(RATIOS, config)["design_m"].values())
    cad, payload = physics.cad(config["cad"], config["material"]), config["task"]["payload_kg"]
    user = np.asarray(mirrored["task"]["points"])
    theta = [joint_angles(design, p) for p in mirror_points(user)]
    rates = np.full((len(theta), 2), 0.7)
    state = loop_state(design, theta, rates, -2.0 * rates)
    assert state.closes.all()
    xml = mujoco.MjModel.from_xml_string(mjcf_xml(design, cad, payload, mirrored=True))
    data = mujoco.MjData(xml)
    for q, point in zip(state.q, user, strict=True):
        data.qpos[:] = q
        mujoco.mj_kinematics(xml, data)
        assert data.site("payload").xpos[:2] == pytest.approx(point, abs=1e-5)
        assert data.site("d_upper").xpos == pytest.approx(data.site("d_coupler").xpos, abs=1e-5)
    plain = inverse_dynamics(model_spec(design, cad, payload).compile(), design, state).tau
    mirror_model = mirror_spec(model_spec(design, cad, payload)).compile()
    assert inverse_dynamics(mirror_model, design, state).tau == pytest.approx(plain, rel=1e-9)
    assert np.abs(plain).min() > 1.0  # loaded: a sign or lever error would show
