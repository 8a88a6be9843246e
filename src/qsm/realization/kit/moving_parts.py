"""The kit's parts that move with the links, as rigid bodies in the links' frames.

The hubs on the drives' outputs and the hardware of the pins and hubs (bearings, shoulder
screws, washers, nuts, screws, inserts) turn with a link. :func:`moving_parts` weighs them
from their solids in the kit's layout and places each in the frame of the link that carries it
(the MJCF model's body frames, :func:`qsm.physics.mjcf.model_spec`), so that the dynamics of the
later rules carry them (:func:`as_built`). The tool flange is left out: the realisation already
carries it at E beside the payload.

Each solid is steel (:data:`qsm.embodiment.kit.joints.STEEL_KG_M3`; the heat-set inserts are
brass, 8 % heavier and a few grams in all), projected onto the plane of motion: a planar model
moves only about z, so only a part's mass, its position in the plane and its inertia about z
enter its motion.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Mapping
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from qsm.embodiment.kit import joints as jt
from qsm.physics.cad import MassProperties
from qsm.physics.kinematics import pose
from qsm.physics.mjcf import combined
from qsm.realization.selection.outputs import props_from_json

#: The assembly step that puts in the tool flange and its screw: carried at E already.
TOOL_FLANGE_STEP = "tool_flange"


def link_frames(
    design: ArrayLike, theta1_rad: float, theta2_rad: float
) -> dict[str, tuple[NDArray[np.float64], NDArray[np.float64]]]:
    """Each link body's frame at motor angles ``theta1_rad``, ``theta2_rad`` (rad), as its
    origin (m, in the plane, A at the origin) and the unit vector of its x axis: the lower arm
    at A along AB, the upper arm at B along DB, the crank at A along AC, the coupler at C along
    CD (:func:`qsm.physics.mjcf.model_spec`)."""
    p = pose(design, theta1_rad, theta2_rad)
    a = np.zeros(2)
    b, c, d = (np.asarray(getattr(p, j), dtype=float).reshape(2) for j in "BCD")

    def unit(v: NDArray[np.float64]) -> NDArray[np.float64]:
        return v / np.linalg.norm(v)

    return {
        "lower_arm": (a, unit(b - a)),
        "upper_arm": (b, unit(b - d)),
        "crank": (a, unit(c - a)),
        "coupler": (c, unit(d - c)),
    }


def _tube(d_m: float, bore_m: float, length_m: float) -> tuple[float, float]:
    """A steel tube's mass (kg) and inertia about its axis (kg m^2)."""
    m = math.pi / 4 * (d_m**2 - bore_m**2) * length_m * jt.STEEL_KG_M3
    return m, m * (d_m**2 + bore_m**2) / 8


def _holes(part: Mapping[str, Any]) -> tuple[float, float]:
    """The steel that a turned part's ``holes`` (x, y about its axis, diameter, z from, z to;
    mm) take out: its mass (kg) and inertia about the part's axis (kg m^2). Holes at one point
    (a counterbore over its hole) count once, at each depth the widest; a hole counts where its
    centre is in the part's material."""
    steps = [(float(d), float(a), float(b)) for d, a, b in part["steps"]]
    mass = izz = 0.0
    for (x, y), group in itertools.groupby(
        sorted(tuple(float(v) for v in h) for h in part.get("holes", [])), key=lambda h: h[:2]
    ):
        group = list(group)
        r = math.hypot(x, y)
        cuts = sorted({z for h in group for z in h[3:]} | {z for s in steps for z in s[1:]})
        for z0, z1 in itertools.pairwise(cuts):
            mid = (z0 + z1) / 2
            d = max((h[2] for h in group if h[3] <= mid <= h[4]), default=0.0)
            solid = any(a <= mid <= b and r < dd / 2 for dd, a, b in steps)
            if d > 0 and solid and r >= float(part["bore_mm"]) / 2:
                m, own = _tube(d * 1e-3, 0.0, (z1 - z0) * 1e-3)
                mass += m
                izz += own + m * (r * 1e-3) ** 2
    return mass, izz


def solid_props(part: Mapping[str, Any], at_m: ArrayLike) -> MassProperties:
    """A turned solid's mass properties (kg, m, kg m^2): its coaxial cylinders (``steps``, mm:
    diameter, start, end along its axis) less its ``bore_mm`` and its ``holes`` (:func:`_holes`),
    in steel, its axis along z through ``at_m`` (m, in the plane). A solid with a ``frame`` (its
    axis in the plane, as a set screw's) counts as a point mass there."""
    bore = float(part["bore_mm"]) * 1e-3
    tubes = [_tube(float(d) * 1e-3, bore, abs(float(b) - float(a)) * 1e-3) for d, a, b in
             part["steps"]]  # fmt: skip
    holes = _holes(part)
    mass = sum(m for m, _ in tubes) - holes[0]
    izz = 0.0 if "frame" in part else sum(i for _, i in tubes) - holes[1]
    inertia = np.diag([izz / 2, izz / 2, izz])  # only izz moves a planar model
    return MassProperties(mass, np.array([*np.asarray(at_m, dtype=float)[:2], 0.0]), inertia)


def _in_frame(
    point_m: NDArray[np.float64], frame: tuple[NDArray[np.float64], NDArray[np.float64]]
) -> NDArray[np.float64]:
    """``point_m`` (m, in the plane) in the coordinates of ``frame`` (origin, x axis)."""
    origin, x = frame
    r = point_m - origin
    return np.array([r @ x, r @ np.array([-x[1], x[0]])])


def _where_m(part: Mapping[str, Any]) -> NDArray[np.float64]:
    """Where a solid sits in the plane (m): its axis's point, or its frame's origin."""
    if "frame" in part:
        return 1e-3 * np.asarray(part["frame"]["origin"][:2], dtype=float)
    return 1e-3 * np.asarray(part["at_mm"], dtype=float)


def moving_parts(
    layout: Mapping[str, Any], design: ArrayLike, step_of: Mapping[str, Any]
) -> dict[str, MassProperties]:
    """The hubs and hardware of a kit ``layout`` that move with each link (``moves_with``), one
    rigid body per link in its frame (:func:`link_frames` at the layout's ``pose_deg``), but
    not the tool flange's (``step_of`` gives each part's step; :data:`TOOL_FLANGE_STEP`)."""
    frames = link_frames(design, *np.radians(layout["pose_deg"]))
    solids = {**layout["hardware"], **layout["turned"]}
    out = {link: MassProperties(0.0, np.zeros(3), np.zeros((3, 3))) for link in frames}
    for name, part in solids.items():
        link = layout["moves_with"].get(name, "base")
        if link == "base" or step_of.get(name) == TOOL_FLANGE_STEP or name == "tool_flange":
            continue
        out[link] = combined(out[link], solid_props(part, _in_frame(_where_m(part), frames[link])))
    return out


def as_built(links: Mapping[str, Any], kit: Mapping[str, Any]) -> dict[str, MassProperties]:
    """The printed links' mass properties (``links``: the topology rule's
    ``optimised_links.json``) with the kit's moving parts on them (``kit``: ``kit.json``, its
    ``moving_parts`` of :func:`moving_parts`), as the dynamics after the kit carry them."""
    parts = props_from_json(kit["moving_parts"])
    return {
        name: combined(p, parts[name]) if name in parts else p
        for name, p in props_from_json(links).items()
    }
