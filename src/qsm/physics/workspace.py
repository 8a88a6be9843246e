"""Workspace area and task containment by slicing the workspace into circles about the base.

With l1 = 1 the end effector is ``E = dir(theta1) * (1 + R_e exp(i psi(delta)))`` (complex
notation), where ``delta = theta1 - theta2``, ``R_e = hypot(EE_x, EE_y)`` and ``psi`` depends
only on ``delta``. So a pose lies at radius ``rho(delta) = |1 + R_e exp(i psi)|`` and polar angle
``theta1 + beta(delta)``, and for a fixed ``delta`` the admissible ``theta1`` form one interval.
The workspace is therefore a union of arcs, and on each circle of radius ``rho`` about the base it
covers the union ``U(rho)`` of the arcs of every ``delta`` with ``rho(delta) = rho``. Folds and
overlaps are handled exactly by that union, and

* the area is ``integral rho |U(rho)| d rho`` (midpoint rule over ``n_levels`` circles);
* a disk of centre ``c`` and radius ``r`` lies in the workspace scaled by ``s`` iff, for every
  ``R`` in ``[|c| - r, |c| + r]``, the disk's arc on the circle of radius ``R`` lies in
  ``U(R / s)``: scaling keeps polar angles, so only the part of ``U`` around the task's polar
  angle matters (``margin``).

The only approximations are the ``delta`` sampling (linear between samples) and the number of
circles; both converge quadratically (tests compare with an independent point-membership count).
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from qsm.physics.kinematics import relative_arm_angle

TWO_PI = 2.0 * np.pi


@dataclass(frozen=True)
class OperatingRange:
    """Motor ranges: theta1 in [theta1_min, theta1_max], theta2 in [theta2_min, theta1] (rad)."""

    theta1_min: float
    theta1_max: float
    theta2_min: float

    @classmethod
    def from_degrees(cls, theta1_deg: ArrayLike, theta2_min_deg: float) -> OperatingRange:
        lo, hi = np.radians(np.asarray(theta1_deg, dtype=float))
        return cls(float(lo), float(hi), float(np.radians(theta2_min_deg)))

    @property
    def delta_max(self) -> float:
        """Largest ``theta1 - theta2`` (rad)."""
        return self.theta1_max - self.theta2_min

    def theta1_lower(self, delta: NDArray[np.float64]) -> NDArray[np.float64]:
        """Smallest admissible theta1 for a given ``delta`` (rad)."""
        return np.maximum(self.theta1_min, delta + self.theta2_min)


@dataclass(frozen=True)
class Resolution:
    """Discretisation of the slicing: ``delta`` samples and circles (levels)."""

    n_delta: int = 721
    n_levels: int = 600


@dataclass(frozen=True)
class Slices:
    """Workspace of a unit design (l1 = 1) cut into circles about the base.

    ``rho`` are the circle radii (midpoints of ``n_levels`` equal bins from ``rho_min`` to
    ``rho_max``), ``covered`` the angular length of ``U(rho)`` (rad) and ``margin`` the
    half-width of the arc of ``U(rho)`` centred on the reference polar angle (rad, -1 where that
    angle is not covered) on the circles ``margin_rho``: ``rho`` with ``rho_min`` and ``rho_max``
    added, so that the margin near the workspace's inner and outer edges is interpolated towards
    its value on the edge rather than held at the outermost midpoint's.
    """

    rho_min: float
    rho_max: float
    rho: NDArray[np.float64]
    covered: NDArray[np.float64]
    margin_rho: NDArray[np.float64]
    margin: NDArray[np.float64]

    @property
    def area(self) -> float:
        """Workspace area in units of l1^2."""
        return float(
            np.sum(self.rho * self.covered) * (self.rho_max - self.rho_min) / self.rho.size
        )


def arcs(
    ratios: ArrayLike, op: OperatingRange, n_delta: int
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Radius and polar-angle interval ``[lo, hi]`` of the workspace arcs at ``n_delta`` deltas.

    ``ratios`` is (..., 5); returns ``(rho, lo, hi)`` each of shape (..., n_delta), angles
    unwrapped (rad); NaN where the loop does not close.
    """
    r = np.asarray(ratios, dtype=float)[..., None, :]
    delta = np.linspace(0.0, op.delta_max, n_delta)
    rel, _ = relative_arm_angle(r, delta)
    alpha0 = -np.arctan2(r[..., 4], r[..., 3])
    w = 1.0 + np.hypot(r[..., 3], r[..., 4]) * np.exp(1j * (rel + alpha0))
    beta = np.unwrap(np.angle(w), axis=-1)
    return np.abs(w), op.theta1_lower(delta) + beta, op.theta1_max + beta


def slice_workspace(
    ratios: ArrayLike,
    op: OperatingRange,
    reference_angle: float = 0.0,
    resolution: Resolution = Resolution(),
) -> Slices:
    """Cut the unit workspace of ``ratios = (l2, l3, l4, ee_x, ee_y)`` into circles.

    ``reference_angle`` (rad) is the polar angle about which ``margin`` is measured (the task
    centre's). Raises ``ValueError`` if the loop does not close everywhere in ``op``.
    """
    rho, lo, hi = arcs(ratios, op, resolution.n_delta)
    if not np.all(np.isfinite(rho)):
        raise ValueError("the loop does not close over the whole operating range")
    return slices_of_arcs(rho, lo, hi, reference_angle, resolution.n_levels)


def slices_of_arcs(
    rho: NDArray[np.float64],
    lo: NDArray[np.float64],
    hi: NDArray[np.float64],
    reference_angle: float,
    n_levels: int,
) -> Slices:
    """:class:`Slices` of one design's closed :func:`arcs` on ``n_levels`` circles."""
    rho_min, rho_max = float(rho.min()), float(rho.max())
    levels = _levels(rho_min, rho_max, n_levels)
    margin_rho = np.concatenate([[rho_min], levels, [rho_max]])
    starts, ends = _interval_per_level(rho, lo, hi, margin_rho)
    starts, ends = wrap_about(starts, ends, reference_angle)
    covered, margin = union_and_margin(starts, ends)
    return Slices(
        rho_min=rho_min,
        rho_max=rho_max,
        rho=levels,
        covered=covered[1:-1],
        margin_rho=margin_rho,
        margin=margin,
    )


def unit_areas(
    ratios: ArrayLike, op: OperatingRange, resolution: Resolution = Resolution()
) -> NDArray[np.float64]:
    """Workspace areas (units of l1^2) of the unit designs ``ratios`` (M, 5): the
    ``slice_workspace(...).area`` of each, without the margins; NaN where the loop does not close
    everywhere in ``op``."""
    rho, lo, hi = arcs(np.atleast_2d(ratios), op, resolution.n_delta)
    out = np.full(len(rho), np.nan)
    for i in np.flatnonzero(np.isfinite(rho).all(axis=1)):
        rho_min, rho_max = float(rho[i].min()), float(rho[i].max())
        levels = _levels(rho_min, rho_max, resolution.n_levels)
        starts, ends = wrap_about(*_interval_per_level(rho[i], lo[i], hi[i], levels), 0.0)
        covered = _union_length(starts, ends)
        out[i] = np.sum(levels * covered) * (rho_max - rho_min) / levels.size
    return out


def _levels(rho_min: float, rho_max: float, n_levels: int) -> NDArray[np.float64]:
    """Midpoints of ``n_levels`` equal bins from ``rho_min`` to ``rho_max``."""
    return rho_min + (np.arange(n_levels) + 0.5) * (rho_max - rho_min) / n_levels


def _monotone_pieces(rho: NDArray[np.float64]) -> list[slice]:
    """Index ranges (sharing their end points) on which ``rho`` is monotone."""
    step = np.sign(np.diff(rho))
    turns = np.flatnonzero(step[1:] * step[:-1] < 0) + 1
    bounds = np.concatenate([[0], turns, [rho.size - 1]])
    return [slice(a, b + 1) for a, b in itertools.pairwise(bounds)]


def _interval_per_level(
    rho: NDArray[np.float64],
    lo: NDArray[np.float64],
    hi: NDArray[np.float64],
    levels: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Arc of every monotone piece of ``rho(delta)`` on every level: (pieces, levels) arrays.

    Levels a piece does not reach get an empty interval (NaN).
    """
    pieces = _monotone_pieces(rho)
    starts = np.full((len(pieces), levels.size), np.nan)
    ends = np.full_like(starts, np.nan)
    for i, sl in enumerate(pieces):
        r, a, b = rho[sl], lo[sl], hi[sl]
        if r[-1] < r[0]:
            r, a, b = r[::-1], a[::-1], b[::-1]
        inside = (levels >= r[0]) & (levels <= r[-1])
        starts[i, inside] = np.interp(levels[inside], r, a)
        ends[i, inside] = np.interp(levels[inside], r, b)
    return starts, ends


def wrap_about(
    starts: NDArray[np.float64], ends: NDArray[np.float64], centre: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Express arcs relative to ``centre`` on [-pi, pi], splitting an arc that crosses pi.

    Every arc is shorter than 2 pi (theta1's range), so one split suffices. Empty arcs become
    zero-length arcs at pi.
    """
    s = starts - centre
    shift = np.floor((s + np.pi) / TWO_PI) * TWO_PI
    s = s - shift
    e = ends - centre - shift
    over = e > np.pi
    s2 = np.where(over, -np.pi, np.pi)
    e2 = np.where(over, e - TWO_PI, np.pi)
    e = np.minimum(e, np.pi)
    empty = ~np.isfinite(s)
    s, e = np.where(empty, np.pi, s), np.where(empty, np.pi, e)
    return np.concatenate([s, s2]), np.concatenate([e, e2])


def _union_length(starts: NDArray[np.float64], ends: NDArray[np.float64]) -> NDArray[np.float64]:
    """Length of the union of intervals; intervals along axis 0, levels along axis 1."""
    return _sorted_apart(starts, ends)[3]


def _sorted_apart(
    starts: NDArray[np.float64], ends: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.bool_], NDArray[np.float64]]:
    """Starts and ends each sorted along axis 0, whether the union has a gap after the k-th end
    (axis 0 one shorter), and the union's length.

    There is a gap between the k-th end and the (k+1)-th start exactly when the first lies below
    the second (the k-th start never exceeds the k-th end), so the union is the hull less those
    gaps: no sort of the ends by their starts.
    """
    s, e = np.sort(starts, axis=0), np.sort(ends, axis=0)
    gap = s[1:] > e[:-1]
    return s, e, gap, e[-1] - s[0] - np.where(gap, s[1:] - e[:-1], 0.0).sum(axis=0)


def margin_about_zero(
    starts: NDArray[np.float64], ends: NDArray[np.float64]
) -> NDArray[np.float64]:
    """Half-width of the largest arc centred on 0 inside the union; -1 where 0 is not covered."""
    return union_and_margin(starts, ends)[1]


def union_and_margin(
    starts: NDArray[np.float64], ends: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Length of the union of closed intervals and the half-width of its largest arc centred on 0
    (-1 where 0 is not covered); intervals along axis 0, levels along axis 1.

    The union's connected pieces (:func:`_sorted_apart`) start at the first start and after each
    gap, and end before each gap and at the last end; 0 is covered when the last piece to start
    at or below 0 is not one that ends below 0.
    """
    s, e, gap, covered = _sorted_apart(starts, ends)
    piece_start = np.concatenate([s[:1], np.where(gap, s[1:], np.inf)])
    piece_end = np.concatenate([np.where(gap, e[:-1], -np.inf), e[-1:]])
    left = np.max(np.where(piece_start <= 0.0, piece_start, -np.inf), axis=0)
    right = np.min(np.where(piece_end >= 0.0, piece_end, np.inf), axis=0)
    ended = np.max(np.where(piece_end < 0.0, piece_end, -np.inf), axis=0)
    holds = (left > ended) & np.isfinite(left) & np.isfinite(right)
    return covered, np.where(holds, np.minimum(right, -left), -1.0)


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
