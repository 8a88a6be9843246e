"""Parametric link solids of one scaled design: outlines, exact mass properties, STL export.

Each link is a flat plate of constant thickness: a 2D outline made of straight bars of width
``width_m`` with circular joint bosses of radius ``boss_radius_m``, extruded by ``thickness_m``
(symmetric about z = 0). The outline is one simple polygon (arcs discretised with
``segments_per_circle``), so

* the mass properties of the prism are computed exactly for that polygon from its area moments
  (cheap: used on the dynamics path for every mechanism), and
* the trimesh solid (for STL export) is the extrusion of the same polygon, one watertight body whose
  ``mass_properties`` agree with the analytic values to rounding.

Link frames (also the MuJoCo body frames of :mod:`qsm.physics.mjcf`), x-y is the mechanism plane:

* ``lower_arm``: origin at A, +x towards B, length l1;
* ``crank``:     origin at A, +x towards C, length l2;
* ``coupler``:   origin at C, +x towards D, length l3;
* ``upper_arm``: origin at the pivot B, +x along the EE_x axis dir(phi); it holds the rocker point
  D = (-l4, 0), the corner E' = (EE_x, 0) and the end effector E = (EE_x, -EE_y): an L-shaped bell
  crank made of the bar D-E' (through B) and the bar E'-E, with bosses at D, B and E. Its inside
  corner (EE_x - w/2, -w/2) is rounded by a fillet of radius ``corner_fillet_ratio * width_m``
  (tangent to both legs' edges; it adds ``(1 - pi/4) r_f^2`` of area), which bounds the stress
  concentration there (docs/strength.md).

The paper gives no cross-sections (its parts were drawn in Rhino and printed in ABS-M30); the
defaults below are a plausible printed section for 0.3-1 m links.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import lru_cache
from typing import NamedTuple

import numpy as np
import shapely
import trimesh
from numpy.typing import ArrayLike, NDArray

from qsm.physics.kinematics import LINK_NAMES, as_design
from qsm.schema.defaults import default


class CadError(ValueError):
    """The cross-section does not fit the design (bosses overlap or a bar is too short)."""


@dataclass(frozen=True)
class CadSettings:
    """Cross-section and material of every link.

    width_m: bar width (m), default 40 mm.
    thickness_m: plate thickness along z (m), default 20 mm.
    boss_radius_m: radius of the joint bosses (m), default 25 mm; must exceed width_m / 2.
    density_kg_m3: material density, default 1040 kg/m^3 (ABS-M30).
    segments_per_circle: polygon segments of a full boss circle, default 64 (area error 0.16 %
        of the boss discs; the mesh and the mass properties use the same polygon).
    corner_fillet_ratio: radius of the upper arm's inside-corner fillet over width_m, default
        0.25 (10 mm); 0 leaves the corner sharp.
    """

    width_m: float = default("cad.width_m")
    thickness_m: float = default("cad.thickness_m")
    boss_radius_m: float = default("cad.boss_radius_m")
    density_kg_m3: float = default("material.density_kg_m3")
    segments_per_circle: int = default("cad.segments_per_circle")
    corner_fillet_ratio: float = default("cad.corner_fillet_ratio")

    def __post_init__(self) -> None:
        if not (self.width_m > 0 and self.thickness_m > 0 and self.density_kg_m3 > 0):
            raise ValueError("width_m, thickness_m and density_kg_m3 must be positive")
        if not self.boss_radius_m > self.width_m / 2:
            raise ValueError("boss_radius_m must exceed width_m / 2")
        if self.segments_per_circle < 8:
            raise ValueError("segments_per_circle must be at least 8")
        if not self.corner_fillet_ratio >= 0:
            raise ValueError("corner_fillet_ratio must be at least 0")

    @property
    def boss_overlap_m(self) -> float:
        """Distance (m) from a boss centre to where the bar's edges meet the boss circle: a bar
        needs more than twice this length."""
        return math.sqrt(self.boss_radius_m**2 - (self.width_m / 2) ** 2)

    @property
    def corner_fillet_m(self) -> float:
        """Radius (m) of the fillet in the upper arm's inside corner."""
        return self.corner_fillet_ratio * self.width_m

    @property
    def leg_min_m(self) -> float:
        """Length (m) the upper arm's legs EE_x and EE_y must exceed: a boss overlap, half a
        width and the corner fillet."""
        return self.boss_overlap_m + self.width_m / 2 + self.corner_fillet_m

    def scaled(self, factor: float) -> CadSettings:
        """This section with width, thickness and boss radius multiplied by ``factor`` (> 0)."""
        return replace(
            self,
            width_m=self.width_m * factor,
            thickness_m=self.thickness_m * factor,
            boss_radius_m=self.boss_radius_m * factor,
        )


def link_settings(settings: CadSettings, scale: ArrayLike | None) -> dict[str, CadSettings]:
    """The section of each link (:data:`qsm.physics.kinematics.LINK_NAMES` order): ``settings``
    scaled by that link's entry of ``scale`` (4,), or ``settings`` for every link (None)."""
    if scale is None:
        return dict.fromkeys(LINK_NAMES, settings)
    factors = np.asarray(scale, dtype=float).reshape(len(LINK_NAMES))
    return {k: settings.scaled(float(f)) for k, f in zip(LINK_NAMES, factors, strict=True)}


DEFAULT_CAD = CadSettings()


class MassProperties(NamedTuple):
    """Rigid-body properties of one link in its link frame (SI units).

    mass_kg; com_m (3,) centre of mass; inertia_kg_m2 (3, 3) inertia tensor about the centre of
    mass in link-frame axes (off-diagonal entries are the tensor elements, -integral(x y dm)).
    """

    mass_kg: float
    com_m: NDArray[np.float64]
    inertia_kg_m2: NDArray[np.float64]


@lru_cache(maxsize=256)
def _unit_arc(a0: float, a1: float, seg: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """cos and sin (read-only) of the angles of :func:`arc` from a0 to a1 (rad): a fixed
    section's arcs have the same angles in every design, so each is computed once."""
    n = max(2, math.ceil((a1 - a0) / (2 * math.pi) * seg) + 1)
    a = np.linspace(a0, a1, n)
    cos, sin = np.cos(a), np.sin(a)
    cos.flags.writeable = sin.flags.writeable = False
    return cos, sin


def arc(cx: float, cy: float, r: float, a0: float, a1: float, seg: int) -> NDArray[np.float64]:
    """Points on a CCW arc from angle a0 to a1 > a0 (rad), both ends included."""
    cos, sin = _unit_arc(a0, a1, seg)
    return np.column_stack([cx + r * cos, cy + r * sin])


def _bar_outline(length: float, s: CadSettings) -> NDArray[np.float64]:
    """CCW outline of a straight bar from (0, 0) to (length, 0) with bosses at both ends."""
    r, h = s.boss_radius_m, s.width_m / 2
    beta = math.asin(h / r)
    if not length > 2 * s.boss_overlap_m:
        raise CadError(f"bar of length {length:.4g} m is too short for bosses of radius {r} m")
    return np.concatenate(
        [
            arc(0.0, 0.0, r, beta, 2 * math.pi - beta, s.segments_per_circle),
            arc(length, 0.0, r, beta - math.pi, math.pi - beta, s.segments_per_circle),
        ]
    )


def inside_corner(ee_x: float, s: CadSettings) -> NDArray[np.float64]:
    """Points (k, 2) of the upper arm's inside corner on its CCW outline, from the B-E' leg's
    lower edge to the E'-E leg's inner edge: the fillet arc of radius ``s.corner_fillet_m`` about
    (ee_x - w/2 - r_f, -w/2 - r_f), or the sharp corner (ee_x - w/2, -w/2) when it is 0."""
    h, rf = s.width_m / 2, s.corner_fillet_m
    if rf == 0:
        return np.array([[ee_x - h, -h]])
    return arc(ee_x - h - rf, -h - rf, rf, 0.0, math.pi / 2, s.segments_per_circle)[::-1]


def _upper_arm_outline(l4: float, ee_x: float, ee_y: float, s: CadSettings) -> NDArray[np.float64]:
    """CCW outline of the L-shaped upper arm: bar D-E' along x, bar E'-E along -y, 3 bosses,
    the inside corner filleted."""
    r, h, seg = s.boss_radius_m, s.width_m / 2, s.segments_per_circle
    beta = math.asin(h / r)
    x0 = s.boss_overlap_m
    if not (l4 > 2 * x0 and ee_x > s.leg_min_m and ee_y > s.leg_min_m):
        raise CadError(
            f"upper arm (l4={l4:.4g}, ee_x={ee_x:.4g}, ee_y={ee_y:.4g} m) is too small for bosses "
            f"of radius {r} m on bars of width {s.width_m} m with a corner fillet of "
            f"{s.corner_fillet_m:.4g} m"
        )
    pi = math.pi
    return np.concatenate(
        [
            arc(-l4, 0.0, r, beta, 2 * pi - beta, seg),  # boss D, ends at bottom edge
            arc(0.0, 0.0, r, pi + beta, 2 * pi - beta, seg),  # boss B, lower half
            inside_corner(ee_x, s),
            arc(ee_x, -ee_y, r, pi / 2 + beta, 5 * pi / 2 - beta, seg),  # boss E
            [[ee_x + h, h]],  # outer corner
            arc(0.0, 0.0, r, beta, pi - beta, seg),  # boss B, upper half
        ]
    )


def link_outlines(
    design: ArrayLike, settings: CadSettings = CadSettings(), scale: ArrayLike | None = None
) -> dict[str, NDArray]:
    """CCW outline polygons (n, 2) of the four links in their link frames (m), each link of the
    section ``settings`` scaled by its entry of ``scale`` (4,) (:func:`link_settings`).

    Raises :class:`CadError` when the section does not fit the design.
    """
    l1, l2, l3, l4, ee_x, ee_y = (float(v) for v in as_design(design))
    s = link_settings(settings, scale)
    return {
        "lower_arm": _bar_outline(l1, s["lower_arm"]),
        "crank": _bar_outline(l2, s["crank"]),
        "coupler": _bar_outline(l3, s["coupler"]),
        "upper_arm": _upper_arm_outline(l4, ee_x, ee_y, s["upper_arm"]),
    }


def polygon_mass_properties(
    outline: ArrayLike, thickness_m: float, density_kg_m3: float
) -> MassProperties:
    """Exact mass properties of the prism extruding a simple CCW polygon (m) symmetrically in z."""
    p = np.asarray(outline, dtype=float)
    x, y = p[:, 0], p[:, 1]
    xn, yn = np.concatenate((x[1:], x[:1])), np.concatenate((y[1:], y[:1]))  # next vertex
    c = x * yn - xn * y
    area = c.sum() / 2
    if not area > 0:
        raise CadError("outline must be a counter-clockwise polygon with positive area")
    cx = ((x + xn) * c).sum() / (6 * area)
    cy = ((y + yn) * c).sum() / (6 * area)
    # second moments about the origin, then about the centroid
    sxx = ((x * x + x * xn + xn * xn) * c).sum() / 12 - area * cx * cx  # integral x^2 dA
    syy = ((y * y + y * yn + yn * yn) * c).sum() / 12 - area * cy * cy  # integral y^2 dA
    sxy = ((x * yn + 2 * x * y + 2 * xn * yn + xn * y) * c).sum() / 24 - area * cx * cy
    return prism_properties(area, (cx, cy), (sxx, syy, sxy), thickness_m, density_kg_m3)


def prism_properties(
    area: float,
    centroid: tuple[float, float],
    second: tuple[float, float, float],
    thickness_m: float,
    density_kg_m3: float,
) -> MassProperties:
    """Mass properties of a plate extruded symmetrically in z from a plane region of ``area``
    (m^2), ``centroid`` (m) and ``second`` moments (int x^2, int y^2, int x y dA about the
    centroid, m^4)."""
    sxx, syy, sxy = second
    sigma = density_kg_m3 * thickness_m  # areal density
    mass = sigma * area
    t2 = mass * thickness_m**2 / 12
    inertia = np.array(
        [
            [sigma * syy + t2, -sigma * sxy, 0.0],
            [-sigma * sxy, sigma * sxx + t2, 0.0],
            [0.0, 0.0, sigma * (sxx + syy)],
        ]
    )
    return MassProperties(float(mass), np.array([centroid[0], centroid[1], 0.0]), inertia)


def mass_properties(
    design: ArrayLike, settings: CadSettings = CadSettings(), scale: ArrayLike | None = None
) -> dict[str, MassProperties]:
    """Mass properties of the four links (link frames, SI units), keyed by link name
    (:data:`qsm.physics.kinematics.LINK_NAMES`); sections as :func:`link_outlines`."""
    s = link_settings(settings, scale)
    return {
        name: polygon_mass_properties(poly, s[name].thickness_m, settings.density_kg_m3)
        for name, poly in link_outlines(design, settings, scale).items()
    }


def link_meshes(
    design: ArrayLike, settings: CadSettings = CadSettings(), scale: ArrayLike | None = None
) -> dict[str, trimesh.Trimesh]:
    """Watertight trimesh solids of the four links in their link frames (m), z in +-thickness/2
    (sections as :func:`link_outlines`)."""
    s = link_settings(settings, scale)
    return {
        name: trimesh.creation.extrude_polygon(
            shapely.Polygon(poly), s[name].thickness_m, mid_plane=True, engine="earcut"
        )
        for name, poly in link_outlines(design, settings, scale).items()
    }
