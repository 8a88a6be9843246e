"""Joint forces and motor torques of the closed chain over a duty, by Newton-Euler on each link.

Given the loop-consistent motion (:func:`qsm.physics.dynamics.loop_state`), each rigid link obeys
F = m a_c and M_c = I alpha in the plane. With the payload a point mass at E (force
``m_p (g - a_E)`` on the upper arm) the unknowns follow in closed form:

1. coupler moments about C and upper-arm moments about B give the coupler force ``d`` (on the
   coupler at D from the upper arm; a 2 x 2 system, singular where C, D, B are collinear);
2. force balances give ``c`` (crank on coupler at C), ``b`` (lower arm on upper arm at B),
   ``a_lower`` and ``a_crank`` (the base on each link at A);
3. moments about A give the motor torques ``tau`` (on the lower arm and the crank, about +z).

Every force is in the world frame (N), gravity along -y. The same arithmetic runs on one design
or a population (leading axes broadcast), so the optimisation's strength constraint and Stage 2's
strength columns share it; tests check it against MuJoCo's torques and coupler force.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from qsm.physics.cad import MassProperties
from qsm.physics.dynamics import LoopState
from qsm.physics.kinematics import LINK_NAMES, as_design, cross, perp
from qsm.physics.mjcf import GRAVITY_M_S2

GRAVITY = np.array([0.0, -GRAVITY_M_S2])


class Inertials(NamedTuple):
    """Mass properties of the four links (:data:`qsm.physics.kinematics.LINK_NAMES` order) of one or
    more designs: mass_kg (..., 4), com_m (..., 4, 2) in the link frames, izz_kg_m2 (..., 4) about
    the centre of mass."""

    mass_kg: NDArray[np.float64]
    com_m: NDArray[np.float64]
    izz_kg_m2: NDArray[np.float64]

    @classmethod
    def of(cls, props: dict[str, MassProperties]) -> Inertials:
        """From :func:`qsm.physics.cad.mass_properties` of one design."""
        return cls(
            np.array([props[k].mass_kg for k in LINK_NAMES]),
            np.array([props[k].com_m[:2] for k in LINK_NAMES]),
            np.array([props[k].inertia_kg_m2[2, 2] for k in LINK_NAMES]),
        )


class LinkMotion(NamedTuple):
    """Planar motion of the four link frames (:data:`LINK_NAMES` order) at the duty samples:
    cos and sin (..., N, 4) of their angles, omega (..., N, 4) rad/s, alpha (..., N, 4) rad/s^2,
    origin (..., N, 4, 2) m and origin_acc (..., N, 4, 2) m/s^2 (world frame; frames of
    :mod:`qsm.physics.cad`)."""

    cos: NDArray[np.float64]
    sin: NDArray[np.float64]
    omega: NDArray[np.float64]
    alpha: NDArray[np.float64]
    origin: NDArray[np.float64]
    origin_acc: NDArray[np.float64]

    def rotate_to_link(self, vec: NDArray[np.float64], link: int) -> NDArray[np.float64]:
        """World vectors (..., N, 2) expressed in the frame of link ``link`` (index)."""
        c, s = self.cos[..., link], self.sin[..., link]
        return np.stack([c * vec[..., 0] + s * vec[..., 1], c * vec[..., 1] - s * vec[..., 0]], -1)

    def accel(self, point: NDArray[np.float64], link: int) -> NDArray[np.float64]:
        """World acceleration (..., N, 2) of the link-frame point (..., 2) of link ``link``."""
        c, s = self.cos[..., link], self.sin[..., link]
        p = np.asarray(point)[..., None, :]
        r = np.stack([c * p[..., 0] - s * p[..., 1], s * p[..., 0] + c * p[..., 1]], -1)
        w, a = self.omega[..., link, None], self.alpha[..., link, None]
        return self.origin_acc[..., link, :] + a * perp(r) - w**2 * r

    def world(self, point: NDArray[np.float64], link: int) -> NDArray[np.float64]:
        """World position (..., N, 2) of the link-frame point (..., 2) of link ``link``."""
        c, s = self.cos[..., link], self.sin[..., link]
        p = np.asarray(point)[..., None, :]
        r = np.stack([c * p[..., 0] - s * p[..., 1], s * p[..., 0] + c * p[..., 1]], -1)
        return self.origin[..., link, :] + r


class JointLoads(NamedTuple):
    """World-frame joint forces (..., N, 2) in N at the duty samples (see the module docstring)
    and the motor torques ``tau`` (..., N, 2) in N m; NaN where the loop does not close."""

    a_lower: NDArray[np.float64]
    a_crank: NDArray[np.float64]
    b: NDArray[np.float64]
    c: NDArray[np.float64]
    d: NDArray[np.float64]
    e: NDArray[np.float64]
    tau: NDArray[np.float64]


def _dir(angle: NDArray[np.float64]) -> NDArray[np.float64]:
    return np.stack([np.cos(angle), np.sin(angle)], axis=-1)


def link_motion(designs: ArrayLike, state: LoopState) -> LinkMotion:
    """Link-frame motion of ``designs`` (..., 6) m from their loop state (..., N)."""
    d = as_design(designs)
    l1, l2 = d[..., 0, None, None], d[..., 1, None, None]
    q, qd, qdd = state.q, state.qd, state.qdd
    angle = np.stack([q[..., 0], q[..., 2], q[..., 2] + q[..., 3], q[..., 0] + q[..., 1]], -1)
    omega = np.stack([qd[..., 0], qd[..., 2], qd[..., 2] + qd[..., 3], qd[..., 0] + qd[..., 1]], -1)
    alpha = np.stack(
        [qdd[..., 0], qdd[..., 2], qdd[..., 2] + qdd[..., 3], qdd[..., 0] + qdd[..., 1]], -1
    )
    e1, e2 = _dir(q[..., 0]), _dir(q[..., 2])
    b_pos, c_pos = l1 * e1, l2 * e2
    b_acc = l1 * (qdd[..., 0, None] * perp(e1) - qd[..., 0, None] ** 2 * e1)
    c_acc = l2 * (qdd[..., 2, None] * perp(e2) - qd[..., 2, None] ** 2 * e2)
    zero = np.zeros_like(b_pos)
    origin = np.stack([zero, zero, c_pos, b_pos], axis=-2)
    origin_acc = np.stack([zero, zero, c_acc, b_acc], axis=-2)
    return LinkMotion(np.cos(angle), np.sin(angle), omega, alpha, origin, origin_acc)


def joint_loads(
    designs: ArrayLike,
    inertials: Inertials,
    payload_kg: float,
    state: LoopState,
    motion: LinkMotion | None = None,
) -> JointLoads:
    """Joint forces and motor torques of ``designs`` (..., 6) m with link ``inertials`` (leading
    axes as the designs) and ``payload_kg`` at E, over the loop-consistent ``state``."""
    d = as_design(designs)
    mo = link_motion(d, state) if motion is None else motion
    m = inertials.mass_kg[..., None, :]  # (..., 1, 4)
    izz = inertials.izz_kg_m2[..., None, :]
    lower, crank, coupler, upper = range(4)

    def com(k: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """World position and acceleration of link k's centre of mass."""
        return mo.world(inertials.com_m[..., k, :], k), mo.accel(inertials.com_m[..., k, :], k)

    def resultant(k: int, about: NDArray[np.float64]) -> tuple[NDArray, NDArray]:
        """m (a_c - g) and I alpha + (c - about) x m (a_c - g) of link k (what its joints must
        supply)."""
        pos, acc = com(k)
        f = m[..., k, None] * (acc - GRAVITY)
        return f, izz[..., k] * mo.alpha[..., k] + cross(pos - about, f)

    zero = np.zeros(2)
    a_pos = np.broadcast_to(zero, mo.origin[..., 0, :].shape)
    b_pos, c_pos = mo.origin[..., upper, :], mo.origin[..., coupler, :]
    ee = np.stack([d[..., 4], -d[..., 5]], axis=-1)
    e_pos = mo.world(ee, upper)
    d_pos = mo.world(np.stack([-d[..., 3], np.zeros_like(d[..., 3])], -1), upper)
    f_e = payload_kg * (GRAVITY - mo.accel(ee, upper))  # payload on the upper arm at E
    f_cp, m_cp = resultant(coupler, c_pos)
    f_u, m_u = resultant(upper, b_pos)
    # (D - C) x d = m_cp;  (D - B) x d = (E - B) x f_e - m_u
    r1, r2 = d_pos - c_pos, d_pos - b_pos
    rhs2 = cross(e_pos - b_pos, f_e) - m_u
    det = cross(r1, r2)
    with np.errstate(invalid="ignore", divide="ignore"):
        fd = (
            np.stack(
                [(m_cp * r2[..., 0] - rhs2 * r1[..., 0]), (m_cp * r2[..., 1] - rhs2 * r1[..., 1])],
                -1,
            )
            / det[..., None]
        )
    fc = f_cp - fd
    fb = f_u + fd - f_e
    f_l, m_l = resultant(lower, a_pos)
    f_k, m_k = resultant(crank, a_pos)
    tau = np.stack([m_l + cross(b_pos, fb), m_k + cross(c_pos, fc)], axis=-1)
    return JointLoads(f_l + fb, f_k + fc, fb, fc, fd, f_e, tau)
