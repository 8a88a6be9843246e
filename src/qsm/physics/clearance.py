"""True clearance: the Euclidean distance (m) from the task disk to the edge of the workspace.

The workspace is built from the slicing arcs of :mod:`qsm.physics.workspace`: for each sample
``delta_k = theta1 - theta2`` the end effector sweeps, as theta1 runs over its admissible interval,
an arc of the circle of radius ``rho_k`` (l1 = 1) between the polar angles ``lo_k`` and ``hi_k``
(:func:`qsm.physics.workspace.arcs`). Between two samples the region swept is, in polar coordinates
(angle, rho), the quadrilateral ``(lo_k, rho_k), (hi_k, rho_k), (hi_k+1, rho_k+1), (lo_k+1,
rho_k+1)``: the same linear interpolation in ``delta`` that Stage 1's slicing makes. The workspace
is the union of these patches (folds and overlaps included; a void inside it becomes a hole).

To keep it cheap only the patches that reach a window around the task disk are united: a polar box
``[|c| - R, |c| + R] x [angle(c) +- asin(R / |c|)]`` that contains the Euclidean ball of radius R
about the disk's centre c. Inside that ball the local union equals the workspace, so a distance to
its boundary below R is the true distance; otherwise R doubles (up to the whole plane). The union
is cut into two angular halves, each densified (polar edges split to at most ``max_step`` rad or
l1) and mapped to the plane at the design's scale, and the halves are united again (so that the
angular seam is no boundary).

``clearance = signed distance of the centre to the boundary - disk radius``: positive when the disk
lies inside with that much room, negative when it is not contained. Errors: the ``delta`` sampling
(``n_delta``, second order) and the densification (chord error ``l1 rho max_step^2 / 8``).

The arc-length margin of :func:`qsm.optimization.constraints.containment_margin_m` is **not** a
lower bound of this distance but an upper bound (up to its sampling of the circles): on each circle
through the disk the end of the workspace arc is a boundary point, whose chord to the disk's arc end
is at most the arc length between them, and the radial cap is the length of a ray from the disk to
beyond the boundary. It keeps the sign (contained or not) but overstates the room: a task of two
points 5 mm apart near (-0.45, 0.05) m had 3.39 mm of arc and 0.31 mm of clearance.
"""

from __future__ import annotations

import math

import numpy as np
import shapely
from numpy.typing import ArrayLike, NDArray

from qsm.physics.kinematics import as_design
from qsm.physics.task import Disk
from qsm.physics.workspace import OperatingRange, arcs

#: Default samples of delta for the patches, the slicing's own: on 40 designs of the default
#: paper front (l1 about 0.4 m) the clearance differs from that with 2001 samples by at most
#: 0.5 micrometres, at 0.4 times the time.
DEFAULT_N_DELTA = 721
#: Default largest polar step (rad, or units of l1) of the densified boundary.
DEFAULT_MAX_STEP = 2e-3
TWO_PI = 2.0 * math.pi


def workspace_patches(
    ratios: ArrayLike, op: OperatingRange, n_delta: int = DEFAULT_N_DELTA
) -> NDArray[np.float64]:
    """Polar patches (n_delta - 1, 4, 2) of the unit workspace: vertices (angle rad, rho l1).

    Raises ``ValueError`` where the loop does not close over the whole operating range.
    """
    rho, lo, hi = arcs(np.asarray(ratios, dtype=float), op, n_delta)
    if not np.all(np.isfinite(rho)):
        raise ValueError("the loop does not close over the whole operating range")
    return np.stack(
        [
            np.column_stack([lo[:-1], rho[:-1]]),
            np.column_stack([hi[:-1], rho[:-1]]),
            np.column_stack([hi[1:], rho[1:]]),
            np.column_stack([lo[1:], rho[1:]]),
        ],
        axis=1,
    )


def _to_plane(polar: shapely.Geometry, angle0: float, scale: float) -> shapely.Geometry:
    def f(p: NDArray[np.float64]) -> NDArray[np.float64]:
        a, r = p[:, 0] + angle0, p[:, 1] * scale
        return np.column_stack([r * np.cos(a), r * np.sin(a)])

    return shapely.transform(polar, f)


def local_workspace(
    patches: NDArray[np.float64],
    scale: float,
    centre: tuple[float, float],
    window_m: float,
    max_step: float = DEFAULT_MAX_STEP,
) -> tuple[shapely.Geometry, bool]:
    """The workspace at ``scale`` (m of l1) near ``centre`` (m): a planar shapely geometry that
    equals the workspace inside the ball of radius ``window_m`` about the centre, and whether the
    window covered the whole workspace."""
    d = math.hypot(*centre)
    angle0 = math.atan2(centre[1], centre[0])
    rho_lo = (d - window_m) / scale
    rho_hi = (d + window_m) / scale
    whole = window_m >= d
    half = math.pi + 1e-9 if whole else math.asin(window_m / d)
    if whole:
        rho_lo = -1.0
    a = patches[..., 0] - angle0
    r = patches[..., 1]
    pieces = []
    mid = 0.5 * (a.min(axis=1) + a.max(axis=1))
    a = a - np.round(mid / TWO_PI)[:, None] * TWO_PI  # patch centres in [-pi, pi]
    for shift in (-TWO_PI, 0.0, TWO_PI):
        aa = a + shift
        near = (
            (aa.max(axis=1) >= -half)
            & (aa.min(axis=1) <= half)
            & (r.max(axis=1) >= rho_lo)
            & (r.min(axis=1) <= rho_hi)
        )
        if near.any():
            coords = np.stack([aa[near], r[near]], axis=-1)
            pieces.append(shapely.polygons(coords))
    window = shapely.box(-half, rho_lo, half, rho_hi)
    if not pieces:
        return shapely.Polygon(), whole
    polys = np.concatenate(pieces)
    polys = polys[shapely.area(polys) > 0]
    union = shapely.intersection(shapely.union_all(shapely.make_valid(polys)), window)
    union = shapely.segmentize(union, max_step)
    # map two overlapping angular halves separately: each spans less than 2 pi
    planar = [
        _to_plane(shapely.intersection(union, shapely.box(lo, rho_lo, hi, rho_hi)), angle0, scale)
        for lo, hi in ((-half, 1e-6), (-1e-6, half))
    ]
    # the polar-to-plane map can fold a piece's boundary onto itself: repaired before the union
    return shapely.union_all(shapely.make_valid(planar)), whole


def disk_clearance_m(
    design: ArrayLike,
    op: OperatingRange,
    disk: Disk,
    n_delta: int = DEFAULT_N_DELTA,
    max_step: float = DEFAULT_MAX_STEP,
    patches: NDArray[np.float64] | None = None,
) -> float:
    """Euclidean clearance (m) of ``disk`` inside the workspace of ``design`` (6 scaled lengths, m).

    Positive: the disk lies in the workspace with that much room to the nearest edge; negative:
    it is not contained (minus the centre's distance to the workspace, minus the radius).
    ``patches`` (from :func:`workspace_patches` of the design's ratios) may be passed to reuse
    them across scales. The window about the disk doubles until the nearest edge lies inside it.
    """
    d = as_design(design)
    scale = float(d[0])
    if patches is None:
        patches = workspace_patches(d[1:] / d[0], op, n_delta)
    c = shapely.Point(disk.centre)
    window = max(4.0 * disk.radius, 0.02 * disk.distance, 1e-3)
    while True:
        region, whole = local_workspace(patches, scale, disk.centre, window, max_step)
        if region.is_empty:
            dist, inside = math.inf, False
        else:
            inside = bool(region.covers(c))
            dist = float(region.boundary.distance(c)) if inside else float(region.distance(c))
        if dist < (1.0 - 1e-6) * window or whole:  # the window's own edges lie >= window away
            return dist - disk.radius if inside else -dist - disk.radius
        window *= 2.0


def disk_clearances_m(
    designs: ArrayLike,
    op: OperatingRange,
    disk: Disk,
    n_delta: int = DEFAULT_N_DELTA,
    max_step: float = DEFAULT_MAX_STEP,
) -> NDArray[np.float64]:
    """:func:`disk_clearance_m` of each of ``designs`` (N, 6); NaN where the loop does not close
    over the whole operating range."""
    d = np.atleast_2d(as_design(designs))
    out = np.full(len(d), np.nan)
    for i, row in enumerate(d):
        try:
            out[i] = disk_clearance_m(row, op, disk, n_delta, max_step)
        except ValueError:
            continue
    return out
