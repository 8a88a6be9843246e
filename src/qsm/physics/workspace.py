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
Designs are sliced many at a time (:func:`slice_stack`, array kernels in
:mod:`qsm.physics.slicing`), each to the same numbers as alone.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray

from qsm.physics.kinematics import end_effector, relative_arm_angle
from qsm.physics.slicing import (
    intervals_on_levels,
    levels_between,
    piece_counts,
    union_and_margin,
    union_length,
    wrap_compact,
)
from qsm.physics.slicing import margin_about_zero as margin_about_zero
from qsm.physics.slicing import wrap_about as wrap_about
from qsm.schema.defaults import default

#: Designs whose arcs are computed and whose scales are searched in one vectorised call.
ARCS_CHUNK = 256
#: Designs sliced in one vectorised call (its arrays, about 1 MB each, stay in the cache).
SLICE_BATCH = 64


@dataclass(frozen=True)
class OperatingRange:
    """The motors' ranges, as configured (deg): theta1 in ``theta1_deg`` (min, max), theta2
    from ``theta2_min_deg`` up to theta1; the same in radians as ``theta1_min``, ``theta1_max``
    and ``theta2_min``. Every setting that needs the range holds one of these."""

    theta1_deg: tuple[float, float] = tuple(default("operating_range.theta1_deg"))
    theta2_min_deg: float = default("operating_range.theta2_min_deg")
    theta1_min: float = field(init=False, repr=False, compare=False)
    theta1_max: float = field(init=False, repr=False, compare=False)
    theta2_min: float = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        lo, hi = np.radians(np.asarray(self.theta1_deg, dtype=float))
        object.__setattr__(self, "theta1_min", float(lo))
        object.__setattr__(self, "theta1_max", float(hi))
        object.__setattr__(self, "theta2_min", float(np.radians(self.theta2_min_deg)))

    @property
    def degrees(self) -> tuple[tuple[float, float], float]:
        """(theta1's (min, max), theta2's minimum), deg: the inverse kinematics' arguments."""
        return self.theta1_deg, self.theta2_min_deg

    @classmethod
    def from_degrees(cls, theta1_deg: ArrayLike, theta2_min_deg: float) -> OperatingRange:
        """The range of theta1's (min, max) and theta2's minimum, in degrees."""
        lo, hi = (float(t) for t in np.asarray(theta1_deg, dtype=float))
        return cls((lo, hi), float(theta2_min_deg))

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
        return float(_area(self.rho, self.covered, self.rho_min, self.rho_max))


@dataclass(frozen=True)
class SliceStack:
    """The :class:`Slices` of designs along a leading axis: ``rho_min``, ``rho_max`` (G,) and the
    arrays (G, ...)."""

    rho_min: NDArray[np.float64]
    rho_max: NDArray[np.float64]
    rho: NDArray[np.float64]
    covered: NDArray[np.float64]
    margin_rho: NDArray[np.float64]
    margin: NDArray[np.float64]

    @classmethod
    def of(cls, slices: Sequence[Slices]) -> SliceStack:
        """The designs ``slices`` (of one ``n_levels``) stacked."""
        return cls(
            *(np.array([getattr(sl, name) for sl in slices]) for name in cls.__dataclass_fields__)
        )

    def row(self, k: int) -> Slices:
        """The ``k``-th design's :class:`Slices`."""
        return Slices(
            float(self.rho_min[k]),
            float(self.rho_max[k]),
            self.rho[k],
            self.covered[k],
            self.margin_rho[k],
            self.margin[k],
        )

    @property
    def area(self) -> NDArray[np.float64]:
        """Workspace areas (G,) in units of l1^2."""
        return _area(self.rho, self.covered, self.rho_min, self.rho_max)


def _area(rho: NDArray, covered: NDArray, rho_min: ArrayLike, rho_max: ArrayLike) -> NDArray:
    """Midpoint rule of ``integral rho |U(rho)| d rho`` over the last axis (l1^2)."""
    width = np.asarray(rho_max) - rho_min
    return np.sum(rho * covered, axis=-1) * width / rho.shape[-1]


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
    return slice_stack(rho[None], lo[None], hi[None], reference_angle, n_levels).row(0)


def slice_stack(
    rho: NDArray[np.float64],
    lo: NDArray[np.float64],
    hi: NDArray[np.float64],
    reference_angle: float,
    n_levels: int,
) -> SliceStack:
    """:class:`Slices` of designs' closed :func:`arcs` (G, n_delta) on ``n_levels`` circles each,
    all at once; every design's numbers are those it has sliced alone."""
    rho_min, rho_max = rho.min(axis=1), rho.max(axis=1)
    levels = levels_between(rho_min, rho_max, n_levels)
    margin_rho = np.column_stack([rho_min, levels, rho_max])
    covered = np.empty_like(margin_rho)
    margin = np.empty_like(margin_rho)
    for rows in _batches(rho):
        starts, ends = intervals_on_levels(rho[rows], lo[rows], hi[rows], margin_rho[rows])
        wrapped = wrap_compact(starts, ends, reference_angle)
        covered[rows], margin[rows] = union_and_margin(*wrapped)
    return SliceStack(rho_min, rho_max, levels, covered[:, 1:-1], margin_rho, margin)


def _batches(rho: NDArray[np.float64]) -> Iterator[NDArray[np.intp]]:
    """Rows of closed arcs (G, n_delta) in batches of :data:`SLICE_BATCH` designs with one number
    of monotone pieces each (the same intervals as alone: no padding pieces)."""
    n_pieces = piece_counts(rho)
    for p in np.unique(n_pieces):
        same = np.flatnonzero(n_pieces == p)
        for start in range(0, same.size, SLICE_BATCH):
            yield same[start : start + SLICE_BATCH]


def unit_areas(
    ratios: ArrayLike, op: OperatingRange, resolution: Resolution = Resolution()
) -> NDArray[np.float64]:
    """Workspace areas (units of l1^2) of the unit designs ``ratios`` (M, 5): the
    ``slice_workspace(...).area`` of each; NaN where the loop does not close everywhere in
    ``op``."""
    ratios = np.atleast_2d(ratios)
    out = np.full(len(ratios), np.nan)
    for start in range(0, len(ratios), ARCS_CHUNK):
        rho, lo, hi = arcs(ratios[start : start + ARCS_CHUNK], op, resolution.n_delta)
        closed = np.flatnonzero(np.isfinite(rho).all(axis=1))
        rho, lo, hi = rho[closed], lo[closed], hi[closed]
        rho_min, rho_max = rho.min(axis=1), rho.max(axis=1)
        levels = levels_between(rho_min, rho_max, resolution.n_levels)
        covered = np.empty_like(levels)  # the circles' union lengths alone: no margins
        for rows in _batches(rho):
            starts, ends = intervals_on_levels(rho[rows], lo[rows], hi[rows], levels[rows])
            covered[rows] = union_length(*wrap_compact(starts, ends, 0.0))
        out[start + closed] = _area(levels, covered, rho_min, rho_max)
    return out


@dataclass(frozen=True)
class Reach:
    """The farthest the tool gets from A within the operating range: ``reach_m`` at
    ``delta_rad`` = theta1 - theta2, and the arm's reach with the lower and upper arm in line
    (``in_line_m``, l1 + |BE|), which the operating range may not allow."""

    reach_m: float
    delta_rad: float
    in_line_m: float


def operating_reach(
    design: ArrayLike, theta1_deg: Sequence[float], theta2_min_deg: float, samples: int = 4001
) -> Reach:
    """:class:`Reach` of ``design`` over motor 1's range ``theta1_deg`` (lo, hi) and theta2
    from ``theta2_min_deg`` up to theta1. |AE| depends only on delta = theta1 - theta2, which
    spans 0 to hi - theta2_min; it is scanned at ``samples`` points where the loop closes."""
    d = np.asarray(design, dtype=float)
    hi = np.radians(theta1_deg[1])
    delta = np.linspace(0.0, hi - np.radians(theta2_min_deg), samples)
    r = np.hypot(*end_effector(d, np.full_like(delta, hi), hi - delta).T)
    i = int(np.nanargmax(r))
    return Reach(float(r[i]), float(delta[i]), float(d[0] + np.hypot(d[4], d[5])))
