"""Where every part of the kit sits, in mm, for the STEP assembly, the DXF outlines and the
exploded view: plates as outlines with holes in their own plane (``outline``, ``holes``,
``thickness_mm``) placed by a frame (``origin``, ``x_dir``, ``normal``: the plate extrudes
along its normal), turned parts and drive envelopes as cylinders along the joint axis z.

Global frame: A at the origin, x and y the arm's plane (y up), z along the joint axis from drive
1 to drive 2; cheek 1's inner face at z = 0. The links stand at the pose ``pose_deg``.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import shapely

from qsm.embodiment.kit import base as bs
from qsm.embodiment.kit import fasteners as fs
from qsm.embodiment.kit import joints as jt
from qsm.embodiment.kit.interfaces import DriveInterface
from qsm.embodiment.parts.link_parts import LinkPart
from qsm.physics.kinematics import pose


def _rings(polygon: shapely.Polygon, scale: float = 1e3) -> dict[str, Any]:
    """A polygon's exterior and holes as lists of [x, y] (mm)."""
    return {
        "outline": (np.asarray(polygon.exterior.coords)[:-1] * scale).round(4).tolist(),
        "holes": [(np.asarray(r.coords)[:-1] * scale).round(4).tolist() for r in polygon.interiors],
    }


#: The links, each a frame that carries its plate (and hub 1, hub 2 or the tool flange).
LINK_FRAMES = ("lower_arm", "crank", "coupler", "upper_arm")
#: A shaft hub's set screw's angle (rad) from its link's axis: midway between two of the hub's
#: screws to the link (at 30 + 60 i degrees), so that its key passes between their heads; the
#: keyway is opposite.
SET_SCREW_RAD = 0.0


def link_frames(design: np.ndarray, t1: float, t2: float) -> dict[str, tuple]:
    """Each link frame's origin (m) and x-axis angle (rad) at motor angles ``t1``, ``t2``."""
    p = pose(design, t1, t2)
    c, d = np.asarray(p.C), np.asarray(p.D)
    return {
        "lower_arm": ((0.0, 0.0), t1),
        "crank": ((0.0, 0.0), t2),
        "coupler": (tuple(c), math.atan2(*(d - c)[::-1])),
        "upper_arm": (tuple(np.asarray(p.B)), float(p.phi)),
    }


def working_pose(design: np.ndarray, theta1_deg: tuple[float, float], theta2_min: float) -> tuple:
    """A pose (theta1, theta2) rad in the middle of the operating range where the loop
    closes, scanning outwards from the middle."""
    mid1 = np.radians(np.mean(theta1_deg))
    for frac in (0.5, 0.4, 0.6, 0.3, 0.7, 0.2, 0.8, 0.1, 0.9):
        t2 = np.radians(theta2_min) + frac * (mid1 - np.radians(theta2_min))
        if bool(pose(design, mid1, t2).closes):
            return float(mid1), float(t2)
    raise ValueError("the loop closes nowhere along the middle of the operating range")


def link_plates(
    design: np.ndarray, parts: dict[str, LinkPart], z: dict[str, float], angles: tuple
) -> dict[str, dict[str, Any]]:
    """The four links as placed plates at the motor ``angles`` (rad)."""
    frames = link_frames(design, *angles)
    out = {}
    for name, part in parts.items():
        (x0, y0), a = frames[name]
        out[name] = _rings(part.polygon) | {
            "thickness_mm": 1e3 * part.section.thickness_m,
            "origin": [1e3 * x0, 1e3 * y0, z[name]],
            "x_dir": [math.cos(a), math.sin(a), 0.0],
            "normal": [0.0, 0.0, 1.0],
            "kind": "printed",
        }
    return out


def circle(x: float, y: float, d: float, n: int = 48) -> list[list[float]]:
    """A circle of diameter ``d`` about (x, y) as a polygon of ``n`` corners (mm)."""
    a = np.linspace(0, 2 * np.pi, n, endpoint=False)
    return np.column_stack([x + d / 2 * np.cos(a), y + d / 2 * np.sin(a)]).round(4).tolist()


def ring(pcd: float, n: int, start_rad: float) -> list[tuple[float, float]]:
    """``n`` points on a circle of ``pcd`` mm about A, the first at ``start_rad``."""
    return [
        (pcd / 2 * math.cos(start_rad + 2 * math.pi * i / n),
         pcd / 2 * math.sin(start_rad + 2 * math.pi * i / n))
        for i in range(n)
    ]  # fmt: skip


def bolt_circle(pcd: float, n: int, hole: float, start_deg: float = 0.0) -> list[list]:
    """``n`` holes of ``hole`` mm on a circle of ``pcd`` mm about the origin."""
    return [circle(x, y, hole, 24) for x, y in ring(pcd, n, math.radians(start_deg))]


def cheek_plate(part: dict[str, Any], iface: DriveInterface, hole: float, z0: float) -> dict:
    """Cheek ``part`` (its sizes, mm) as a placed plate: a bar of the cheek's width from the
    base plate up to A, rounded about A, with the central bore, the drive's mounting holes
    (``hole`` mm, a square pattern of 4 turned by 45 degrees); its three fixing screws' tapped
    holes in its bottom edge (``edge_holes``: x, diameter, y from, y to; 2 mm deeper than the
    screw reaches); a ``pocket`` about A (diameter and depth, mm) in its outer face, from
    ``pocket["z0_mm"]`` to ``pocket["z1_mm"]`` in its own frame."""
    b, h, t = part["width_mm"], part["height_mm"], part["thickness_mm"]
    body = shapely.union(shapely.box(-b / 2, -h, b / 2, 0.0), shapely.Point(0, 0).buffer(b / 2, 32))
    start = 45.0 if iface.mount_bolts == 4 else 0.0
    holes = [circle(0.0, 0.0, part["bore_mm"])]
    holes += bolt_circle(iface.mount_pcd_mm, iface.mount_bolts, hole, start)
    return {
        "outline": np.asarray(body.exterior.coords)[:-1].round(4).tolist(),
        "holes": holes,
        "thickness_mm": t,
        "origin": [0.0, 0.0, z0],
        "x_dir": [1.0, 0.0, 0.0],
        "normal": [0.0, 0.0, 1.0],
        "kind": "cut",
        "edge_holes": _fixing_holes(part),
        "pocket": _pocket_of(part, outer_low=z0 < 0),
    }


def _fixing_holes(part: dict[str, Any]) -> list[list[float]]:
    """A cheek's tapped holes (x, diameter, y from, y to; mm) for its three fixing screws, at
    x = -s, 0 and s (s = b / 2 - 10 mm), from its bottom edge as deep as each screw reaches past
    the base plate and its washer, and 2 mm."""
    screw = part["fixing"]["screw"]
    if not screw:
        return []
    thread, length = screw.split()[2], float(screw.split(" x ")[-1])
    depth = length - bs.BASE_PLATE_MM - fs.washer_mm(thread)[2] + 2.0
    h = part["height_mm"]
    return [[x, float(thread[1:]), -h, -h + depth] for x in fixing_x_mm(part)]


def fixing_x_mm(part: dict[str, Any]) -> tuple[float, float, float]:
    """Where (x, mm) a cheek's three fixing screws go: -s, 0 and s, s = b / 2 - 10 mm."""
    span = part["width_mm"] / 2 - 10
    return (-span, 0.0, span)


def _pocket_of(part: dict[str, Any], outer_low: bool) -> dict[str, float]:
    """A cheek's pocket (diameter, depth, and its span across the plate in the plate's own
    frame, mm), in the outer face: the low one (``outer_low``) or the high one."""
    d, depth, t = part["pocket"]["d_mm"], part["pocket"]["depth_mm"], part["thickness_mm"]
    z = (0.0, depth) if outer_low else (t - depth, t)
    return {"d_mm": d, "depth_mm": depth, "z0_mm": z[0], "z1_mm": z[1]}


def base_plate_size(cheeks: list[dict[str, Any]], stack: dict[str, float]) -> tuple[float, float]:
    """The base plate's width across (x) and length along the axis (z), mm: 40 mm beyond the
    widest cheek on each side and beyond each cheek's outer face."""
    span = stack["cheek_2"] + cheeks[0]["thickness_mm"] + cheeks[1]["thickness_mm"]
    return max(c["width_mm"] for c in cheeks) + 80.0, span + 80.0


def base_plate(cheeks: list[dict[str, Any]], z: tuple[float, float], h: float, t: float) -> dict:
    """The base plate under both cheeks (``z``: cheek 1's outer face and cheek 2's, mm), 40 mm
    beyond them, with 4 x 9 mm table holes 15 mm in from its corners and each cheek's three
    fixing holes under it. Its plane: x and z (the plate's local y is the global z)."""
    w = max(c["width_mm"] for c in cheeks) + 80.0
    z0, z1 = z[0] - 40.0, z[1] + 40.0
    holes = [circle(x, zz, 9.0) for x in (-w / 2 + 15, w / 2 - 15) for zz in (z0 + 15, z1 - 15)]
    middles = (z[0] + cheeks[0]["thickness_mm"] / 2, z[1] - cheeks[1]["thickness_mm"] / 2)
    for c, zc in zip(cheeks, middles, strict=True):
        screw = c["fixing"]["screw"]
        hole = fs.clearance_hole_mm(screw.split()[2] if screw else "M6")
        holes += [circle(x, zc, hole) for x in fixing_x_mm(c)]
    return {
        "outline": [[-w / 2, z0], [w / 2, z0], [w / 2, z1], [-w / 2, z1]],
        "holes": holes,
        "thickness_mm": t,
        "origin": [0.0, -h, 0.0],
        "x_dir": [1.0, 0.0, 0.0],
        "normal": [0.0, -1.0, 0.0],
        "kind": "cut",
        "size_mm": [w, z1 - z0],
    }


def turned(
    steps: list[tuple[float, float, float]], bore: float = 0.0, at: tuple = (0.0, 0.0)
) -> dict[str, Any]:
    """A turned part or envelope along z, as coaxial cylinders ``steps`` (diameter, z from, z
    to; mm) with a ``bore`` through them, its axis at ``at`` (x, y) mm; ``d_mm``,
    ``length_mm`` and ``z0_mm`` give its bounds."""
    z0 = min(a for _, a, _ in steps)
    return {
        "steps": [[float(d), float(a), float(b)] for d, a, b in steps],
        "d_mm": max(d for d, _, _ in steps),
        "length_mm": max(b for _, _, b in steps) - z0,
        "z0_mm": z0,
        "bore_mm": float(bore),
        "at_mm": [float(at[0]), float(at[1])],
    }


def _hub_steps(hub: dict[str, Any], link_face: float, toward: int, drive_face: float) -> list:
    """A hub's cylinders: its flange against the link's face, its spigot into the link's bore
    (10 mm, at most half the gap) and its boss through the cheek to the drive's face;
    ``toward``: -1 when the drive is at lower z."""
    screws = hub["link_screws"]
    flange_d = screws["pcd_mm"] + fs.washer_mm(screws["thread"] or "M8")[1]  # washers inside
    f0 = link_face + toward * jt.FLANGE_MM
    spigot = (link_face, link_face - toward * 10.0)
    return [
        (flange_d, min(link_face, f0), max(link_face, f0)),
        (hub["spigot_d_mm"], min(spigot), max(spigot)),
        (hub["boss_d_mm"], min(f0, drive_face), max(f0, drive_face)),
    ]


def _hub_holes(hub: dict[str, Any], link_face: float, toward: int, angle: float) -> list:
    """The holes (x, y, diameter, z from, z to; mm) through a hub's flange for its link screws,
    on their bolt circle turned with the link (``angle`` rad, the first 30 degrees from its
    axis): tapped (the thread's diameter) where the screws come from the link, clearance holes
    where they come from the hub."""
    s = hub["link_screws"]
    if not s["thread"]:
        return []
    d = float(s["thread"][1:]) if s["side"] == "link" else fs.clearance_hole_mm(s["thread"])
    z = sorted((link_face, link_face + toward * jt.FLANGE_MM))
    return [[x, y, d, *z] for x, y in ring(s["pcd_mm"], jt.HUB_SCREWS, angle + math.radians(30))]


def _drive_holes(iface: DriveInterface, faces: tuple[float, int, float], angle: float) -> list:
    """The holes (as in :func:`_hub_holes`) for a hub's screws to its drive's output flange:
    each a counterbore for the head (its diameter and 1 mm, its height deep) from the link's
    face, and a clearance hole on through the hub to the drive's face (``faces``: the link's
    face, the direction to the drive and the drive's face); the first at the link's ``angle``."""
    if iface.output != "flange":
        return []
    link_face, toward, drive_face = faces
    head_d, head_h = fs.screw_head_mm(iface.flange_thread)
    bore = sorted((link_face, link_face + toward * head_h))
    through = sorted((bore[0] if toward > 0 else bore[1], drive_face))
    hole = fs.clearance_hole_mm(iface.flange_thread)
    out = []
    for x, y in ring(iface.flange_pcd_mm, iface.flange_bolts, angle):
        out += [[x, y, head_d + 1.0, *bore], [x, y, hole, *through]]
    return out


def _shaft_cuts(hub: dict[str, Any], iface: DriveInterface, part: dict, set_z: float, angle: float):
    """A shaft hub's set screw's tapped hole across the wall at ``set_z`` mm, at
    :data:`SET_SCREW_RAD` from the link's ``angle``, and opposite it the keyway (DIN 6885-1's
    hub depth, through the turned ``part``): the screw bears on the shaft's round."""
    if iface.output != "shaft":
        return {}
    depth = iface.shaft_d_mm / 2 + fs.key_hub_depth_mm(iface.key_w_mm, iface.key_h_mm)
    z = (part["z0_mm"], part["z0_mm"] + part["length_mm"])
    thread = float(hub["set_screw"].split()[2][1:])
    return {
        "keyways": [[angle + SET_SCREW_RAD + math.pi, iface.key_w_mm, depth, *z]],
        "cross_holes": [[angle + SET_SCREW_RAD, set_z, thread]],
    }


def kit_geometry(
    design: np.ndarray,
    parts: dict[str, LinkPart],
    stack: dict[str, float],
    cheeks: list[dict[str, Any]],
    drives: list[dict[str, Any]],
    hubs: list[dict[str, Any]],
    flange: dict[str, Any],
    angles: tuple[float, float],
) -> dict[str, Any]:
    """Every part placed, mm: the plates (links at motor ``angles``, cheeks, base plate), and
    along z the hubs (flange on the link, boss to the drive), the drives' envelopes outside the
    cheeks and the tool flange's disc against the upper arm at E, tapped for its centre screw;
    ``moves_with`` names the link whose frame carries each part (``base``: it stands still)."""
    t1, t2 = cheeks[0]["thickness_mm"], cheeks[1]["thickness_mm"]
    end = stack["cheek_2"]
    plates = link_plates(design, parts, stack, angles)
    for k, (c, z0) in enumerate(zip(cheeks, (-t1, end), strict=True), 1):
        iface = drives[k - 1]["interface"]
        plates[f"cheek_{k}"] = cheek_plate(c, iface, fs.clearance_hole_mm(iface.mount_thread), z0)
    plates["base_plate"] = base_plate(cheeks, (-t1, end + t2), cheeks[0]["height_mm"],
                                      bs.BASE_PLATE_MM)  # fmt: skip
    p1, p2 = (c["pocket"]["depth_mm"] for c in cheeks)
    faces = {1: (stack["lower_arm"], -1, -t1 + p1), 2: (stack["crank_end"], 1, end + t2 - p2)}
    out = {}
    for hub in hubs:
        k, iface = hub["motor"], drives[hub["motor"] - 1]["interface"]
        bore = iface.shaft_d_mm if iface.output == "shaft" else 0.0
        a, part = angles[k - 1], turned(_hub_steps(hub, *faces[k]), bore)
        part["holes"] = _hub_holes(hub, *faces[k][:2], a) + _drive_holes(iface, faces[k], a)
        set_z = jt.set_screw_z_mm(faces[k][0], faces[k][1], (0.0, end)[k - 1])
        out[f"hub_{k}"] = part | _shaft_cuts(hub, iface, part, set_z, a)
        face = faces[k][2]
        z = (face - iface.body_length_mm, face) if k == 1 else (face, face + iface.body_length_mm)
        out[f"drive_{k}"] = turned([(iface.body_d_mm, *z)])
    if flange.get("pattern"):
        e = np.asarray(pose(design, *angles).E) * 1e3
        z_e = stack["upper_arm"] - jt.ADAPTER_MM
        out["tool_flange"] = turned([(flange["face_d_mm"], z_e, stack["upper_arm"])], 0.0, e)
        thread = float(flange["centre_screw"].split()[2][1:])  # tapped for the centre screw
        out["tool_flange"]["holes"] = [[0.0, 0.0, thread, z_e, stack["upper_arm"]]]
    carried = {"hub_1": "lower_arm", "hub_2": "crank", "tool_flange": "upper_arm"}
    moves = {name: name if name in LINK_FRAMES else carried.get(name, "base")
             for name in [*plates, *out]}  # fmt: skip
    return {"plates": plates, "turned": out, "pose_deg": np.degrees(angles).tolist(),
            "moves_with": moves}  # fmt: skip
