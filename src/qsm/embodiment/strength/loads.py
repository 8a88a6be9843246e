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
from qsm.physics.dynamics import LoopState, components_first
from qsm.physics.kinematics import LINK_NAMES, as_design
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


def link_motion(designs: ArrayLike, state: LoopState) -> LinkMotion:
    """Link-frame motion of ``designs`` (..., 6) m from their loop state (..., N)."""
    d = as_design(designs)
    l1, l2 = d[..., 0, None], d[..., 1, None]
    q, qd, qdd = state.q, state.qd, state.qdd
    lead = q.shape[:-1]
    cos, sin, omega, alpha = (components_first(*lead, last=(4,)) for _ in range(4))
    for x, out in ((qd, omega), (qdd, alpha)):
        out[..., 0], out[..., 1] = x[..., 0], x[..., 2]
        np.add(x[..., 2], x[..., 3], out=out[..., 2])
        np.add(x[..., 0], x[..., 1], out=out[..., 3])
    # the motor angles (often the duty's, shared by all designs: then computed once); the
    # coupler's and the upper arm's angles are the loop's psi and phi
    for k, joint in enumerate((0, 2)):
        angle = q[..., joint].reshape(-1, q.shape[-2])
        if (angle == angle[:1]).all():
            angle = angle[0]
        cos[..., k], sin[..., k] = np.cos(angle), np.sin(angle)
    cos[..., 2], sin[..., 2] = state.coupler_dir[..., 0], state.coupler_dir[..., 1]
    cos[..., 3], sin[..., 3] = state.rocker_dir[..., 0], state.rocker_dir[..., 1]
    origin, origin_acc = components_first(*lead, last=(4, 2)), components_first(*lead, last=(4, 2))
    origin[..., :2, :], origin_acc[..., :2, :] = 0.0, 0.0
    # B and C: the far ends of the lower arm and the crank, the upper arm's and coupler's origins
    for link, slot, length in ((0, 3, l1), (1, 2, l2)):
        c, s, a = cos[..., link], sin[..., link], alpha[..., link]
        w2 = omega[..., link] ** 2
        origin[..., slot, 0], origin[..., slot, 1] = length * c, length * s
        origin_acc[..., slot, 0] = length * (a * -s - w2 * c)
        origin_acc[..., slot, 1] = length * (a * c - w2 * s)
    return LinkMotion(cos, sin, omega, alpha, origin, origin_acc)


class _Point(NamedTuple):
    """World position (x, y) and acceleration (ax, ay; None when not asked for) of a link-frame
    point, each (..., N)."""

    x: NDArray[np.float64]
    y: NDArray[np.float64]
    ax: NDArray[np.float64] | None
    ay: NDArray[np.float64] | None


def _point(mo: LinkMotion, px: NDArray, py: NDArray | None, link: int, acc: bool = True) -> _Point:
    """:class:`_Point` of the link-frame point (px, py) (..., 1; py None: 0) of link ``link``."""
    c, s = mo.cos[..., link], mo.sin[..., link]
    rx, ry = (c * px, s * px) if py is None else (c * px - s * py, s * px + c * py)
    o = mo.origin[..., link, :]
    x, y = o[..., 0] + rx, o[..., 1] + ry
    if not acc:
        return _Point(x, y, None, None)
    w2, a = mo.omega[..., link] ** 2, mo.alpha[..., link]
    oa = mo.origin_acc[..., link, :]
    return _Point(x, y, oa[..., 0] + a * -ry - w2 * rx, oa[..., 1] + a * rx - w2 * ry)


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
    g = GRAVITY[1]

    def resultant(k: int, o: tuple[NDArray, NDArray] | None) -> tuple[NDArray, ...]:
        """m (a_c - g) and I alpha + (c - o) x m (a_c - g) of link k (what its joints must
        supply), o = (x, y) (None: A, the origin)."""
        com = inertials.com_m[..., k, None, :]
        p = _point(mo, com[..., 0], com[..., 1], k)
        m = inertials.mass_kg[..., k, None]
        fx, fy = m * p.ax, m * (p.ay - g)
        rx, ry = (p.x, p.y) if o is None else (p.x - o[0], p.y - o[1])
        return fx, fy, inertials.izz_kg_m2[..., k, None] * mo.alpha[..., k] + (rx * fy - ry * fx)

    lower, crank, coupler, upper = range(4)
    bx, by = mo.origin[..., upper, 0], mo.origin[..., upper, 1]
    cx, cy = mo.origin[..., coupler, 0], mo.origin[..., coupler, 1]
    e = _point(mo, d[..., 4, None], -d[..., 5, None], upper)
    dp = _point(mo, -d[..., 3, None], None, upper, acc=False)
    # the results, a_lower ... tau, each component one contiguous block
    out = np.empty((len(JointLoads._fields), 2, *bx.shape))
    a_l, a_k, f_b, f_c, f_d, f_e, tau = out
    fex = np.multiply(payload_kg, 0.0 - e.ax, out=f_e[0])  # payload on the upper arm at E
    fey = np.multiply(payload_kg, g - e.ay, out=f_e[1])
    fcpx, fcpy, m_cp = resultant(coupler, (cx, cy))
    fux, fuy, m_u = resultant(upper, (bx, by))
    # (D - C) x d = m_cp;  (D - B) x d = (E - B) x f_e - m_u
    r1x, r1y, r2x, r2y = dp.x - cx, dp.y - cy, dp.x - bx, dp.y - by
    rhs2 = ((e.x - bx) * fey - (e.y - by) * fex) - m_u
    det = r1x * r2y - r1y * r2x
    with np.errstate(invalid="ignore", divide="ignore"):
        fdx = np.divide(m_cp * r2x - rhs2 * r1x, det, out=f_d[0])
        fdy = np.divide(m_cp * r2y - rhs2 * r1y, det, out=f_d[1])
    fcx, fcy = np.subtract(fcpx, fdx, out=f_c[0]), np.subtract(fcpy, fdy, out=f_c[1])
    fbx, fby = np.subtract(fux + fdx, fex, out=f_b[0]), np.subtract(fuy + fdy, fey, out=f_b[1])
    flx, fly, m_l = resultant(lower, None)
    fkx, fky, m_k = resultant(crank, None)
    for dst, x, y in (
        (a_l[0], flx, fbx),
        (a_l[1], fly, fby),
        (a_k[0], fkx, fcx),
        (a_k[1], fky, fcy),
    ):
        np.add(x, y, out=dst)
    np.add(m_l, bx * fby - by * fbx, out=tau[0])
    np.add(m_k, cx * fcy - cy * fcx, out=tau[1])
    return JointLoads(*(np.moveaxis(v, 0, -1) for v in out))
