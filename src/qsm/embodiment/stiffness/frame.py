"""The closed chain as a planar frame: the tool's compliance at any pose (direct stiffness).

Each link is a Timoshenko beam of its own section (width ``w`` in the plane, thickness ``t``)
between its joint centres; the upper arm is three beams joined rigidly (D - B, B - E', E' - E,
with E' its corner). B, C and D are pins: the links there share a position and turn freely.
At A both links' positions are fixed and each one's turning is held by its drive, a torsional
spring of stiffness ``k`` (N m/rad at the joint), or fixed when the drives are rigid. The bosses
and bores are not modelled (each bar has its plain section from centre to centre); bearings are
rigid. Everything is vectorised over designs and poses: arrays (..., n) solve at once.

Degrees of freedom (m, rad), in the order of :data:`DOFS`: the two links' turning at A, then for
B, C, D the node's position and each link's own turning there, then the corner E' and the tool E.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from qsm.physics.kinematics import as_design, pose

#: The frame's degrees of freedom (``qA_lower`` is the lower arm's turning at A, and so on).
DOFS: tuple[str, ...] = (
    "qA_lower", "qA_crank",
    "xB", "yB", "qB_lower", "qB_upper",
    "xC", "yC", "qC_crank", "qC_coupler",
    "xD", "yD", "qD_coupler", "qD_upper",
    "xE'", "yE'", "qE'_upper",
    "xE", "yE", "qE_upper",
)  # fmt: skip
_AT = {name: k for k, name in enumerate(DOFS)}
#: Each beam: its link (0 lower arm, 1 crank, 2 coupler, 3 upper arm) and the (x, y, turn) degrees
#: of freedom of its two ends (None: fixed).
BEAMS: tuple[tuple[int, tuple, tuple], ...] = (
    (0, (None, None, "qA_lower"), ("xB", "yB", "qB_lower")),
    (1, (None, None, "qA_crank"), ("xC", "yC", "qC_crank")),
    (2, ("xC", "yC", "qC_coupler"), ("xD", "yD", "qD_coupler")),
    (3, ("xD", "yD", "qD_upper"), ("xB", "yB", "qB_upper")),
    (3, ("xB", "yB", "qB_upper"), ("xE'", "yE'", "qE'_upper")),
    (3, ("xE'", "yE'", "qE'_upper"), ("xE", "yE", "qE_upper")),
)
#: The tool's position degrees of freedom.
TOOL = (_AT["xE"], _AT["yE"])
#: Shear correction of a rectangle (Timoshenko).
SHEAR_FACTOR = 5.0 / 6.0


class FrameSections(NamedTuple):
    """Each link's section and material: ``width_m``, ``thickness_m`` (..., 4) in the links'
    order, Young's modulus ``youngs_pa``, Poisson's ratio (for the shear modulus), and each
    link's ``factor`` (..., 4) on its solid section's stiffness (a topology-optimised plate's
    FE compliance ratio; None: solid links)."""

    width_m: NDArray[np.float64]
    thickness_m: NDArray[np.float64]
    youngs_pa: float
    poisson: float
    factor: NDArray[np.float64] | None = None


def nodes(design: ArrayLike, theta1: ArrayLike, theta2: ArrayLike) -> dict[str, NDArray]:
    """Positions (..., 2) m of A, B, C, D, the upper arm's corner E' and the tool E."""
    d = as_design(design)
    p = pose(d, theta1, theta2)
    extra = p.phi.ndim - (d.ndim - 1)
    ee_x = d[..., 4].reshape(d.shape[:-1] + (1,) * extra)
    corner = p.B + ee_x[..., None] * np.stack([np.cos(p.phi), np.sin(p.phi)], axis=-1)
    return {"A": np.zeros_like(p.B), "B": p.B, "C": p.C, "D": p.D, "E'": corner, "E": p.E}


_ENDS = {"qA": "A", "xB": "B", "xC": "C", "xD": "D", "xE'": "E'", "xE": "E"}


def _end_node(end: tuple) -> str:
    return _ENDS[end[0] if end[0] is not None else end[2][:2]]


def beam_ends(at: dict[str, NDArray], first: tuple, second: tuple) -> tuple[NDArray, NDArray]:
    """The positions (..., 2) m of a beam's two ends (a :data:`BEAMS` entry's ends)."""
    return at[_end_node(first)], at[_end_node(second)]


def at_dofs(first: tuple, second: tuple) -> tuple[NDArray[np.int_], list[int]]:
    """A beam's free degrees of freedom in :data:`DOFS` and which of its 6 end ones they are."""
    index = [None if n is None else _AT[n] for n in (*first, *second)]
    keep = [i for i, n in enumerate(index) if n is not None]
    return np.array([index[i] for i in keep]), keep


def rotation(start: NDArray, end: NDArray) -> NDArray[np.float64]:
    """The (..., 6, 6) rotation from global to a beam's local (axial, transverse, turn) end
    degrees of freedom."""
    v = end - start
    length = np.hypot(v[..., 0], v[..., 1])
    c, s = v[..., 0] / length, v[..., 1] / length
    r = np.zeros((*length.shape, 6, 6))
    for o in (0, 3):
        r[..., o, o] = r[..., o + 1, o + 1] = c
        r[..., o, o + 1], r[..., o + 1, o] = s, -s
        r[..., o + 2, o + 2] = 1.0
    return r


def beam_stiffness(
    start: NDArray, end: NDArray, ea: NDArray, ei: NDArray, phi_s: NDArray
) -> NDArray[np.float64]:
    """Global stiffness (..., 6, 6) of plane Timoshenko beams from ``start`` to ``end`` (..., 2) m
    with axial stiffness ``ea`` (N), bending stiffness ``ei`` (N m^2) and shear parameter
    ``phi_s`` = 12 EI / (kappa G A L^2); end degrees of freedom (x, y, turn) at each end."""
    length = np.linalg.norm(end - start, axis=-1)
    a, b = ea / length, ei / (length**3 * (1 + phi_s))
    k = np.zeros((*length.shape, 6, 6))
    k[..., 0, 0] = k[..., 3, 3] = a
    k[..., 0, 3] = k[..., 3, 0] = -a
    k[..., 1, 1] = k[..., 4, 4] = 12 * b
    k[..., 1, 4] = k[..., 4, 1] = -12 * b
    for i, j, f in ((1, 2, 6), (1, 5, 6), (2, 4, -6), (4, 5, -6)):
        k[..., i, j] = k[..., j, i] = f * b * length
    k[..., 2, 2] = k[..., 5, 5] = (4 + phi_s) * b * length**2
    k[..., 2, 5] = k[..., 5, 2] = (2 - phi_s) * b * length**2
    r = rotation(start, end)
    return np.matmul(np.matmul(r.swapaxes(-1, -2), k), r)  # R^T K R


def _section_terms(sec: FrameSections, link: int) -> tuple[NDArray, NDArray, NDArray]:
    w, t = np.asarray(sec.width_m)[..., link], np.asarray(sec.thickness_m)[..., link]
    f = 1.0 if sec.factor is None else np.asarray(sec.factor)[..., link]
    area, inertia = w * t * f, t * w * w * w / 12 * f
    shear_modulus = sec.youngs_pa / (2 * (1 + sec.poisson))
    return sec.youngs_pa * area, sec.youngs_pa * inertia, shear_modulus * SHEAR_FACTOR * area


def stiffness_matrix(
    design: ArrayLike,
    theta1: ArrayLike,
    theta2: ArrayLike,
    sections: FrameSections,
    drive_stiffness: ArrayLike | None = None,
) -> NDArray[np.float64]:
    """The frame's stiffness matrix (..., 20, 20) at the poses (N, m, rad); ``drive_stiffness``
    (..., 2) N m/rad per drive, None for rigid drives (then the matrix is (..., 18, 18) without
    the turning at A). ``sections`` broadcast against the designs, the angles carry extra axes."""
    at = nodes(design, theta1, theta2)
    shape = at["B"].shape[:-1]
    extra = len(shape) - (as_design(design).ndim - 1)
    grow = (...,) + (None,) * extra
    big = np.zeros((*shape, len(DOFS), len(DOFS)))
    for link, first, second in BEAMS:
        ea, ei, gka = (np.asarray(x)[grow] for x in _section_terms(sections, link))
        start, end = beam_ends(at, first, second)
        length = np.linalg.norm(end - start, axis=-1)
        k = beam_stiffness(start, end, ea, ei, 12 * ei / (gka * length**2))
        rows, keep = at_dofs(first, second)
        big[..., rows[:, None], rows[None, :]] += k[..., keep, :][..., :, keep]
    if drive_stiffness is None:
        return big[..., 2:, 2:]
    ks = np.broadcast_to(
        np.asarray(drive_stiffness, dtype=float)[(..., *(None,) * extra, slice(None))], (*shape, 2)
    )
    big[..., 0, 0] += ks[..., 0]
    big[..., 1, 1] += ks[..., 1]
    return big


def tool_compliance(
    design: ArrayLike,
    theta1: ArrayLike,
    theta2: ArrayLike,
    sections: FrameSections,
    drive_stiffness: ArrayLike | None = None,
) -> NDArray[np.float64]:
    """The tool's translational compliance (..., 2, 2) m/N at the poses: its displacement under
    a unit force at E, by :func:`stiffness_matrix`. Symmetric (reciprocity)."""
    k = stiffness_matrix(design, theta1, theta2, sections, drive_stiffness)
    offset = 0 if drive_stiffness is not None else 2
    tool = [i - offset for i in TOOL]
    unit = np.zeros((*k.shape[:-1], 2))
    unit[..., tool[0], 0] = unit[..., tool[1], 1] = 1.0
    u = np.linalg.solve(k, unit)
    return u[..., tool, :]


def weight_loads(
    design: ArrayLike, theta1: ArrayLike, theta2: ArrayLike, link_mass_kg: ArrayLike, g: float
) -> NDArray[np.float64]:
    """The links' weight as the frame's consistent nodal loads (..., 20) (N, N m, in
    :data:`DOFS`' order): each link's mass ``link_mass_kg`` (..., 4) spread evenly along its
    beams, ``g`` (m/s^2) along -y; a beam of length L under a load q per metre takes q L / 2 at
    each end and the moments +-p L^2 / 12 of its transverse part p (exact nodal loads of a
    uniform load on an Euler-Bernoulli beam)."""
    at = nodes(design, theta1, theta2)
    shape = at["B"].shape[:-1]
    extra = len(shape) - (as_design(design).ndim - 1)
    mass = np.asarray(link_mass_kg, dtype=float)[(..., *(None,) * extra, slice(None))]
    ends = [beam_ends(at, first, second) for _, first, second in BEAMS]
    lengths = [np.linalg.norm(end - start, axis=-1) for start, end in ends]
    total = np.zeros((*shape, 4))
    for (link, _, _), length in zip(BEAMS, lengths, strict=True):
        total[..., link] += length
    f = np.zeros((*shape, len(DOFS)))
    for (link, first, second), (start, end), length in zip(BEAMS, ends, lengths, strict=True):
        q = -g * mass[..., link] / total[..., link]  # N/m along y
        p = q * (end - start)[..., 0] / length  # its part across the beam
        zero = np.zeros_like(q)
        ends6 = np.stack([zero, q * length / 2, p * length**2 / 12] * 2, axis=-1)
        ends6[..., 5] *= -1
        rows, keep = at_dofs(first, second)
        f[..., rows] += ends6[..., keep]
    return f


def tool_displacement(
    design: ArrayLike,
    theta1: ArrayLike,
    theta2: ArrayLike,
    sections: FrameSections,
    loads: ArrayLike,
    drive_stiffness: ArrayLike | None = None,
) -> NDArray[np.float64]:
    """The tool's displacement (..., 2) m under nodal ``loads`` (..., 20) in :data:`DOFS`' order
    (:func:`weight_loads`; a force at E in its last three but one), by
    :func:`stiffness_matrix`; rigid drives without ``drive_stiffness``."""
    k = stiffness_matrix(design, theta1, theta2, sections, drive_stiffness)
    offset = 0 if drive_stiffness is not None else 2
    f = np.asarray(loads, dtype=float)[..., offset:]
    u = np.linalg.solve(k, f[..., None])[..., 0]
    return u[..., [i - offset for i in TOOL]]
