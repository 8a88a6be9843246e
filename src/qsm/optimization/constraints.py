"""Constraints g11 (the task lies in the workspace) and g12 (every link fits the printer).

Both are vectorised over a population of scaled designs (N, 6) and return a continuous violation,
positive where the constraint is violated, so that NSGA-II can climb towards feasibility.

**g11, task containment** (metres). It uses Stage 1's slicing of the workspace into circles about
the base (:mod:`qsm.physics.workspace`), but evaluates it directly on the circles the task disk
needs at the design's own scale ``l1``: a disk of centre distance ``d`` and radius ``r`` lies in the
workspace iff on every circle of radius ``R`` in ``[d - r, d + r]`` the disk's arc, of half-width
``w(R)``, lies in the workspace's arc union ``U(R / l1)`` around the task's polar angle. The margin
on that circle is ``(h(R) - w(R)) R`` metres of arc, where ``h`` is the half-width of the part of
``U`` centred on the task angle; where the task angle is not covered it is ``-(w(R) + g(R)) R`` with
``g`` the angular gap to the nearest covered arc. Each circle's margin is also capped by its signed
radial distance (m) to the workspace's radial range (negative outside it, where the arcs are
measured on the range's edge), so the margin changes continuously with the design and has the sign
of Stage 1's test. g11 = ``- min over R of the margin`` of the task disk grown by the tolerance:
<= 0 exactly when the task keeps at least ``tolerance`` metres of Euclidean clearance from the
workspace's edge. The margin itself is an arc length, an upper bound on that clearance
(:mod:`qsm.physics.clearance` computes the clearance).

**g12, printability** (millimetres). A link fits when its bounding box in the link frame
(:func:`qsm.embodiment.parts.printing.link_boxes_mm`, the closed form of the outlines),
sorted, is no larger than the sorted build volume. g12 = the largest excess over every link and
dimension; a design whose section does not fit its links at all (:class:`qsm.physics.cad.CadError`)
also violates it, by how much a bar is too short.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from qsm.mechanisms.filters import kinematic_checks
from qsm.physics.containment import disk_arc_half_width
from qsm.physics.kinematics import as_design
from qsm.physics.task import Disk
from qsm.physics.workspace import OperatingRange, arcs, margin_about_zero, wrap_about

#: Violation (m) given to a design whose loop does not close over the operating range.
OPEN_LOOP_VIOLATION_M = 10.0


def _crossings(
    rho: NDArray[np.float64], levels: NDArray[np.float64]
) -> tuple[NDArray[np.intp], NDArray[np.intp], NDArray[np.intp]]:
    """Indices (design, segment, level) where segment ``[rho_k, rho_k+1]`` of a design reaches
    its level ``u`` (``min <= u <= max``), in lexicographic order.

    Each design's levels (N, J) are sorted, so a segment's levels are one run found by binary
    search, rather than by testing every segment against every level.
    """
    n, k = rho.shape[0], rho.shape[1] - 1
    low = np.minimum(rho[:, :-1], rho[:, 1:])
    high = np.maximum(rho[:, :-1], rho[:, 1:])
    first = np.empty((n, k), dtype=np.intp)
    stop = np.empty((n, k), dtype=np.intp)
    for i in range(n):
        first[i] = np.searchsorted(levels[i], low[i], side="left")
        stop[i] = np.searchsorted(levels[i], high[i], side="right")
    count = np.maximum(stop - first, 0).ravel()
    pair = np.repeat(np.arange(n * k), count)
    offset = np.arange(pair.size) - np.repeat(np.cumsum(count) - count, count)
    return pair // k, pair % k, first.ravel()[pair] + offset


def _arcs_on_circles(
    rho: NDArray[np.float64],
    lo: NDArray[np.float64],
    hi: NDArray[np.float64],
    levels: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Arcs of the workspace on the circles ``levels`` (N, J) of each design.

    Every segment of ``rho(delta)`` that crosses a level contributes the interpolated arc there
    (a monotone piece crosses a level once, so these are the arcs of Stage 1's pieces). Returns
    ``(starts, ends)`` of shape (M, N * J): at most M arcs per circle, NaN-padded.
    """
    n, j = levels.shape
    design, segment, level = _crossings(rho, levels)
    a, b = rho[design, segment], rho[design, segment + 1]
    span = b - a
    t = np.where(span != 0.0, (levels[design, level] - a) / np.where(span != 0, span, 1.0), 0.0)
    start = lo[design, segment] + t * (lo[design, segment + 1] - lo[design, segment])
    end = hi[design, segment] + t * (hi[design, segment + 1] - hi[design, segment])
    circle = design * j + level
    order = np.argsort(circle, kind="stable")
    circle, start, end = circle[order], start[order], end[order]
    first = np.searchsorted(circle, np.arange(n * j))
    rank = np.arange(circle.size) - first[circle]
    m = max(1, int(rank.max()) + 1) if rank.size else 1
    starts = np.full((m, n * j), np.nan)
    ends = np.full((m, n * j), np.nan)
    starts[rank, circle] = start
    ends[rank, circle] = end
    return starts, ends


def containment_margin_m(
    designs: ArrayLike,
    op: OperatingRange,
    disk: Disk,
    n_delta: int = 721,
    n_radii: int = 64,
) -> NDArray[np.float64]:
    """Smallest arc-length slack (m) of ``disk`` inside the workspace of each design at its scale.

    ``designs`` (N, 6) scaled lengths (m). Negative where the disk is not contained (see the
    module docstring); ``-OPEN_LOOP_VIOLATION_M`` where the loop does not close.
    """
    d = np.atleast_2d(as_design(designs))
    out = np.full(len(d), -OPEN_LOOP_VIOLATION_M)
    if disk.radius >= disk.distance:
        return out
    ratios = d[:, 1:] / d[:, :1]
    closes = kinematic_checks(ratios, op, 0.0)["loop_closes"]
    if not closes.any():
        return out
    ratios, scale = ratios[closes], d[closes, 0]
    rho, lo, hi = arcs(ratios, op, n_delta)
    radii = disk.distance - disk.radius * np.cos(np.linspace(0.0, np.pi, n_radii))
    need = disk_arc_half_width(radii, disk.distance, disk.radius)
    levels = radii[None, :] / scale[:, None]
    rho_min, rho_max = rho.min(axis=1)[:, None], rho.max(axis=1)[:, None]
    radial_m = np.minimum(levels - rho_min, rho_max - levels) * scale[:, None]  # < 0 outside
    levels = np.clip(levels, rho_min, rho_max)  # beyond the workspace: measured on its edge
    starts, ends = _arcs_on_circles(rho, lo, hi, levels)
    starts, ends = wrap_about(starts, ends, disk.angle)
    have = margin_about_zero(starts, ends).reshape(levels.shape)
    real = starts < ends  # wrap_about turns empty arcs into zero-length arcs at pi
    gap = np.where(real, np.where(starts > 0, starts, np.where(ends < 0, -ends, 0.0)), np.pi)
    gap = gap.min(axis=0).reshape(levels.shape)
    covered = have >= 0.0
    margin = np.minimum(np.where(covered, have - need, -(need + gap)) * radii, radial_m)
    out[closes] = margin.min(axis=1)
    return out
