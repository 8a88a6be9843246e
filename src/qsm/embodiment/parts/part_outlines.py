"""Outlines of the bored link parts (link frames, m): bars and the L-shaped upper arm with a boss
radius of their own at each joint, and the polygonal bores that circumscribe a nominal circle.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from qsm.physics.cad import CadError, CadSettings, arc, inside_corner


def _overlap(r: float, h: float) -> float:
    return math.sqrt(r * r - h * h)


def bar_outline(length: float, r0: float, r1: float, cad: CadSettings) -> NDArray[np.float64]:
    """CCW outline of a bar from (0, 0) to (length, 0) with bosses of radius r0 and r1 (m).

    With ``r0 = r1 = cad.boss_radius_m`` it is the outline of :mod:`qsm.physics.cad`, point for
    point.
    """
    h, seg = cad.width_m / 2, cad.segments_per_circle
    if not (r0 > h and r1 > h):
        raise CadError("boss radii must exceed half the bar width")
    if not length > _overlap(r0, h) + _overlap(r1, h):
        raise CadError(
            f"bar of length {length:.4g} m is too short for bosses of radius {r0:.4g} and "
            f"{r1:.4g} m"
        )
    b0, b1 = math.asin(h / r0), math.asin(h / r1)
    return np.concatenate(
        [
            arc(0.0, 0.0, r0, b0, 2 * math.pi - b0, seg),
            arc(length, 0.0, r1, b1 - math.pi, math.pi - b1, seg),
        ]
    )


def upper_arm_outline(
    l4: float, ee_x: float, ee_y: float, r_d: float, r_b: float, r_e: float, cad: CadSettings
) -> NDArray[np.float64]:
    """CCW outline of the L-shaped upper arm (qsm.physics.cad's, its inside corner filleted) with
    its own boss radius at D, B and E (m)."""
    h, seg, pi = cad.width_m / 2, cad.segments_per_circle, math.pi
    if not (r_d > h and r_b > h and r_e > h):
        raise CadError("boss radii must exceed half the bar width")
    bd, bb, be = (math.asin(h / r) for r in (r_d, r_b, r_e))
    if not (
        l4 > _overlap(r_d, h) + _overlap(r_b, h)
        and ee_x - h - cad.corner_fillet_m > _overlap(r_b, h)
        and ee_y - h - cad.corner_fillet_m > _overlap(r_e, h)
    ):
        raise CadError(
            f"upper arm (l4={l4:.4g}, ee_x={ee_x:.4g}, ee_y={ee_y:.4g} m) is too small for bosses "
            f"of radius {r_d:.4g}, {r_b:.4g}, {r_e:.4g} m on bars of width {cad.width_m} m"
        )
    return np.concatenate(
        [
            arc(-l4, 0.0, r_d, bd, 2 * pi - bd, seg),
            arc(0.0, 0.0, r_b, pi + bb, 2 * pi - bb, seg),
            inside_corner(ee_x, cad),
            arc(ee_x, -ee_y, r_e, pi / 2 + be, 5 * pi / 2 - be, seg),
            [[ee_x + h, h]],
            arc(0.0, 0.0, r_b, bb, pi - bb, seg),
        ]
    )


def hole_polygon(centre: Sequence[float], diameter_m: float, segments: int) -> NDArray[np.float64]:
    """Clockwise regular ``segments``-gon whose inscribed circle has ``diameter_m`` (m)."""
    rv = diameter_m / 2 / math.cos(math.pi / segments)
    a = -(np.arange(segments) + 0.5) * 2 * math.pi / segments  # clockwise
    return np.column_stack([centre[0] + rv * np.cos(a), centre[1] + rv * np.sin(a)])
