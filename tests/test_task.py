"""Minimum enclosing circle against a brute-force search over point pairs and triples."""

import itertools

import numpy as np
import pytest

from qsm.config.reading import load_config
from qsm.physics.task import _circumcircle, min_enclosing_circle


def brute_force_radius(points):
    """Smallest circle through 2 or 3 of the points that contains them all."""
    best = np.inf
    for a, b in itertools.combinations(points, 2):
        c, r = (a + b) / 2, np.hypot(*(a - b)) / 2
        if np.all(np.hypot(*(points - c).T) <= r + 1e-9):
            best = min(best, r)
    for a, b, c in itertools.combinations(points, 3):
        d = _circumcircle(a, b, c)
        if np.all(np.hypot(*(points - d.centre).T) <= d.radius + 1e-9):
            best = min(best, d.radius)
    return best


@pytest.mark.parametrize("seed", range(12))
def test_matches_brute_force(seed):
    rng = np.random.default_rng(seed)
    points = rng.normal(size=(rng.integers(2, 14), 2))
    disk = min_enclosing_circle(points)
    assert disk.contains(points).all()
    assert disk.radius == pytest.approx(brute_force_radius(points), rel=1e-9)


def test_circumcircle_by_hand():
    # right triangle: the circumcentre is the middle of the hypotenuse
    d = _circumcircle(np.array([0.0, 0.0]), np.array([4.0, 0.0]), np.array([0.0, 3.0]))
    assert d.centre == pytest.approx((2.0, 1.5))
    assert d.radius == pytest.approx(2.5)


def test_single_collinear_and_duplicate_points():
    assert min_enclosing_circle([[1.0, 2.0]]).radius == 0.0
    line = min_enclosing_circle([[0, 0], [1, 0], [3, 0], [2, 0]])
    assert line.centre == pytest.approx((1.5, 0.0)) and line.radius == pytest.approx(1.5)
    dup = min_enclosing_circle([[0, 0], [0, 0], [2, 0]])
    assert dup.radius == pytest.approx(1.0)


def test_independent_of_point_order():
    pts = np.random.default_rng(5).uniform(-1, 1, (30, 2))
    a = min_enclosing_circle(pts)
    b = min_enclosing_circle(pts[::-1])
    assert a.radius == pytest.approx(b.radius, rel=1e-12)


def test_default_task_disk():
    """The default palletising points: the farthest pair (-0.53, 0.17), (-0.70, 0.02) is a
    diameter (the other points lie within 0.089 m of its middle), so by hand the centre is
    (-0.615, 0.095) and the radius sqrt(0.17^2 + 0.15^2) / 2 = 0.113358 m."""
    pts = load_config()["task"]["points"]
    disk = min_enclosing_circle(pts)
    assert disk.centre == pytest.approx((-0.615, 0.095), abs=1e-12)
    assert disk.radius == pytest.approx(np.sqrt(0.17**2 + 0.15**2) / 2, rel=1e-12)


@pytest.mark.parametrize("bad", [[], [[1.0, 2.0, 3.0]], [1.0, 2.0]])
def test_rejects_malformed_points(bad):
    with pytest.raises(ValueError, match="task points"):
        min_enclosing_circle(bad)
