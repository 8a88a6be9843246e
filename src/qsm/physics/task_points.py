"""Which task points the payload test (and so its animation) visits when the task has many.

Up to :data:`MAX_VISITED_POINTS` points are all visited in the order given. Beyond that the test
visits a bounded subset of at most that many: the first point (where the test starts), then the
points on the boundary of the task disk (the minimum enclosing circle, which is the task region),
then any other points, each group taken in farthest-point order (every next point the one
farthest from those already chosen), so the subset spans the region; the subset is then visited
as a nearest-neighbour tour from the first point.

The workflow's stages get the task through :func:`design_task`: its points as designed, and for a
task of more points only the subset the payload test visits, whose enclosing disk is the task's
(it holds the points on the disk's edge, or, when more than the subset's size lie on it, points
spread around it), so the rules' parameters stay a few pairs long.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from qsm.physics.mirror import mirror_points
from qsm.physics.task import min_enclosing_circle

#: Most task points the payload test visits (the five-point default task visits all five).
MAX_VISITED_POINTS = 8

#: The payload test's keys that shape the task's motion through its points (path and timing),
#: which the realisation's accuracy reads; its gains, limits and tolerance only the simulations
#: read (light here: the workflow's rule files read it when they are parsed).
MOTION_KEYS: tuple[str, ...] = ("segment_duration_s", "dwell_s", "return_to_start")

#: Relative distance from the disk's edge (of its radius) within which a point lies on it.
EDGE_TOLERANCE = 1e-9


def _farthest_first(
    pts: NDArray[np.float64], chosen: list[int], pool: NDArray[np.intp], n: int
) -> None:
    """Append indices of ``pool`` to ``chosen`` until it holds ``n``, each the point of the pool
    farthest from those already chosen."""
    pool = np.setdiff1d(pool, chosen)
    gap = np.min(np.hypot(*(pts[pool, None, :] - pts[None, chosen, :]).T), axis=0)
    while len(chosen) < n and len(pool):
        k = int(np.argmax(gap))
        chosen.append(int(pool[k]))
        pool, gap = np.delete(pool, k), np.delete(gap, k)
        gap = np.minimum(gap, np.hypot(*(pts[pool] - pts[chosen[-1]]).T))


def visited_points(points: ArrayLike, cap: int = MAX_VISITED_POINTS) -> NDArray[np.intp]:
    """Indices of the task ``points`` (n, 2) m the payload test visits, in visiting order.

    All of them in their order when ``n <= cap``; otherwise ``cap`` of them chosen and ordered as
    the module docstring says (``cap >= 2``).
    """
    pts = np.asarray(points, dtype=float).reshape(-1, 2)
    if len(pts) <= cap:
        return np.arange(len(pts))
    disk = min_enclosing_circle(pts)
    dist = np.hypot(*(pts - disk.centre).T)
    edge = np.flatnonzero(dist >= disk.radius * (1.0 - EDGE_TOLERANCE))
    chosen = [0]
    _farthest_first(pts, chosen, edge, cap)
    _farthest_first(pts, chosen, np.arange(len(pts)), cap)
    order = [chosen.pop(0)]
    while chosen:
        here = pts[order[-1]]
        k = int(np.argmin([np.hypot(*(pts[i] - here)) for i in chosen]))
        order.append(chosen.pop(k))
    return np.asarray(order, dtype=np.intp)


def design_task(points: ArrayLike, cap: int = MAX_VISITED_POINTS) -> tuple[bool, list[list[float]]]:
    """Whether the task of ``points`` (n, 2) m is designed mirrored (its disk's centre at x > 0,
    :mod:`qsm.physics.mirror`), and the points every stage designs for: all of them as designed
    when ``n <= cap`` (:func:`qsm.physics.mirror.design_points`), else the :func:`visited_points`
    of them as designed, in visiting order."""
    pts = np.asarray(points, dtype=float).reshape(-1, 2)
    mirrored = min_enclosing_circle(pts).centre[0] > 0.0
    if mirrored:
        pts = mirror_points(pts)
    if len(pts) > cap:
        pts = pts[visited_points(pts, cap)]
    return mirrored, pts.tolist()


class TaskCycle(NamedTuple):
    """A task as a cycle: the ``visits`` (point numbers of task.points, 1-based, in order, the
    first again at the end when it returns), their design ``points`` ((x, y) m each, mirrored as
    the task is) and the ``dwell_s`` at each."""

    visits: list[int]
    points: list[list[float]]
    dwell_s: float

    @property
    def returns(self) -> bool:
        """Whether the cycle ends where it began (its first visit again at the end)."""
        return len(self.visits) > 1 and self.visits[0] == self.visits[-1]


def task_cycle(
    points: ArrayLike,
    cycle: Mapping[str, Any] | None,
    dwell_s: float,
    return_to_start: bool,
) -> TaskCycle:
    """The cycle of ``task.cycle`` over the task ``points`` (n, 2) m, each key it leaves out
    (or all, None) the payload test's: its visited points in order, ``dwell_s`` and
    ``return_to_start``. ValueError for a point number outside 1..n."""
    pts = np.asarray(points, dtype=float).reshape(-1, 2)
    cycle = cycle or {}
    order: Sequence[int] = cycle.get("order") or (visited_points(pts) + 1).tolist()
    if bad := [k for k in order if not 1 <= k <= len(pts)]:
        raise ValueError(f"point numbers {bad} are not among the {len(pts)} task points")
    visits = list(order)
    if cycle.get("return_to_start", return_to_start) and visits[-1] != visits[0]:
        visits.append(visits[0])
    mirrored = min_enclosing_circle(pts).centre[0] > 0.0
    design = mirror_points(pts) if mirrored else pts
    return TaskCycle(visits, design[np.array(visits) - 1].tolist(), cycle.get("dwell_s", dwell_s))
