"""The builder's kit of a realised design: the base, the hubs, pins and tool flange, every
fastener, their checks, and the layout the STEP, DXF and assembly-view files are drawn from.

:func:`builders_kit` takes a :class:`qsm.realization.pipeline.Realization` and its final parts
(topology-optimised plates with their bores) and applies :mod:`qsm.embodiment.kit`: the drives'
interfaces (:mod:`~qsm.embodiment.kit.interfaces`), the pins, hubs and tool flange
(:mod:`~qsm.embodiment.kit.joints`) and the base (:mod:`~qsm.embodiment.kit.base`, whose
module docs state the arrangement). The loads are the realisation's: each joint's peak force
over the duty, each drive's peak torque over the duty and the task's motion, and the payload's
peak force at the tool.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np
import shapely

from qsm.config.defaults import default
from qsm.embodiment.kit import base as bs
from qsm.embodiment.kit import fasteners as fs
from qsm.embodiment.kit import joints as jt
from qsm.embodiment.kit.interfaces import DriveInterface, interface_of
from qsm.embodiment.parts.link_parts import LinkPart
from qsm.physics.kinematics import pose
from qsm.realization import kit_layout as kl
from qsm.realization.pipeline import Realization

#: The seat plate and the pin plate at each pin joint.
#: The base's arrangement, as :mod:`qsm.embodiment.kit.base` states it.
ARRANGEMENT = " ".join(bs.__doc__.split("**Arrangement.**")[1].split("**Check.**")[0].split())
PIN_PLATES = {
    "B": ("lower_arm", "upper_arm"),
    "C": ("crank", "coupler"),
    "D": ("coupler", "upper_arm"),
}


@dataclass(frozen=True)
class KitSettings:
    """The payload's offset (m) from the tool flange's face, the motors' operating range
    (``theta1_deg`` (lo, hi), ``theta2_min_deg``; the links' sweep sizes the base), the drive
    catalogue's folder (None: the shipped one), where ``interfaces.csv`` is read, and the
    task's placing tolerance (mm; the base takes :data:`~qsm.embodiment.kit.base.BASE_SHARE`
    of it)."""

    tool_offset_m: float = default("kit.tool_offset_m")
    theta1_deg: tuple[float, float] = (45.0, 180.0)
    theta2_min_deg: float = -37.5
    catalogue: str | None = None
    tolerance_mm: float = default("task.tolerance_mm")


class Kit(NamedTuple):
    """``record`` (``kit.json``: parts, checks, fasteners, layout) and the BOM rows it adds."""

    record: dict[str, Any]
    bom: list[dict[str, Any]]


def _plates(done: Realization, parts: dict[str, LinkPart]) -> dict[str, dict[str, jt.Plate]]:
    """Each link's plate at each of its joints (thickness, allowable, boss), mm and MPa."""
    links = done.strength["links"]
    return {
        name: {
            b.joint: jt.Plate(
                name,
                1e3 * part.section.thickness_m,
                float(links[name]["allowable_MPa"]),
                1e3 * b.boss_radius_m,
            )
            for b in part.bores
        }
        for name, part in parts.items()
    }


def _drives(done: Realization, settings: KitSettings) -> list[dict[str, Any]]:
    """Per motor: its drive's interface, mass (kg) and peak torque (N m, the larger of the duty
    and the task's motion)."""
    motion = done.drives.get("task_motion", {})
    out = []
    for k in (1, 2):
        motor = done.drives["motors"][f"motor{k}"]
        peak = float(motor["required"]["peak_torque_Nm"])
        if motion.get("defined"):
            peak = max(peak, float(motion["peak_torque_Nm"][k - 1]))
        drive = motor.get("drive") or {}
        key = drive.get("gearbox_key", f"motor {k}: no drive")
        iface = interface_of(key, peak, settings.catalogue)
        out.append(
            {
                "interface": iface,
                "mass_kg": float(drive.get("mass_kg", 0.0)),
                "peak_torque_Nm": peak,
                "name": _drive_name(drive),
            }
        )
    return out


def _drive_name(drive: dict[str, Any]) -> str:
    return f"{drive['motor']} + {drive['gearbox']}" if drive else "no drive"


def lowest_point_mm(done: Realization, parts: dict[str, LinkPart], s: KitSettings) -> float:
    """How far (mm) below A any link reaches over the operating range (a 61 x 61 grid)."""
    t1 = np.radians(np.linspace(*s.theta1_deg, 61))[:, None]
    frac = np.linspace(0.0, 1.0, 61)[None, :]
    t2 = np.radians(s.theta2_min_deg) + frac * (t1 - np.radians(s.theta2_min_deg))
    t1 = np.broadcast_to(t1, t2.shape)
    p = pose(done.design, t1, t2)
    ok = p.closes[..., None]
    joints = {
        "A": np.zeros((*t1.shape, 2)),
        **{j: np.where(ok, getattr(p, j), np.nan) for j in "BCDE"},
    }
    radii = {n: {b.joint: 1e3 * b.boss_radius_m for b in part.bores} for n, part in parts.items()}
    return bs.lowest_point_mm(joints, radii)


def _bearing(done: Realization, joint: str) -> dict[str, Any]:
    """The bearing of ``joint`` (bore ``d_mm``, width ``B_mm``, ``peak_force_N``); where none
    of the catalogue fits, the bore the parts were drawn with (width 0)."""
    record = dict(done.strength["bearings"][joint])
    if record.get("d_mm") is None:
        bores = [b for p in done.parts.values() for b in p.bores if b.joint == joint]
        small = min(b.diameter_m for b in bores if b.diameter_m > 0)
        record |= {"d_mm": 1e3 * small, "B_mm": 0.0}
    return record


def _joint_hardware(
    done: Realization, plates: dict[str, dict[str, jt.Plate]], drives: list[dict[str, Any]]
) -> dict[str, Any]:
    """The pins at B, C, D and the hubs at A (the drives' output bearings carry A)."""
    bearings = {j: _bearing(done, j) for j in "ABCD"}
    sf = max(float(v["required_safety_factor"]) for v in done.strength["links"].values())
    pins = {
        j: jt.pin(j, bearings[j], plates[a][j], plates[b][j], sf)
        for j, (a, b) in PIN_PLATES.items()
    }
    force_a = float(bearings["A"]["peak_force_N"])
    spigot = float(bearings["A"]["d_mm"])
    hubs = []
    for k, (link, drive) in enumerate(zip(("lower_arm", "crank"), drives, strict=True), 1):
        iface: DriveInterface = drive["interface"]
        hub = jt.hub(k, iface, plates[link]["A"], spigot, drive["peak_torque_Nm"], sf)
        hubs.append(
            hub
            | {
                "output_bearing": {
                    "force_N": force_a,
                    "checked": False,
                    "note": f"the drive's own output bearing carries the joint's {force_a:.0f} N "
                    "at A; the catalogue gives no rating for it, so this is not checked: compare "
                    "with the maker's permissible radial load",
                }
            }
        )
    return {"pins": pins, "hubs": hubs, "safety_factor": sf}


def _cheeks(
    done: Realization,
    drives: list[dict[str, Any]],
    hardware: dict[str, Any],
    drop_mm: float,
    stack: dict[str, float],
    reach_mm: float,
    tolerance_mm: float,
) -> list[dict[str, Any]]:
    """Both cheeks: their outline sizes, holes and checks (:mod:`qsm.embodiment.kit.base`),
    each moving the tool by at most half the base's share of ``tolerance_mm``."""
    force = float(done.strength["bearings"]["A"]["peak_force_N"])
    allow = bs.BASE_SHARE * tolerance_mm / 2
    sizes = []
    for drive in drives:
        iface: DriveInterface = drive["interface"]
        washer = fs.washer_mm(iface.mount_thread)[1]
        if iface.output == "shaft":
            bore = max(iface.mount_pilot_mm, iface.shaft_d_mm + 2)
        else:
            head = fs.screw_head_mm(iface.flange_thread)[0]
            bore = max(iface.mount_pilot_mm, iface.flange_pcd_mm + head + 4)
        sizes.append((bore, max(iface.mount_pcd_mm + 3 * washer, bore + 30)))
    h = max(
        drop_mm + bs.CLEARANCE_MM, *(d["interface"].body_d_mm / 2 + bs.CLEARANCE_MM for d in drives)
    )
    out = []
    for k, (drive, (bore, b)) in enumerate(zip(drives, sizes, strict=True), 1):
        iface = drive["interface"]
        load = bs.CheekLoad(
            force,
            drive["peak_torque_Nm"],
            drive["mass_kg"],
            iface.body_length_mm / 2,
            stack[f"offset_{k}"],
        )
        for t in bs.PLATE_STOCK_MM:
            part = bs.cheek(load, h, b, hardware["safety_factor"], reach_mm, t, allow)
            fixing = bs.fixing_screws(load, part, hardware["safety_factor"])
            if fixing["holds"]:
                break
        part |= {
            "motor": k,
            "bore_mm": bore,
            "drive": drive["name"],
            "fixing": fixing,
            "load": load,
        }
        out.append(part)
    return out


def _stack(parts: dict[str, LinkPart], hardware: dict[str, Any]) -> dict[str, float]:
    """The plates' z (mm) from cheek 1's inner face (the arrangement of
    :mod:`qsm.embodiment.kit.base`) and each link's offset from its cheek's face."""
    t = {n: 1e3 * p.section.thickness_m for n, p in parts.items()}
    spacer = {j: fs.washer_mm(p["spacer"].split()[-1])[2] for j, p in hardware["pins"].items()}
    gap = jt.FLANGE_MM + max(fs.washer_mm("M8")[2] + fs.nut_height_mm("M8") + 2, 10.0)
    z = {"lower_arm": gap}
    z["upper_arm"] = z["lower_arm"] + t["lower_arm"] + spacer["B"]
    z["coupler"] = z["upper_arm"] + t["upper_arm"] + spacer["D"]
    z["crank"] = z["coupler"] + t["coupler"] + spacer["C"]
    z["cheek_2"] = z["crank"] + t["crank"] + gap
    z["offset_1"] = gap + t["lower_arm"] / 2
    z["offset_2"] = gap + t["crank"] / 2
    z["gap"] = gap
    return z


def _geometry(
    done: Realization,
    parts: dict[str, LinkPart],
    stack: dict[str, float],
    cheeks: list[dict[str, Any]],
    drives: list[dict[str, Any]],
    hardware: dict[str, Any],
    flange: dict[str, Any],
    angles: tuple[float, float],
) -> dict[str, Any]:
    """Every part placed (:mod:`qsm.realization.kit_layout`), mm: the plates, and along z the
    hubs' flanges against their links, the drives' envelopes outside the cheeks and the tool
    flange's disc against the upper arm at E."""
    screw = cheeks[0]["fixing"]["screw"]
    fix = bs.clearance_hole_mm(screw.split()[2] if screw else "M6")
    t1, t2 = cheeks[0]["thickness_mm"], cheeks[1]["thickness_mm"]
    end = stack["cheek_2"]
    plates = kl.link_plates(done.design, parts, stack, angles)
    for k, (c, z0) in enumerate(zip(cheeks, (-t1, end), strict=True), 1):
        iface = drives[k - 1]["interface"]
        plates[f"cheek_{k}"] = kl.cheek_plate(
            c, iface, bs.clearance_hole_mm(iface.mount_thread), fix, z0
        )
    plates["base_plate"] = kl.base_plate(
        cheeks, (-t1, end + t2), cheeks[0]["height_mm"], bs.BASE_PLATE_MM, fix
    )
    crank_end = stack["crank"] + 1e3 * parts["crank"].section.thickness_m
    flange_z = {1: stack["lower_arm"] - jt.FLANGE_MM, 2: crank_end}
    outside = {1: -t1 - drives[0]["interface"].body_length_mm, 2: end + t2}
    turned = {}
    for hub in hardware["hubs"]:
        k, iface = hub["motor"], drives[hub["motor"] - 1]["interface"]
        screws = hub["link_screws"]
        d = float(screws["pcd_mm"]) + 2 * fs.washer_mm(screws["thread"] or "M8")[1]
        turned[f"hub_{k}"] = kl.cylinder(d, jt.FLANGE_MM, flange_z[k], hub["spigot_d_mm"])
        turned[f"drive_{k}"] = kl.cylinder(iface.body_d_mm, iface.body_length_mm, outside[k])
    if flange.get("pattern"):
        e = np.asarray(kl.pose(done.design, *angles).E) * 1e3
        z_e = stack["upper_arm"] - jt.ADAPTER_MM
        turned["tool_flange"] = kl.cylinder(flange["face_d_mm"], jt.ADAPTER_MM, z_e, 0.0, e)
    return {"plates": plates, "turned": turned, "pose_deg": np.degrees(angles).tolist()}


def screw_lines(name: str, qty: int, where: str) -> list[tuple[str, int, str]]:
    """The lines of ``qty`` screws ``name``; a threaded rod (DIN 976-1) brings a nut for the end
    a screw's head would be (its washer is counted with the head's)."""
    lines = [(name, qty, where)]
    if name.startswith("DIN 976-1"):
        lines.append((f"ISO 10511 {name.split()[2]}", qty, f"{where}: rod ends"))
    return lines


def _fastener_lines(
    hardware: dict[str, Any],
    cheeks: list[dict[str, Any]],
    drives: list[dict[str, Any]],
    flange: dict[str, Any],
    table: dict[str, Any],
) -> list[tuple[str, int, str]]:
    """(order line, quantity, where) of every fastener, key and washer of the assembly."""
    lines: list[tuple[str, int, str]] = []
    for j, pin in hardware["pins"].items():
        thread = pin["nut"].split()[-1]
        lines += [
            (pin["screw"] or f"made: {pin['made']}", 1, f"pin {j}"),
            (pin["spacer"], 1, f"spacer between the plates at {j}"),
            (f"ISO 7089 {thread}", 1, f"under the nut at {j}"),
            (pin["nut"], 1, f"{j}"),
        ]
    for hub, drive, c in zip(hardware["hubs"], drives, cheeks, strict=True):
        k, iface, screws = hub["motor"], drive["interface"], hub["link_screws"]
        if screws["screw"]:
            th = screws["thread"]
            lines += screw_lines(screws["screw"], 6, f"hub {k} to the {hub['link']}")
            lines += [
                (f"ISO 7089 {th}", 12, f"hub {k}: under heads and nuts"),
                (f"ISO 10511 {th}", 6, f"hub {k}"),
            ]
        if iface.output == "shaft":
            key = hub["key"]
            lines.append(
                (
                    f"DIN 6885 A {key['w_mm']:g} x {key['h_mm']:g} x {key['length_mm']:g}",
                    1,
                    f"drive {k} to hub {k}",
                )
            )
        else:
            s = fs.cap_screw(iface.flange_thread, jt.FLANGE_MM, True, "")
            lines += screw_lines(
                s.name, iface.flange_bolts, f"hub {k} to drive {k}'s output flange"
            )
        mount = fs.cap_screw(iface.mount_thread, c["thickness_mm"], True, "")
        lines += screw_lines(mount.name, iface.mount_bolts, f"drive {k} to cheek {k}")
        if c["fixing"]["screw"]:
            th = c["fixing"]["screw"].split()[2]
            lines += screw_lines(c["fixing"]["screw"], 3, f"cheek {k} to the base plate")
            lines += [(f"ISO 7089 {th}", 3, f"cheek {k}: under the heads")]
    lines += screw_lines(table["screw"], 4, "base plate to the table")
    lines += [("ISO 7089 M8", 4, "base plate: under the heads")]
    if flange.get("pattern"):
        lines += screw_lines(flange["centre_screw"], 1, "tool flange to the upper arm")
        lines += [("ISO 7089 M8", 1, "tool flange: under the head")]
    return lines


def fastener_rows(lines: list[tuple[str, int, str]]) -> list[dict[str, Any]]:
    """BOM rows of ``lines``, one per order line, quantities added across the assembly."""
    merged: dict[str, dict[str, Any]] = {}
    for name, qty, where in lines:
        row = merged.setdefault(
            name,
            {
                "item": name,
                "category": _category(name),
                "where": [],
                "quantity": 0,
                "designation": name,
            },
        )
        row["quantity"] += qty
        row["where"].append(f"{where} ({qty})")
    for row in merged.values():
        row["where"] = "; ".join(row["where"])
        row["material"] = _fastener_material(row["item"])
    return list(merged.values())


def _category(name: str) -> str:
    if name.startswith("made"):
        return "made part"
    return "key" if name.startswith("DIN 6885") else "fastener"


def _fastener_material(name: str) -> str:
    standard = " ".join(name.split()[:2])
    return {
        "ISO 4762": "steel 8.8",
        "ISO 7379": "steel 12.9",
        "ISO 7089": "steel 200 HV",
        "ISO 10511": "steel 8, nylon insert",
        "DIN 6885": "C45+C",
        "DIN 976-1": "steel 8.8",
    }.get(standard, "steel")


def _plate_mass_kg(plate: dict[str, Any], density: float) -> float:
    """Mass (kg) of a placed plate: its outline less its holes times its thickness."""
    poly = shapely.Polygon(plate["outline"], plate["holes"])
    return poly.area * plate["thickness_mm"] * density * 1e-9


def _made_rows(geometry: dict[str, Any], hardware: dict[str, Any]) -> list[dict[str, Any]]:
    """BOM rows of the parts to cut or turn: the cheeks and base plate (aluminium, from their
    DXF), the hubs and the tool flange's disc (steel)."""
    rows = []
    al = bs.ALUMINIUM
    for name in ("cheek_1", "cheek_2", "base_plate"):
        plate = geometry["plates"][name]
        x0, y0, x1, y1 = shapely.Polygon(plate["outline"]).bounds
        rows.append(
            {
                "item": name.replace("_", " "),
                "category": "cut part",
                "where": "base",
                "quantity": 1,
                "material": al["name"],
                "mass_kg": _plate_mass_kg(plate, al["density_kg_m3"]),
                "bbox_x_mm": round(x1 - x0, 1),
                "bbox_y_mm": round(y1 - y0, 1),
                "bbox_z_mm": plate["thickness_mm"],
                "source": al["source"],
                "notes": f"cut from kit/dxf/{name}.dxf",
            }
        )
    for name, c in geometry["turned"].items():
        if name.startswith("drive"):
            continue
        mass = np.pi / 4 * (c["d_mm"] ** 2 - c["bore_mm"] ** 2) * c["length_mm"] * 7850e-9
        rows.append(
            {
                "item": name.replace("_", " "),
                "category": "turned part",
                "where": "A" if name.startswith("hub") else "E",
                "quantity": 1,
                "material": "C45+N steel",
                "mass_kg": float(mass),
                "bbox_x_mm": c["d_mm"],
                "bbox_y_mm": c["d_mm"],
                "bbox_z_mm": c["length_mm"],
                "notes": f"kit/step/{name}.step",
            }
        )
    return rows


def _checks(
    hardware: dict[str, Any], cheeks: list[dict], table: dict, flange: dict
) -> dict[str, bool]:
    """Whether each of the kit's checks holds."""
    out = {f"pin {j}": bool(p["holds"]) for j, p in hardware["pins"].items()}
    out |= {f"hub {h['motor']}": bool(h["holds"]) for h in hardware["hubs"]}
    for c in cheeks:
        out[f"cheek {c['motor']}"] = bool(c["holds"])
        out[f"cheek {c['motor']} screws"] = bool(c["fixing"]["holds"])
    out["table screws"] = bool(table["holds"])
    out["tool flange"] = bool(flange["holds"])
    return out


def _problems(hardware: dict[str, Any], cheeks: list[dict], table: dict, flange: dict) -> list[str]:
    """Each of the kit's failing checks, with its numbers."""
    out = []
    for j, pin in hardware["pins"].items():
        if not pin["holds"]:
            out.append(
                f"the pin of joint {j} ({pin['shoulder_d_mm']:g} mm) reaches a safety factor of "
                f"{pin['safety_factor']:.2f} ({pin['required_safety_factor']:g} required), or "
                f"needs {pin['printed_bearing_length_mm']:.1f} mm of printed bore"
            )
    for hub in hardware["hubs"]:
        if not hub["holds"]:
            out.append(f"hub {hub['motor']} does not carry {hub['peak_torque_Nm']:.1f} N m")
    for c in cheeks:
        if not c["holds"] or not c["fixing"]["holds"]:
            out.append(
                f"cheek {c['motor']} reaches a safety factor of {c['safety_factor']:.2f} "
                f"({c['required_safety_factor']:g} required), its fixing screws "
                f"{'hold' if c['fixing']['holds'] else 'do not hold'}"
            )
    if not table["holds"]:
        out.append(f"the table screws reach a safety factor of {table['safety_factor']:.2f}")
    if not flange["holds"]:
        out.append(
            f"no ISO 9409-1 flange of {', '.join(flange['tried'])} carries "
            f"{flange['payload_force_N']:.0f} N and fits the boss at E"
        )
    return out


#: Each part's assembly step (the exploded view's labels).
STEP_OF = {
    "base_plate": 1,
    "cheek_1": 2,
    "drive_1": 2,
    "hub_1": 3,
    "lower_arm": 5,
    "upper_arm": 6,
    "coupler": 7,
    "crank": 8,
    "cheek_2": 9,
    "drive_2": 9,
    "hub_2": 9,
    "tool_flange": 10,
}


def _named(lines: list[tuple[str, int, str]], where: str) -> str:
    """The fasteners of ``lines`` whose place starts with ``where``: "n x name, ..."."""
    found = [f"{q} x {n}" for n, q, w in lines if w.startswith(where)]
    return ", ".join(found) or "none"


def assembly_steps(
    record: dict[str, Any], lines: list[tuple[str, int, str]], bearings: dict[str, Any]
) -> list[str]:
    """The numbered assembly steps (:data:`STEP_OF`), each naming its parts and fasteners."""
    drives = record["drives"]
    pins = record["pins"]
    hubs = {h["motor"]: h for h in record["hubs"]}

    def hub(k: int) -> str:
        h = hubs[k]
        fix = (
            f"its key ({_named(lines, f'drive {k} to hub')})"
            if h["output"] == "shaft"
            else _named(lines, f"hub {k} to drive")
        )
        return f"hub {k} onto drive {k}'s {h['output']} with {fix}"

    def pin(j: str) -> str:
        a, b = pins[j]["plates"]
        return (
            f"{pins[j]['screw'] or pins[j]['made']} through the {b.replace('_', ' ')}, "
            f"the {pins[j]['spacer']} spacer and the bearing in the {a.replace('_', ' ')}; "
            f"{pins[j]['nut']} on an ISO 7089 washer"
        )

    return [
        f"Bolt the base plate (dxf/base_plate.dxf) to the table: {_named(lines, 'base plate')}.",
        f"Bolt cheek 1 to the base plate ({_named(lines, 'cheek 1')}) and drive 1 "
        f"({drives[0]['drive']}) to its outer face ({_named(lines, 'drive 1 to cheek')}).",
        f"Fit {hub(1)}.",
        "Press the bearings into their seats: "
        + ", ".join(f"{b['designation']} at {j}" for j, b in bearings.items() if j != "A")
        + ".",
        f"Bolt the lower arm to hub 1, its bore at A on the hub's spigot: "
        f"{_named(lines, 'hub 1 to the')}, with washers and nuts.",
        f"Join the upper arm to the lower arm at B: {pin('B')}.",
        f"Join the coupler to the upper arm at D: {pin('D')}.",
        f"Join the crank to the coupler at C: {pin('C')}.",
        f"Bolt drive 2 ({drives[1]['drive']}) to cheek 2 ({_named(lines, 'drive 2 to cheek')}), "
        f"fit {hub(2)}, bolt the crank to hub 2 ({_named(lines, 'hub 2 to the')}) and cheek 2 "
        f"to the base plate ({_named(lines, 'cheek 2')}).",
        f"Fix the tool flange at E ({_named(lines, 'tool flange')}); the tool bolts to its "
        f"{record['tool_flange'].get('pattern') or 'pattern (none holds)'}.",
    ]


def builders_kit(
    done: Realization, parts: dict[str, LinkPart], payload_force_N: float, settings: KitSettings
) -> Kit:
    """The kit of ``done`` with its final ``parts`` (module docs); ``payload_force_N``: the
    payload's peak force on the tool."""
    plates = _plates(done, parts)
    drives = _drives(done, settings)
    hardware = _joint_hardware(done, plates, drives)
    stack = _stack(parts, hardware)
    drop = lowest_point_mm(done, parts, settings)
    l1, _, _, _, ee_x, ee_y = done.design
    reach = 1e3 * (l1 + float(np.hypot(ee_x, ee_y)))
    cheeks = _cheeks(done, drives, hardware, drop, stack, reach, settings.tolerance_mm)
    angles = kl.working_pose(done.design, settings.theta1_deg, settings.theta2_min_deg)
    e_plate = plates["upper_arm"]["E"]
    flange = jt.tool_flange(
        payload_force_N,
        settings.tool_offset_m,
        e_plate.boss_mm,
        e_plate.thickness_mm,
        hardware["safety_factor"],
    )
    geometry = _geometry(done, parts, stack, cheeks, drives, hardware, flange, angles)
    w, length = geometry["plates"]["base_plate"]["size_mm"]
    table = bs.table_screws(
        cheeks[0]["load"], cheeks[0]["height_mm"], w, length, hardware["safety_factor"]
    )
    checks = _checks(hardware, cheeks, table, flange)
    lines = _fastener_lines(hardware, cheeks, drives, flange, table)
    record = {
        "holds": all(checks.values()),
        "checks": checks,
        "problems": _problems(hardware, cheeks, table, flange),
        "drives": [_interface_record(d) for d in drives],
        "pins": hardware["pins"],
        "hubs": hardware["hubs"],
        "not_checked": [h["output_bearing"]["note"] for h in hardware["hubs"]],
        "base": {
            "tool_error_mm": sum(c["tool_error_mm"] for c in cheeks),
            "cheeks": [_cheek_record(c) for c in cheeks],
            "table_screws": table,
            "links_lowest_mm": drop,
            "material": bs.ALUMINIUM,
            "arrangement": ARRANGEMENT,
        },
        "tool_flange": flange,
        "stack_mm": stack,
        "layout": geometry,
    }
    record["assembly_steps"] = assembly_steps(record, lines, done.strength["bearings"])
    record["step_of"] = STEP_OF
    return Kit(record, _made_rows(geometry, hardware) + fastener_rows(lines))


def _interface_record(drive: dict[str, Any]) -> dict[str, Any]:
    iface = drive["interface"]
    return {
        "drive": drive["name"],
        "peak_torque_Nm": drive["peak_torque_Nm"],
        "mass_kg": drive["mass_kg"],
        **iface.__dict__,
    }


def _cheek_record(c: dict[str, Any]) -> dict[str, Any]:
    return {k: v for k, v in c.items() if k != "load"}
