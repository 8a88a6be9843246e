"""Joint loads and link strength: MuJoCo's torques, equilibrium of every link, hand-computed
cantilevers, lugs and columns, and the g13 check."""

from __future__ import annotations

import math

import numpy as np
import pytest

from qsm.embodiment.strength.beam import Section
from qsm.embodiment.strength.link_checks import STRENGTH_COLUMNS, StrengthCheck
from qsm.embodiment.strength.loads import (
    GRAVITY,
    Inertials,
    JointLoads,
    LinkMotion,
    joint_loads,
)
from qsm.embodiment.strength.material import Material, StrengthSettings
from qsm.embodiment.strength.stresses import link_strength
from qsm.physics import duty as duty_mod
from qsm.physics.batch_mass import batch_mass_properties
from qsm.physics.cad import CadSettings, mass_properties
from qsm.physics.dynamics import loop_state, tree_inverse_dynamics
from qsm.physics.kinematics import LINK_NAMES
from qsm.physics.mjcf import body_inertials

DESIGNS = np.array(
    [
        [0.5, 0.15, 0.5, 0.22, 0.6, 0.2],
        [0.35, 0.1, 0.38, 0.14, 0.42, 0.2],
        [0.8, 0.3, 0.8, 0.4, 1.0, 0.45],
    ]
)
PAYLOAD_KG = 5.0
SEC = Section(width_m=0.04, thickness_m=0.02, boss_radius_m=0.025)
BORES = np.full(4, 0.022)
MAT = Material()
REQ = StrengthSettings()


def _rot(angle: np.ndarray) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.stack([np.stack([c, -s], -1), np.stack([s, c], -1)], -2)


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


@pytest.fixture(scope="module")
def duty() -> duty_mod.Duty:
    return duty_mod.duty_cycle()


@pytest.mark.parametrize("design", DESIGNS)
def test_torques_and_coupler_force_equal_mujoco(design, duty):
    props = mass_properties(design)
    state = loop_state(design, duty.theta, duty.dtheta, duty.ddtheta)
    mujoco_result = tree_inverse_dynamics(design, body_inertials(design, props, PAYLOAD_KG), state)
    loads = joint_loads(design, Inertials.of(props), PAYLOAD_KG, state)
    scale = np.abs(mujoco_result.tau).max()
    assert np.abs(loads.tau - mujoco_result.tau).max() <= 1e-9 * scale
    force = np.abs(mujoco_result.coupler_force).max()
    assert np.abs(loads.d - mujoco_result.coupler_force).max() <= 1e-9 * force


@pytest.mark.parametrize("design", DESIGNS)
def test_every_link_is_in_equilibrium(design, duty):
    """Sum of forces and of moments about the link origin, weight and inertia included, with
    MuJoCo's motor torques: zero to 1e-9 of the peak load. Kinematics from the loop state."""
    props = mass_properties(design)
    state = loop_state(design, duty.theta, duty.dtheta, duty.ddtheta)
    tau = tree_inverse_dynamics(design, body_inertials(design, props, PAYLOAD_KG), state).tau
    f = joint_loads(design, Inertials.of(props), PAYLOAD_KG, state)
    l1, l2, _, l4, ex, ey = design
    q, qd, qdd = state.q, state.qd, state.qdd
    angles = {
        "lower_arm": (q[:, 0], qd[:, 0], qdd[:, 0]),
        "crank": (q[:, 2], qd[:, 2], qdd[:, 2]),
        "coupler": (q[:, 2] + q[:, 3], qd[:, 2] + qd[:, 3], qdd[:, 2] + qdd[:, 3]),
        "upper_arm": (q[:, 0] + q[:, 1], qd[:, 0] + qd[:, 1], qdd[:, 0] + qdd[:, 1]),
    }

    def point(link, local):
        """World position and acceleration of a link-frame point (link origins by hand)."""
        th1, w1, a1 = angles["lower_arm"]
        th2, w2, a2 = angles["crank"]
        if link in ("lower_arm", "crank"):
            o, ao = np.zeros((len(q), 2)), np.zeros((len(q), 2))
        elif link == "coupler":
            e2 = np.stack([np.cos(th2), np.sin(th2)], -1)
            o = l2 * e2
            ao = l2 * (a2[:, None] * np.stack([-e2[:, 1], e2[:, 0]], -1) - w2[:, None] ** 2 * e2)
        else:
            e1 = np.stack([np.cos(th1), np.sin(th1)], -1)
            o = l1 * e1
            ao = l1 * (a1[:, None] * np.stack([-e1[:, 1], e1[:, 0]], -1) - w1[:, None] ** 2 * e1)
        th, w, a = angles[link]
        r = np.einsum("nij,j->ni", _rot(th), local)
        acc = ao + a[:, None] * np.stack([-r[:, 1], r[:, 0]], -1) - w[:, None] ** 2 * r
        return o + r, acc

    joints = {
        "lower_arm": [(np.zeros(2), f.a_lower), (np.array([l1, 0.0]), -f.b)],
        "crank": [(np.zeros(2), f.a_crank), (np.array([l2, 0.0]), -f.c)],
        "coupler": [(np.zeros(2), f.c), (np.array([design[2], 0.0]), f.d)],
        "upper_arm": [
            (np.zeros(2), f.b),
            (np.array([-l4, 0.0]), -f.d),
            (np.array([ex, -ey]), f.e),
        ],
    }
    motor = {"lower_arm": tau[:, 0], "crank": tau[:, 1]}
    peak = max(np.abs(f.a_lower).max(), np.abs(f.d).max())
    for link in LINK_NAMES:
        p = props[link]
        com, acc = point(link, p.com_m[:2])
        origin, _ = point(link, np.zeros(2))
        force = sum(fj for _, fj in joints[link]) + p.mass_kg * (GRAVITY - acc)
        moment = motor.get(link, 0.0) - p.inertia_kg_m2[2, 2] * angles[link][2]
        moment = moment + _cross(com - origin, p.mass_kg * (GRAVITY - acc))
        for local, fj in joints[link]:
            moment = moment + _cross(point(link, local)[0] - origin, fj)
        assert np.abs(force).max() <= 1e-9 * peak, link
        assert np.abs(moment).max() <= 1e-9 * peak * design[0], link


def test_batch_mass_properties_equal_the_outline_ones():
    mass, com, izz = batch_mass_properties(DESIGNS)
    for k, design in enumerate(DESIGNS):
        props = mass_properties(design)
        for j, link in enumerate(LINK_NAMES):
            assert mass[k, j] == pytest.approx(props[link].mass_kg, rel=1e-12)
            assert com[k, j] == pytest.approx(props[link].com_m[:2], abs=1e-14)
            assert izz[k, j] == pytest.approx(props[link].inertia_kg_m2[2, 2], rel=1e-12)


def _static(n_links: int = 4, angle: float = 0.0) -> LinkMotion:
    """One sample, every link frame at rest at the origin, rotated by ``angle``."""
    z = np.zeros((1, n_links))
    return LinkMotion(
        np.cos(z + angle), np.sin(z + angle), z, z, np.zeros((1, 4, 2)), np.zeros((1, 4, 2))
    )


def _loads(**forces: tuple[float, float]) -> JointLoads:
    fields = {k: np.zeros((1, 2)) for k in JointLoads._fields}
    fields.update({k: np.array([v], dtype=float) for k, v in forces.items()})
    fields["tau"] = np.zeros((1, 2))
    return JointLoads(**fields)


#: Weightless links: the joint loads alone.
WEIGHTLESS = Inertials(np.zeros(4), np.zeros((4, 2)), np.zeros(4))
DESIGN = np.array([0.4, 0.2, 0.5, 0.2, 0.5, 0.2])


def test_cantilever_lower_arm_hand_computed():
    """Lower arm along x, clamped by the motor at A, a transverse force F at B (the upper arm on
    it): M(x) = F (l1 - x). Peak: the larger of the bar stress at the first boss edge,
    6 M / (t w^2), the net section at A, M R / I_net, and the lug K F / (t (2R - d))."""
    force = 400.0
    res = link_strength(DESIGN, SEC, MAT, REQ, WEIGHTLESS, _loads(b=(0.0, force)), _static(), BORES)
    w, t, r, d = 0.04, 0.02, 0.025, 0.022
    x0 = math.sqrt(r**2 - (w / 2) ** 2)
    bar = 6 * force * (0.4 - x0) / (t * w**2)
    net = force * 0.4 * r / (t * ((2 * r) ** 3 - d**3) / 12)
    lug = 3.0 * force / (t * (2 * r - d))
    assert res["lower_arm"].stress_pa == pytest.approx(max(bar, net, lug), rel=1e-12)
    assert res["lower_arm"].compression_N == pytest.approx(0.0, abs=1e-9)


def test_pin_loaded_lug_and_euler_column_of_the_coupler_hand_computed():
    """Coupler along x pulled (then pushed) at D by F: uniform N = F, no moment. Tension: lug
    K F / (t (2R - d)) governs; compression F against the pinned-pinned Euler load
    pi^2 E (w t^3 / 12) / l3^2 (t < w: out of the plane is weaker)."""
    force = 2000.0
    pulled = link_strength(
        DESIGN, SEC, MAT, REQ, WEIGHTLESS, _loads(d=(force, 0.0)), _static(), BORES
    )
    assert pulled["coupler"].stress_pa == pytest.approx(3.0 * force / (0.02 * 0.028), rel=1e-12)
    assert pulled["coupler"].labels[pulled["coupler"].where].startswith("pin-loaded bore")
    assert pulled["coupler"].compression_N == pytest.approx(0.0, abs=1e-9)
    pushed = link_strength(
        DESIGN, SEC, MAT, REQ, WEIGHTLESS, _loads(d=(-force, 0.0)), _static(), BORES
    )
    assert pushed["coupler"].compression_N == pytest.approx(force, rel=1e-12)
    euler = math.pi**2 * 2.2e9 * (0.04 * 0.02**3 / 12) / 0.5**2
    assert pushed["coupler"].euler_N == pytest.approx(euler, rel=1e-12)


def test_own_weight_of_a_horizontal_bar_hand_computed():
    """Crank along x with only its weight, spread along its length: at the first boss edge
    M = mu g (l2 - x0)^2 / 2 with mu = m / l2."""
    mass = 0.3
    inertials = Inertials(np.array([0.0, mass, 0.0, 0.0]), np.zeros((4, 2)), np.zeros(4))
    res = link_strength(DESIGN, SEC, MAT, REQ, inertials, _loads(), _static(), BORES)
    x0 = math.sqrt(0.025**2 - 0.02**2)
    moment = mass / 0.2 * 9.81 * (0.2 - x0) ** 2 / 2
    assert res["crank"].stress_pa == pytest.approx(6 * moment / (0.02 * 0.04**2), rel=1e-12)
    # the same bar pointing up: no bending; its weight compresses the net section at A
    up = link_strength(
        DESIGN, SEC, MAT, REQ, inertials, _loads(), _static(angle=math.pi / 2), BORES
    )
    assert up["crank"].stress_pa == pytest.approx(mass * 9.81 / (0.02 * 0.028), rel=1e-12)
    assert up["crank"].compression_N == pytest.approx(mass * 9.81 * (0.2 - x0) / 0.2, rel=1e-12)


def test_g13_is_the_largest_utilization_over_the_links(duty):
    check = StrengthCheck(payload_kg=PAYLOAD_KG, duty=duty)
    table = check.evaluate(DESIGNS)
    assert list(table.columns) == list(STRENGTH_COLUMNS)
    allow = MAT.yield_strength_pa / REQ.safety_factor / 1e6
    expected = np.max(
        [
            np.maximum(
                table[f"stress_peak_{k}_MPa"] / allow,
                REQ.buckling_safety_factor / table[f"buckling_factor_{k}"],
            )
            for k in LINK_NAMES
        ]
        + [table["bearing_utilisation"]],
        axis=0,
    )
    g13 = check.violation(DESIGNS)
    assert g13 == pytest.approx(expected - 1.0, rel=1e-12)
    assert np.array_equal(g13 <= 0, table["holds_loads"].to_numpy())


def test_heavier_payload_and_thinner_section_fail(duty):
    light = StrengthCheck(payload_kg=1.0, duty=duty).violation(DESIGNS)
    heavy = StrengthCheck(payload_kg=200.0, duty=duty).violation(DESIGNS)
    thin = StrengthCheck(cad=CadSettings(thickness_m=0.008), payload_kg=1.0, duty=duty).violation(
        DESIGNS
    )
    assert np.all(light < 0)
    assert np.all(heavy > 0) and np.all(thin > light)


def test_spinning_bar_hand_computed():
    """Crank about A with angular acceleration alpha, its origin falling freely (g - a_0 = 0):
    body force -mu alpha x across the bar, so M(x) = mu alpha (l^3 / 3 - x l^2 / 2 + x^3 / 6)
    at the cut x (quadratic in the integrand: Simpson's rule is needed to be exact)."""
    mass, alpha, length = 0.3, 50.0, 0.2
    inertials = Inertials(np.array([0.0, mass, 0.0, 0.0]), np.zeros((4, 2)), np.zeros(4))
    free_fall = np.broadcast_to(GRAVITY, (1, 4, 2)).copy()
    z = np.zeros((1, 4))
    motion = LinkMotion(np.ones((1, 4)), z, z, z + alpha, np.zeros((1, 4, 2)), free_fall)
    res = link_strength(DESIGN, SEC, MAT, REQ, inertials, _loads(), motion, BORES)
    mu = mass / length

    def moment(x):
        return mu * alpha * (length**3 / 3 - x * length**2 / 2 + x**3 / 6)

    net = moment(0.0) * 0.025 / (0.02 * (0.05**3 - 0.022**3) / 12)
    x0 = math.sqrt(0.025**2 - 0.02**2)
    bar = 6 * moment(x0) / (0.02 * 0.04**2)
    assert res["crank"].stress_pa == pytest.approx(max(net, bar), rel=1e-12)


def test_peak_joint_forces_and_their_poses(duty):
    """The table's peak force at each joint and the motor angles where it occurs, against the
    joint loads over the duty computed here."""
    table = StrengthCheck(payload_kg=PAYLOAD_KG, duty=duty).evaluate(DESIGNS)
    for k, design in enumerate(DESIGNS):
        props = mass_properties(design)
        state = loop_state(design, duty.theta, duty.dtheta, duty.ddtheta)
        loads = joint_loads(design, Inertials.of(props), PAYLOAD_KG, state)
        for column, force in (("B", loads.b), ("D", loads.d), ("A_crank", loads.a_crank)):
            magnitude = np.hypot(force[:, 0], force[:, 1])
            peak = int(np.argmax(magnitude))
            row = table.iloc[k]
            assert row[f"joint_force_peak_{column}_N"] == pytest.approx(magnitude[peak], rel=1e-9)
            pose = [row[f"joint_force_peak_{column}_theta{i}_deg"] for i in (1, 2)]
            assert pose == pytest.approx(np.degrees(duty.theta[peak]), abs=1e-9)


def test_a_joint_without_a_bearing_is_not_ready_to_build():
    """The headline's verdict names a joint whose load no bearing carries, even when every
    link holds."""
    from qsm.report.readiness import build_verdict

    link = {"holds": True}
    strength = {
        "links": dict.fromkeys(LINK_NAMES, link),
        "bearings": {"A": {"designation": "", "peak_force_N": 9000.0}},
        "required_bearing_safety": 2.0,
        "holds_loads": False,
        "utilisation": 1.3,
    }
    selected = {"printable": True, "strength": strength}
    ready, problems = build_verdict(selected, {"links": {}}, {"passed": True})
    assert not ready
    assert problems == [
        "no bearing of the catalogue fits joint A (9000 N peak, static safety 2 required, "
        "within the boss)"
    ]


def test_parts_drawn_at_another_section_than_the_checked_one_are_not_ready():
    """Each link's part must be drawn at the section (width x thickness) its strength was checked
    with, link by link (sized sections differ per link): ready when every link matches, not ready
    with both numbers when one does not."""
    from qsm.report.readiness import build_verdict

    checked = {
        "lower_arm": [40.0, 20.0],
        "crank": [30.0, 15.0],
        "coupler": [52.0, 26.0],
        "upper_arm": [44.0, 22.0],
    }
    links = {k: {"holds": True, "width_mm": w, "thickness_mm": t} for k, (w, t) in checked.items()}
    selected = {
        "printable": True,
        "strength": {"links": links, "bearings": {}, "holds_loads": True},
    }

    def topology(coupler: list[float]) -> dict:
        return {"links": {}, "parts": {"section_mm": {**checked, "coupler": coupler}}}

    assert build_verdict(selected, topology([52.0, 26.0]), {"passed": True}) == (True, [])
    ready, problems = build_verdict(selected, topology([40.0, 20.0]), {"passed": True})
    assert not ready and len(problems) == 1
    assert "coupler" in problems[0]
    assert "52.0 x 26.0 mm" in problems[0] and "40.0 x 20.0 mm" in problems[0]


def test_a_link_that_fails_by_another_check_than_its_stress_is_named_with_that_check():
    """A link can fail by its bearing seat while its peak stress is within the allowable: the
    strength record marks it as not holding, and the verdict names the check and its use."""
    from qsm.report.readiness import build_verdict

    ok = {"holds": True, "stress_peak_MPa": 9.0, "allowable_MPa": 15.5}
    strength = {
        "links": {**dict.fromkeys(LINK_NAMES, ok), "lower_arm": {**ok, "holds": False}},
        "bearings": {},
        "holds_loads": False,
        "utilisation": 1.12,
        "weakest_link": "lower_arm",
        "weakest_check": "bearing seat",
    }
    ready, problems = build_verdict(
        {"printable": True, "strength": strength}, {"links": {}}, {"passed": True}
    )
    assert not ready and len(problems) == 1
    assert "lower arm does not hold its loads: its bearing seat is at 1.12" in problems[0]
    bearing = strength | {"links": dict.fromkeys(LINK_NAMES, ok), "weakest_link": "bearing B"}
    bearing["weakest_check"] = "static load rating"
    _, problems = build_verdict(
        {"printable": True, "strength": bearing}, {"links": {}}, {"passed": True}
    )
    assert problems == [
        "the strength check fails: the bearing B's static load rating is at 1.12 of what it may "
        "take (at most 1)"
    ]
