"""Containment of a task disk in the scaled workspace, and the smallest scale that holds it.

A disk of centre ``c`` and radius ``r`` lies in the unit workspace scaled by ``s`` iff, for every
``R`` in ``[|c| - r, |c| + r]``, the disk's arc on the circle of radius ``R`` about the base lies
in ``U(R / s)``, the workspace's union of arcs on the circle of radius ``R / s``
(:class:`qsm.physics.workspace.Slices`). Scaling keeps polar angles, so only the part of ``U``
around the task's polar angle matters: its ``margin``. Containment is not monotone in ``s`` (the
disk can leave through the inner edge of a crescent), so the scale search scans before it bisects.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from qsm.physics.workspace import Slices


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
    return _DiskCheck(slices, centre_distance, disk_radius, n_radii).margin(scale)


def _disk_circles(
    centre_distance: float, disk_radius: float, n_radii: int = 64
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Radii (m) of the circles about the base that cross the task disk, Chebyshev-spaced (the arc
    width changes fastest near the disk's ends), and the half-width (rad) of the disk's arc on
    each."""
    radii = centre_distance - disk_radius * np.cos(np.linspace(0.0, np.pi, n_radii))
    return radii, disk_arc_half_width(radii, centre_distance, disk_radius)


class _DiskCheck:
    """:func:`containment_margin` for one design and disk, at any scale: the disk's circles and
    arc widths are computed once."""

    def __init__(
        self, slices: Slices, centre_distance: float, disk_radius: float, n_radii: int = 64
    ) -> None:
        self.slices = slices
        self.radii, need = _disk_circles(centre_distance, disk_radius, n_radii)
        self.need = need[None, :]

    def margin(self, scale: ArrayLike) -> NDArray[np.float64]:
        """:func:`containment_margin` at each of ``scale`` (m)."""
        s = np.atleast_1d(np.asarray(scale, dtype=float))[:, None]
        return np.min(self._have(self.radii[None, :] / s) - self.need, axis=1)

    def _have(self, unit: NDArray[np.float64]) -> NDArray[np.float64]:
        """Half-width of the workspace arc centred on the task angle at radii ``unit`` (l1);
        -1 off the workspace (its ``margin_rho`` run from ``rho_min`` to ``rho_max``)."""
        sl = self.slices
        return np.interp(unit, sl.margin_rho, sl.margin, left=-1.0, right=-1.0)


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
    return minimal_scales([slices], centre_distance, disk_radius, scale_max, n_scan, rel_tol)[0]


def minimal_scales(
    slices: Sequence[Slices],
    centre_distance: float,
    disk_radius: float,
    scale_max: float,
    n_scan: int = 128,
    rel_tol: float = 1e-9,
) -> list[Fit]:
    """:func:`minimal_scale` of each of ``slices`` for one disk: the scans one design at a time,
    the bisections of all designs at once (the same steps, so the same scales)."""
    fits: list[Fit] = []
    pending: list[int] = []
    brackets: list[tuple[float, float]] = []
    for k, sl in enumerate(slices):
        fit = _scan(sl, centre_distance, disk_radius, scale_max, n_scan)
        if isinstance(fit, Fit):
            fits.append(fit)
        else:
            fits.append(Fit(np.nan, False, "bisection pending"))
            pending.append(k)
            brackets.append(fit)
    if pending:
        a, b = np.array(brackets).T
        rows = [slices[k] for k in pending]
        xp = np.stack([sl.margin_rho for sl in rows])
        fp = np.stack([sl.margin for sl in rows])
        radii, need = _disk_circles(centre_distance, disk_radius)
        active = b - a > rel_tol * b
        while active.any():
            i = np.flatnonzero(active)
            mid = 0.5 * (a[i] + b[i])
            have = _interp_rows(radii[None, :] / mid[:, None], xp[i], fp[i], -1.0)
            holds = np.min(have - need, axis=1) >= 0.0
            b[i] = np.where(holds, mid, b[i])
            a[i] = np.where(holds, a[i], mid)
            active[i] = b[i] - a[i] > rel_tol * b[i]
        for k, scale in zip(pending, b, strict=True):
            fits[k] = Fit(float(scale), True, "")
    return fits


def _scan(
    slices: Slices, centre_distance: float, disk_radius: float, scale_max: float, n_scan: int
) -> Fit | tuple[float, float]:
    """The fit of :func:`minimal_scale` where no bisection is needed, else the bracket of scales
    (m) that it bisects: the last scanned scale without and the first with the disk inside."""
    radial = radial_misfit(slices.rho_min, slices.rho_max, centre_distance, disk_radius, scale_max)
    if radial:
        return Fit(np.nan, False, radial)
    lo = (centre_distance + disk_radius) / slices.rho_max  # disk must reach no further out
    hi_geometry = (centre_distance - disk_radius) / slices.rho_min  # nor further in
    hi = min(scale_max, hi_geometry)
    scan = np.linspace(lo, hi, n_scan)
    check = _DiskCheck(slices, centre_distance, disk_radius)
    # blocks of 8, 16, 32, ... scales from the smallest: the first admissible one is mostly early
    start, size = 0, 8
    while start < n_scan:
        ok = check.margin(scan[start : start + size]) >= 0.0
        if ok.any():
            first = start + int(np.argmax(ok))
            if first == 0:
                return Fit(float(lo), True, "")
            return float(scan[first - 1]), float(scan[first])
        start, size = start + size, 2 * size
    where = "up to scale.max_m " if hi_geometry > scale_max else ""
    return Fit(np.nan, False, f"no scale {where}holds the task")


def _interp_rows(
    x: NDArray[np.float64], xp: NDArray[np.float64], fp: NDArray[np.float64], outside: float
) -> NDArray[np.float64]:
    """``np.interp(x[i], xp[i], fp[i], left=outside, right=outside)`` for every row ``i`` at once,
    with ``np.interp``'s arithmetic; each ``xp[i]`` increasing and about evenly spaced (as
    :attr:`Slices.margin_rho` is), which makes the first guess of the segment exact or one off."""
    n = xp.shape[1]
    first, last = xp[:, :1], xp[:, -1:]
    with np.errstate(invalid="ignore", divide="ignore"):
        guess = np.floor((x - first) / (last - first) * (n - 1))
    j = np.clip(np.nan_to_num(guess), 0, n - 2).astype(np.intp)
    row = np.arange(len(xp))[:, None]
    while True:
        down = (j > 0) & (xp[row, j] > x)
        up = (j < n - 2) & (xp[row, j + 1] <= x)
        if not (down.any() or up.any()):
            break
        j = j - down + up
    x0, x1, y0, y1 = xp[row, j], xp[row, j + 1], fp[row, j], fp[row, j + 1]
    with np.errstate(invalid="ignore", divide="ignore"):
        out = (y1 - y0) / (x1 - x0) * (x - x0) + y0
    out = np.where(x == x0, y0, out)
    out = np.where(x == last, fp[:, -1:], out)
    return np.where((x < first) | (x > last), outside, out)
