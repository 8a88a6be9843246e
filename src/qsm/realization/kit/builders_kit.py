"""The builder's kit of a realised design: the base, the hubs, pins and tool flange, every
fastener, their checks, and the layout the STEP, DXF and assembly-view files are drawn from.

:func:`builders_kit` takes a :class:`qsm.realization.selection.pipeline.Realization` and its final
parts (topology-optimised plates with their bores) and applies :mod:`qsm.embodiment.kit`: the
drives' interfaces (:mod:`~qsm.embodiment.kit.interfaces`), the pins, hubs and tool flange
(:mod:`~qsm.embodiment.kit.joints`) and the base (:mod:`~qsm.embodiment.kit.base`, whose module docs
state the arrangement). The loads are the realisation's: each joint's peak force
over the duty, each drive's peak torque over the duty and the task's motion, and the payload's
peak force at the tool.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field, replace
from typing import Any, NamedTuple

import numpy as np
import shapely

from qsm.embodiment.kit import base as bs
from qsm.embodiment.kit import fasteners as fs
from qsm.embodiment.kit import fits as ft
from qsm.embodiment.kit import joints as jt
from qsm.embodiment.kit.interfaces import DriveInterface, interface_of
from qsm.embodiment.parts.link_parts import LinkPart
from qsm.embodiment.strength.printed import PrintedMaterial
from qsm.embodiment.strength.record import BearingLoad
from qsm.physics.kinematics import pose
from qsm.physics.workspace import OperatingRange
from qsm.realization.kit import kit_bom as kb
from qsm.realization.kit import kit_hardware as kh
from qsm.realization.kit import kit_layout as kl
from qsm.realization.kit import kit_steps as ks
from qsm.realization.kit import moving_parts as mp
from qsm.realization.kit.kit_assembly import HUB_LINKS as HUB_LINK_OF
from qsm.realization.kit.kit_assembly import PIN_PLATES, kit_sequence
from qsm.realization.kit.kit_sequence import record_of
from qsm.realization.selection.outputs import props_to_json
from qsm.realization.selection.pipeline import Realization
from qsm.schema.defaults import default

#: The base's arrangement, as :mod:`qsm.embodiment.kit.base` states it (its cross-references
#: as plain names).
ARRANGEMENT = re.sub(
    r":\w+:`~?([\w.]+)`",
    lambda m: m.group(1).rsplit(".", 1)[-1],
    " ".join(bs.__doc__.split("**Arrangement.**")[1].split("**Check.**")[0].split()),
)
#: The links the hubs turn: motor 1's, motor 2's.
HUB_LINKS = tuple(HUB_LINK_OF.values())


@dataclass(frozen=True)
class KitSettings:
    """The motors' ``operating_range`` (the links' sweep sizes the base), the drive catalogue's
    folder (None: the shipped one), where ``interfaces.csv``
    is read, the task's placing tolerance (mm; the base takes
    :data:`~qsm.embodiment.kit.base.BASE_SHARE` of it) and the printed material, whose
    across-layer factor derates the bearing pressures in the printed holes."""

    operating_range: OperatingRange = field(default_factory=OperatingRange)
    catalogue: str | None = None
    tolerance_mm: float = default("task.tolerance_mm")
    printed: PrintedMaterial = field(default_factory=PrintedMaterial)


class Kit(NamedTuple):
    """``record`` (``kit.json``: parts, checks, fasteners, layout), the BOM rows it adds and
    the printed parts with the hubs' screw holes."""

    record: dict[str, Any]
    bom: list[dict[str, Any]]
    parts: dict[str, LinkPart]


def _plates(
    done: Realization, parts: dict[str, LinkPart], printed: PrintedMaterial
) -> dict[str, dict[str, jt.Plate]]:
    """Each link's plate at each of its joints (thickness, allowables in the plane and across
    the layers, boss), mm and MPa."""
    links = done.strength.links
    return {
        name: {
            b.joint: jt.Plate(
                name,
                1e3 * part.section.thickness_m,
                links[name].allowable_MPa,
                1e3 * b.boss_radius_m,
                printed.across_layers_MPa(links[name].allowable_MPa),
            )
            for b in part.bores
        }
        for name, part in parts.items()
    }


def _flange(done: Realization) -> jt.ToolFlange:
    """The tool flange the realisation chose; ``ValueError`` where it carries none."""
    if done.tool_flange is None:
        raise ValueError("the kit needs the realisation's tool flange; this one carries none")
    return done.tool_flange


def _drives(done: Realization, settings: KitSettings) -> list[dict[str, Any]]:
    """Per motor: its drive's interface, mass (kg) and torque limit (N m at the joint, the
    realisation's: the controller keeps to it, and the kit is sized for it)."""
    out = []
    for k in (1, 2):
        motor = done.drives.motors.get(f"motor{k}")  # none: no drive check ran
        limit = done.torque_limits_Nm[k - 1]
        drive = None if motor is None else motor.drive  # the chosen, else the nearest
        key = f"motor {k}: no drive" if drive is None else drive.gearbox_key
        out.append(
            {
                "interface": interface_of(key, limit, settings.catalogue),
                "mass_kg": 0.0 if drive is None else drive.mass_kg,
                "torque_limit_Nm": limit,
                "name": "no drive" if drive is None else f"{drive.motor} + {drive.gearbox}",
                "has_drive": motor is not None and motor.has_drive,
            }
        )
    return out


def _grid(s: KitSettings) -> tuple[np.ndarray, np.ndarray]:
    """The motors' angles (rad, (61, 61)) over the operating range."""
    t1 = np.radians(np.linspace(*s.operating_range.theta1_deg, 61))[:, None]
    frac = np.linspace(0.0, 1.0, 61)[None, :]
    low = np.radians(s.operating_range.theta2_min_deg)
    t2 = low + frac * (t1 - low)
    return np.broadcast_to(t1, t2.shape), t2


def _sweep(done: Realization, s: KitSettings) -> dict[str, np.ndarray]:
    """The joints' positions (mm, (61, 61, 2)) over the operating range (:func:`_grid`), NaN
    where the loop does not close."""
    p = pose(done.design, *_grid(s))
    ok = p.closes[..., None]
    return {
        "A": np.zeros((*ok.shape[:-1], 2)),
        **{j: 1e3 * np.where(ok, getattr(p, j), np.nan) for j in "BCDE"},
    }


def _radii(parts: dict[str, LinkPart]) -> dict[str, dict[str, float]]:
    """Each link's boss radius (mm) at each of its joints."""
    return {n: {b.joint: 1e3 * b.boss_radius_m for b in p.bores} for n, p in parts.items()}


def lowest_point_mm(done: Realization, parts: dict[str, LinkPart], s: KitSettings) -> float:
    """How far (mm) below A any link reaches over the operating range."""
    joints = {j: v * (1e-3 if j != "A" else 1.0) for j, v in _sweep(done, s).items()}
    return bs.lowest_point_mm(joints, _radii(parts))


#: What stands out of a plate into a neighbour's layer at a pin (the side the pin's head or nut
#: is on, :mod:`qsm.embodiment.kit.joints`): (joint, head or nut, the link whose layer it is in).
#: The pins whose nut ends face a cheek across the gap between it and the outer links (B's
#: on the lower arm toward cheek 1, C's on the crank toward cheek 2): the gap passes them by 1 mm.
OUTER_NUTS = ("B", "C")
#: The last entry: the pin joint whose spacers stand between the two layers.
PROTRUSIONS = (
    ("B", "head", "coupler", "D"),
    ("D", "head", "lower_arm", "B"),
    ("D", "nut", "crank", "C"),
    ("C", "head", "upper_arm", "D"),
)
#: Each link frame's origin joint (the frame's x axis as in
#: :func:`qsm.realization.kit.kit_layout.link_plates`: the lower arm at theta1, the crank at
#: theta2, the coupler along C-D, the upper arm at phi).
FRAME_ORIGINS = {"lower_arm": "A", "crank": "A", "coupler": "C", "upper_arm": "B"}


def outline_gap_mm(
    done: Realization, parts: dict[str, LinkPart], s: KitSettings, link: str, joint: str
) -> float:
    """The least distance (mm) over the operating range (:func:`_grid`) from ``joint`` to the
    ``link``'s true outline (its plate filled in: a head passes under no opening), 0 where
    the outline passes over it; poses where the loop does not close are left out."""
    t1, t2 = _grid(s)
    p = pose(done.design, t1, t2)
    at = {j: 1e3 * np.asarray(getattr(p, j)) for j in "BCD"} | {"A": np.zeros((*t1.shape, 2))}
    cd = at["D"] - at["C"]
    angle = {"lower_arm": t1, "crank": t2, "coupler": np.arctan2(cd[..., 1], cd[..., 0]),
             "upper_arm": np.asarray(p.phi)}[link]  # fmt: skip
    rel = at[joint] - at[FRAME_ORIGINS[link]]
    c, sn = np.cos(angle), np.sin(angle)
    local = np.stack([c * rel[..., 0] + sn * rel[..., 1], -sn * rel[..., 0] + c * rel[..., 1]], -1)
    local = local[np.asarray(p.closes) & np.isfinite(local).all(-1)]
    outline = shapely.Polygon(np.asarray(parts[link].polygon.exterior.coords) * 1e3)
    return float(np.min(shapely.distance(outline, shapely.points(local))))


def _protrusion_mm(pin: dict[str, Any], end: str) -> tuple[float, float]:
    """A pin's head, or its nut end: its radius and how far it stands out of its plate (mm).
    The nut end is the spacers filling the shoulder, the shims and the float left, then the
    farther of the nut on its washer and the screw's thread end (a made pin: a nut at each
    end)."""
    thread = pin["nut"].split()[-1]
    d = pin["shoulder_d_mm"]
    if end == "head" and pin["screw"]:
        head_d, h = fs.shoulder_head_mm(d)
        return head_d / 2, h
    size = max(fs.nut_across_corners_mm(thread), fs.washer_mm(thread)[1]) / 2
    nut = fs.washer_mm(thread)[2] + fs.nut_height_mm(thread)
    if not pin["screw"]:
        return size, nut
    fill = pin["fill_spacers"] * fs.washer_mm(pin["spacer"].split()[-1])[2]
    beyond = fill + pin["shims_mm"] + pin["axial_float_mm"]
    return size, beyond + max(nut, fs.shoulder_thread_mm(d))


def clearances(
    done: Realization, parts: dict[str, LinkPart], pins: dict[str, Any], s: KitSettings
) -> list[dict[str, Any]]:
    """For each pin's head or nut that stands toward a neighbour's layer (:data:`PROTRUSIONS`),
    its least distance (mm) over the operating range from that link's true outline
    (:func:`outline_gap_mm`), against the head's or the nut's and washer's radius and 1 mm;
    where that fails, the spacers between the two layers (``spacers_mm``) must pass its
    height and 1 mm, so that the neighbour runs beside it."""
    out = []
    for joint, end, link, gap_joint in PROTRUSIONS:
        size, height = _protrusion_mm(pins[joint], end)
        least = outline_gap_mm(done, parts, s, link, joint)
        spacers = pins[gap_joint]["spacers_mm"]
        out.append({"what": f"pin {joint}'s {end}", "into": link, "clearance_mm": least,
                    "needed_mm": size + 1.0, "height_mm": height, "spacers_mm": spacers,
                    "holds": least >= size + 1.0 or spacers >= height + 1.0})  # fmt: skip
    return out


#: Per motor: the link whose layer its hub's link-side screw heads stand into, and the pin
#: joint whose spacers stand between the two layers.
HEAD_NEIGHBOURS = (("upper_arm", "B"), ("coupler", "C"))


def hub_head_clearances(
    done: Realization,
    parts: dict[str, LinkPart],
    screws: list[dict[str, Any]],
    pins: dict[str, Any],
    s: KitSettings,
) -> list[dict[str, Any]]:
    """For each hub whose screws come from its link's far face, the least distance (mm) over
    the operating range of the neighbouring layer's link (:data:`HEAD_NEIGHBOURS`, its true
    outline: :func:`outline_gap_mm`) from A, against the heads' circle (half the bolt circle,
    half the larger of head and washer, and 1 mm); where that fails, the spacers between the
    layers must pass the heads' height and 1 mm."""
    out = []
    for k, (screw, (link, gap_joint)) in enumerate(zip(screws, HEAD_NEIGHBOURS, strict=True), 1):
        if screw["side"] != "link" or not screw["thread"]:
            continue
        th = screw["thread"]
        head = max(fs.screw_head_mm(th)[0], fs.washer_mm(th)[1])
        height = fs.screw_head_mm(th)[1] + fs.washer_mm(th)[2]
        needed = screw["pcd_mm"] / 2 + head / 2 + 1.0
        least = outline_gap_mm(done, parts, s, link, "A")
        spacers = pins[gap_joint]["spacers_mm"]
        out.append({"what": f"hub {k}'s screw heads", "into": link, "clearance_mm": least,
                    "needed_mm": needed, "height_mm": height, "spacers_mm": spacers,
                    "holds": least >= needed or spacers >= height + 1.0})  # fmt: skip
    return out


def spacer_counts(
    done: Realization,
    parts: dict[str, LinkPart],
    pins: dict[str, Any],
    screws: list[dict[str, Any]],
    s: KitSettings,
) -> dict[str, int]:
    """The spacer washers each pin joint needs between its plates: one, or as many as lift the
    next layer clear of a pin's head or nut, or a hub's screw heads, that its link does not
    clear in the plane (:func:`clearances`, :func:`hub_head_clearances`)."""
    out = dict.fromkeys(pins, 1)
    gaps = [g for *_, g in PROTRUSIONS] + [
        g for (_, g), sc in zip(HEAD_NEIGHBOURS, screws, strict=True)
        if sc["side"] == "link" and sc["thread"]
    ]  # fmt: skip
    found = clearances(done, parts, pins, s) + hub_head_clearances(done, parts, screws, pins, s)
    for c, gap_joint in zip(found, gaps, strict=True):
        if c["clearance_mm"] < c["needed_mm"]:
            washer = fs.washer_mm(pins[gap_joint]["spacer"].split()[-1])[2]
            out[gap_joint] = max(out[gap_joint], math.ceil((c["height_mm"] + 1.0) / washer))
    return out


def _bearing(done: Realization, joint: str) -> BearingLoad:
    """The bearing of ``joint`` (bore ``d_mm``, width ``B_mm``, ``peak_force_N``); where none
    of the catalogue fits, the bore the parts were drawn with (width 0)."""
    bearing = done.strength.bearings[joint]
    if bearing.d_mm is None:
        bores = [b for p in done.parts.values() for b in p.bores if b.joint == joint]
        small = min(b.diameter_m for b in bores if b.diameter_m > 0)
        bearing = replace(bearing, d_mm=1e3 * small, B_mm=0.0)
    return bearing


def _safety(done: Realization) -> float:
    """The links' required safety factor, which every part of the kit keeps."""
    return done.strength.required_safety_factor


def _pins(
    done: Realization, plates: dict[str, dict[str, jt.Plate]], spacers: dict[str, int] | None
) -> dict[str, Any]:
    """The shoulder screws of B, C and D (:func:`qsm.embodiment.kit.joints.pin`), each with its
    number of spacer washers between its plates (None: one)."""
    n = spacers or {}
    return {
        j: jt.pin(j, _bearing(done, j), plates[a][j], plates[b][j], _safety(done), n.get(j, 1))
        for j, (a, b) in PIN_PLATES.items()
    }


#: How far (mm) a link-side hub screw's end may stand beyond the hub's flange, toward the cheek:
#: the least gap between flange and cheek (10 mm) less 2 mm.
HUB_SCREW_TIP_MM = 8.0


def _hub_screws(
    plates: dict[str, dict[str, jt.Plate]], drives: list[dict[str, Any]], spigot: float
) -> list[dict[str, Any]]:
    """Each hub's screws to its link: from the link's far face into the hub's tapped flange
    where the drive has an output flange (the hub goes on after the drive), else from the
    hub's side into inserts (:mod:`qsm.embodiment.kit.joints`)."""
    out = []
    for link, d in zip(HUB_LINKS, drives, strict=True):
        plate, torque = plates[link]["A"], d["torque_limit_Nm"]
        if d["interface"].output == "flange":
            out.append(jt.hub_screws_through_link(plate, spigot, torque, HUB_SCREW_TIP_MM))
        else:
            out.append(jt.hub_screws(plate, spigot, torque))
    return out


def _mount_heads(drives: list[dict[str, Any]]) -> list[tuple[tuple[float, float, float], ...]]:
    """Per cheek, the rings its drive's mounting screws' washers and heads cover on its inner
    face: each ring's inner and outer radius about A and how far it stands out (mm)."""
    out = []
    for d in drives:
        iface = d["interface"]
        _, washer, h = fs.washer_mm(iface.mount_thread)
        head_d, head_h = fs.screw_head_mm(iface.mount_thread)
        r = iface.mount_pcd_mm / 2
        out.append(
            ((r - washer / 2, r + washer / 2, h), (r - head_d / 2, r + head_d / 2, h + head_h))
        )
    return out


def _past_heads(height: float, span: tuple[float, float], heads: tuple) -> float:
    """How far (mm) from a cheek's inner face a part facing it must stand: its own ``height``
    out of its link, and as much more as the drive's mounting screws' ``heads`` (rings: inner
    and outer radius about A, height; mm) stand out where the ring ``span`` (inner and outer
    radius about A, mm) that it sweeps meets them, and 1 mm."""
    over = [h for lo, hi, h in heads if span[0] < hi and lo < span[1]]
    return height + max(over, default=0.0) + 1.0


def _hub_gap(screws: dict[str, Any], heads: tuple) -> float:
    """The gap (mm) between a hub's link and its cheek: the hub's flange and 10 mm (room for a
    key to the set screw, a link screw's end), its screws' washers and heads where they come
    from the hub's side and 2 mm, each past the mounting screws' ``heads`` it passes over."""
    flange = (screws["pcd_mm"] + fs.washer_mm(screws["thread"] or "M8")[1]) / 2
    need = [jt.FLANGE_MM + 10.0, _past_heads(jt.FLANGE_MM, (0.0, flange), heads)]
    if screws["thread"] and screws["side"] == "hub":
        _, outer, h = fs.washer_mm(screws["thread"])
        height = jt.FLANGE_MM + h + fs.screw_head_mm(screws["thread"])[1]
        ring = (screws["pcd_mm"] / 2 - outer / 2, screws["pcd_mm"] / 2 + outer / 2)
        need += [height + 2.0, _past_heads(height, ring, heads)]
    return max(need)


def _stack(
    parts: dict[str, LinkPart],
    pins: dict[str, Any],
    screws: list[dict[str, Any]],
    heads: list[tuple[tuple[float, float, float], ...]],
    arms: dict[str, float],
) -> dict[str, float]:
    """The plates' z (mm) from cheek 1's inner face (the arrangement of
    :mod:`qsm.embodiment.kit.base`), each link's offset from its cheek's face, and the gap
    between a cheek and its link: a hub's flange and its screws' washers and heads, and at least
    the nut ends of :data:`OUTER_NUTS` and 1 mm; each more by the drives' mounting screws'
    ``heads`` (:func:`_mount_heads`) where it passes over them, the pins at ``arms`` (mm) from
    A."""
    t = {n: 1e3 * p.section.thickness_m for n, p in parts.items()}
    spacer = {j: p["spacers_mm"] for j, p in pins.items()}
    gaps = [_hub_gap(s, heads[k]) for k, s in enumerate(screws)]
    for k, j in enumerate(OUTER_NUTS):  # B's and C's nut ends face the cheeks
        size, end = _protrusion_mm(pins[j], "nut")
        gaps.append(_past_heads(end, (arms[j] - size, arms[j] + size), heads[k]))
    gap = max(gaps)
    z = {"lower_arm": gap}
    z["upper_arm"] = z["lower_arm"] + t["lower_arm"] + spacer["B"]
    z["coupler"] = z["upper_arm"] + t["upper_arm"] + spacer["D"]
    z["crank"] = z["coupler"] + t["coupler"] + spacer["C"]
    z["crank_end"] = z["crank"] + t["crank"]
    z["cheek_2"] = z["crank_end"] + gap
    z["offset_1"] = gap + t["lower_arm"] / 2
    z["offset_2"] = gap + t["crank"] / 2
    z["gap"] = gap
    return z


def _cheek_size(iface: DriveInterface) -> tuple[float, float]:
    """A cheek's bore (mm: the drive's pilot, and room for the hub's boss) and its least
    width (mm: the drive's bolt circle and three washers, or the bore and 30 mm)."""
    bore = max(iface.mount_pilot_mm, jt.hub_boss_mm(iface) + 2.0)
    washer = fs.washer_mm(iface.mount_thread)[1]
    return bore, max(iface.mount_pcd_mm + 3 * washer, bore + 30.0)


def _cheeks(
    done: Realization,
    drives: list[dict[str, Any]],
    drop_mm: float,
    stack: dict[str, float],
    reach_mm: float,
    tolerance_mm: float,
) -> list[dict[str, Any]]:
    """Both cheeks: sizes, holes and checks (:mod:`qsm.embodiment.kit.base`), each moving the
    tool in the plane by at most half the base's share of ``tolerance_mm``; the thinnest plate
    that holds, takes its fixing screws and keeps its tilt's error at the tool within half the
    tilt's share (the thickest when none does)."""
    force = done.strength.bearings["A"].peak_force_N
    allow = (bs.BASE_SHARE * tolerance_mm / 2, bs.TILT_SHARE * tolerance_mm / 2)
    sf = _safety(done)
    tool_z = stack["upper_arm"] - jt.ADAPTER_MM - 1e3 * _flange(done).offset_m
    h = max(drop_mm, *(d["interface"].body_d_mm / 2 for d in drives)) + bs.CLEARANCE_MM
    out = []
    for k, drive in enumerate(drives, 1):
        iface = drive["interface"]
        bore, b = _cheek_size(iface)
        for t in bs.PLATE_STOCK_MM:
            pocket = _pocket(iface, t, stack["gap"])
            load = bs.CheekLoad(
                force,
                drive["torque_limit_Nm"],
                drive["mass_kg"],
                iface.body_length_mm / 2 - pocket.depth_mm,
                stack[f"offset_{k}"],
            )
            mid = -t / 2 if k == 1 else stack["cheek_2"] + t / 2
            part = bs.cheek(load, h, b, sf, (reach_mm, abs(tool_z - mid)), t, allow, pocket)
            fixing = bs.fixing_screws(load, part, sf)
            steady = part["tilt_error_mm"] <= part["allowed_tilt_error_mm"]
            if part["holds"] and fixing["holds"] and steady:
                break
        out.append(
            part
            | {"motor": k, "bore_mm": bore, "drive": drive["name"], "fixing": fixing, "load": load}
        )
    return out


def _pocket(iface: DriveInterface, t: float, gap: float) -> bs.Pocket:
    """The pocket (:class:`qsm.embodiment.kit.base.Pocket`) a shaft drive sits in, in a cheek
    ``t`` mm thick ``gap`` mm from its link: deep enough (to 0.5 mm) that the shaft reaches 1 mm
    past the hub's set screw (:func:`set_screw_reach_mm`), and at most down to the least web;
    as wide as the drive's body or its diagonal, and 1 mm. None for a flange drive."""
    if iface.output != "shaft":
        return bs.Pocket()
    d = float(jt.set_screw().split()[2][1:])
    short = t + (gap - jt.FLANGE_MM) / 2 + d / 2 + 1.0 - iface.shaft_length_mm
    depth = min(math.ceil(2 * max(short, 0.0)) / 2, t - bs.MIN_WEB_MM)
    if depth <= 0:
        return bs.Pocket()
    return bs.Pocket(round(iface.body_d_mm * math.sqrt(2) + 1.0, 1), depth)


def _hubs(
    done: Realization,
    plates: dict[str, dict[str, jt.Plate]],
    drives: list[dict[str, Any]],
    screws: list[dict[str, Any]],
    stack: dict[str, float],
    cheeks: list[dict[str, Any]],
) -> list[dict[str, Any]]:
    """The hubs (:func:`qsm.embodiment.kit.joints.hub`), each boss reaching through its cheek
    to the drive's face; a motor without a drive has no hub that holds."""
    bearing = _bearing(done, "A")
    force, spigot = bearing.peak_force_N, float(bearing.d_mm)
    boss = {
        1: stack["lower_arm"] - jt.FLANGE_MM + cheeks[0]["pocket"]["web_mm"],
        2: stack["cheek_2"] - stack["crank_end"] - jt.FLANGE_MM + cheeks[1]["pocket"]["web_mm"],
    }
    out = []
    for k, (link, d, s) in enumerate(zip(HUB_LINKS, drives, screws, strict=True), 1):
        hub = jt.hub(
            k,
            d["interface"],
            plates[link]["A"],
            spigot,
            d["torque_limit_Nm"],
            _safety(done),
            boss[k],
            s,
        )
        hub["has_drive"] = d["has_drive"]
        hub["holds"] = bool(hub["holds"] and d["has_drive"])
        hub["output_bearing"] = {
            "force_N": force,
            "checked": False,
            "note": f"the drive's own output bearing carries the joint's {force:.0f} N at A; the "
            "catalogue gives no rating for it, so this is not checked: compare with the "
            "maker's permissible radial load",
        }
        out.append(hub)
    return out


def with_hub_holes(parts: dict[str, LinkPart], hubs: list[dict[str, Any]]) -> dict[str, LinkPart]:
    """``parts`` with each hub's six holes for its heat-set inserts cut into its link around A,
    on the hub's bolt circle, the first at 30 degrees from the link's axis."""
    out = dict(parts)
    for link, hub in zip(HUB_LINKS, hubs, strict=True):
        s = hub["link_screws"]
        if not s["thread"]:
            continue
        part = parts[link]
        holes = kl.bolt_circle(s["pcd_mm"], jt.HUB_SCREWS, s["hole_mm"], 30)
        cut = shapely.union_all([shapely.Polygon(np.asarray(h) * 1e-3) for h in holes])
        out[link] = LinkPart(link, part.polygon.difference(cut), part.bores, part.section)
    return out


def _checks(
    pins: dict[str, Any],
    hubs: list[dict],
    cheeks: list[dict],
    table: dict,
    flange: dict,
    clear: list[dict],
) -> dict[str, bool]:
    """Whether each of the kit's checks holds."""
    out = {f"pin {j}": bool(p["holds"]) for j, p in pins.items()}
    out |= {
        f"{c['what']} clears the {c['into'].replace('_', ' ')}": bool(c["holds"]) for c in clear
    }
    out |= {f"hub {h['motor']}": bool(h["holds"]) for h in hubs}
    for c in cheeks:
        out[f"cheek {c['motor']}"] = bool(c["holds"])
        out[f"cheek {c['motor']} screws"] = bool(c["fixing"]["holds"])
    out["table screws"] = bool(table["holds"])
    out["tool flange"] = bool(flange["holds"])
    return out


def _problems(
    pins: dict[str, Any],
    hubs: list[dict],
    cheeks: list[dict],
    table: dict,
    flange: dict,
    clear: list[dict],
) -> list[str]:
    """Each of the kit's failing checks, with its numbers."""
    out = [
        f"{c['what']} comes within {c['clearance_mm']:.1f} mm of the "
        f"{c['into'].replace('_', ' ')}'s layer ({c['needed_mm']:.1f} mm needed)"
        for c in clear
        if not c["holds"]
    ] + [
        f"the pin of joint {j} ({p['shoulder_d_mm']:g} mm) reaches a safety factor of "
        f"{p['safety_factor']:.2f} ({p['required_safety_factor']:g} required), or needs "
        f"{p['printed_bearing_length_mm']:.1f} mm of printed bore"
        for j, p in pins.items()
        if not p["holds"]
    ]
    for hub in hubs:
        if not hub["has_drive"]:
            out.append(f"motor {hub['motor']} has no drive, so hub {hub['motor']} is not sized")
        elif not hub["link_screws"]["thread"]:
            out.append(
                f"no heat-set insert and screw fit the {hub['link'].replace('_', ' ')}'s "
                f"boss at A for hub {hub['motor']}"
            )
        elif not hub["holds"]:
            out.append(
                f"hub {hub['motor']} does not carry {hub['torque_Nm']:.1f} N m, its drive's "
                "torque limit"
            )
    out += [
        f"cheek {c['motor']} reaches a safety factor of {c['safety_factor']:.2f} "
        f"({c['required_safety_factor']:g} required), its fixing screws "
        f"{'hold' if c['fixing']['holds'] else 'do not hold'}"
        for c in cheeks
        if not (c["holds"] and c["fixing"]["holds"])
    ]
    if not table["holds"]:
        out.append(f"the table screws reach a safety factor of {table['safety_factor']:.2f}")
    if not flange["holds"]:
        out.append(
            f"no ISO 9409-1 flange of {', '.join(flange['tried'])} carries "
            f"{flange['payload_force_N']:.0f} N and fits the boss at E"
        )
    return out


def builders_kit(done: Realization, parts: dict[str, LinkPart], settings: KitSettings) -> Kit:
    """The kit of ``done`` with its final ``parts`` (module docs) and the tool flange the
    realisation chose and carried (``done.tool_flange``). Its ``parts`` are those with the hubs'
    screw holes. ``ValueError`` for a realisation without its flange (:func:`realize_once`)."""
    plates, drives = _plates(done, parts, settings.printed), _drives(done, settings)
    screws = _hub_screws(plates, drives, float(_bearing(done, "A").d_mm))
    pins = _pins(done, plates, None)
    pins = _pins(done, plates, spacer_counts(done, parts, pins, screws, settings))
    arms = {"B": 1e3 * float(done.design[0]), "C": 1e3 * float(done.design[1])}  # l1, l2
    stack = _stack(parts, pins, screws, _mount_heads(drives), arms)
    l1, _, _, _, ee_x, ee_y = done.design
    reach = 1e3 * (l1 + float(np.hypot(ee_x, ee_y)))
    drop = lowest_point_mm(done, parts, settings)
    cheeks = _cheeks(done, drives, drop, stack, reach, settings.tolerance_mm)
    hubs = _hubs(done, plates, drives, screws, stack, cheeks)
    for hub, drive in zip(hubs, drives, strict=True):
        if "set_screw" in hub:
            hub["set_screw_on_shaft_mm"] = set_screw_reach_mm(hub, drive, stack, cheeks)
    flange = _flange(done).record()
    table = bs.table_screws(
        [c["load"] for c in cheeks],
        cheeks[0]["height_mm"],
        kl.base_plate_size(cheeks, stack),
        _safety(done),
    )
    holed = with_hub_holes(parts, hubs)
    angles = kl.working_pose(done.design, *settings.operating_range.degrees)
    geometry = kl.kit_geometry(done.design, holed, stack, cheeks, drives, hubs, flange, angles)
    lines = kb.fastener_lines(pins, hubs, cheeks, drives, flange, table)
    clear = clearances(done, parts, pins, settings)
    clear += hub_head_clearances(done, parts, screws, pins, settings)
    checks = _checks(pins, hubs, cheeks, table, flange, clear)
    fits = _fits(done, plates, hubs, drives)
    seats = [f for f in fits if "held" in f]
    checks |= {f"bearing {f['joint']}'s seat": f["holds"] for f in seats}
    record = {
        "holds": all(checks.values()),
        "checks": checks,
        "problems": _problems(pins, hubs, cheeks, table, flange, clear) + _seat_problems(seats),
        "clearances": clear,
        "fits": fits,
        "not_checked": [h["output_bearing"]["note"] for h in hubs],
        "drives": [_interface_record(d) for d in drives],
        "pins": pins,
        "hubs": hubs,
        "base": {
            "tool_error_mm": sum(c["tool_error_mm"] + c["tilt_error_mm"] for c in cheeks),
            "cheeks": [{k: v for k, v in c.items() if k != "load"} for c in cheeks],
            "table_screws": table,
            "links_lowest_mm": drop,
            "material": bs.ALUMINIUM,
            "arrangement": ARRANGEMENT,
        },
        "tool_flange": flange,
        "printed_material": _printed_record(done, settings.printed),
        "stack_mm": stack,
        "layout": geometry,
    }
    _with_sequence(record, done, holed, settings)
    return Kit(record, kb.made_rows(geometry) + kb.fastener_rows(lines), holed)


def _printed_record(done: Realization, printed: PrintedMaterial) -> dict[str, Any]:
    """The printed material as the kit uses it: its orientation and factors, and each link's
    allowable (MPa) along its layers and across them."""
    along = {name: r.allowable_MPa for name, r in done.strength.links.items()}
    across = {name: printed.across_layers_MPa(a) for name, a in along.items()}
    return printed.record() | {
        "allowable_along_layers_MPa": along,
        "allowable_across_layers_MPa": across,
        "across_layers_loads": "pins' and screws' bearing in printed holes; washers' clamp",
    }


def _fits(
    done: Realization,
    plates: dict[str, dict[str, jt.Plate]],
    hubs: list[dict[str, Any]],
    drives: list[dict[str, Any]],
) -> list[dict[str, Any]]:
    """The kit's fits (:mod:`qsm.embodiment.kit.fits`): each joint bearing's seat in its
    printed plate and its pin's shoulder, and each hub's spigot and bore."""
    material = done.strength_check.material
    e, nu = material.youngs_modulus_pa * 1e-6, material.poisson_ratio
    out = []
    for j, (seat, _) in PIN_PLATES.items():
        plate = plates[seat][j]
        boss = (seat, 2 * plate.boss_mm, plate.allowable_MPa)
        out += ft.joint_fits(j, done.strength.bearings[j], boss, e, nu)
    for hub, drive in zip(hubs, drives, strict=True):
        shaft = drive["interface"].shaft_d_mm if drive["interface"].output == "shaft" else 0.0
        out += ft.hub_fits(hub["motor"], hub["link"], hub["spigot_d_mm"], shaft)
    return out


def _seat_problems(seats: list[dict[str, Any]]) -> list[str]:
    """What a failed bearing seat says: the ring loose at its least interference, or the
    printed boss over its allowable at its largest."""
    out = []
    for f in seats:
        if not f["held"]:
            out.append(f"{f['what']} ({f['hole']}) may be {f['max_clearance_um']:.0f} um loose")
        elif not f["holds"]:
            out.append(
                f"{f['what']} ({f['hole']}) stresses the printed boss to "
                f"{f['hoop_stress_MPa']:.1f} MPa ({f['allowable_MPa']:.1f} MPa allowed)"
            )
    return out


def _with_sequence(
    record: dict[str, Any], done: Realization, parts: dict[str, LinkPart], s: KitSettings
) -> None:
    """``record`` with its hardware's solids (:mod:`qsm.realization.kit.kit_hardware`), its
    assembly sequence (:mod:`qsm.realization.kit.kit_assembly`), the steps as a person reads
    them, each part's step, and the sequence's check and problem."""
    kit_hardware = kh.hardware(record, done.design, done.strength.bearings)
    record["layout"]["hardware"] = kit_hardware.solids
    record["layout"]["moves_with"] |= kit_hardware.moves_with
    moving = mp.moving_parts(record["layout"], done.design, kit_hardware.step)
    record["moving_parts"] = props_to_json(moving)  # for the dynamics after the kit
    # a washer's clamp presses the plate across its layers
    allow = {
        k: s.printed.across_layers_MPa(v.allowable_MPa) for k, v in done.strength.links.items()
    }
    found = kit_sequence(
        record, done.design, parts, *s.operating_range.degrees, allow,
        done.strength.bearings, kit_hardware.step,
    )  # fmt: skip
    sequence = record_of(found, kit_hardware.step)
    record["assembly_sequence"] = sequence
    record["assembly_steps"] = ks.assembly_steps(sequence)
    record["step_of"] = ks.step_of(sequence)
    record["checks"]["assembly sequence"] = found.exists
    for hub in record["hubs"]:
        reach = hub.get("set_screw_on_shaft_mm")
        if reach is not None:
            record["checks"][f"hub {hub['motor']} set screw"] = reach >= 0
            if reach < 0:
                record["problems"].append(
                    f"drive {hub['motor']}'s shaft ends {-reach:.1f} mm short of hub "
                    f"{hub['motor']}'s set screw (in the gap between the hub's flange and the "
                    "cheek), so nothing holds the hub along the shaft"
                )
    if not found.exists:
        record["problems"].append("no order of assembly reaches every part and screw: " +
                                  "; ".join(found.blocked))  # fmt: skip
    record["holds"] = all(record["checks"].values())


def set_screw_reach_mm(
    hub: dict[str, Any], drive: dict[str, Any], stack: dict[str, float], cheeks: list[dict]
) -> float:
    """How far (mm) the drive's shaft reaches past a shaft hub's set screw, which sits halfway
    across the gap between the hub's flange and the cheek (where a key reaches it): the shaft
    runs its length from the drive's face on the cheek's web (its outer face, or its pocket's
    floor); negative where it ends short of the screw's far edge."""
    k, iface = hub["motor"], drive["interface"]
    t = cheeks[k - 1]["pocket"]["web_mm"]
    inner = 0.0 if k == 1 else stack["cheek_2"]
    link_face = stack["lower_arm"] if k == 1 else stack["crank_end"]
    toward = -1.0 if k == 1 else 1.0  # along z from the link to the drive
    face = inner + toward * t
    screw_z = jt.set_screw_z_mm(link_face, toward, inner)
    d = float(hub["set_screw"].split()[2][1:])
    return toward * (screw_z - (face - toward * iface.shaft_length_mm)) - d / 2


def _interface_record(drive: dict[str, Any]) -> dict[str, Any]:
    iface = drive["interface"]
    return {
        "drive": drive["name"],
        "torque_limit_Nm": drive["torque_limit_Nm"],
        "mass_kg": drive["mass_kg"],
        **iface.__dict__,
    }
