"""The kit's moving parts in the dynamics (qsm.realization.kit.moving_parts): each link's frame
against MuJoCo's own kinematics, a tube's mass properties by hand, each part where the layout
puts it, the tool flange counted once, and the torques a hub's weight adds by statics."""

import math

import mujoco
import numpy as np
import pytest

from qsm.embodiment.kit.joints import STEEL_KG_M3
from qsm.physics.cad import MassProperties, mass_properties
from qsm.physics.dynamics import inverse_dynamics, loop_state
from qsm.physics.mjcf import GRAVITY_M_S2, JOINT_NAMES, model_spec
from qsm.realization.kit.moving_parts import as_built, link_frames, moving_parts, solid_props
from qsm.realization.selection.outputs import props_to_json

# the paper's optimised design (m): l1, l2, l3, l4, ee_x, ee_y
DESIGN = np.array([0.43, 0.17, 0.43, 0.17, 0.53, 0.10])
THETA = (math.radians(112.5), math.radians(37.5))


def _qpos(design: np.ndarray, theta: tuple[float, float]) -> np.ndarray:
    state = loop_state(design, np.array([theta]), np.zeros((1, 2)), np.zeros((1, 2)))
    return state.q[0]


def test_link_frames_are_mujocos_body_frames():
    """Origin and x axis of every link as MuJoCo places its body at the same motor angles."""
    model = model_spec(DESIGN).compile()
    data = mujoco.MjData(model)
    data.qpos[:] = _qpos(DESIGN, THETA)
    mujoco.mj_kinematics(model, data)
    for link, (origin, x) in link_frames(DESIGN, *THETA).items():
        body = data.body(link)
        np.testing.assert_allclose(origin, body.xpos[:2], atol=1e-9)
        np.testing.assert_allclose(x, body.xmat.reshape(3, 3)[:2, 0], atol=1e-9)


def test_a_tubes_mass_properties_by_hand():
    """A steel tube 20 mm across, bored 8 mm, 30 mm long: m = rho pi/4 (D^2 - d^2) L and
    I_z = m (D^2 + d^2) / 8 about its axis."""
    part = {"steps": [(20.0, 5.0, 35.0)], "bore_mm": 8.0}
    props = solid_props(part, (0.1, -0.2))
    mass = STEEL_KG_M3 * math.pi / 4 * (0.020**2 - 0.008**2) * 0.030
    assert props.mass_kg == pytest.approx(mass, rel=1e-12)
    assert props.inertia_kg_m2[2, 2] == pytest.approx(mass * (0.020**2 + 0.008**2) / 8, rel=1e-12)
    np.testing.assert_allclose(props.com_m, [0.1, -0.2, 0.0])


def test_a_counterbored_hole_counts_once():
    """A disc 60 mm across, 20 mm thick, with a 6 mm hole through it 20 mm off its axis,
    counterbored 10 mm for its last 6 mm: the steel taken out is pi/4 (6^2 x 14 + 10^2 x 6) mm^3,
    its inertia about the axis each cylinder's own plus its mass times 20 mm squared."""
    part = {"steps": [(60.0, 0.0, 20.0)], "bore_mm": 0.0,
            "holes": [(20.0, 0.0, 6.0, 0.0, 20.0), (20.0, 0.0, 10.0, 14.0, 20.0)]}  # fmt: skip
    disc = solid_props({"steps": part["steps"], "bore_mm": 0.0}, (0.0, 0.0))
    holed = solid_props(part, (0.0, 0.0))
    hole, counterbore = (
        STEEL_KG_M3 * math.pi / 4 * d**2 * h for d, h in ((6e-3, 14e-3), (1e-2, 6e-3))
    )
    assert disc.mass_kg - holed.mass_kg == pytest.approx(hole + counterbore, rel=1e-12)
    izz = hole * (6e-3**2 / 8 + 0.02**2) + counterbore * (1e-2**2 / 8 + 0.02**2)
    assert disc.inertia_kg_m2[2, 2] - holed.inertia_kg_m2[2, 2] == pytest.approx(izz, rel=1e-12)


def _layout() -> tuple[dict, dict]:
    """A small kit layout at the pose THETA: a hub at A on the crank, a bearing at B on the
    lower arm, a washer on the base, and the tool flange with its screw at E."""
    from qsm.physics.kinematics import pose

    p = pose(DESIGN, *THETA)
    b, e = (1e3 * np.asarray(getattr(p, j)).reshape(2) for j in "BE")
    hardware = {
        "bearing B": {"steps": [(22.0, 0.0, 7.0)], "bore_mm": 8.0, "at_mm": b.tolist()},
        "washer on base": {"steps": [(16.0, 0.0, 1.6)], "bore_mm": 8.4, "at_mm": [50.0, 0.0]},
        "flange screw": {"steps": [(13.0, 0.0, 58.0)], "bore_mm": 0.0, "at_mm": e.tolist()},
    }
    turned = {
        "hub_2": {"steps": [(60.0, 0.0, 20.0)], "bore_mm": 17.0, "at_mm": [0.0, 0.0]},
        "tool_flange": {"steps": [(40.0, 0.0, 16.0)], "bore_mm": 0.0, "at_mm": e.tolist()},
    }
    moves = {"bearing B": "lower_arm", "washer on base": "base", "flange screw": "upper_arm",
             "hub_2": "crank", "tool_flange": "upper_arm"}  # fmt: skip
    layout = {"pose_deg": [112.5, 37.5], "hardware": hardware, "turned": turned,
              "moves_with": moves}  # fmt: skip
    return layout, {"flange screw": "tool_flange"}


def test_each_part_is_where_the_layout_puts_it_and_the_flange_is_left_out():
    """A part placed in its link's frame returns, through MuJoCo's kinematics at the layout's
    pose, to the layout's point; the base's part and the tool flange (carried at E beside the
    payload already) add nothing."""
    layout, steps = _layout()
    parts = moving_parts(layout, DESIGN, steps)
    bearing = solid_props(layout["hardware"]["bearing B"], (0.0, 0.0))
    hub = solid_props(layout["turned"]["hub_2"], (0.0, 0.0))
    assert parts["lower_arm"].mass_kg == pytest.approx(bearing.mass_kg, rel=1e-12)
    assert parts["crank"].mass_kg == pytest.approx(hub.mass_kg, rel=1e-12)
    assert parts["upper_arm"].mass_kg == 0.0 and parts["coupler"].mass_kg == 0.0
    model = model_spec(DESIGN).compile()
    data = mujoco.MjData(model)
    data.qpos[:] = _qpos(DESIGN, THETA)
    mujoco.mj_kinematics(model, data)
    body = data.body("lower_arm")
    world = body.xpos + body.xmat.reshape(3, 3) @ parts["lower_arm"].com_m
    np.testing.assert_allclose(1e3 * world[:2], layout["hardware"]["bearing B"]["at_mm"], atol=1e-6)


def test_a_parts_weight_adds_its_static_torque():
    """Held still, the bearing at B adds m g x_B to motor 1's torque (statics: B is on the lower
    arm, which motor 1 turns alone), and the hub on the crank's axis adds nothing to motor 2's."""
    layout, steps = _layout()
    links = mass_properties(DESIGN)
    kit = {"moving_parts": props_to_json(moving_parts(layout, DESIGN, steps))}
    built = as_built(props_to_json(links), kit)
    state = loop_state(DESIGN, np.array([THETA]), np.zeros((1, 2)), np.zeros((1, 2)))

    def torques(props: dict[str, MassProperties]) -> np.ndarray:
        model = model_spec(DESIGN, props=props).compile()
        return inverse_dynamics(model, DESIGN, state).tau[0]

    added = torques(built) - torques(links)
    mass = solid_props(layout["hardware"]["bearing B"], (0.0, 0.0)).mass_kg
    x_b = layout["hardware"]["bearing B"]["at_mm"][0] * 1e-3
    assert JOINT_NAMES[0] == "theta1"
    assert added[0] == pytest.approx(mass * GRAVITY_M_S2 * x_b, rel=1e-3)
    assert added[1] == pytest.approx(0.0, abs=1e-9)
