"""Workspace area by slicing the workspace into circles about the base.

With l1 = 1 the end effector is ``E = dir(theta1) * (1 + R_e exp(i psi(delta)))`` (complex
notation), where ``delta = theta1 - theta2``, ``R_e = hypot(EE_x, EE_y)`` and ``psi`` depends
only on ``delta``. So a pose lies at radius ``rho(delta) = |1 + R_e exp(i psi)|`` and polar angle
``theta1 + beta(delta)``, and for a fixed ``delta`` the admissible ``theta1`` form one interval.
The workspace is therefore a union of arcs, and on each circle of radius ``rho`` about the base it
covers the union ``U(rho)`` of the arcs of every ``delta`` with ``rho(delta) = rho``. Folds and
overlaps are handled exactly by that union; the area is ``integral rho |U(rho)| d rho``
(midpoint rule over ``n_levels`` circles), and the half-width of ``U`` about the task's polar
angle (``margin``) is what task containment needs (:mod:`qsm.physics.containment`).

The only approximations are the ``delta`` sampling (linear between samples) and the number of
circles; both converge quadratically (tests compare with an independent point-membership count).
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from qsm.defaults import default
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

    n_delta: int = default("workspace.n_delta")
    n_levels: int = default("workspace.n_levels")


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
