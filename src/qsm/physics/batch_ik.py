"""The inverse kinematics of :func:`qsm.physics.inverse_kinematics.joint_angles` for many designs
and points at once (no Python work per design): the motor angles that place each design's end
effector at each point, with the same choice among the solutions (the largest transmission
margin, then the largest theta1), NaN where a point is out of reach in the operating range."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from qsm.physics.inverse_kinematics import THETA1_RANGE_DEG, THETA2_MIN_DEG, in_operating_range
from qsm.physics.kinematics import as_design, pose

#: Branch check: a candidate's D from the forward kinematics within this (m, per m of l1 >= 1).
_BRANCH_TOL_M = 1e-6


def _intersections(
    centre: NDArray, r0: NDArray, r1: NDArray
) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """Both intersections (..., 2, 2) of the circles |x| = r0 and |x - centre| = r1, and where
    they exist (...)."""
    d = np.linalg.norm(centre, axis=-1)
    safe = np.where(d > 0, d, 1.0)
    a = (r0 * r0 - r1 * r1 + d * d) / (2 * safe)
    h2 = r0 * r0 - a * a
    ok = (d > 0) & (d <= r0 + r1 + 1e-12) & (d >= np.abs(r0 - r1) - 1e-12)
    h = np.sqrt(np.maximum(h2, 0.0))
    unit = centre / safe[..., None]
    mid = a[..., None] * unit
    normal = np.stack([-unit[..., 1], unit[..., 0]], axis=-1)
    both = np.stack([mid + h[..., None] * normal, mid - h[..., None] * normal], axis=-2)
    return both, ok


def _candidates(d: NDArray, p: NDArray) -> tuple[NDArray, NDArray[np.bool_], NDArray]:
    """The four (theta1, theta2) candidates (N, P, 4, 2) of designs (N, 6) at points (P, 2),
    which are real circle intersections, and the rocker point D (N, P, 2, 2) of each theta1."""
    l1, l2, l3, l4, ee_x, ee_y = (d[:, k, None] for k in range(6))
    pts = np.broadcast_to(p[None], (len(d), len(p), 2))
    b, ok_b = _intersections(pts, l1, np.hypot(ee_x, ee_y))  # (N, P, 2, 2)
    t1 = np.arctan2(b[..., 1], b[..., 0])  # (N, P, 2)
    pb = pts[:, :, None, :] - b
    phi = np.arctan2(pb[..., 1], pb[..., 0]) + np.arctan2(ee_y, ee_x)[..., None]
    dpt = b - l4[..., None, None] * np.stack([np.cos(phi), np.sin(phi)], axis=-1)
    c, ok_c = _intersections(dpt, l2[..., None], l3[..., None])  # (N, P, 2, 2, 2)
    t2 = np.arctan2(c[..., 1], c[..., 0])
    theta = np.stack([np.broadcast_to(t1[..., None], t2.shape), t2], axis=-1)
    ok = np.broadcast_to(ok_b[..., None, None] & ok_c[..., None], t2.shape)
    return theta.reshape(len(d), len(p), 4, 2), ok.reshape(len(d), len(p), 4), dpt


def batch_joint_angles(
    designs: ArrayLike,
    points: ArrayLike,
    theta1_range_deg: tuple[float, float] = THETA1_RANGE_DEG,
    theta2_min_deg: float = THETA2_MIN_DEG,
) -> NDArray[np.float64]:
    """Motor angles (N, P, 2) rad placing designs (N, 6) m at points (P, 2) m, as
    :func:`qsm.physics.inverse_kinematics.joint_angles` chooses them; NaN where none exists."""
    d = np.atleast_2d(as_design(designs)).astype(float)
    p = np.asarray(points, dtype=float).reshape(-1, 2)
    if not d.size or not p.size:
        return np.full((len(d), len(p), 2), np.nan)
    theta, ok, dpt = _candidates(d, p)
    theta = np.mod(theta + math.pi, 2 * math.pi) - math.pi
    theta = np.where(theta <= -math.pi + 1e-12, theta + 2 * math.pi, theta)
    at = pose(d, theta[..., 0].reshape(len(d), -1), theta[..., 1].reshape(len(d), -1))
    shape = theta.shape[:-1]
    d_pose = at.D.reshape(*shape, 2)
    d_want = np.repeat(dpt, 2, axis=-2).reshape(*shape, 2)
    tol = _BRANCH_TOL_M * np.maximum(d[:, 0], 1.0)[:, None, None]
    ok &= at.closes.reshape(shape) & (np.linalg.norm(d_pose - d_want, axis=-1) <= tol)
    ok &= in_operating_range(theta, theta1_range_deg, theta2_min_deg)
    u = (at.B - at.D).reshape(*shape, 2)
    v = (at.C - at.D).reshape(*shape, 2)
    cross = np.abs(u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0])
    sin_t = cross / (np.linalg.norm(u, axis=-1) * np.linalg.norm(v, axis=-1))
    score = np.where(ok, sin_t, -np.inf)
    best = score.max(axis=-1, keepdims=True)
    tie = ok & (score == best)
    pick = np.argmax(np.where(tie, theta[..., 0], -np.inf), axis=-1)
    out = np.take_along_axis(theta, pick[..., None, None], axis=-2)[..., 0, :]
    return np.where(ok.any(axis=-1)[..., None], out, np.nan)
