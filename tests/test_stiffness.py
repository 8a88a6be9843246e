"""The closed chain's stiffness (qsm.embodiment.stiffness) against independent references:
virtual work on the statically determinate chain, the Jacobian of the kinematics, reciprocity,
a plane-stress finite-element plate, and a point mass on the tool's compliance."""

import numpy as np
import pytest

from qsm.embodiment.stiffness.error_terms import (
    lost_motion_m,
    peak_sag_m,
    sag_m,
    tool_acceleration,
    tool_jacobian,
    torque_reverses,
)
from qsm.embodiment.stiffness.frame import (
    SHEAR_FACTOR,
    FrameSections,
    beam_stiffness,
    nodes,
    tool_compliance,
)
from qsm.embodiment.stiffness.modes import loaded_first_mode_hz
from qsm.physics.kinematics import end_effector, perp

DESIGN = np.array([0.55, 0.22, 0.5, 0.16, 0.42, 0.12])  # m
POSES = np.radians([[60.0, 150.0], [100.0, 190.0], [30.0, 80.0], [140.0, 230.0]])
E_PA, NU = 2.2e9, 0.35
SECTIONS = FrameSections(
    width_m=np.array([0.04, 0.03, 0.025, 0.045]),
    thickness_m=np.array([0.02, 0.018, 0.015, 0.022]),
    youngs_pa=E_PA,
    poisson=NU,
)
DRIVES = np.array([3.0e3, 1.5e3])  # N m/rad


def _cross(a, b):
    return a[0] * b[1] - a[1] * b[0]


def _member_work(p0, p1, loads, loads_v, link):
    """Virtual work integral over one straight member from p0 to p1, cut at points along it;
    ``loads``: (point, force) on the part beyond the cut (toward p1), real and virtual."""
    w, t = SECTIONS.width_m[link], SECTIONS.thickness_m[link]
    ea, ei = E_PA * w * t, E_PA * t * w**3 / 12
    gka = E_PA / (2 * (1 + NU)) * SHEAR_FACTOR * w * t
    length = np.linalg.norm(p1 - p0)
    tangent = (p1 - p0) / length
    normal = perp(tangent)
    s, weight = np.polynomial.legendre.leggauss(4)
    total = 0.0
    for si, wi in zip(s, weight, strict=True):
        at = p0 + (si + 1) / 2 * (p1 - p0)
        terms = []
        for set_ in (loads, loads_v):
            m = sum(_cross(q - at, f) for q, f in set_)
            n = sum(f @ tangent for _, f in set_)
            v = sum(f @ normal for _, f in set_)
            terms.append((m, n, v))
        (m, n, v), (mv, nv, vv) = terms
        total += wi * length / 2 * (m * mv / ei + n * nv / ea + v * vv / gka)
    return total


def _statics(at, force):
    """Forces of the determinate chain under ``force`` at E: the coupler's force on the upper
    arm at D (along C->D), the lower arm's load at B, the crank's at C."""
    e_cd = (at["D"] - at["C"]) / np.linalg.norm(at["D"] - at["C"])
    f = -_cross(at["E"] - at["B"], force) / _cross(at["D"] - at["B"], e_cd)
    return f * e_cd, force + f * e_cd, -f * e_cd


def _virtual_work_compliance(theta1, theta2, drives):
    """The tool's compliance by the unit-load method on the statically determinate chain."""
    at = {k: v for k, v in nodes(DESIGN, theta1, theta2).items()}
    units = [np.array([1.0, 0.0]), np.array([0.0, 1.0])]
    out = np.zeros((2, 2))
    for i, real in enumerate(units):
        for j, virt in enumerate(units):
            d_r, b_r, c_r = _statics(at, real)
            d_v, b_v, c_v = _statics(at, virt)
            work = _member_work(at["D"], at["B"], [(at["D"], d_r)], [(at["D"], d_v)], 3)
            work += _member_work(at["B"], at["E'"], [(at["E"], real)], [(at["E"], virt)], 3)
            work += _member_work(at["E'"], at["E"], [(at["E"], real)], [(at["E"], virt)], 3)
            work += _member_work(at["C"], at["D"], [(at["D"], -d_r)], [(at["D"], -d_v)], 2)
            work += _member_work(at["A"], at["B"], [(at["B"], b_r)], [(at["B"], b_v)], 0)
            work += _member_work(at["A"], at["C"], [(at["C"], c_r)], [(at["C"], c_v)], 1)
            if drives is not None:
                work += _cross(at["B"], b_r) * _cross(at["B"], b_v) / drives[0]
                work += _cross(at["C"], c_r) * _cross(at["C"], c_v) / drives[1]
            out[i, j] = work
    return out


@pytest.mark.parametrize("drives", [None, DRIVES], ids=["rigid drives", "drive springs"])
@pytest.mark.parametrize("pose", range(len(POSES)))
def test_compliance_is_the_virtual_work_of_the_determinate_chain(pose, drives):
    t1, t2 = POSES[pose]
    frame = tool_compliance(DESIGN, t1, t2, SECTIONS, drives)
    reference = _virtual_work_compliance(t1, t2, drives)
    np.testing.assert_allclose(frame, reference, rtol=1e-8, atol=1e-12 * np.abs(reference).max())


def test_compliance_is_symmetric_and_positive_definite():
    c = tool_compliance(DESIGN, POSES[:, 0], POSES[:, 1], SECTIONS, DRIVES)
    np.testing.assert_allclose(c, np.swapaxes(c, -1, -2), rtol=1e-10, atol=1e-15)
    assert (np.linalg.eigvalsh(c) > 0).all()


def test_stiff_links_leave_the_drives_compliance_through_the_jacobian():
    """With links 1e4 times stiffer, the tool moves as the drives' springs let the motors turn:
    C = J K_drive^-1 J^T, with J from the kinematics alone."""
    stiff = SECTIONS._replace(factor=np.full(4, 1e6))
    t1, t2 = POSES[:, 0], POSES[:, 1]
    c = tool_compliance(DESIGN, t1, t2, stiff, DRIVES)
    j = tool_jacobian(DESIGN, t1, t2)
    expected = np.einsum("...ik,k,...jk->...ij", j, 1 / DRIVES, j)
    np.testing.assert_allclose(c, expected, rtol=1e-4)


def test_a_batch_of_designs_and_poses_is_each_one_alone():
    designs = np.stack([DESIGN, DESIGN * 1.3])
    t1 = np.stack([POSES[:, 0], POSES[:, 0]])
    t2 = np.stack([POSES[:, 1], POSES[:, 1]])
    batch = tool_compliance(designs, t1, t2, SECTIONS, DRIVES)
    alone = tool_compliance(designs[1], POSES[2, 0], POSES[2, 1], SECTIONS, DRIVES)
    np.testing.assert_allclose(batch[1, 2], alone, rtol=1e-10)


def test_one_beam_is_the_cantilever_formula():
    """A single clamped beam's tip: L^3 / 3EI + L / (kappa G A) across, L / EA along."""
    length, w, t = 0.4, 0.04, 0.02
    ea, ei = E_PA * w * t, E_PA * t * w**3 / 12
    gka = E_PA / (2 * (1 + NU)) * SHEAR_FACTOR * w * t
    k = beam_stiffness(np.zeros(2), np.array([0.0, length]), ea, ei, 12 * ei / (gka * length**2))
    tip = np.linalg.inv(k[3:, 3:])
    assert tip[0, 0] == pytest.approx(length**3 / (3 * ei) + length / gka, rel=1e-12)
    assert tip[1, 1] == pytest.approx(length / ea, rel=1e-12)


def test_the_beam_agrees_with_plane_stress_finite_elements():
    """A second path: pyMOTO's plane-stress FE of the bar's outline, clamped at one end and
    loaded across at the other, against the Timoshenko beam (within 3 %)."""
    from qsm.realization.topology.fe import DEFAULT_TOPOLOGY, FeProblem, Grid, analyse

    length, w, t, h = 0.3, 0.04, 0.02, 0.0025
    grid = Grid((0.0, -w / 2), h, round(length / h), round(w / h))
    pos = grid.node_positions()
    left = np.flatnonzero(pos[:, 0] < 1e-9)
    right = np.flatnonzero(pos[:, 0] > length - 1e-9)
    force = 50.0
    f = np.zeros(2 * len(pos))
    f[2 * right + 1] = force / len(right)
    cells = np.ones((grid.ny, grid.nx), bool)
    problem = FeProblem(grid, np.concatenate([2 * left, 2 * left + 1]), f[:, None], cells, cells, t)
    settings = DEFAULT_TOPOLOGY.__class__(youngs_modulus_pa=E_PA, poisson_ratio=NU)
    fe_tip = analyse(problem, np.ones((grid.ny, grid.nx)), settings).compliance_J / force
    ea, ei = E_PA * w * t, E_PA * t * w**3 / 12
    gka = E_PA / (2 * (1 + NU)) * SHEAR_FACTOR * w * t
    k = beam_stiffness(np.zeros(2), np.array([length, 0.0]), ea, ei, 12 * ei / (gka * length**2))
    beam_tip = np.linalg.solve(k[3:, 3:], [0.0, force, 0.0])[1]
    assert fe_tip == pytest.approx(beam_tip, rel=0.03)


def test_a_point_mass_on_light_links_rings_at_its_spring_rate():
    """Links of negligible mass: the payload on the tool's compliance C rings at
    1 / (2 pi sqrt(m lambda_max(C)))."""
    t1, t2 = POSES[:, 0], POSES[:, 1]
    mass = 4.0
    f = loaded_first_mode_hz(DESIGN, t1, t2, SECTIONS, np.full(4, 1e-7), mass, DRIVES, [0, 0])
    c = tool_compliance(DESIGN, t1, t2, SECTIONS, DRIVES)
    expected = 1 / (2 * np.pi * np.sqrt(mass * np.linalg.eigvalsh(c)[..., -1]))
    np.testing.assert_allclose(f, expected, rtol=1e-3)


def test_the_links_and_rotors_mass_lower_the_first_mode():
    t1, t2 = POSES[0]
    bare = loaded_first_mode_hz(DESIGN, t1, t2, SECTIONS, np.full(4, 1e-7), 4.0, DRIVES, [0, 0])
    links = loaded_first_mode_hz(DESIGN, t1, t2, SECTIONS, np.full(4, 0.5), 4.0, DRIVES, [0, 0])
    rotors = loaded_first_mode_hz(DESIGN, t1, t2, SECTIONS, np.full(4, 0.5), 4.0, DRIVES, [1, 1])
    assert bare > links > rotors > 0


def test_lost_motion_counts_only_the_joints_whose_torque_reverses():
    tau = np.array([[1.0, -2.0], [3.0, 1.0], [2.0, 0.5]])  # joint 1 one-signed, joint 2 reverses
    reverses = torque_reverses(tau)
    assert reverses.tolist() == [False, True]
    j = np.array([[0.3, 0.0], [0.4, 0.2]])
    assert lost_motion_m(j, [0.01, 0.02], reverses) == pytest.approx(0.2 * 0.02)
    assert lost_motion_m(j, [0.01, 0.02], [True, True]) == pytest.approx(0.5 * 0.01 + 0.2 * 0.02)


def test_sag_terms():
    c = np.array([[2e-4, 1e-5], [1e-5, 1e-4]])
    assert sag_m(c, [0.0, -10.0]) == pytest.approx(np.hypot(1e-4, 1e-3))
    assert peak_sag_m(c, 10.0) == pytest.approx(10 * np.linalg.eigvalsh(c)[-1])


def test_tool_acceleration_is_the_second_derivative_along_the_motion():
    """Against a fine time grid of a motion with constant motor accelerations."""
    t = np.linspace(-0.01, 0.01, 2001)
    th0, v0, a0 = np.radians([70.0, 160.0]), np.array([1.2, -0.7]), np.array([3.0, 5.0])
    q = th0 + np.outer(t, v0) + np.outer(t * t / 2, a0)
    e = end_effector(DESIGN, q[:, 0], q[:, 1])
    dt = t[1] - t[0]
    numeric = (e[1001] - 2 * e[1000] + e[999]) / dt**2
    np.testing.assert_allclose(tool_acceleration(DESIGN, th0, v0, a0), numeric, rtol=1e-4)


@pytest.mark.parametrize("pose", range(len(POSES)))
def test_the_serial_arm_is_the_virtual_work_of_its_cantilever_chain(pose):
    """The serial 2R arm of the comparison: link 1 from A to B, the upper arm's L from B, a drive
    spring at A and one at B; its tool compliance against the unit-load method."""
    from qsm.embodiment.stiffness.serial_arm import serial_matrices

    t1, t2 = POSES[pose]
    k, _ = serial_matrices(DESIGN, t1, t2, SECTIONS, DRIVES, (1.0, 1.0, 1.0, 1.0, 0.0, 0.0))
    c = np.linalg.inv(k)[np.ix_([8, 9], [8, 9])]
    at = nodes(DESIGN, t1, t2)
    units = [np.array([1.0, 0.0]), np.array([0.0, 1.0])]
    ref = np.zeros((2, 2))
    for i, real in enumerate(units):
        for j, virt in enumerate(units):
            r, v = [(at["E"], real)], [(at["E"], virt)]
            work = _member_work(at["A"], at["B"], r, v, 0)
            work += _member_work(at["B"], at["E'"], r, v, 3)
            work += _member_work(at["E'"], at["E"], r, v, 3)
            work += _cross(at["E"], real) * _cross(at["E"], virt) / DRIVES[0]
            arm = at["E"] - at["B"]
            work += _cross(arm, real) * _cross(arm, virt) / DRIVES[1]
            ref[i, j] = work
    np.testing.assert_allclose(c, ref, rtol=1e-8)


def test_the_serial_arms_elbow_rotor_lowers_its_first_mode():
    """Motor 2's reflected inertia rides on link 2's turning at B, as the quasi-serial model
    puts each rotor on its joint's driven side."""
    from qsm.embodiment.stiffness.serial_arm import serial_comparison

    base = (0.5, 0.5, 1.0, 4.0, 0.2, 0.0)
    without = serial_comparison(DESIGN, POSES, SECTIONS, DRIVES, base)["first_mode_hz"]
    rotor = serial_comparison(DESIGN, POSES, SECTIONS, DRIVES, (*base[:5], 0.5))["first_mode_hz"]
    assert (rotor < without).all()
