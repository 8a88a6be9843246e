"""The kit's parts as prisms, for the assembly sequence's checks: each solid is a few prisms, a
shape in the plane across an axis (shapely, mm, holes kept) and an interval along it; the
plates of :mod:`qsm.realization.kit.kit_layout` are one prism each, its turned parts one per
cylinder step, and a tool's path (a straight key, a spanner) or a part's way in are prisms too.

Two prisms on the same axis meet where their intervals overlap by more than
:data:`TOUCH_MM` and their shapes by more than :data:`TOUCH_MM2` (parts that only rest on each
other do not meet); prisms on different axes meet where their bounding boxes do (a bound).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import shapely
from shapely import affinity

#: Overlap (mm) along an axis below which two prisms only touch.
TOUCH_MM = 0.05
#: Overlap (mm^2) across an axis below which two prisms only touch.
TOUCH_MM2 = 0.01


@dataclass(frozen=True)
class Prism:
    """A ``shape`` (mm) across ``axis`` extruded from ``lo`` to ``hi`` (mm) along it."""

    axis: str
    shape: shapely.Geometry
    lo: float
    hi: float

    def box(self) -> tuple[np.ndarray, np.ndarray]:
        """The bounding box's (x, y, z) corners, mm."""
        x0, a0, x1, a1 = self.shape.bounds
        if self.axis == "z":
            return np.array([x0, a0, self.lo]), np.array([x1, a1, self.hi])
        return np.array([x0, self.lo, a0]), np.array([x1, self.hi, a1])

    def meets(self, other: Prism) -> bool:
        """Whether the two prisms overlap by more than a touch."""
        if self.axis != other.axis:
            (a0, a1), (b0, b1) = self.box(), other.box()
            return bool(np.all(np.minimum(a1, b1) - np.maximum(a0, b0) > TOUCH_MM))
        if min(self.hi, other.hi) - max(self.lo, other.lo) <= TOUCH_MM:
            return False
        return bool(self.shape.intersection(other.shape).area > TOUCH_MM2)

    def swept(self, along: Sequence[float], stroke_mm: float) -> Prism:
        """The space the prism passes through when moved by ``stroke_mm`` along the unit
        vector ``along`` (x, y, z) to where it is: stretched along its axis, or its shape and
        its shape moved back joined by their hull."""
        d = np.asarray(along, dtype=float) * stroke_mm
        on_axis = d[2] if self.axis == "z" else d[1]
        across = (d[0], d[1]) if self.axis == "z" else (d[0], d[2])
        lo = self.lo - max(on_axis, 0.0)
        hi = self.hi - min(on_axis, 0.0)
        if math.hypot(*across) < 1e-9:
            return Prism(self.axis, self.shape, lo, hi)
        back = affinity.translate(self.shape, -across[0], -across[1])
        hull = shapely.union(self.shape, back).convex_hull
        return Prism(self.axis, hull, lo, hi)


def disc(x: float, y: float, d: float, hole: float = 0.0) -> shapely.Geometry:
    """A disc of diameter ``d`` about (x, y) mm, less a concentric ``hole``."""
    outer = shapely.Point(x, y).buffer(d / 2, 24)
    return outer if hole <= 0 else outer.difference(shapely.Point(x, y).buffer(hole / 2, 24))


def plate_prism(plate: Mapping[str, Any]) -> Prism:
    """A placed plate of the layout (outline and holes in its frame, ``origin``, ``x_dir``,
    ``normal`` along z or -y) as a prism."""
    shape = shapely.Polygon(plate["outline"], plate["holes"])
    ox, oy, oz = plate["origin"]
    t = plate["thickness_mm"]
    if plate["normal"][2] != 0:
        c, s = plate["x_dir"][0], plate["x_dir"][1]
        moved = affinity.affine_transform(shape, [c, -s, s, c, ox, oy])
        lo = oz if plate["normal"][2] > 0 else oz - t
        return Prism("z", moved, lo, lo + t)
    moved = affinity.translate(shape, ox, oz)
    return Prism("y", moved, oy - t, oy)  # the base plate: down from its origin


def plate_prisms(plate: Mapping[str, Any]) -> tuple[Prism, ...]:
    """A placed plate as its prism, or, with a ``pocket`` (a cheek's, along z), as the plate
    less the pocket's span and, across the pocket's span, the plate less the pocket's disc."""
    whole = plate_prism(plate)
    pocket = plate.get("pocket") or {}
    if pocket.get("depth_mm", 0.0) <= 0:
        return (whole,)
    lo = whole.lo + pocket["z0_mm"]
    hi = whole.lo + pocket["z1_mm"]
    rim = whole.shape.difference(disc(plate["origin"][0], plate["origin"][1], pocket["d_mm"]))
    rest = (whole.lo, lo) if pocket["z0_mm"] > 0 else (hi, whole.hi)
    return Prism("z", whole.shape, *rest), Prism("z", rim, lo, hi)


def turned_prisms(part: Mapping[str, Any]) -> tuple[Prism, ...]:
    """A turned part of the layout, one prism per cylinder step, its bore cut out."""
    x, y = part["at_mm"]
    return tuple(
        Prism("z", disc(x, y, d, part["bore_mm"]), a, b)
        for d, a, b in part["steps"]
        if d > part["bore_mm"]
    )


def hardware_prisms(part: Mapping[str, Any]) -> tuple[Prism, ...]:
    """A piece of the kit's hardware (:mod:`qsm.realization.kit.kit_hardware`) as prisms: along
    z as a turned part; along y (a cheek's or the table's screw) as discs across y; across the
    plane (a hub's set screw) as the box each cylinder sweeps, across z as deep as it is wide."""
    frame = part.get("frame")
    if frame is None:
        return turned_prisms(part)
    (ox, oy, oz), n = frame["origin"], frame["normal"]
    if abs(n[1]) > 0.5:
        ends = [(oy + n[1] * a, oy + n[1] * b) for _, a, b in part["steps"]]
        return tuple(
            Prism("y", disc(ox, oz, d, part["bore_mm"]), min(e), max(e))
            for (d, _, _), e in zip(part["steps"], ends, strict=True)
        )
    out = []
    for d, a, b in part["steps"]:
        line = shapely.LineString([(ox + n[0] * t, oy + n[1] * t) for t in (a, b)])
        out.append(Prism("z", line.buffer(d / 2, cap_style="flat"), oz - d / 2, oz + d / 2))
    return tuple(out)


def moved_prism(prism: Prism, start: tuple, end: tuple) -> Prism:
    """A prism along z carried by a link from its frame ``start`` to ``end`` (each the origin,
    m, and the angle, rad)."""
    (x0, y0), a = start
    (x1, y1), b = end
    turned = affinity.rotate(prism.shape, b - a, origin=(1e3 * x0, 1e3 * y0), use_radians=True)
    shape = affinity.translate(turned, 1e3 * (x1 - x0), 1e3 * (y1 - y0))
    return Prism(prism.axis, shape, prism.lo, prism.hi)


def solids(layout: Mapping[str, Any]) -> dict[str, tuple[Prism, ...]]:
    """Every part of a kit ``layout`` (:func:`qsm.realization.kit.kit_layout.kit_geometry`) as
    its prisms, by its name."""
    out = {name: plate_prisms(p) for name, p in layout["plates"].items()}
    out |= {name: turned_prisms(t) for name, t in layout["turned"].items()}
    return out


def blockers(
    reach: Sequence[Prism], placed: Mapping[str, Sequence[Prism]], skip: Sequence[str] = ()
) -> list[str]:
    """The parts of ``placed`` (name: prisms) that any prism of ``reach`` meets, except
    ``skip``."""
    return [
        name
        for name, prisms in placed.items()
        if name not in skip and any(r.meets(p) for r in reach for p in prisms)
    ]
