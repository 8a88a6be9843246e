"""The batch inverse kinematics (qsm.physics.batch_ik) against the per-point one it vectorises."""

import numpy as np
import pytest

from qsm.physics.batch_ik import batch_joint_angles
from qsm.physics.inverse_kinematics import joint_angles
from qsm.physics.kinematics import end_effector


def _designs(n, seed):
    rng = np.random.default_rng(seed)
    lo = np.array([0.3, 0.05, 0.3, 0.1, 0.3, 0.0])
    hi = np.array([0.7, 0.3, 0.7, 0.3, 0.7, 0.2])
    return lo + (hi - lo) * rng.random((n, 6))


@pytest.mark.parametrize("seed", [3, 4])
def test_every_point_gets_joint_angles_choice_or_nan_where_it_has_none(seed):
    designs = _designs(120, seed)
    points = np.array([[-0.53, 0.17], [-0.7, 0.02], [-0.6, 0.12], [0.3, 0.5], [0.0, 0.2]])
    got = batch_joint_angles(designs, points, (45.0, 180.0), -37.5)
    reached = 0
    for i, d in enumerate(designs):
        for j, p in enumerate(points):
            try:
                want = joint_angles(d, p, (45.0, 180.0), -37.5)
            except ValueError:
                assert np.isnan(got[i, j]).all(), (i, j)
                continue
            reached += 1
            np.testing.assert_allclose(got[i, j], want, atol=1e-9)
            np.testing.assert_allclose(end_effector(d, *got[i, j]), p, atol=1e-9)
    assert reached > 100  # the comparison covers reachable points, not only NaN


def test_a_narrower_operating_range_leaves_points_out_of_reach():
    designs = _designs(50, 5)
    points = np.array([[-0.6, 0.1], [-0.5, 0.2]])
    wide = batch_joint_angles(designs, points, (45.0, 180.0), -37.5)
    narrow = batch_joint_angles(designs, points, (90.0, 100.0), -37.5)
    assert np.isfinite(narrow).sum() < np.isfinite(wide).sum()
    ok = np.isfinite(narrow[..., 0])
    assert (np.degrees(narrow[ok][:, 0]) <= 100.0 + 1e-7).all()


def test_no_designs_give_an_empty_answer():
    assert batch_joint_angles(np.empty((0, 6)), [[-0.6, 0.1]]).shape == (0, 1, 2)
