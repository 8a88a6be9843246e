"""The serial 2R arm a quasi-serial design is measured against (the paper's claim that
quasi-serial arms are stiffer than serial arms with the same motors).

The serial arm has the same kinematics at the tool: link 1 is the lower arm (A to B), link 2 the
upper arm's L (B to its corner E' to E), turned at B by motor 2, whose drive (motor and gearbox)
the arm now carries at B. Same sections, material and drives; each drive a torsional spring (at
A to the ground, at B between the links).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from qsm.embodiment.stiffness.error_terms import GRAVITY_M_S2
from qsm.embodiment.stiffness.frame import FrameSections, beam_stiffness, nodes
from qsm.embodiment.stiffness.modes import beam_mass, first_mode_hz
from qsm.physics.kinematics import as_design

#: Degrees of freedom: link 1's turning at A, B's position, each link's turning at B, E', E.
SERIAL_DOFS = ("qA", "xB", "yB", "qB_1", "qB_2", "xE'", "yE'", "qE'", "xE", "yE", "qE")
_BEAMS = ((0, (None, None, 0), (1, 2, 3)), (3, (1, 2, 4), (5, 6, 7)), (3, (5, 6, 7), (8, 9, 10)))


def _assemble(
    at: dict[str, NDArray], sections: FrameSections, masses: NDArray | None
) -> NDArray[np.float64]:
    """The serial frame's stiffness (masses None) or consistent mass matrix (..., 11, 11)."""
    shape = at["B"].shape[:-1]
    big = np.zeros((*shape, len(SERIAL_DOFS), len(SERIAL_DOFS)))
    ends = [("A", "B"), ("B", "E'"), ("E'", "E")]
    lengths = [np.linalg.norm(at[b] - at[a], axis=-1) for a, b in ends]
    for (link, first, second), (a, b), length in zip(_BEAMS, ends, lengths, strict=True):
        w, t = sections.width_m[..., link], sections.thickness_m[..., link]
        e = sections.youngs_pa * (1.0 if sections.factor is None else sections.factor[..., link])
        if masses is None:
            ea, ei = e * w * t, e * t * w**3 / 12
            gka = e / (2 * (1 + sections.poisson)) * 5 / 6 * w * t
            k = beam_stiffness(at[a], at[b], ea, ei, 12 * ei / (gka * length**2))
        else:
            share = length if link == 0 else length / (lengths[1] + lengths[2])
            k = beam_mass(at[a], at[b], masses[..., 0 if link == 0 else 1] * (share if link else 1))
        index = [*first, *second]
        keep = [i for i, n in enumerate(index) if n is not None]
        rows = np.array([index[i] for i in keep])
        big[..., rows[:, None], rows[None, :]] += k[..., keep, :][..., :, keep]
    return big


def serial_matrices(
    design: ArrayLike,
    theta1: ArrayLike,
    theta2: ArrayLike,
    sections: FrameSections,
    drive_stiffness: ArrayLike,
    masses: tuple[float, float, float, float, float, float],
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Stiffness and mass matrices (..., 11, 11) of the serial arm at the quasi-serial design's
    poses; ``drive_stiffness`` (2,) N m/rad, ``masses`` (kg): link 1, link 2, the elbow drive
    at B, the payload at E, and each motor's reflected inertia (kg m^2) on its joint's driven
    side (link 1 at A, link 2 at B), as the quasi-serial first mode has them."""
    at = nodes(design, theta1, theta2)
    k = _assemble(at, sections, None)
    k1, k2 = np.asarray(drive_stiffness, dtype=float)
    k[..., 0, 0] += k1
    for i, j, s in ((3, 3, 1), (4, 4, 1), (3, 4, -1), (4, 3, -1)):
        k[..., i, j] += s * k2
    link1, link2, elbow, payload, reflected1, reflected2 = masses
    m = _assemble(at, sections, np.array([link1, link2]))
    m[..., 1, 1] += elbow
    m[..., 2, 2] += elbow
    m[..., 8, 8] += payload
    m[..., 9, 9] += payload
    m[..., 0, 0] += reflected1
    m[..., 4, 4] += reflected2
    return k, m


def serial_comparison(
    design: ArrayLike,
    angles: NDArray[np.float64],
    sections: FrameSections,
    drive_stiffness: ArrayLike,
    masses: tuple[float, float, float, float, float, float],
) -> dict[str, NDArray[np.float64]]:
    """The serial arm at the task points' motor ``angles`` (n, 2): its tool sag under the
    payload's weight (mm), first mode (Hz) and holding torques of motor 1 and 2 (N m), each
    (n,) or (n, 2)."""
    d = as_design(design)
    t1, t2 = angles[:, 0], angles[:, 1]
    k, m = serial_matrices(d, t1, t2, sections, drive_stiffness, masses)
    load = np.zeros((*k.shape[:-1],))
    load[..., 9] = -masses[3] * GRAVITY_M_S2
    u = np.linalg.solve(k, load[..., None])[..., 0]
    at = nodes(d, t1, t2)
    g = GRAVITY_M_S2
    link1, link2, elbow, payload, _, _ = masses
    a = np.linalg.norm(at["E'"] - at["B"], axis=-1)[:, None]
    b = np.linalg.norm(at["E"] - at["E'"], axis=-1)[:, None]
    mid2 = (a * (at["B"] + at["E'"]) + b * (at["E'"] + at["E"])) / (2 * (a + b))  # the L's centroid
    tau2 = g * (payload * (at["E"][:, 0] - at["B"][:, 0]) + link2 * (mid2[:, 0] - at["B"][:, 0]))
    tau1 = g * (
        payload * at["E"][:, 0] + link2 * mid2[:, 0] + elbow * at["B"][:, 0]
        + link1 * at["B"][:, 0] / 2
    )  # fmt: skip
    return {
        "sag_mm": 1e3 * np.hypot(u[..., 8], u[..., 9]),
        "first_mode_hz": first_mode_hz(k, m),
        "holding_torque_Nm": np.abs(np.column_stack([tau1, tau2])),
    }
