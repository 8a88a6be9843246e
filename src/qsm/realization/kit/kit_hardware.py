"""The kit's bought hardware as solids for ``assembly.step``: each pin joint's bearing, shoulder
screw (or made pin), spacer washers, shims, nut washers and nuts; each hub's screws to its link
(and, on a drive's output flange, to the drive); each drive's mounting screws; the tool flange's
centre screw. Each is a turned part of :func:`qsm.realization.kit.kit_layout.turned` (coaxial
cylinders along z at a point of the plane, mm), placed at the layout's pose, named with its
standard designation, its place and its count (``ISO 4762 M3 x 16, hub 1 to lower arm, 1 of
6``), with the link whose frame carries it. A thread is its nominal diameter, with no helix; a
nut is the cylinder of its across-corners size; the sockets are left out.

Not here yet: the cheeks' fixing screws and the table screws (along y), the hubs' set screws
(across the shaft) and the heat-set inserts, which the BOM lists.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from qsm.embodiment.kit import fasteners as fs
from qsm.embodiment.kit import joints as jt
from qsm.physics.kinematics import pose
from qsm.realization.kit import kit_layout as kl
from qsm.realization.kit.kit_assembly import (
    HUB_LINKS,
    PIN_PLATES,
    link_faces,
    mount_screws,
    pin_faces,
    ring,
)
from qsm.realization.kit.kit_sequence import TOWARD


def _span(a: float, length: float, sign: float) -> tuple[float, float]:
    """The interval (mm) from ``a`` for ``length`` along ``sign`` z, low end first."""
    b = a + sign * length
    return min(a, b), max(a, b)


def _part(steps: list[tuple[float, float, float]], at: tuple, moves: str, bore: float = 0.0):
    return kl.turned(steps, bore, at) | {"moves_with": moves}


def _nut_end(thread: str, face: float, sign: float, at: tuple, moves: str, where: str) -> dict:
    """An ISO 7089 washer on ``face`` (z, mm) and an ISO 10511 nut on it, along ``sign``."""
    inner, outer, h = fs.washer_mm(thread)
    nut = fs.nut_height_mm(thread)
    return {
        f"ISO 7089 {thread}, {where}": _part([(outer, *_span(face, h, sign))], at, moves, inner),
        f"ISO 10511 {thread}, {where}": _part(
            [(fs.nut_across_corners_mm(thread), *_span(face + sign * h, nut, sign))],
            at,
            moves,
            float(thread[1:]),
        ),
    }


def _stacked(
    name: str,
    d: tuple[float, float],
    start: float,
    each: float,
    n: int,
    sign: float,
    at: tuple,
    moves: str,
) -> dict:
    """``n`` rings ``d`` (inner, outer mm), ``each`` mm thick, stacked from ``start`` along
    ``sign`` z, named ``name, i of n``."""
    return {
        f"{name}, {i + 1} of {n}": _part(
            [(d[1], *_span(start + sign * i * each, each, sign))], at, moves, d[0]
        )
        for i in range(n)
    }


def pin_hardware(record: dict[str, Any], j: str, at: tuple, bearing: dict[str, Any]) -> dict:
    """Pin joint ``j``'s hardware at ``at`` (mm): the bearing flush in its seat toward the other
    plate, the spacers between the plates, the screw (its head on the other plate, its
    shoulder through both, its thread beyond the seat) or the made pin, and beyond the seat
    the fill spacers, the shims, the washer and the nut."""
    pin, (seat, _) = record["pins"][j], PIN_PLATES[j]
    head_z, up, nut_z, down = pin_faces(record, j)
    d, t_seat = pin["shoulder_d_mm"], record["layout"]["plates"][seat]["thickness_mm"]
    inner_face = nut_z - down * t_seat  # the seat's face toward the other plate
    out = {}
    if bearing.get("D_mm"):
        b = float(bearing["B_mm"])
        name = f"{bearing['designation']} bearing, joint {j}"
        out[name] = _part([(bearing["D_mm"], *_span(inner_face, b, down))], at, seat, d)
    spacer = pin["spacer"].split()[-1]
    w = fs.washer_mm(spacer)
    out |= _stacked(
        f"ISO 7089 {spacer}, pin {j} spacer", w[:2], inner_face, w[2], pin["spacers"], up, at, seat
    )
    out |= _stacked(
        f"ISO 7089 {spacer}, pin {j} fill", w[:2], nut_z, w[2], pin["fill_spacers"], down, at, seat
    )
    if pin["shim"]:
        start = nut_z + down * pin["fill_spacers"] * w[2]
        out[f"{pin['shim']}, pin {j}"] = _part(
            [(w[1], *_span(start, pin["shims_mm"], down))], at, seat, d
        )
    thread = pin["nut"].split()[-1]
    if pin["screw"] is None:  # a made pin: a nut at each end
        end = head_z + down * pin["grip_mm"]
        out[f"{pin['made']}, joint {j}"] = _part(
            [(d, *_span(head_z, pin["grip_mm"], down))], at, seat
        )
        out |= _nut_end(thread, head_z, up, at, seat, f"pin {j} head end")
        return out | _nut_end(thread, end, down, at, seat, f"pin {j}")
    length = float(pin["screw"].split(" x ")[1].split()[0])
    head_d, head_h = fs.shoulder_head_mm(d)
    end = head_z + down * length
    out[f"{pin['screw']}, joint {j}"] = _part(
        [
            (head_d, *_span(head_z, head_h, up)),
            (d, *_span(head_z, length, down)),
            (float(thread[1:]), *_span(end, fs.shoulder_thread_mm(d), down)),
        ],
        at,
        seat,
    )
    return out | _nut_end(thread, end, down, at, seat, f"pin {j}")


def _screws(screw: str, points: list, face: float, sign: float, moves: str, where: str) -> dict:
    """ISO 4762 ``screw`` (an order line) at each of ``points`` (mm): an ISO 7089 washer and
    the head on ``face`` (z, mm) outward of ``sign``, the shank from ``face`` along ``-sign``."""
    thread = screw.split()[2]
    length = float(screw.split(" x ")[-1])
    inner, outer, h = fs.washer_mm(thread)
    head_d, head_h = fs.screw_head_mm(thread)
    out = {}
    for i, p in enumerate(points, 1):
        tag = f"{where}, {i} of {len(points)}"
        out[f"ISO 7089 {thread}, {tag}"] = _part([(outer, *_span(face, h, sign))], p, moves, inner)
        top = face + sign * h
        out[f"{screw}, {tag}"] = _part(
            [(head_d, *_span(top, head_h, sign)), (float(thread[1:]), *_span(top, length, -sign))],
            p,
            moves,
        )
    return out


def _rotated(points: list, angle: float) -> list[tuple[float, float]]:
    c, s = math.cos(angle), math.sin(angle)
    return [(c * x - s * y, s * x + c * y) for x, y in points]


def hub_hardware(record: dict[str, Any], k: int, link_angle: float) -> dict:
    """Hub ``k``'s screws to its link at the link's angle ``link_angle`` (rad): from the link's
    far face into the hub's tapped flange, or from the hub's flange into the link's inserts."""
    hub, link = record["hubs"][k - 1], HUB_LINKS[k]
    s = hub["link_screws"]
    if not s["thread"]:
        return {}
    near, far, _ = link_faces(record, k)
    points = _rotated(ring(s["pcd_mm"], jt.HUB_SCREWS, math.radians(30)), link_angle)
    where = f"hub {k} to {link.replace('_', ' ')}"
    if s["side"] == "link":
        return _screws(s["screw"], points, far, -TOWARD[k], link, where)
    flange = near + TOWARD[k] * jt.FLANGE_MM
    return _screws(s["screw"], points, flange, TOWARD[k], link, where)


def mount_hardware(record: dict[str, Any], k: int) -> dict:
    """Drive ``k``'s mounting screws, heads on its cheek's inner face, into the drive."""
    screw, points = mount_screws(record, k)
    where = f"drive {k} to cheek {k}"
    return _screws(screw, points, link_faces(record, k)[2], -TOWARD[k], "base", where)


def hardware(
    record: dict[str, Any], design: np.ndarray, bearings: dict[str, Any]
) -> tuple[dict[str, dict], dict[str, str]]:
    """Every solid of the kit's hardware at the layout's pose (module docs), by its name, and
    the link whose frame carries each (``base``: it stands still)."""
    angles = np.radians(record["layout"]["pose_deg"])
    p = pose(design, *angles)
    out = {}
    for j in PIN_PLATES:
        at = tuple(1e3 * float(v) for v in np.asarray(getattr(p, j)))
        out |= pin_hardware(record, j, at, bearings[j])
    for k in (1, 2):
        out |= hub_hardware(record, k, float(angles[k - 1])) | mount_hardware(record, k)
    parts = {n: {k: v for k, v in h.items() if k != "moves_with"} for n, h in out.items()}
    return parts, {n: h["moves_with"] for n, h in out.items()}
