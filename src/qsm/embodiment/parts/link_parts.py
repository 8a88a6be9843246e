"""Link parts you can assemble: the outlines of :mod:`qsm.physics.cad`, a through bore per joint.

The link frames, bar width, plate thickness and material are those of :mod:`qsm.physics.cad`, each
link with its own section (:attr:`PartSettings.scale`: the configured section, or the one sized
by strength, :mod:`qsm.embodiment.strength.sizing`); what changes is that every joint has a
**bore** and a
**boss sized for it**:

========== ======= ================ ====================================================
link       joint   bore             what goes in it
========== ======= ================ ====================================================
lower_arm  A       d (shaft)        hub 1's spigot (the builder's kit: the hub is bolted to
                                    the link, motor 1's drive turns it and carries A)
lower_arm  B       D (seat)         the bearing of joint B (outer ring pressed in)
crank      A       d (shaft)        hub 2's spigot, like the lower arm
crank      C       D (seat)         the bearing of joint C
coupler    C       d (pin)          the pin of joint C (held by the coupler, turns in the
                                    crank's bearing)
coupler    D       D (seat)         the bearing of joint D
upper_arm  B       d (pin)          the pin of joint B (turns in the lower arm's bearing)
upper_arm  D       d (pin)          the pin of joint D (turns in the coupler's bearing)
upper_arm  E       tool hole        a clearance hole for the tool mount (``tool_hole_m``,
                                    default 9 mm: ISO 273 medium clearance for M8);
                                    0 leaves the end effector's boss solid
========== ======= ================ ====================================================

d and D are the bore and outer diameter of the joint's bearing
(:mod:`qsm.embodiment.parts.bearings`), so each of B, C and D has one bearing and one pin (at A
the bearing sized by the strength check sets the bore for the hubs' spigots). A link's boss at a
joint has the radius ``max(R, D / 2 + boss_wall_m)`` (at E: ``tool_hole_m / 2 +
boss_wall_m``), R the boss radius of the link's section: with one section for all links, both
links at a joint get the same boss.

Bores are regular polygons of ``cad.segments_per_circle`` sides that *circumscribe* the nominal
circle (flats at the nominal radius), so a bearing or pin of the nominal diameter fits the STL; the
mass properties are those of exactly that polygonal plate. They are exact for the holed prism: the
area moments of the outline (the polygon formulas of
:func:`qsm.physics.cad.polygon_mass_properties`) less the moments of every hole
(:mod:`qsm.embodiment.parts.part_mass`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from functools import cache
from pathlib import Path

import numpy as np
import shapely
import trimesh
from numpy.typing import ArrayLike, NDArray

from qsm.embodiment.parts.bearings import (
    DEFAULT_BOSS_WALL_M,
    JOINTS,
    BearingTable,
    boss_radius_m,
    load_catalogue,
)
from qsm.embodiment.parts.part_outlines import bar_outline, hole_polygon, upper_arm_outline
from qsm.physics.cad import DEFAULT_CAD, CadError, CadSettings, link_settings
from qsm.physics.kinematics import LINK_NAMES, as_design

#: Default tool-mount hole at E (m): ISO 273 medium-series clearance hole for an M8 screw.
DEFAULT_TOOL_HOLE_M = 0.009
#: Bore kinds: a bearing's outer ring ("seat"), a clamped pin or motor shaft, the tool mount.
BORE_KINDS: tuple[str, ...] = ("seat", "pin", "shaft", "tool")

#: (joint, kind) of each link's bores, in link order; see the module docstring.
LINK_BORES: dict[str, tuple[tuple[str, str], ...]] = {
    "lower_arm": (("A", "shaft"), ("B", "seat")),
    "crank": (("A", "shaft"), ("C", "seat")),
    "coupler": (("C", "pin"), ("D", "seat")),
    "upper_arm": (("B", "pin"), ("D", "pin"), ("E", "tool")),
}


@dataclass(frozen=True)
class PartSettings:
    """What the bored parts need beyond the section: bearing catalogue, boss wall, tool hole.

    cad: the section and material (:class:`qsm.physics.cad.CadSettings`); boss_wall_m: printed
    wall around a bearing seat or the tool hole (m, default 4 mm); tool_hole_m: diameter of the
    tool-mount hole at E (m, default 9 mm; 0 for none); catalogue: bearing table (default
    :func:`qsm.embodiment.parts.bearings.load_catalogue`); scale: each link's section as ``cad``'s
    scaled by this factor (:data:`qsm.physics.kinematics.LINK_NAMES` order; the sized sections
    of :mod:`qsm.embodiment.strength.sizing`), None: ``cad`` for every link.
    """

    cad: CadSettings = field(default_factory=CadSettings)
    boss_wall_m: float = DEFAULT_BOSS_WALL_M
    tool_hole_m: float = DEFAULT_TOOL_HOLE_M
    catalogue: BearingTable | None = None
    scale: tuple[float, ...] | None = None

    def __post_init__(self) -> None:
        if not self.boss_wall_m > 0:
            raise ValueError("boss_wall_m must be positive")
        if not self.tool_hole_m >= 0:
            raise ValueError("tool_hole_m must be >= 0")
        if self.scale is not None:
            if len(self.scale) != len(LINK_NAMES) or not all(f > 0 for f in self.scale):
                raise ValueError(f"scale needs one positive factor per link {LINK_NAMES}")
            object.__setattr__(self, "scale", tuple(float(f) for f in self.scale))

    def sections(self) -> dict[str, CadSettings]:
        """Each link's section (:func:`qsm.physics.cad.link_settings`)."""
        return link_settings(self.cad, self.scale)

    def of_link(self, name: str) -> PartSettings:
        """These settings with the section of link ``name`` for every link."""
        return replace(self, cad=self.sections()[name], scale=None)

    @property
    def table(self) -> BearingTable:
        return self.catalogue if self.catalogue is not None else _catalogue()


@cache
def _catalogue() -> BearingTable:
    return load_catalogue()


@dataclass(frozen=True)
class Bore:
    """One through bore of a link, in the link frame (m).

    joint: A-E; kind: one of :data:`BORE_KINDS`; centre_m: (x, y); diameter_m: nominal diameter
    (0: no hole); boss_radius_m: radius of the boss around it; bearing: the joint's bearing
    designation ("" at E).
    """

    joint: str
    kind: str
    centre_m: tuple[float, float]
    diameter_m: float
    boss_radius_m: float
    bearing: str

    def net_width_m(self) -> float:
        """Width (m) of material across the boss through the bore's centre: 2 r - diameter."""
        return 2 * self.boss_radius_m - self.diameter_m

    def ligament_m(self) -> float:
        """Material (m) between the bore and the boss's edge on each side: r - diameter / 2."""
        return self.boss_radius_m - self.diameter_m / 2


@dataclass(frozen=True)
class LinkPart:
    """A bored link: its name, outline with holes (shapely, link frame, m), its bores and its
    ``section`` (width, thickness, boss radius and material of this link)."""

    name: str
    polygon: shapely.Polygon
    bores: tuple[Bore, ...]
    section: CadSettings

    @property
    def holes(self) -> int:
        """Number of through holes."""
        return len(self.polygon.interiors)


def joint_radii(
    bearing_index: ArrayLike, settings: PartSettings = PartSettings()
) -> NDArray[np.float64]:
    """Boss radii (..., 5) in m at A, B, C, D (from the bearings ``bearing_index`` (..., 4),
    catalogue rows as :attr:`qsm.embodiment.parts.bearings.BearingChoice.index`) and at E (the tool
    hole's), with the boss radius of ``settings.cad`` (a link's own: :meth:`PartSettings.of_link`).
    Vectorised over designs."""
    i = np.asarray(bearing_index, dtype=np.intp)
    if i.shape[-1] != len(JOINTS):
        raise ValueError(f"one bearing per joint {JOINTS}, got shape {i.shape}")
    r = boss_radius_m(i, settings.table, settings.boss_wall_m, settings.cad.boss_radius_m)
    if settings.tool_hole_m > 0:
        r_e = max(settings.cad.boss_radius_m, settings.tool_hole_m / 2 + settings.boss_wall_m)
    else:
        r_e = settings.cad.boss_radius_m
    return np.concatenate([r, np.full((*r.shape[:-1], 1), r_e)], axis=-1)


def link_bores(
    design: ArrayLike, bearing_index: Sequence[int], settings: PartSettings = PartSettings()
) -> dict[str, tuple[Bore, ...]]:
    """The bores of every link (link frames, m) for one design and its bearings at A, B, C, D;
    each boss radius from the link's own section (:meth:`PartSettings.of_link`)."""
    l1, l2, l3, l4, ee_x, ee_y = (float(v) for v in as_design(design))
    table = settings.table
    idx = np.asarray(bearing_index, dtype=np.intp)
    fallback = int(np.argmax(table.D_m))
    by_joint = {}
    for k, joint in enumerate(JOINTS):
        row = int(idx[k]) if idx[k] >= 0 else fallback
        by_joint[joint] = (table.d_m[row], table.D_m[row], str(table.designation[row]))
    centres = {
        "lower_arm": {"A": (0.0, 0.0), "B": (l1, 0.0)},
        "crank": {"A": (0.0, 0.0), "C": (l2, 0.0)},
        "coupler": {"C": (0.0, 0.0), "D": (l3, 0.0)},
        "upper_arm": {"B": (0.0, 0.0), "D": (-l4, 0.0), "E": (ee_x, -ee_y)},
    }
    out: dict[str, tuple[Bore, ...]] = {}
    for link, specs in LINK_BORES.items():
        radii = dict(zip((*JOINTS, "E"), joint_radii(idx, settings.of_link(link)), strict=True))
        bores = []
        for joint, kind in specs:
            if joint == "E":
                bores.append(
                    Bore(joint, kind, centres[link][joint], settings.tool_hole_m, radii["E"], "")
                )
                continue
            d, big_d, name = by_joint[joint]
            dia = big_d if kind == "seat" else d
            r = float(radii[joint])
            bores.append(Bore(joint, kind, centres[link][joint], float(dia), r, name))
        out[link] = tuple(bores)
    return out


def link_parts(
    design: ArrayLike, bearing_index: Sequence[int], settings: PartSettings = PartSettings()
) -> dict[str, LinkPart]:
    """The four bored links of one design (link frames, m), keyed by
    :data:`qsm.physics.cad.LINK_NAMES`, each with its own section
    (:meth:`PartSettings.sections`).

    Raises :class:`qsm.physics.cad.CadError` when the bosses do not fit the design (see
    :func:`boss_fit_violation_m` for the continuous measure).
    """
    l1, l2, l3, l4, ee_x, ee_y = (float(v) for v in as_design(design))
    bores = link_bores(design, bearing_index, settings)
    r = {name: {b.joint: b.boss_radius_m for b in bores[name]} for name in LINK_NAMES}
    s = settings.sections()
    outlines = {
        "lower_arm": bar_outline(l1, *(r["lower_arm"][j] for j in "AB"), s["lower_arm"]),
        "crank": bar_outline(l2, *(r["crank"][j] for j in "AC"), s["crank"]),
        "coupler": bar_outline(l3, *(r["coupler"][j] for j in "CD"), s["coupler"]),
        "upper_arm": upper_arm_outline(
            l4, ee_x, ee_y, *(r["upper_arm"][j] for j in "DBE"), s["upper_arm"]
        ),
    }
    parts = {}
    for name in LINK_NAMES:
        cad = s[name]
        holes = [
            hole_polygon(b.centre_m, b.diameter_m, cad.segments_per_circle)
            for b in bores[name]
            if b.diameter_m > 0
        ]
        poly = shapely.Polygon(outlines[name], holes)
        if not poly.is_valid:
            raise CadError(f"{name}: the bores do not fit inside the outline")
        parts[name] = LinkPart(name, poly, bores[name], cad)
    return parts


def part_meshes(parts: Mapping[str, LinkPart]) -> dict[str, trimesh.Trimesh]:
    """Watertight extrusions (link frames, m, z in +-thickness / 2, each part's own thickness)
    of the bored parts; the genus of each (``(2 - euler_number) / 2``) is its number of holes."""
    return {
        name: trimesh.creation.extrude_polygon(
            p.polygon, p.section.thickness_m, mid_plane=True, engine="earcut"
        )
        for name, p in parts.items()
    }


def export_parts_stl(parts: Mapping[str, LinkPart], directory: str | Path) -> list[Path]:
    """Write ``<link>.stl`` (binary, millimetres, link frame) per bored part; returns the paths."""
    out = Path(directory)
    out.mkdir(parents=True, exist_ok=True)
    paths = [out / f"{name}.stl" for name in parts]
    for path, mesh in zip(paths, part_meshes(parts).values(), strict=True):
        mesh.copy().apply_scale(1000.0).export(path)
    return paths


def boss_fit_violation_m(
    designs: ArrayLike, radii: ArrayLike, cad: CadSettings = DEFAULT_CAD
) -> NDArray[np.float64]:
    """How much (m) the shortest bar of each design falls short of holding its bosses (> 0: the
    bored parts cannot be built; <= 0: the slack). Vectorised: ``designs`` (N, 6), ``radii``
    (N, 5) boss radii at A-E (:func:`joint_radii`). Does not check that bosses of the upper arm's
    B and E overlap (``link_parts`` rejects such outlines)."""
    d = np.atleast_2d(as_design(designs))
    r = np.atleast_2d(np.asarray(radii, dtype=float))
    h = cad.width_m / 2
    x = np.sqrt(np.maximum(r**2 - h**2, 0.0))
    xa, xb, xc, xd, xe = (x[:, k] for k in range(5))
    short = np.column_stack(
        [
            xa + xb - d[:, 0],
            xa + xc - d[:, 1],
            xc + xd - d[:, 2],
            xd + xb - d[:, 3],
            xb + h - d[:, 4],
            xe + h - d[:, 5],
            h - r.min(axis=1),  # a boss must be wider than the bar
        ]
    )
    return short.max(axis=1)
