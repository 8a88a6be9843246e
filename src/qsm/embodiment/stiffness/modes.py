"""The first natural frequency of the loaded arm: the frame of :mod:`.frame` with consistent beam
masses, the payload at the tool and the drives' reflected inertias, as K v = w^2 M v.

Each link's mass is spread along its beams in proportion to their lengths (consistent
Euler-Bernoulli masses), so a link weighs what its part weighs; the payload is a point mass at E.
A drive's reflected inertia (rotor and gearbox input, times the ratio squared) is lumped on the
joint's turning at A, on the arm's side of the gearbox's spring: the rotor is held by its servo
only through the gearbox, which gives a lower (safer) frequency than a rotor held rigidly.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg
from numpy.typing import ArrayLike, NDArray

from qsm.embodiment.stiffness.frame import (
    BEAMS,
    DOFS,
    TOOL,
    FrameSections,
    at_dofs,
    beam_ends,
    nodes,
    rotation,
    stiffness_matrix,
)
from qsm.physics.kinematics import as_design


def beam_mass(start: NDArray, end: NDArray, mass_kg: NDArray) -> NDArray[np.float64]:
    """Consistent mass matrices (..., 6, 6) kg of plane beams of ``mass_kg`` (...) from ``start``
    to ``end`` (..., 2) m, in global (x, y, turn) degrees of freedom at each end."""
    length = np.linalg.norm(end - start, axis=-1)
    L = length
    m = np.zeros((*length.shape, 6, 6))
    m[..., 0, 0] = m[..., 3, 3] = 140
    m[..., 0, 3] = m[..., 3, 0] = 70
    m[..., 1, 1] = m[..., 4, 4] = 156
    m[..., 1, 4] = m[..., 4, 1] = 54
    for i, j, f in ((1, 2, 22), (2, 4, 13), (1, 5, -13), (4, 5, -22)):
        m[..., i, j] = m[..., j, i] = f * L
    m[..., 2, 2] = m[..., 5, 5] = 4 * L * L
    m[..., 2, 5] = m[..., 5, 2] = -3 * L * L
    m *= (np.asarray(mass_kg) / 420)[..., None, None]
    r = rotation(start, end)
    return np.einsum("...ji,...jk,...kl->...il", r, m, r)


def mass_matrix(
    design: ArrayLike,
    theta1: ArrayLike,
    theta2: ArrayLike,
    link_mass_kg: ArrayLike,
    payload_kg: float,
    reflected_kgm2: ArrayLike | None = None,
) -> NDArray[np.float64]:
    """The frame's mass matrix (..., 20, 20) at the poses; ``link_mass_kg`` (..., 4) in the links'
    order, ``reflected_kgm2`` (..., 2) per drive (None: rigid drives, (..., 18, 18))."""
    at = nodes(design, theta1, theta2)
    shape = at["B"].shape[:-1]
    extra = len(shape) - (as_design(design).ndim - 1)
    grow = (...,) + (None,) * extra
    links = np.asarray(link_mass_kg, dtype=float)
    lengths = {k: 0.0 for k in range(4)}
    for link, first, second in BEAMS:
        start, end = beam_ends(at, first, second)
        lengths[link] = lengths[link] + np.linalg.norm(end - start, axis=-1)
    big = np.zeros((*shape, len(DOFS), len(DOFS)))
    for link, first, second in BEAMS:
        start, end = beam_ends(at, first, second)
        share = np.linalg.norm(end - start, axis=-1) / lengths[link]
        m = beam_mass(start, end, links[..., link][grow] * share)
        rows, keep = at_dofs(first, second)
        big[..., rows[:, None], rows[None, :]] += m[..., keep, :][..., :, keep]
    tool = (DOFS.index("xE"), DOFS.index("yE"))
    big[..., tool, tool] += payload_kg
    if reflected_kgm2 is None:
        return big[..., 2:, 2:]
    ref = np.broadcast_to(
        np.asarray(reflected_kgm2, dtype=float)[(..., *(None,) * extra, slice(None))], (*shape, 2)
    )
    big[..., 0, 0] += ref[..., 0]
    big[..., 1, 1] += ref[..., 1]
    return big


def first_mode_hz(stiffness: ArrayLike, mass: ArrayLike) -> NDArray[np.float64]:
    """The lowest natural frequency (...) Hz of K v = w^2 M v for stiffness and mass matrices
    (..., n, n), both symmetric and M positive definite: by M's Cholesky factor L, the lowest
    eigenvalue of L^-1 K L^-T."""
    low = np.linalg.cholesky(np.asarray(mass, dtype=float))
    half = np.linalg.solve(low, np.asarray(stiffness, dtype=float))
    sym = np.linalg.solve(low, np.swapaxes(half, -1, -2))
    omega2 = np.linalg.eigvalsh((sym + np.swapaxes(sym, -1, -2)) / 2)[..., 0]
    return np.sqrt(np.maximum(omega2, 0.0)) / (2 * np.pi)


def loaded_first_mode_hz(
    design: ArrayLike,
    theta1: ArrayLike,
    theta2: ArrayLike,
    sections: FrameSections,
    link_mass_kg: ArrayLike,
    payload_kg: float,
    drive_stiffness: ArrayLike | None = None,
    reflected_kgm2: ArrayLike | None = None,
) -> NDArray[np.float64]:
    """The loaded arm's first natural frequency (...) Hz at the poses (:func:`first_mode_hz` of
    :func:`matrices`)."""
    args = (sections, link_mass_kg, payload_kg, drive_stiffness, reflected_kgm2)
    return first_mode_hz(*matrices(design, theta1, theta2, *args))


def matrices(
    design: ArrayLike,
    theta1: ArrayLike,
    theta2: ArrayLike,
    sections: FrameSections,
    link_mass_kg: ArrayLike,
    payload_kg: float,
    drive_stiffness: ArrayLike | None = None,
    reflected_kgm2: ArrayLike | None = None,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The loaded arm's stiffness and mass matrices at the poses
    (:func:`~qsm.embodiment.stiffness.frame.stiffness_matrix`, :func:`mass_matrix`): the drives'
    springs and reflected inertias (None: none) where ``drive_stiffness`` is given, else rigid
    drives."""
    k = stiffness_matrix(design, theta1, theta2, sections, drive_stiffness)
    if drive_stiffness is None:
        reflected_kgm2 = None
    elif reflected_kgm2 is None:
        reflected_kgm2 = np.zeros(2)
    return k, mass_matrix(design, theta1, theta2, link_mass_kg, payload_kg, reflected_kgm2)


def tool_mode(
    design: ArrayLike,
    theta1: float,
    theta2: float,
    sections: FrameSections,
    link_mass_kg: ArrayLike,
    payload_kg: float,
    drive_stiffness: ArrayLike | None = None,
    reflected_kgm2: ArrayLike | None = None,
) -> tuple[float, NDArray[np.float64]]:
    """The loaded arm's first mode at one pose (as :func:`loaded_first_mode_hz`): its frequency
    (Hz) and the unit direction (2,) in which it moves the tool (sign arbitrary)."""
    args = (sections, link_mass_kg, payload_kg, drive_stiffness, reflected_kgm2)
    k, m = matrices(design, theta1, theta2, *args)
    omega2, vectors = scipy.linalg.eigh(k, m, subset_by_index=[0, 0])
    offset = 0 if drive_stiffness is not None else 2
    tool = vectors[[i - offset for i in TOOL], 0]
    return float(np.sqrt(max(omega2[0], 0.0)) / (2 * np.pi)), tool / np.linalg.norm(tool)
