"""The kit's bought hardware as solids for ``assembly.step``: each pin joint's bearing, shoulder
screw (or made pin), spacer washers, shims, nut washers and nuts; each hub's screws to its link
(with their heat-set inserts where they come from the hub), its screws to a drive's output flange
(heads in the hub's counterbores) or its set screw across the wall onto a drive's shaft; each
drive's mounting screws; the cheeks' fixing screws and the table screws (along y, through the
base plate); the tool flange's centre screw.

Each is a turned part of :func:`qsm.realization.kit.kit_layout.turned` (coaxial cylinders along
its axis, mm): along z at a point of the plane, or along its ``frame`` (origin, axis, x
direction). It stands at the layout's pose, named with its standard designation, its place and
its count (``ISO 4762 M3 x 16, hub 1 to lower arm, 1 of 6``), with the link whose frame carries
it and the assembly step that puts it in. A thread is its nominal diameter, with no helix; a nut
is the cylinder of its across-corners size; the sockets are left out.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from qsm.embodiment.kit import fasteners as fs
from qsm.embodiment.kit import joints as jt
from qsm.embodiment.strength.record import BearingLoad
from qsm.physics.kinematics import pose
from qsm.realization.kit import kit_layout as kl
from qsm.realization.kit.kit_assembly import (
    HUB_LINKS,
    PIN_PLATES,
    cheek_screw_points,
    link_faces,
    mount_screws,
    pin_faces,
    table_screw_points,
)
from qsm.realization.kit.kit_sequence import TOWARD


def _span(a: float, length: float, sign: float) -> tuple[float, float]:
    """The interval (mm) from ``a`` for ``length`` along ``sign`` z, low end first."""
    b = a + sign * length
    return min(a, b), max(a, b)


def _along_y(x: float, z: float) -> dict[str, list[float]]:
    """The frame of a part along y at (x, z) mm: its own z along the global y."""
    return {"origin": [x, 0.0, z], "normal": [0.0, 1.0, 0.0], "x_dir": [1.0, 0.0, 0.0]}


def _part(
    steps: list[tuple[float, float, float]],
    at: tuple,
    moves: str,
    bore: float = 0.0,
    axis: str = "z",
) -> dict[str, Any]:
    """A turned part (``steps`` along its axis, mm) at ``at``: (x, y) along z, or (x, z) along y
    (``axis``), carried by the link ``moves``."""
    if axis == "y":
        return kl.turned(steps, bore) | {"frame": _along_y(*at), "moves_with": moves}
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


def pin_hardware(record: dict[str, Any], j: str, at: tuple, bearing: BearingLoad) -> dict:
    """Pin joint ``j``'s hardware at ``at`` (mm): the bearing flush in its seat toward the other
    plate, the spacers between the plates, the screw (its head on the other plate, its
    shoulder through both, its thread beyond the seat) or the made pin, and beyond the seat
    the fill spacers, the shims, the washer and the nut."""
    pin, (seat, _) = record["pins"][j], PIN_PLATES[j]
    head_z, up, nut_z, down = pin_faces(record, j)
    d, t_seat = pin["shoulder_d_mm"], record["layout"]["plates"][seat]["thickness_mm"]
    inner_face = nut_z - down * t_seat  # the seat's face toward the other plate
    out = {}
    if bearing.D_mm:
        b = float(bearing.B_mm)
        name = f"{bearing.designation} bearing, joint {j}"
        out[name] = _part([(bearing.D_mm, *_span(inner_face, b, down))], at, seat, d)
        out[name]["step"] = f"bearing {j}"
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


def _screws(
    screw: str,
    points: list,
    face: float,
    sign: float,
    moves: str,
    where: str,
    axis: str = "z",
    washer: bool = True,
) -> dict:
    """ISO 4762 ``screw`` (an order line) at each of ``points`` (mm, as :func:`_part` takes
    them): an ISO 7089 washer (where ``washer``) and the head on ``face`` (mm along ``axis``)
    outward of ``sign``, the shank from under the head along ``-sign``."""
    thread = screw.split()[2]
    length = float(screw.split(" x ")[-1])
    inner, outer, h = fs.washer_mm(thread)
    head_d, head_h = fs.screw_head_mm(thread)
    top = face + sign * h if washer else face
    out = {}
    for i, p in enumerate(points, 1):
        tag = f"{where}, {i} of {len(points)}"
        if washer:
            out[f"ISO 7089 {thread}, {tag}"] = _part(
                [(outer, *_span(face, h, sign))], p, moves, inner, axis
            )
        out[f"{screw}, {tag}"] = _part(
            [(head_d, *_span(top, head_h, sign)), (float(thread[1:]), *_span(top, length, -sign))],
            p,
            moves,
            0.0,
            axis,
        )
    return out


def hub_hardware(record: dict[str, Any], k: int, link_angle: float) -> dict:
    """Hub ``k``'s screws to its link at the link's angle ``link_angle`` (rad): from the link's
    far face into the hub's tapped flange, or from the hub's flange into the link's inserts."""
    hub, link = record["hubs"][k - 1], HUB_LINKS[k]
    s = hub["link_screws"]
    if not s["thread"]:
        return {}
    near, far, _ = link_faces(record, k)
    points = kl.ring(s["pcd_mm"], jt.HUB_SCREWS, link_angle + math.radians(30))
    where = f"hub {k} to {link.replace('_', ' ')}"
    if s["side"] == "link":
        return _screws(s["screw"], points, far, -TOWARD[k], link, where)
    flange = near + TOWARD[k] * jt.FLANGE_MM
    length, outer, name = fs.insert(s["thread"])
    inserts = {
        f"{name} heat-set insert, {where}, {i} of {len(points)}": _part(
            [(outer, *_span(near, length, -TOWARD[k]))], p, link, float(s["thread"][1:])
        )
        for i, p in enumerate(points, 1)
    }
    return _screws(s["screw"], points, flange, TOWARD[k], link, where) | _tagged(
        inserts, f"inserts {k}"
    )


def drive_hardware(record: dict[str, Any], k: int, link_angle: float) -> dict:
    """Hub ``k``'s screws to its drive's output flange, heads in the hub's counterbores at the
    link's face; or its set screw across the boss onto the drive's shaft, opposite the key
    (:data:`qsm.realization.kit.kit_layout.SET_SCREW_RAD`)."""
    hub, iface, link = record["hubs"][k - 1], record["drives"][k - 1], HUB_LINKS[k]
    near, _, inner = link_faces(record, k)
    if iface["output"] == "flange":
        floor = near + TOWARD[k] * fs.screw_head_mm(iface["flange_thread"])[1]
        points = kl.ring(iface["flange_pcd_mm"], iface["flange_bolts"], link_angle)
        where = f"hub {k} to drive {k}"
        return _tagged(
            _screws(hub["flange_screw"], points, floor, -TOWARD[k], link, where, washer=False),
            f"hub {k} to drive",
        )
    thread, length = hub["set_screw"].split()[2], hub["set_screw"].split(" x ")[-1]
    turn = link_angle + kl.SET_SCREW_RAD
    frame = {
        "origin": [0.0, 0.0, jt.set_screw_z_mm(near, TOWARD[k], inner)],
        "normal": [math.cos(turn), math.sin(turn), 0.0],
        "x_dir": [0.0, 0.0, 1.0],
    }
    r = iface["shaft_d_mm"] / 2
    screw = kl.turned([(float(thread[1:]), r, r + float(length))]) | {"frame": frame}
    name = f"{hub['set_screw']}, hub {k} on drive {k}'s shaft"
    return {name: screw | {"moves_with": link, "step": f"hub {k} set screw"}}


def mount_hardware(record: dict[str, Any], k: int) -> dict:
    """Drive ``k``'s mounting screws, heads on its cheek's inner face, into the drive."""
    screw, points = mount_screws(record, k)
    where = f"drive {k} to cheek {k}"
    face = link_faces(record, k)[2]
    return _tagged(_screws(screw, points, face, -TOWARD[k], "base", where), f"drive {k} screws")


def base_hardware(record: dict[str, Any]) -> dict:
    """Each cheek's fixing screws, heads under the base plate, up into its tapped bottom edge;
    the table screws, heads on the plate, down into the table."""
    plate = record["layout"]["plates"]["base_plate"]
    top = plate["origin"][1]
    out = {}
    for k, cheek in enumerate(record["base"]["cheeks"], 1):
        if cheek["fixing"]["screw"]:
            where, points = f"cheek {k} to base plate", cheek_screw_points(record, k)
            bottom = top - plate["thickness_mm"]
            screws = _screws(cheek["fixing"]["screw"], points, bottom, -1.0, "base", where, "y")
            out |= _tagged(screws, f"cheek {k} screws")
    table = _screws(record["base"]["table_screws"]["screw"], table_screw_points(plate), top,
                    1.0, "base", "base plate to table", "y")  # fmt: skip
    return out | _tagged(table, "table")


def flange_hardware(record: dict[str, Any], e: tuple[float, float]) -> dict:
    """The tool flange's centre screw at E (``e``, mm), its head and washer on the upper arm's
    far face, into the flange's tapped centre."""
    flange = record["tool_flange"]
    if not flange.get("pattern"):
        return {}
    face = record["stack_mm"]["upper_arm"] + record["layout"]["plates"]["upper_arm"]["thickness_mm"]
    screws = _screws(
        flange["centre_screw"], [e], face, 1.0, "upper_arm", "tool flange to upper arm"
    )
    return _tagged(screws, "tool_flange")


def _tagged(parts: dict[str, dict], step: str) -> dict[str, dict]:
    """``parts`` each with the key of the assembly step that puts it in, where it has none."""
    return {n: {"step": step} | p for n, p in parts.items()}


@dataclass(frozen=True)
class Hardware:
    """The kit's hardware (module docs): each solid by its name, the link whose frame carries
    it (``base``: it stands still) and the key of the assembly step that puts it in."""

    solids: dict[str, dict[str, Any]]
    moves_with: dict[str, str]
    step: dict[str, str]


def hardware(
    record: dict[str, Any], design: np.ndarray, bearings: Mapping[str, BearingLoad]
) -> Hardware:
    """Every solid of the kit's hardware at the layout's pose."""
    angles = np.radians(record["layout"]["pose_deg"])
    p = pose(design, *angles)
    out = {}
    for j in PIN_PLATES:
        at = tuple(1e3 * float(v) for v in np.asarray(getattr(p, j)))
        out |= _tagged(pin_hardware(record, j, at, bearings[j]), f"pin {j}")
    for k in (1, 2):
        a = float(angles[k - 1])
        out |= _tagged(hub_hardware(record, k, a), f"hub {k} screws") | drive_hardware(record, k, a)
        out |= mount_hardware(record, k)
    e = tuple(1e3 * float(v) for v in np.asarray(p.E))
    out |= base_hardware(record) | flange_hardware(record, e)
    solids = {
        n: {k: v for k, v in h.items() if k not in ("moves_with", "step")} for n, h in out.items()
    }
    return Hardware(
        solids, {n: h["moves_with"] for n, h in out.items()}, {n: h["step"] for n, h in out.items()}
    )


def mass_kg(solids: dict[str, dict[str, Any]]) -> float:
    """The mass (kg) of the hardware's ``solids`` as drawn (:attr:`Hardware.solids`: each
    cylinder less its bore), all taken as steel (:data:`qsm.embodiment.kit.joints.STEEL_KG_M3`;
    the heat-set inserts are brass, 8 % heavier, and a few grams in all)."""
    mm3 = sum(
        math.pi / 4 * (d**2 - part["bore_mm"] ** 2) * (b - a)
        for part in solids.values()
        for d, a, b in part["steps"]
    )
    return mm3 * 1e-9 * jt.STEEL_KG_M3


def moving_mass_kg(layout: dict[str, Any]) -> float:
    """The mass (kg, :func:`mass_kg`) of a kit ``layout``'s hardware that moves with a link
    (its ``moves_with`` other than the base)."""
    moves = layout.get("moves_with", {})
    hardware = layout.get("hardware", {})
    return mass_kg({n: s for n, s in hardware.items() if moves.get(n, "base") != "base"})
