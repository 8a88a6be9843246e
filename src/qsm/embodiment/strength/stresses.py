"""Strength of every link over the duty: bar stresses, bores, pin-loaded lugs and buckling.

Each link is a flat plate of the CAD section (width ``w`` in the plane, thickness ``t``; bosses of
radius ``R`` with a bore at every joint but E, of diameter ``d_b`` given per joint A-D: the joint's
bearing seat, or at A the motor shaft; :mod:`qsm.embodiment.strength.link_checks` chooses them). It
is analysed as a beam along its spine (the straight bars between the joint centres; the upper arm's
spine is D - B - E' - E) under the joint forces of :mod:`qsm.embodiment.strength.loads`, its weight
and its d'Alembert inertia. The link's mass is spread evenly along its spine (a simplification: the
bosses hold more than the bars; a finite-element comparison bounds the error, docs/strength.md).

At a cut through the spine the piece beyond the cut (away from the motor for the lower arm and the
crank, away from C for the coupler, towards D or E for the upper arm) gives the axial force N and
the in-plane bending moment M (the distributed load's moment by Simpson's rule, exact for its
linear variation). Checks:

* bar, at the boss edges and mid-span: ``|N| / (w t) + 6 |M| / (t w^2)``; at the upper arm's
  filleted inside corner E' (:data:`CORNER_CUTS`) times ``corner_stress_concentration``;
* net section through a bore where a moment passes (A of the lower arm and crank, B of the upper
  arm): ``|N| / (t (2R - d_b)) + |M| R / I_net`` with ``I_net = t ((2R)^3 - d_b^3) / 12``;
* pin-loaded lug at every bore: ``K_t |F| / (t (2R - d_b))`` (F the joint force, K_t
  ``lug_stress_concentration``);
* Euler buckling of every bar ever in compression (the lower arm, the crank, the coupler and the
  upper arm's D-B leg), about the weaker axis (``I = min(w t^3, t w^3) / 12``), between its joint
  centres, pinned at both ends (K = 1): the joints are held in place by their shafts and bearings
  and free to rotate. That is conservative for the lower arm and the crank, which the motor shaft
  clamps at A (fixed-pinned, K = 0.7); it is not if a joint can sway out of the plane, which the
  buckling safety factor is meant to cover. Bending-compression interaction is not modelled.

The safety factor of a link is yield / peak stress, its buckling factor the Euler load over the
peak compression. It holds when both reach
:class:`qsm.embodiment.strength.material.StrengthSettings`' factors; the utilisation ``max(stress *
safety_factor / yield, compression * buckling_safety_factor / Euler load)`` is at most 1 then, and
g13 is the largest utilisation minus 1 over the links.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from qsm.embodiment.strength.beam import LOADS, Cuts, Section, link_cuts
from qsm.embodiment.strength.loads import GRAVITY, Inertials, JointLoads, LinkMotion
from qsm.embodiment.strength.material import Material, StrengthSettings
from qsm.physics.kinematics import LINK_NAMES, as_design, cross

#: Euler effective-length factor (K) of every member checked for buckling: pinned-pinned.
BUCKLING_K = 1.0


#: Joints with a bore (A-D, the order of the bore diameters) and, per link, the joint of the bore
#: its net-section cuts pass through.
JOINTS: tuple[str, ...] = ("A", "B", "C", "D")
NET_SECTION_JOINT: dict[str, str] = {"lower_arm": "A", "crank": "A", "upper_arm": "B"}
#: Bored joints of each link and the joint force through each bore.
BORES: dict[str, tuple[tuple[str, str], ...]] = {
    "lower_arm": (("A", "a_lower"), ("B", "b")),
    "crank": (("A", "a_crank"), ("C", "c")),
    "coupler": (("C", "c"), ("D", "d")),
    "upper_arm": (("B", "b"), ("D", "d")),
}


#: Length (m) of the column of each link's buckling check: l1, l2, l3, and l4 (the D-B leg).
_COLUMN = {k: (lambda d, i=i: d[..., i]) for i, k in enumerate(LINK_NAMES)}
#: Spine length (m) of each link, over which its mass is spread.
_SPINE = {**_COLUMN, "upper_arm": lambda d: d[..., 3] + d[..., 4] + d[..., 5]}
_SIMPSON = np.array([1.0, 4.0, 1.0]) / 6


def cut_coefficients(cuts: Cuts, n_loads: int, mu: NDArray) -> tuple[NDArray, NDArray]:
    """Coefficients (..., C, 2 n_loads + 4) of the axial force N (tension > 0) and the moment M
    at each cut, linear in the link-frame sample vector ``[F_1, ..., F_n, g - a_0, alpha,
    omega^2]`` (joint forces with their signs, gravity less the frame origin's acceleration,
    angular acceleration and squared rate): the piece beyond the cut carries its joint load and
    the body force ``mu (g - a_0 - alpha perp(p) + omega^2 p)`` per metre of spine."""
    t = cuts.tangent
    s = cuts.at[..., None, :]
    p0, p1 = cuts.piece[..., :-1, :], cuts.piece[..., 1:, :]  # segments (..., C, 2, 2)
    seg = np.linalg.norm(p1 - p0, axis=-1)  # (..., C, 2)
    pm = (p0 + p1) / 2
    pts = np.stack([p0, pm, p1], axis=-2)  # (..., C, 2, 3, 2)
    r = pts - s[..., None, :]
    wl = seg[..., None] * _SIMPSON  # Simpson weights times segment length (..., C, 2, 3)
    m_uniform = mu[..., None, None] * (wl[..., None] * np.stack([-r[..., 1], r[..., 0]], -1)).sum(
        (-3, -2)
    )
    m_alpha = -mu[..., None] * (wl * (r * pts).sum(-1)).sum((-2, -1))
    m_omega = mu[..., None] * (wl * cross(r, pts)).sum((-2, -1))
    n_uniform = mu[..., None, None] * seg.sum(-1)[..., None] * t
    n_alpha = mu[..., None] * (seg * cross(t[:, None, :], pm)).sum(-1)
    n_omega = mu[..., None] * (seg * (pm * t[:, None, :]).sum(-1)).sum(-1)
    lead = cuts.at.shape[:-1]
    cn = np.zeros((*lead, 2 * n_loads + 4))
    cm = np.zeros_like(cn)
    arm = cuts.load - cuts.at
    for k in range(n_loads):
        on = cuts.slot == k
        cn[..., 2 * k : 2 * k + 2] = np.where(on[:, None], t, 0.0)
        cm[..., 2 * k : 2 * k + 2] = np.where(
            on[:, None], np.stack([-arm[..., 1], arm[..., 0]], -1), 0.0
        )
    j = 2 * n_loads
    cn[..., j : j + 2], cn[..., j + 2], cn[..., j + 3] = n_uniform, n_alpha, n_omega
    cm[..., j : j + 2], cm[..., j + 2], cm[..., j + 3] = m_uniform, m_alpha, m_omega
    return cn, cm


class LinkStrength(NamedTuple):
    """One link's peaks over the duty (leading axes of the designs): stress_pa, the check where
    it peaks (index into ``labels``), compression_N, euler_N (Euler load of its column)."""

    stress_pa: NDArray[np.float64]
    where: NDArray[np.intp]
    compression_N: NDArray[np.float64]
    euler_N: NDArray[np.float64]
    labels: tuple[str, ...]


def _link_sample(loads: JointLoads, motion: LinkMotion, link: str) -> NDArray[np.float64]:
    """The link-frame sample vectors of :func:`cut_coefficients` of ``link`` over the duty
    samples, (..., 2 n_loads + 4, N) with one contiguous row per entry, but for the signs of
    the joint loads (:data:`LOADS`; the caller applies them to the coefficients)."""
    k = LINK_NAMES.index(link)
    c, s = motion.cos[..., k], motion.sin[..., k]
    n_loads = len(LOADS[link])
    out = np.empty((*c.shape[:-1], 2 * n_loads + 4, c.shape[-1]))
    forces = loads._asdict()
    g_rel = (0.0 - motion.origin_acc[..., k, 0], GRAVITY[1] - motion.origin_acc[..., k, 1])
    vectors = [(forces[n][..., 0], forces[n][..., 1]) for n, _ in LOADS[link]] + [g_rel]
    for j, (x, y) in enumerate(vectors):  # rotated into the link frame
        np.multiply(c, x, out=out[..., 2 * j, :])
        out[..., 2 * j, :] += s * y
        np.multiply(c, y, out=out[..., 2 * j + 1, :])
        out[..., 2 * j + 1, :] -= s * x
    out[..., -2, :] = motion.alpha[..., k]
    np.square(motion.omega[..., k], out=out[..., -1, :])
    return out


def cut_forces(
    design: ArrayLike,
    sec: Section,
    inertials: Inertials,
    loads: JointLoads,
    motion: LinkMotion,
    link: str,
    cuts: Cuts | None = None,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Axial force N (tension > 0, N) and in-plane moment M (N m) at every cut of ``link``, each
    (..., N, C) over the duty samples of ``loads`` and ``motion`` (..., N): its own cuts of
    :func:`link_cuts`, or ``cuts`` (for example extra cuts along a bar). Each cut's values over
    the samples are contiguous in memory (the arrays are views with the last two axes swapped)."""
    d = as_design(design)
    k = LINK_NAMES.index(link)
    cuts = link_cuts(d, sec, (link,))[link] if cuts is None else cuts
    mu = inertials.mass_kg[..., k] / _SPINE[link](d)
    cn, cm = cut_coefficients(cuts, len(LOADS[link]), mu)
    coef = np.concatenate([cn, cm], axis=-2)
    for j, (_, sign) in enumerate(LOADS[link]):
        coef[..., 2 * j : 2 * j + 2] *= sign
    both = coef @ _link_sample(loads, motion, link)  # (..., 2C, N)
    n_cuts = len(cuts.labels)
    return np.swapaxes(both[..., :n_cuts, :], -1, -2), np.swapaxes(both[..., n_cuts:, :], -1, -2)


def section_stress(
    axial_N: ArrayLike, moment_Nm: ArrayLike, sec: Section, bore_m: ArrayLike = 0.0
) -> NDArray[np.float64]:
    """Beam stress (Pa) of a cut: the bar's ``|N| / (w t) + 6 |M| / (t w^2)``, or where
    ``bore_m`` (m, broadcast with the cuts) is positive the net section through a bore of that
    diameter across the boss, ``|N| / (t (2R - d_b)) + |M| R / I_net``."""
    w, t, r = sec.width_m, sec.thickness_m, sec.boss_radius_m
    d_b = np.asarray(bore_m, dtype=float)
    bored = d_b > 0
    area = np.where(bored, t * (2 * r - d_b), w * t)
    modulus = np.where(bored, t * ((2 * r) ** 3 - d_b**3) / (12 * r), t * w**2 / 6)
    shape = np.broadcast_shapes(np.shape(axial_N), np.shape(moment_Nm), area.shape)
    stress, bending = (np.abs(np.broadcast_to(x, shape)) for x in (axial_N, moment_Nm))
    stress /= area  # in place: the cuts' layout stays (cut_forces: contiguous over the samples)
    stress += np.divide(bending, modulus, out=bending)
    return stress


class LinkLoads(NamedTuple):
    """What one link's checks need besides its section (leading axes of the designs): axial
    force and moment (..., N, C) at its cuts, the bore diameter (..., 1, C) where a cut passes
    through one (0 elsewhere), the peak force (..., J) and diameter (..., J) of each bore of
    :data:`BORES`, the peak compression (...) and column length (...) of the buckling check."""

    axial_N: NDArray[np.float64]
    moment_Nm: NDArray[np.float64]
    cut_bore_m: NDArray[np.float64]
    bore_force_N: NDArray[np.float64]
    bore_m: NDArray[np.float64]
    compression_N: NDArray[np.float64]
    column_m: NDArray[np.float64]
    labels: tuple[str, ...]


def peak_forces(loads: JointLoads) -> dict[str, NDArray[np.float64]]:
    """Peak magnitude (N) over the duty samples of each joint force of ``loads`` with a bore,
    (...) each, keyed as :class:`qsm.embodiment.strength.loads.JointLoads`."""
    f = loads._asdict()
    names = {n for bores in BORES.values() for _, n in bores}
    return {n: np.sqrt((f[n][..., 0] ** 2 + f[n][..., 1] ** 2).max(axis=-1)) for n in names}


def link_loads(
    design: ArrayLike,
    sec: Section,
    inertials: Inertials,
    loads: JointLoads,
    motion: LinkMotion,
    bores_m: ArrayLike,
    link: str,
    cuts: Cuts | None = None,
    peaks: Mapping[str, NDArray[np.float64]] | None = None,
) -> LinkLoads:
    """The loads of ``link`` of ``design`` (..., 6) m at the cuts of section ``sec`` over the
    duty samples of ``loads`` and ``motion`` (..., N), bores of ``bores_m`` (..., 4) m at A-D;
    ``cuts``: the link's cuts (:func:`link_cuts`) and ``peaks``: :func:`peak_forces` of
    ``loads``, when computed already."""
    d = as_design(design)
    bores = np.broadcast_to(np.asarray(bores_m, dtype=float), (*d.shape[:-1], len(JOINTS)))
    cuts = link_cuts(d, sec, (link,))[link] if cuts is None else cuts
    axial, moment = cut_forces(d, sec, inertials, loads, motion, link, cuts)
    compression = -axial.min(axis=-2)[..., cuts.column].min(axis=-1)
    joint = JOINTS.index(NET_SECTION_JOINT.get(link, "A"))  # the coupler has no net section
    peaks = peak_forces(loads) if peaks is None else peaks
    return LinkLoads(
        axial,
        moment,
        np.where(cuts.bore, bores[..., joint, None], 0.0)[..., None, :],
        np.stack([peaks[n] for _, n in BORES[link]], -1),
        np.stack([bores[..., JOINTS.index(j)] for j, _ in BORES[link]], -1),
        np.maximum(compression, 0.0),
        _COLUMN[link](d) * BUCKLING_K,
        cuts.labels + tuple(f"pin-loaded bore {j}" for j, _ in BORES[link]),
    )


#: The upper arm's cuts at its inside corner, whose stress ``corner_stress_concentration`` scales.
CORNER_CUTS = ("bar at the corner", "bar below the corner")


def corner_factor(labels: tuple[str, ...], strength: StrengthSettings) -> NDArray[np.float64]:
    """Factor on the stress of each cut ``labels``: the corner's stress concentration at
    :data:`CORNER_CUTS`, 1 elsewhere."""
    return np.where(np.isin(labels, CORNER_CUTS), strength.corner_stress_concentration, 1.0)


def link_peaks(
    link: LinkLoads, sec: Section, material: Material, strength: StrengthSettings
) -> LinkStrength:
    """A link's peak stress over its cuts and bores and its Euler load with section ``sec``
    under ``link``'s loads (the cuts stay where :func:`link_loads` put them)."""
    r, t = np.asarray(sec.boss_radius_m)[..., None], np.asarray(sec.thickness_m)[..., None]
    if not (link.bore_m < 2 * r).all():
        raise ValueError("every bore must be smaller than the boss diameter")
    stress = section_stress(link.axial_N, link.moment_Nm, sec.trailing(2), link.cut_bore_m)
    stress = stress * corner_factor(link.labels[: stress.shape[-1]], strength)
    lug = strength.lug_stress_concentration / (t * (2 * r - link.bore_m)) * link.bore_force_N
    checks = np.concatenate([stress.max(axis=-2), lug], axis=-1)
    euler = math.pi**2 * material.youngs_modulus_pa * sec.weak_inertia_m4 / link.column_m**2
    return LinkStrength(checks.max(-1), checks.argmax(-1), link.compression_N, euler, link.labels)


def link_strength(
    design: ArrayLike,
    sec: Section | Mapping[str, Section],
    material: Material,
    strength: StrengthSettings,
    inertials: Inertials,
    loads: JointLoads,
    motion: LinkMotion,
    bores_m: ArrayLike,
) -> dict[str, LinkStrength]:
    """Peak stress and compression of each link of ``design`` (..., 6) m over the duty samples
    of ``loads`` and ``motion`` (..., N), with bores of diameter ``bores_m`` (..., 4) m at the
    joints A-D (each smaller than the boss); ``sec`` is every link's section or one per link
    (keyed by link name)."""
    shared = link_cuts(design, sec) if isinstance(sec, Section) else None
    peaks = peak_forces(loads)
    out = {}
    for link in LOADS:
        s = sec if isinstance(sec, Section) else sec[link]
        cuts = link_cuts(design, s, (link,))[link] if shared is None else shared[link]
        forces = link_loads(design, s, inertials, loads, motion, bores_m, link, cuts, peaks)
        out[link] = link_peaks(forces, s, material, strength)
    return out
