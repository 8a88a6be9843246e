"""Containment of a task disk in the scaled workspace, and the smallest scale that holds it.

A disk of centre ``c`` and radius ``r`` lies in the unit workspace scaled by ``s`` iff, for every
``R`` in ``[|c| - r, |c| + r]``, the disk's arc on the circle of radius ``R`` about the base lies
in ``U(R / s)``, the workspace's union of arcs on the circle of radius ``R / s``
(:class:`qsm.physics.workspace.Slices`). Scaling keeps polar angles, so only the part of ``U``
around the task's polar angle matters: its ``margin``. Containment is not monotone in ``s`` (the
disk can leave through the inner edge of a crescent), so the scale search scans before it bisects.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from qsm.physics.slicing import count_guess
from qsm.physics.workspace import Slices, SliceStack


def disk_arc_half_width(
    radius: NDArray[np.float64], centre_distance: float, disk_radius: float
) -> NDArray[np.float64]:
    """Half-width (rad) of the arc a disk cuts from the circle of ``radius`` about the origin."""
    cos_w = (radius**2 + centre_distance**2 - disk_radius**2) / (2.0 * radius * centre_distance)
    return np.arccos(np.clip(cos_w, -1.0, 1.0))


def containment_margin(
    slices: Slices,
    scale: ArrayLike,
    centre_distance: float,
    disk_radius: float,
    n_radii: int = 64,
) -> NDArray[np.float64]:
    """Smallest angular slack (rad) of a task disk inside the workspace scaled by ``scale``.

    The disk (centre at ``centre_distance`` from the base along the reference angle of ``slices``,
    radius ``disk_radius``, metres) is contained iff the result is >= 0. Vectorised over ``scale``.
    """
    s = np.atleast_1d(np.asarray(scale, dtype=float))
    circles = _disk_circles(centre_distance, disk_radius, n_radii)
    return _slack(slices.margin_rho[None], slices.margin[None], *circles, s[None])[0]


def _disk_circles(
    centre_distance: float, disk_radius: float, n_radii: int = 64
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Radii (m) of the circles about the base that cross the task disk, Chebyshev-spaced (the arc
    width changes fastest near the disk's ends), and the half-width (rad) of the disk's arc on
    each."""
    radii = centre_distance - disk_radius * np.cos(np.linspace(0.0, np.pi, n_radii))
    return radii, disk_arc_half_width(radii, centre_distance, disk_radius)


def _slack(
    margin_rho: NDArray[np.float64],
    margin: NDArray[np.float64],
    radii: NDArray[np.float64],
    need: NDArray[np.float64],
    scale: NDArray[np.float64],
) -> NDArray[np.float64]:
    """:func:`containment_margin` of designs (rows of their :class:`Slices`' ``margin_rho`` and
    ``margin``) at scales (G, k): the half-width of the workspace arc centred on the task angle
    at the unit radii ``radii / scale`` (-1 off the workspace) less the disk's ``need``."""
    have = _interp_rows(
        (radii / scale[..., None]).reshape(len(scale), -1), margin_rho, margin, -1.0
    )
    return np.min(have.reshape(*scale.shape, -1) - need, axis=-1)


@dataclass(frozen=True)
class Fit:
    """Smallest scale (metres of l1) at which the task disk fits, or NaN if none up to the limit."""

    scale: float
    feasible: bool
    reason: str


def radial_misfit(
    rho_min: float, rho_max: float, centre_distance: float, disk_radius: float, scale_max: float
) -> str:
    """Why no scale up to ``scale_max`` can hold the disk, judged by the workspace's inner and
    outer radii (``rho_min``, ``rho_max``, units of l1) alone; ``""`` if the radii allow one."""
    if disk_radius >= centre_distance:
        return "task disk covers the base"
    lo = (centre_distance + disk_radius) / rho_max  # disk must reach no further out
    if lo > (centre_distance - disk_radius) / rho_min:  # nor further in
        return "workspace too thin for the task disk"
    if lo > scale_max:
        return "scale.max_m below the smallest scale that could hold the task"
    return ""


def minimal_scale(
    slices: Slices,
    centre_distance: float,
    disk_radius: float,
    scale_max: float,
    n_scan: int = 128,
    rel_tol: float = 1e-9,
) -> Fit:
    """Smallest ``s <= scale_max`` with the disk inside ``s`` times the unit workspace.

    Containment is not monotone in ``s`` (the disk can leave through the inner edge of a
    crescent), so the admissible range implied by the radii is scanned at ``n_scan`` scales for the
    first one that contains the disk, then the boundary is bisected to ``rel_tol``.
    """
    stack = SliceStack.of([slices])
    return minimal_scales(stack, centre_distance, disk_radius, scale_max, n_scan, rel_tol)[0]


def minimal_scales(
    stack: SliceStack,
    centre_distance: float,
    disk_radius: float,
    scale_max: float,
    n_scan: int = 128,
    rel_tol: float = 1e-9,
) -> list[Fit]:
    """:func:`minimal_scale` of each design of ``stack`` for one disk, all at once (the same
    steps as one at a time, so the same scales)."""
    fits = [
        Fit(np.nan, False, radial_misfit(a, b, centre_distance, disk_radius, scale_max))
        for a, b in zip(stack.rho_min, stack.rho_max, strict=True)
    ]
    rows = np.array([k for k, fit in enumerate(fits) if not fit.reason], dtype=np.intp)
    if not rows.size:
        return fits
    xp, fp = stack.margin_rho[rows], stack.margin[rows]
    lo = (centre_distance + disk_radius) / stack.rho_max[rows]  # disk must reach no further out
    hi_geometry = (centre_distance - disk_radius) / stack.rho_min[rows]  # nor further in
    hi = np.minimum(scale_max, hi_geometry)
    # np.linspace(lo, hi, n_scan) of each row, with its arithmetic
    scan = np.arange(n_scan) * ((hi - lo) / max(n_scan - 1, 1))[:, None] + lo[:, None]
    if n_scan > 1:
        scan[:, -1] = hi
    circles = _disk_circles(centre_distance, disk_radius)
    first = _first_contained(xp, fp, circles, scan)
    where = np.where(hi_geometry > scale_max, "up to scale.max_m ", "")
    for j, k in enumerate(rows):
        if first[j] < 0:
            fits[k] = Fit(np.nan, False, f"no scale {where[j]}holds the task")
        elif first[j] == 0:
            fits[k] = Fit(float(lo[j]), True, "")
    bisect = np.flatnonzero(first > 0)
    a, b = scan[bisect, first[bisect] - 1], scan[bisect, first[bisect]]
    xp, fp = xp[bisect], fp[bisect]
    active = b - a > rel_tol * b
    while active.any():
        i = np.flatnonzero(active)
        mid = 0.5 * (a[i] + b[i])
        holds = _slack(xp[i], fp[i], *circles, mid[:, None])[:, 0] >= 0.0
        b[i] = np.where(holds, mid, b[i])
        a[i] = np.where(holds, a[i], mid)
        active[i] = b[i] - a[i] > rel_tol * b[i]
    for k, scale in zip(rows[bisect], b, strict=True):
        fits[k] = Fit(float(scale), True, "")
    return fits


def _first_contained(
    margin_rho: NDArray[np.float64],
    margin: NDArray[np.float64],
    circles: tuple[NDArray[np.float64], NDArray[np.float64]],
    scan: NDArray[np.float64],
    max_points: int = 4096,
) -> NDArray[np.intp]:
    """Index of the first of each row's scanned scales ``scan`` (G, n_scan) that holds the disk
    (-1 if none), checked in blocks of 8, 16, 32, ... scales from the smallest (the first
    admissible one is mostly early), ``max_points`` scales at a time."""
    first = np.full(len(scan), -1, dtype=np.intp)
    pending = np.arange(len(scan))
    start, size = 0, 8
    while start < scan.shape[1] and pending.size:
        for rows in np.array_split(pending, -(-pending.size * size // max_points)):
            ok = _slack(margin_rho[rows], margin[rows], *circles, scan[rows, start : start + size])
            hit = (ok >= 0.0).any(axis=1)
            first[rows[hit]] = start + np.argmax(ok[hit] >= 0.0, axis=1)
        pending = pending[first[pending] < 0]
        start, size = start + size, 2 * size
    return first


def _interp_rows(
    x: NDArray[np.float64], xp: NDArray[np.float64], fp: NDArray[np.float64], outside: float
) -> NDArray[np.float64]:
    """``np.interp(x[i], xp[i], fp[i], left=outside, right=outside)`` for every row ``i`` at once,
    with ``np.interp``'s arithmetic: the segment ``[xp[j], xp[j + 1])`` that holds ``x``; each
    ``xp[i]`` increasing (found fastest if spaced as :attr:`Slices.margin_rho` is)."""
    n = xp.shape[1]
    base = (np.arange(len(xp)) * n)[:, None]
    j = base + np.clip(count_guess(xp, x) - 1, 0, n - 2)  # flat index of xp[i, j]
    flat_x, flat_f = xp.ravel(), fp.ravel()
    while True:
        x0, x1 = flat_x[j], flat_x[j + 1]
        down = (j > base) & (x0 > x)
        up = (j < base + n - 2) & (x1 <= x)
        if not (down.any() or up.any()):
            break
        j = j - down + up
    y0, y1 = flat_f[j], flat_f[j + 1]
    with np.errstate(invalid="ignore", divide="ignore"):
        out = (y1 - y0) / (x1 - x0) * (x - x0) + y0
    out = np.where(x == x0, y0, out)
    first, last = xp[:, :1], xp[:, -1:]
    out = np.where(x == last, fp[:, -1:], out)
    return np.where((x < first) | (x > last), outside, out)
