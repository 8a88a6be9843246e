"""Independent workspace reference for the tests: exact point membership by inverse kinematics.

A point P is reachable iff some pose puts the end effector there. The upper arm is rigid, so
|P - B| = hypot(EE_x, EE_y) with B on the circle of radius l1: at most two theta1. Each fixes the
upper arm, hence D, and C lies on both |C| = l2 and |C - D| = l3: at most two theta2. A candidate
counts if it is in the operating range and the forward kinematics (the assembly branch of
qsm.physics.kinematics.pose) puts D where the candidate has it. Counting pixels of a fine grid
gives an area estimate that shares nothing with the slicing of qsm.physics.workspace but the
forward model.
"""

from __future__ import annotations

import numpy as np

from qsm.physics.kinematics import pose
from qsm.physics.workspace import OperatingRange


def _circle_intersections(c0, r0, c1, r1):
    """Both intersection points of circles (c0, r0) and (c1, r1); NaN where they do not meet."""
    d_vec = c1 - c0
    d = np.linalg.norm(d_vec, axis=-1)
    a = (r0**2 - r1**2 + d**2) / (2 * d)
    with np.errstate(invalid="ignore"):
        h = np.sqrt(r0**2 - a**2)  # NaN where they do not meet
    u = d_vec / d[..., None]
    base = c0 + a[..., None] * u
    perp = np.stack([-u[..., 1], u[..., 0]], axis=-1)
    return base + h[..., None] * perp, base - h[..., None] * perp


def reachable(design: np.ndarray, points: np.ndarray, op: OperatingRange) -> np.ndarray:
    """Whether each point (M, 2) is an end-effector position of ``design`` (6 lengths)."""
    l1, l2, l3, l4, ex, ey = design
    r_e = np.hypot(ex, ey)
    alpha0 = -np.arctan2(ey, ex)
    zero = np.zeros_like(points)
    hit = np.zeros(len(points), dtype=bool)
    for b in _circle_intersections(zero, l1, points, r_e):
        theta1 = np.arctan2(b[:, 1], b[:, 0])
        theta1 = np.where(theta1 < op.theta1_min - 1e-12, theta1 + 2 * np.pi, theta1)
        pe = points - b
        phi = np.arctan2(pe[:, 1], pe[:, 0]) - alpha0
        d = b - l4 * np.stack([np.cos(phi), np.sin(phi)], axis=-1)
        for c in _circle_intersections(zero, l2, d, l3):
            theta2 = np.arctan2(c[:, 1], c[:, 0])
            delta = np.mod(theta1 - theta2, 2 * np.pi)
            theta2 = theta1 - delta
            ok = (
                (theta1 >= op.theta1_min)
                & (theta1 <= op.theta1_max)
                & (delta <= op.delta_max)
                & (theta2 >= op.theta2_min)
            )
            fk = pose(design, theta1, theta2)
            same_branch = np.linalg.norm(fk.D - d, axis=-1) < 1e-9 * l1
            hit |= ok & same_branch & np.isfinite(theta2)
    return hit


def pixel_area(design: np.ndarray, op: OperatingRange, n: int = 1000) -> float:
    """Workspace area by counting the pixel centres of an n x n grid that are reachable."""
    t1 = np.linspace(op.theta1_min, op.theta1_max, 200)
    t2 = np.linspace(op.theta2_min, op.theta1_max, 200)
    g1, g2 = np.meshgrid(t1, t2)
    keep = g2 <= g1
    e = pose(design, g1[keep], g2[keep]).E
    pad = 0.05 * design[0]
    (x0, y0), (x1, y1) = e.min(axis=0) - pad, e.max(axis=0) + pad
    hx, hy = (x1 - x0) / n, (y1 - y0) / n
    xs = x0 + (np.arange(n) + 0.5) * hx
    ys = y0 + (np.arange(n) + 0.5) * hy
    total = 0
    for y in np.array_split(ys, 20):
        gx, gy = np.meshgrid(xs, y)
        total += int(reachable(design, np.column_stack([gx.ravel(), gy.ravel()]), op).sum())
    return total * hx * hy
