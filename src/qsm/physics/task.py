"""The task region: the minimum enclosing circle of the task points (paper Section 2.1)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

#: Above this many points the enclosing circle is sought among the convex hull's vertices only
#: (the same circle, far faster for thousands of points; smaller tasks keep their exact path).
HULL_ABOVE = 64


@dataclass(frozen=True)
class Disk:
    """A disk in the mechanism plane: centre (m) and radius (m)."""

    centre: tuple[float, float]
    radius: float

    @property
    def area(self) -> float:
        """Area in m^2."""
        return float(np.pi * self.radius**2)

    @property
    def distance(self) -> float:
        """Distance of the centre from the base joint A (m)."""
        return float(np.hypot(*self.centre))

    @property
    def angle(self) -> float:
        """Polar angle of the centre about the base joint A (rad)."""
        return float(np.arctan2(self.centre[1], self.centre[0]))

    def contains(self, points: ArrayLike, tol: float = 1e-9) -> NDArray[np.bool_]:
        """Whether each point lies in the disk (within ``tol`` m)."""
        p = np.atleast_2d(np.asarray(points, dtype=float))
        return np.hypot(*(p - self.centre).T) <= self.radius + tol


def _diameter_circle(a: NDArray[np.float64], b: NDArray[np.float64]) -> Disk:
    c = 0.5 * (a + b)
    return Disk((float(c[0]), float(c[1])), float(0.5 * np.hypot(*(a - b))))


def _circumcircle(a: NDArray[np.float64], b: NDArray[np.float64], c: NDArray[np.float64]) -> Disk:
    """Circle through three points; for (nearly) collinear points the widest diameter circle."""
    bx, by = b - a
    cx, cy = c - a
    det = 2.0 * (bx * cy - by * cx)
    scale = max(bx * bx + by * by, cx * cx + cy * cy)
    if abs(det) <= 1e-12 * scale:
        pairs = [(a, b), (a, c), (b, c)]
        return max((_diameter_circle(p, q) for p, q in pairs), key=lambda d: d.radius)
    ux = (cy * (bx * bx + by * by) - by * (cx * cx + cy * cy)) / det
    uy = (bx * (cx * cx + cy * cy) - cx * (bx * bx + by * by)) / det
    return Disk((float(a[0] + ux), float(a[1] + uy)), float(np.hypot(ux, uy)))


def min_enclosing_circle(points: ArrayLike, seed: int = 0) -> Disk:
    """Smallest disk containing all ``points`` (n, 2), by Welzl's algorithm (iterative form).

    Exact up to floating point; expected O(n) after a seeded shuffle, so the result does not
    depend on the order of the points.
    """
    p = np.asarray(points, dtype=float)
    if p.ndim != 2 or p.shape[1] != 2 or len(p) == 0:
        raise ValueError(f"task points must be a non-empty list of [x, y], got shape {p.shape}")
    if len(p) > HULL_ABOVE:
        # imported here: scipy.spatial costs 0.5 s, and every Snakemake start checks the task
        from scipy.spatial import ConvexHull, QhullError

        try:
            p = p[ConvexHull(p).vertices]
        except QhullError:  # collinear or repeated points: no 2-D hull, search them all
            pass
    p = p[np.random.default_rng(seed).permutation(len(p))]
    disk = Disk((float(p[0, 0]), float(p[0, 1])), 0.0)
    for i in range(1, len(p)):
        if disk.contains(p[i])[0]:
            continue
        disk = Disk((float(p[i, 0]), float(p[i, 1])), 0.0)
        for j in range(i):
            if disk.contains(p[j])[0]:
                continue
            disk = _diameter_circle(p[i], p[j])
            for k in range(j):
                if not disk.contains(p[k])[0]:
                    disk = _circumcircle(p[i], p[j], p[k])
    return disk
