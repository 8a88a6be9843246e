"""Analytic inverse kinematics of the quasi-serial mechanism (inverse of
qsm.physics.kinematics.pose).

For an end-effector point P (m, base frame):

1. |P - B| = R = hypot(EE_x, EE_y) with B = l1 dir(theta1): a circle-circle intersection gives up
   to two theta1;
2. each theta1 fixes the upper arm: E - B = R dir(phi - alpha), alpha = atan2(EE_y, EE_x), so
   phi = atan2(P - B) + alpha and D = B - l4 dir(phi);
3. C on |C| = l2 and |C - D| = l3 gives up to two theta2.

A candidate is kept when it lies in the operating range (theta1_min <= theta1 <= theta1_max,
theta2_min <= theta2 <= theta1) and on the assembly branch of :func:`qsm.physics.kinematics.pose`,
i.e.
``pose(design, theta1, theta2)`` closes and reproduces D (the other circle intersection is the
mirror assembly). Angles are in radians, wrapped to (-pi, pi].
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from qsm import prose
from qsm.physics.kinematics import as_design, pose
from qsm.schema.defaults import default

#: The motor ranges (deg) of the config's default ``operating_range`` (the paper's).
THETA1_RANGE_DEG: tuple[float, float] = default("operating_range.theta1_deg")
THETA2_MIN_DEG: float = default("operating_range.theta2_min_deg")
_TOL_M = 1e-9  # relative to l1 for the branch check
_TOL_RAD = 1e-9


def _wrap(a: NDArray[np.float64]) -> NDArray[np.float64]:
    """Wrap angles to (-pi, pi]."""
    w = np.mod(a + np.pi, 2 * np.pi) - np.pi
    return np.where(w <= -np.pi + 1e-12, w + 2 * np.pi, w)


def _circle_intersections(
    c0: NDArray[np.float64], r0: float, c1: NDArray[np.float64], r1: float
) -> NDArray[np.float64]:
    """Intersections (k, 2), k in {0, 1, 2}, of circles (centre, radius) in the plane."""
    d_vec = c1 - c0
    d = float(np.hypot(*d_vec))
    if d == 0.0 or d > r0 + r1 + 1e-12 or d < abs(r0 - r1) - 1e-12:
        return np.empty((0, 2))
    a = (r0**2 - r1**2 + d**2) / (2 * d)
    h = math.sqrt(max(r0**2 - a**2, 0.0))
    mid = c0 + a * d_vec / d
    perp = np.array([-d_vec[1], d_vec[0]]) / d
    if h == 0.0:
        return mid[None]
    return np.stack([mid + h * perp, mid - h * perp])


def all_solutions(design: ArrayLike, point: ArrayLike) -> NDArray[np.float64]:
    """Every (theta1, theta2) (k, 2) in rad, wrapped to (-pi, pi], on the assembly branch of
    :func:`qsm.physics.kinematics.pose` that places the end effector at ``point`` (m); operating
    range not applied."""
    d = as_design(design)
    if d.ndim != 1:
        raise ValueError("all_solutions takes one design of 6 lengths")
    l1, l2, l3, l4, ee_x, ee_y = (float(v) for v in d)
    p = np.asarray(point, dtype=float)
    radius, alpha = math.hypot(ee_x, ee_y), math.atan2(ee_y, ee_x)
    out = []
    for b in _circle_intersections(np.zeros(2), l1, p, radius):
        t1 = math.atan2(b[1], b[0])
        pb = p - b
        phi = math.atan2(pb[1], pb[0]) + alpha
        d_pt = b - l4 * np.array([math.cos(phi), math.sin(phi)])
        for c in _circle_intersections(np.zeros(2), l2, d_pt, l3):
            t2 = math.atan2(c[1], c[0])
            ps = pose(d, t1, t2)
            if bool(ps.closes) and np.hypot(*(ps.D - d_pt)) <= _TOL_M * max(l1, 1.0) * 1e3:
                out.append((t1, t2))
    sols = _wrap(np.asarray(out, dtype=float).reshape(-1, 2))
    return np.unique(np.round(sols, 12), axis=0) if len(sols) else sols


def in_operating_range(
    theta: ArrayLike,
    theta1_range_deg: tuple[float, float] = THETA1_RANGE_DEG,
    theta2_min_deg: float = THETA2_MIN_DEG,
) -> NDArray[np.bool_]:
    """Whether motor angles (..., 2) in rad lie in the operating range."""
    th = np.asarray(theta, dtype=float)
    t1, t2 = th[..., 0], th[..., 1]
    lo, hi = math.radians(theta1_range_deg[0]), math.radians(theta1_range_deg[1])
    return (
        (t1 >= lo - _TOL_RAD)
        & (t1 <= hi + _TOL_RAD)
        & (t2 >= math.radians(theta2_min_deg) - _TOL_RAD)
        & (t2 <= t1 + _TOL_RAD)
    )


def joint_angles(
    design: ArrayLike,
    point: ArrayLike,
    theta1_range_deg: tuple[float, float] = THETA1_RANGE_DEG,
    theta2_min_deg: float = THETA2_MIN_DEG,
    prefer: ArrayLike | None = None,
) -> tuple[float, float]:
    """Motor angles (theta1, theta2) in rad placing the end effector of ``design`` at ``point`` (m).

    Among the solutions in the operating range on the assembly branch of
    :func:`qsm.physics.kinematics.pose`, returns the one closest (in joint space) to ``prefer``
    (rad) when given, else the one with the largest transmission margin (largest theta1 on a tie).
    Raises ``ValueError`` naming the point when none exists.
    """
    sols = all_solutions(design, point)
    ok = sols[in_operating_range(sols, theta1_range_deg, theta2_min_deg)] if len(sols) else sols
    if not len(ok):
        p = np.asarray(point, dtype=float)
        why = "outside the workspace" if not len(sols) else "reachable only outside the range"
        raise ValueError(
            f"point {prose.point(p, 4)} is {why} of the design of lengths "
            f"{prose.listed(1e3 * as_design(design), 1, 'mm')} (theta1 {theta1_range_deg[0]:g} to "
            f"{theta1_range_deg[1]:g} deg, theta2 at least {theta2_min_deg:g} deg)"
        )
    if prefer is not None:
        k = int(np.argmin(np.linalg.norm(ok - np.asarray(prefer, dtype=float), axis=1)))
    else:
        k = int(np.lexsort((-ok[:, 0], -_sin_transmission(design, ok)))[0])
    return float(ok[k, 0]), float(ok[k, 1])


def _sin_transmission(design: ArrayLike, theta: NDArray[np.float64]) -> NDArray[np.float64]:
    """|sin| of the transmission angle at D for motor angles (k, 2)."""
    p = pose(design, theta[:, 0], theta[:, 1])
    u, v = p.B - p.D, p.C - p.D
    cross = u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]
    return np.abs(cross) / (np.linalg.norm(u, axis=1) * np.linalg.norm(v, axis=1))


def joint_path(
    design: ArrayLike,
    points: ArrayLike,
    theta1_range_deg: tuple[float, float] = THETA1_RANGE_DEG,
    theta2_min_deg: float = THETA2_MIN_DEG,
) -> NDArray[np.float64]:
    """Motor angles (n, 2) in rad for task points (n, 2) in m, each solution chosen closest to the
    previous one (the first by :func:`joint_angles`' default rule)."""
    out: list[tuple[float, float]] = []
    for p in np.asarray(points, dtype=float):
        prefer = out[-1] if out else None
        out.append(joint_angles(design, p, theta1_range_deg, theta2_min_deg, prefer))
    return np.asarray(out)
