"""The bounded subset of task points the payload test visits (qsm.physics.task_points)."""

import time

import numpy as np
import pytest

from qsm.physics.task import min_enclosing_circle
from qsm.physics.task_points import MAX_VISITED_POINTS, task_cycle, visited_points

DEFAULT = [[-0.53, 0.17], [-0.70, 0.02], [-0.60, 0.02], [-0.70, 0.12], [-0.60, 0.12]]


def test_few_points_are_all_visited_in_their_order():
    assert visited_points(DEFAULT).tolist() == [0, 1, 2, 3, 4]
    assert visited_points(DEFAULT[:2]).tolist() == [0, 1]


def _cloud(n, seed=0):
    return np.random.default_rng(seed).normal(size=(n, 2)) * 0.1 + [-0.6, 0.1]


@pytest.mark.parametrize(
    "points",
    [
        _cloud(10_000),
        _cloud(9, seed=3),
        np.c_[np.cos(np.linspace(0, 6, 500)), np.sin(np.linspace(0, 6, 500))] * 0.1 - [0.6, 0],
        np.c_[np.linspace(-0.9, -0.3, 300), np.full(300, 0.1)],
    ],
    ids=["cloud", "nine", "circle", "line"],
)
def test_many_points_a_bounded_subset_that_spans_the_task_disk(points):
    order = visited_points(points)
    assert len(order) == MAX_VISITED_POINTS
    assert len(set(order.tolist())) == len(order)
    assert order[0] == 0  # the test starts where the user's task starts
    whole, subset = min_enclosing_circle(points), min_enclosing_circle(points[order])
    assert subset.radius == pytest.approx(whole.radius, rel=1e-9)
    assert np.allclose(subset.centre, whole.centre, atol=1e-9)


def test_the_subset_is_a_nearest_neighbour_tour():
    points = _cloud(50, seed=1)
    order = visited_points(points)
    for k in range(1, len(order) - 1):
        here, rest = points[order[k - 1]], points[order[k:]]
        assert np.argmin(np.hypot(*(rest - here).T)) == 0


def test_ten_thousand_points_take_milliseconds():
    points = _cloud(10_000, seed=2)
    start = time.perf_counter()
    visited_points(points)
    assert time.perf_counter() - start < 0.5


def test_the_points_on_the_disk_edge_come_before_interior_ones():
    """Farthest-point order alone would take the interior point (0.5, 0.85) before (-1, 0)."""
    points = np.array([[-0.9, 0.0], [0.5, 0.85], [1.0, 0.0], [-1.0, 0.0], [0.0, 0.1]])
    assert sorted(visited_points(points, cap=3).tolist()) == [0, 2, 3]


def test_the_default_cycle_is_the_payload_tests_visits_and_returns():
    points = [[-0.53, 0.17], [-0.7, 0.02], [-0.6, 0.02]]
    cycle = task_cycle(points, None, 0.5, True)
    assert cycle.visits == [1, 2, 3, 1]
    assert cycle.points == [points[0], points[1], points[2], points[0]]
    assert cycle.dwell_s == 0.5


def test_a_given_cycle_keeps_its_order_dwell_and_mirrors_with_the_task():
    points = [[0.53, 0.17], [0.7, 0.02], [0.6, 0.02]]  # at x > 0: designed mirrored
    cycle = task_cycle(
        points, {"order": [3, 1], "dwell_s": 1.0, "return_to_start": False}, 0.5, True
    )
    assert cycle.visits == [3, 1]
    assert cycle.points == [[-0.6, 0.02], [-0.53, 0.17]]
    assert cycle.dwell_s == 1.0


def test_a_cycle_of_an_unknown_point_is_refused():
    with pytest.raises(ValueError, match=r"\[4\] are not among the 3"):
        task_cycle([[0, 0], [1, 0], [0, 1]], {"order": [1, 4]}, 0.5, True)
