"""Planar mass properties of the four links of many designs at once, no Python work per design.

The outlines of :func:`qsm.physics.cad.link_outlines` written as templates plus offsets linear in
the design's six lengths, so the polygon area moments vectorise over any number of designs (SI
units).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from qsm.physics.cad import DEFAULT_CAD, CadSettings, arc, inside_corner
from qsm.physics.kinematics import as_design


def _outline_terms(s: CadSettings) -> dict[str, list[tuple[NDArray[np.float64], NDArray]]]:
    """Each link's outline as pieces (template points (k, 2), offset matrix (2, 6)): a piece's
    points are the template plus the offset matrix times the design's 6 lengths (the outlines of
    :func:`link_outlines`, vertex for vertex)."""
    r, h, seg, pi = s.boss_radius_m, s.width_m / 2, s.segments_per_circle, math.pi
    beta = math.asin(h / r)

    def at(x: dict[int, float] | None = None, y: dict[int, float] | None = None) -> NDArray:
        m = np.zeros((2, 6))
        for row, coef in enumerate((x or {}, y or {})):
            for k, v in coef.items():
                m[row, k] = v
        return m

    def bar(k: int) -> list[tuple[NDArray[np.float64], NDArray]]:
        return [
            (arc(0.0, 0.0, r, beta, 2 * pi - beta, seg), at()),
            (arc(0.0, 0.0, r, beta - pi, pi - beta, seg), at({k: 1.0})),
        ]

    upper = [
        (arc(0.0, 0.0, r, beta, 2 * pi - beta, seg), at({3: -1.0})),
        (arc(0.0, 0.0, r, pi + beta, 2 * pi - beta, seg), at()),
        (inside_corner(0.0, s), at({4: 1.0})),
        (arc(0.0, 0.0, r, pi / 2 + beta, 5 * pi / 2 - beta, seg), at({4: 1.0}, {5: -1.0})),
        (np.array([[h, h]]), at({4: 1.0})),
        (arc(0.0, 0.0, r, beta, pi - beta, seg), at()),
    ]
    return {"lower_arm": bar(0), "crank": bar(1), "coupler": bar(2), "upper_arm": upper}


def batch_mass_properties(
    designs: ArrayLike, settings: CadSettings = DEFAULT_CAD, scale: ArrayLike | None = None
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Planar mass properties of the four links (:data:`qsm.physics.kinematics.LINK_NAMES`
    order) of designs (..., 6) m, without Python work per design: mass (..., 4) kg, centre of
    mass (..., 4, 2) m in the link frames and inertia about z through it (..., 4) kg m^2; those
    of :func:`mass_properties` to rounding. ``scale`` (..., 4): each link's section is
    ``settings`` scaled by it (every length of the section, so the outline's template scales).
    The section must fit every design (:func:`link_outlines` raises otherwise)."""
    d = as_design(designs)
    masses, coms, izz = [], [], []
    for k, pieces in enumerate(_outline_terms(settings).values()):
        f = None if scale is None else np.asarray(scale, dtype=float)[..., k]
        sigma = settings.density_kg_m3 * settings.thickness_m * (1.0 if f is None else f)
        p = np.concatenate(
            [
                (tpl if f is None else f[..., None, None] * tpl) + d[..., None, :] @ m.T
                for tpl, m in pieces
            ],
            axis=-2,
        )
        x, y = p[..., 0], p[..., 1]
        xn, yn = np.roll(x, -1, axis=-1), np.roll(y, -1, axis=-1)
        c = x * yn - xn * y
        area = c.sum(-1) / 2
        cx = ((x + xn) * c).sum(-1) / (6 * area)
        cy = ((y + yn) * c).sum(-1) / (6 * area)
        polar = ((x * x + x * xn + xn * xn + y * y + y * yn + yn * yn) * c).sum(-1) / 12
        masses.append(sigma * area)
        coms.append(np.stack([cx, cy], -1))
        izz.append(sigma * (polar - area * (cx * cx + cy * cy)))
    return np.stack(masses, -1), np.stack(coms, -2), np.stack(izz, -1)
