"""Exact mass properties (link frames, SI units) of the bored link parts: the area moments of the
outline (the polygon formulas of :func:`qsm.physics.cad.polygon_mass_properties`) less the
moments of every hole.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
import shapely
from numpy.typing import ArrayLike, NDArray

from qsm.embodiment.parts.link_parts import LinkPart, PartSettings, link_parts
from qsm.physics.cad import CadError, MassProperties, prism_properties


def _moments(ring: NDArray[np.float64]) -> NDArray[np.float64]:
    """Signed area moments of a closed polygon about the origin: [A, int x, int y, int x^2,
    int y^2, int x y] (positive for a CCW ring)."""
    x, y = ring[:, 0], ring[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    c = x * yn - xn * y
    return np.array(
        [
            c.sum() / 2,
            ((x + xn) * c).sum() / 6,
            ((y + yn) * c).sum() / 6,
            ((x * x + x * xn + xn * xn) * c).sum() / 12,
            ((y * y + y * yn + yn * yn) * c).sum() / 12,
            ((x * yn + 2 * x * y + 2 * xn * yn + xn * y) * c).sum() / 24,
        ]
    )


def _ring(coords: ArrayLike) -> NDArray[np.float64]:
    p = np.asarray(coords, dtype=float)[:, :2]
    return p[:-1] if len(p) > 1 and np.array_equal(p[0], p[-1]) else p


def polygon_with_holes_mass_properties(
    polygon: shapely.Polygon, thickness_m: float, density_kg_m3: float
) -> MassProperties:
    """Exact mass properties of the prism extruding ``polygon`` (m, with holes) symmetrically in z.

    The outline's area moments (the formulas of :func:`qsm.physics.cad.polygon_mass_properties`)
    less every hole's, whatever the rings' orientations.
    """
    ext = _moments(_ring(polygon.exterior.coords))
    m = ext * np.sign(ext[0])
    for interior in polygon.interiors:
        hole = _moments(_ring(interior.coords))
        m = m - hole * np.sign(hole[0])
    area, qx, qy, ixx, iyy, ixy = m
    if not area > 0:
        raise CadError("polygon must have positive area")
    cx, cy = qx / area, qy / area
    second = (ixx - area * cx * cx, iyy - area * cy * cy, ixy - area * cx * cy)
    return prism_properties(area, (cx, cy), second, thickness_m, density_kg_m3)


def part_mass_properties(parts: Mapping[str, LinkPart]) -> dict[str, MassProperties]:
    """Mass properties (link frames, SI) of bored parts, each of its own section: a drop-in for
    :func:`qsm.physics.cad.mass_properties`."""
    return {
        name: polygon_with_holes_mass_properties(
            p.polygon, p.section.thickness_m, p.section.density_kg_m3
        )
        for name, p in parts.items()
    }


def bored_mass_properties(
    design: ArrayLike,
    bearing_index: Sequence[int],
    settings: PartSettings = PartSettings(),  # noqa: B008
) -> dict[str, MassProperties]:
    """:func:`qsm.physics.cad.mass_properties` of the bored links of one design."""
    return part_mass_properties(link_parts(design, bearing_index, settings))
