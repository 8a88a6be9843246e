"""Analytic inverse kinematics: round trip with qsm.physics.kinematics.pose, the range and
unreachable points."""

from __future__ import annotations

import math

import numpy as np
import pytest

from qsm.physics import inverse_kinematics as ik
from qsm.physics import kinematics

DESIGNS = np.array([[0.40, 0.12, 0.40, 0.20, 0.48, 0.16], [0.5, 0.15, 0.5, 0.22, 0.6, 0.2]])


@pytest.mark.parametrize("design", DESIGNS)
def test_round_trip_at_random_poses(design: np.ndarray) -> None:
    rng = np.random.default_rng(4)
    checked = 0
    for _ in range(200):
        t1 = rng.uniform(math.radians(45), math.pi)
        t2 = rng.uniform(math.radians(-37.5), t1)
        p = kinematics.pose(design, t1, t2)
        if not p.closes:
            continue
        checked += 1
        t1s, t2s = ik.joint_angles(design, p.E, prefer=(t1, t2))
        assert (t1s, t2s) == pytest.approx((t1, t2), abs=1e-8)
        # whatever solution is returned by default reproduces the point on the pose branch
        d1, d2 = ik.joint_angles(design, p.E)
        q = kinematics.pose(design, d1, d2)
        np.testing.assert_allclose(q.E, p.E, atol=1e-9)
        assert ik.in_operating_range(np.array([d1, d2]))
    assert checked > 100


def test_unreachable_point_raises_naming_it() -> None:
    with pytest.raises(ValueError, match=r"\(3\.0000, 0\.5000\)"):
        ik.joint_angles(DESIGNS[0], [3.0, 0.5])
    # reachable by the linkage only with theta1 < 45 deg: outside the operating range
    p = kinematics.pose(DESIGNS[0], math.radians(20), math.radians(0)).E
    with pytest.raises(ValueError, match="range"):
        ik.joint_angles(DESIGNS[0], p)


def test_joint_path_follows_points() -> None:
    pts = kinematics.pose(DESIGNS[0], np.radians([100, 120, 140]), np.radians([40, 30, 20])).E
    path = ik.joint_path(DESIGNS[0], pts)
    np.testing.assert_allclose(np.degrees(path), [[100, 40], [120, 30], [140, 20]], atol=1e-7)
