"""Kinematics against the loop constraints and the seed's closed-form end effector."""

import numpy as np
import pytest

from qsm.physics.kinematics import (
    design_from_ratios,
    end_effector,
    loop_closes_everywhere,
    pose,
    transmission_angle_range,
)

pytestmark = pytest.mark.filterwarnings("ignore:invalid value encountered:RuntimeWarning")

DELTA_MAX = np.radians(217.5)


def random_ratios(rng, n):
    return np.column_stack(
        [
            rng.uniform(0.18, 0.6, n),
            rng.uniform(0.8, 1.3, n),
            rng.uniform(0.3, 0.6, n),
            rng.uniform(1.0, 1.4, n),
            rng.uniform(0.2, 0.7, n),
        ]
    )


def random_designs(rng, n):
    return design_from_ratios(random_ratios(rng, n), rng.uniform(0.2, 1.0, n))


def random_poses(rng, n):
    t1 = np.radians(rng.uniform(45.0, 180.0, n))
    t2 = rng.uniform(np.radians(-37.5), t1)
    return t1, t2


def seed_end_effector(design, t1, t2):
    """The paper's equations for a, zeta (unsigned arccos), xi, x and y, verbatim."""
    l1, l2, l3, l4, ex, ey = design.T
    a = np.sqrt(l1**2 + l2**2 - 2 * l1 * l2 * np.cos(t1 - t2))
    zeta = np.arccos((l1**2 + a**2 - l2**2) / (2 * l1 * a))
    xi = np.arccos((l4**2 + a**2 - l3**2) / (2 * l4 * a))
    x = l1 * np.cos(t1) + ey * np.cos(t1 + zeta + xi - np.pi / 2) + ex * np.cos(t1 + zeta + xi)
    y = l1 * np.sin(t1) + ey * np.sin(t1 + zeta + xi - np.pi / 2) + ex * np.sin(t1 + zeta + xi)
    return np.column_stack([x, y])


def test_loop_closes_at_random_poses():
    rng = np.random.default_rng(0)
    design = random_designs(rng, 20000)
    p = pose(design, *random_poses(rng, 20000))
    ok = p.closes
    assert 0.7 < ok.mean() < 0.95  # some random pairs cannot close (NOTES: about 16.5 %)
    cd = np.linalg.norm(p.D - p.C, axis=-1)
    bd = np.linalg.norm(p.D - p.B, axis=-1)
    np.testing.assert_allclose(cd[ok], design[ok, 2], rtol=0, atol=1e-12)
    np.testing.assert_allclose(bd[ok], design[ok, 3], rtol=0, atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(p.B, axis=-1), design[:, 0], atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(p.C, axis=-1), design[:, 1], atol=1e-12)
    # the upper arm is rigid: |BE| = hypot(EE_x, EE_y) and |DE| fixed
    np.testing.assert_allclose(
        np.linalg.norm(p.E - p.B, axis=-1)[ok], np.hypot(design[ok, 4], design[ok, 5]), atol=1e-12
    )
    assert np.isnan(p.E[~ok]).all()


def test_matches_seed_formula_where_it_is_valid():
    rng = np.random.default_rng(1)
    design = random_designs(rng, 20000)
    t1, t2 = random_poses(rng, 20000)
    ours = end_effector(design, t1, t2)
    seed = seed_end_effector(design, t1, t2)
    valid = np.isfinite(ours[:, 0]) & (t1 - t2 < np.pi)
    assert valid.sum() > 10000
    np.testing.assert_allclose(ours[valid], seed[valid], atol=1e-10)


def test_seed_formula_breaks_beyond_180_deg_and_ours_does_not():
    """The unsigned arccos picks the mirror solution when theta1 - theta2 > 180 deg."""
    rng = np.random.default_rng(2)
    design = random_designs(rng, 4000)
    t1 = np.radians(rng.uniform(150.0, 180.0, 4000))
    t2 = np.radians(rng.uniform(-37.5, -1.0, 4000))
    over = t1 - t2 > np.pi
    p = pose(design, t1, t2)
    ok = p.closes & over
    assert ok.sum() > 500
    # reconstruct D from the seed's angles and check |CD| = l3 fails there
    l1, l2, l3, l4 = design[:, :4].T
    a = np.sqrt(l1**2 + l2**2 - 2 * l1 * l2 * np.cos(t1 - t2))
    zeta = np.arccos((l1**2 + a**2 - l2**2) / (2 * l1 * a))
    xi = np.arccos((l4**2 + a**2 - l3**2) / (2 * l4 * a))
    phi = t1 + zeta + xi
    d_seed = p.B - l4[:, None] * np.column_stack([np.cos(phi), np.sin(phi)])
    seed_error = np.abs(np.linalg.norm(d_seed - p.C, axis=-1) - l3)[ok]
    ours_error = np.abs(np.linalg.norm(p.D - p.C, axis=-1) - l3)[ok]
    assert np.median(seed_error) > 1e-3 * np.median(l3)
    assert ours_error.max() < 1e-12


def test_batch_of_designs_with_several_poses_each():
    rng = np.random.default_rng(3)
    design = random_designs(rng, 5)
    t1 = np.radians(np.tile(np.linspace(60, 170, 7), (5, 1)))
    t2 = np.radians(np.tile(np.linspace(-30, 40, 7), (5, 1)))
    e = end_effector(design, t1, t2)
    assert e.shape == (5, 7, 2)
    for i in range(5):
        np.testing.assert_allclose(e[i], end_effector(design[i], t1[i], t2[i]), atol=1e-14)


def test_rejects_wrong_design_length():
    with pytest.raises(ValueError, match="6 lengths"):
        end_effector([1, 2, 3], 1.0, 0.5)


def test_loop_closes_everywhere_agrees_with_dense_sampling():
    rng = np.random.default_rng(4)
    ratios = random_ratios(rng, 3000)
    delta = np.linspace(0.0, DELTA_MAX, 4001)
    l2, l3, l4 = ratios[:, 0:1], ratios[:, 1:2], ratios[:, 2:3]
    a = np.sqrt(1 + l2**2 - 2 * l2 * np.cos(delta))
    brute = ((a >= np.abs(l3 - l4)) & (a <= l3 + l4)).all(axis=1)
    fast = loop_closes_everywhere(ratios, DELTA_MAX)
    assert 0.1 < fast.mean() < 0.9
    assert (brute == fast).mean() > 0.999  # may differ only within the sampling step of the brute
    mu_a, mu_b = transmission_angle_range(ratios[fast], DELTA_MAX)
    cos_mu = (l3**2 + l4**2 - a**2) / (2 * l3 * l4)
    mu = np.arccos(np.clip(cos_mu[fast], -1, 1))
    np.testing.assert_allclose(np.minimum(mu_a, mu_b), mu.min(axis=1), atol=1e-6)
    np.testing.assert_allclose(np.maximum(mu_a, mu_b), mu.max(axis=1), atol=1e-6)
