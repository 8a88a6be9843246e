"""Planar kinematics of the quasi-serial mechanism (paper Section 4, Eqs. for a, zeta, xi, x, y).

Frame (the seed's): the base joint A is the origin, gravity is -y.

* lower arm (l1):  B = l1 dir(theta1), driven by motor 1 at A;
* crank (l2):      C = l2 dir(theta2), driven by motor 2 at A;
* coupler (l3):    from C to the rocker point D;
* upper arm:       a rigid bell-crank pivoting at B that holds the rocker point
  D = B - l4 dir(phi) and the end effector E = B + EE_x dir(phi) + EE_y dir(phi - pi/2),
  with phi = theta1 + zeta + xi.

zeta is the *signed* angle from BA to BC. The seed writes it as an unsigned arccos, which picks the
mirror assembly when theta1 - theta2 > 180 deg (allowed by the operating range, up to 217.5 deg) and
then violates |CD| = l3; the signed angle keeps the assembly mode continuous (docs/stages.md:
The mechanism).

A design is the vector of the 6 lengths ``(l1, l2, l3, l4, ee_x, ee_y)``; every function accepts a
single design of shape (6,) or a batch of shape (N, 6) and broadcasts it against the joint angles.
Angles are in radians, lengths in the design's unit (metres for scaled designs).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

DESIGN_NAMES: tuple[str, ...] = ("l1", "l2", "l3", "l4", "ee_x", "ee_y")
#: The four links (their solids in :mod:`qsm.physics.cad`).
LINK_NAMES: tuple[str, ...] = ("lower_arm", "crank", "coupler", "upper_arm")
RATIO_NAMES: tuple[str, ...] = DESIGN_NAMES[1:]
#: Table columns of the 6 scaled lengths (m).
DESIGN_COLUMNS: tuple[str, ...] = tuple(f"{name}_m" for name in DESIGN_NAMES)


def as_design(design: ArrayLike) -> NDArray[np.float64]:
    """Return ``design`` as a float array whose last axis holds the 6 lengths."""
    d = np.asarray(design, dtype=float)
    if d.shape[-1] != 6:
        raise ValueError(f"a design has 6 lengths {DESIGN_NAMES}, got shape {d.shape}")
    return d


def design_from_ratios(ratios: ArrayLike, scale: ArrayLike = 1.0) -> NDArray[np.float64]:
    """Scaled design (l1 = scale) from the 5 ratios ``(l2, l3, l4, ee_x, ee_y)`` to l1."""
    r = np.asarray(ratios, dtype=float)
    if r.shape[-1] != 5:
        raise ValueError(f"ratios are 5 values {RATIO_NAMES}, got shape {r.shape}")
    s = np.asarray(scale, dtype=float)[..., None]
    ones = np.ones((*r.shape[:-1], 1))
    return np.concatenate([ones, r], axis=-1) * s


def _columns(design: ArrayLike, extra_dims: int = 0) -> list[NDArray[np.float64]]:
    d = as_design(design)
    cols = [d[..., i] for i in range(6)]
    return [c.reshape(c.shape + (1,) * extra_dims) for c in cols]


def relative_arm_angle(
    ratios: ArrayLike, delta: ArrayLike
) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """Angle ``zeta + xi`` of the upper arm relative to the lower arm, and where the loop closes.

    Depends only on the ratios and on ``delta = theta1 - theta2`` (rad). ``ratios`` is (..., 5)
    broadcast against ``delta``. Where the loop cannot close the angle is NaN.
    """
    r = np.asarray(ratios, dtype=float)
    l2, l3, l4 = r[..., 0], r[..., 1], r[..., 2]
    cos_d, sin_d = np.cos(delta), np.sin(delta)
    # B at (1, 0) and A at the origin, C = l2 dir(-delta) after rotating by -theta1.
    bc_x, bc_y = l2 * cos_d - 1.0, -l2 * sin_d
    a = np.hypot(bc_x, bc_y)
    # signed angle from BA = (-1, 0) to BC
    zeta = np.arctan2(-bc_y, -bc_x)
    cos_xi = (l4**2 + a**2 - l3**2) / (2.0 * l4 * a)
    closes = np.abs(cos_xi) <= 1.0
    xi = np.arccos(np.clip(cos_xi, -1.0, 1.0))
    return np.where(closes, zeta + xi, np.nan), closes


class LoopPose(NamedTuple):
    """Joint positions of the mechanism at given motor angles; arrays of shape (..., 2)."""

    B: NDArray[np.float64]
    C: NDArray[np.float64]
    D: NDArray[np.float64]
    E: NDArray[np.float64]
    phi: NDArray[np.float64]  # absolute angle of the upper arm's EE_x axis (rad)
    closes: NDArray[np.bool_]


def perp(v: ArrayLike) -> NDArray[np.float64]:
    """Plane vectors (..., 2) rotated by +90 degrees."""
    w = np.asarray(v, dtype=float)
    return np.stack([-w[..., 1], w[..., 0]], axis=-1)


def cross(a: ArrayLike, b: ArrayLike) -> NDArray[np.float64]:
    """z-component of the cross product of plane vectors (..., 2)."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def _dir(angle: NDArray[np.float64]) -> NDArray[np.float64]:
    return np.stack([np.cos(angle), np.sin(angle)], axis=-1)


def pose(design: ArrayLike, theta1: ArrayLike, theta2: ArrayLike) -> LoopPose:
    """Positions of B, C, D, E for motor angles ``theta1``, ``theta2`` (rad, broadcast with design).

    A design batch (N, 6) broadcasts against angle arrays of shape (N,) or (N, K) when the angles
    carry one more axis than the batch: pass angles of shape (N, K) to evaluate K poses per design.
    """
    t1, t2 = np.asarray(theta1, dtype=float), np.asarray(theta2, dtype=float)
    d = as_design(design)
    extra = max(t1.ndim, t2.ndim) - (d.ndim - 1)
    l1, l2, l3, l4, ee_x, ee_y = _columns(d, max(extra, 0))
    ratios = np.stack([l2 / l1, l3 / l1, l4 / l1], axis=-1)
    rel, closes = relative_arm_angle(ratios, t1 - t2)
    phi = t1 + rel
    B = l1[..., None] * _dir(t1)
    C = l2[..., None] * _dir(t2)
    u = _dir(phi)
    D = B - l4[..., None] * u
    E = B + ee_x[..., None] * u + ee_y[..., None] * _dir(phi - np.pi / 2)
    return LoopPose(B=B, C=C, D=D, E=E, phi=phi, closes=np.broadcast_to(closes, phi.shape))


def end_effector(design: ArrayLike, theta1: ArrayLike, theta2: ArrayLike) -> NDArray[np.float64]:
    """End-effector position (..., 2) for motor angles in rad; NaN where the loop does not close."""
    return pose(design, theta1, theta2).E


def loop_closes_everywhere(ratios: ArrayLike, delta_max: float) -> NDArray[np.bool_]:
    """Whether the loop closes for every ``delta = theta1 - theta2`` in ``[0, delta_max]`` (rad).

    |BC| = sqrt(1 + l2^2 - 2 l2 cos delta) sweeps from 1 - l2 up to its largest value on the
    interval; the loop closes iff |l3 - l4| <= |BC| <= l3 + l4 over that whole range.
    """
    r = np.asarray(ratios, dtype=float)
    l2, l3, l4 = r[..., 0], r[..., 1], r[..., 2]
    a_min, a_max = bc_range(l2, delta_max)
    return (np.abs(l3 - l4) <= a_min) & (a_max <= l3 + l4)


def bc_range(l2: ArrayLike, delta_max: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Smallest and largest |BC| (in units of l1) for delta in [0, delta_max] rad."""
    l2 = np.asarray(l2, dtype=float)
    cos_min = -1.0 if delta_max >= np.pi else np.cos(delta_max)
    return 1.0 - l2, np.sqrt(1.0 + l2**2 - 2.0 * l2 * cos_min)


def transmission_angle_range(
    ratios: ArrayLike, delta_max: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Smallest and largest transmission angle at D (between coupler DC and rocker DB), rad.

    The angle is a monotone function of |BC|, so its extremes occur at the ends of ``bc_range``.
    At 0 or pi the coupler and rocker align and the motor torques grow without bound.
    """
    r = np.asarray(ratios, dtype=float)
    l2, l3, l4 = r[..., 0], r[..., 1], r[..., 2]
    a_min, a_max = bc_range(l2, delta_max)

    def mu(a: NDArray[np.float64]) -> NDArray[np.float64]:
        return np.arccos(np.clip((l3**2 + l4**2 - a**2) / (2 * l3 * l4), -1.0, 1.0))

    return mu(a_min), mu(a_max)
