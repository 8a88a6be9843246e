"""The builder's kit's assembly steps (:mod:`qsm.realization.kit.kit_sequence`) and the solids
they are checked against, at five poses of the arm over the operating range.

The steps and what each needs first:
- the base plate; each cheek on it, and its three screws from below the plate; the plate on
  the table last of these (the table closes the cheeks' screws);
- per motor whose drive has an output flange: the drive onto its cheek and its mounting screws
  (heads on the cheek's inner face), the hub onto the drive's flange (the hub's flange is wider
  than the cheek's bore, so it comes from the arm's side) and its screws to the drive (heads in
  the hub's flange, under the link), the link onto the hub's spigot and the link's screws from
  its far face into the hub's tapped flange;
- per motor whose drive has a shaft: the link, the hub onto it and the hub's screws from its own
  side into the link's inserts; on the bench the drive onto its cheek; the module slides its
  shaft into the hub along the axis, then the cheek's screws and the hub's set screw;
- the upper arm, the coupler, each pin once both its plates are on (a key on the head, an open
  spanner on the nut), and the tool flange and its centre screw.

Tightening torques: :func:`qsm.embodiment.kit.fasteners.tightening_torque_Nm`, at most what the
printed plate bears under the washer where a screw clamps one.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import replace
from typing import Any

import numpy as np

from qsm.embodiment.kit import fasteners as fs
from qsm.embodiment.kit import joints as jt
from qsm.embodiment.strength.record import BearingLoad
from qsm.physics.kinematics import pose
from qsm.realization.kit import kit_layout as kl
from qsm.realization.kit.kit_sequence import (
    TOWARD,
    Step,
    Tool,
    key_path,
    sequence,
    short_key_path,
    spanner_slab,
)
from qsm.realization.kit.kit_solids import (
    Prism,
    disc,
    hardware_prisms,
    moved_prism,
    plate_prism,
    solids,
)

#: Fractions of theta1's operating range of the poses besides the kit's own.
POSE_FRACTIONS = (0.1, 0.35, 0.65, 0.9)
#: The pins' plates: the plate that seats the bearing, the other (the head is on its outer face).
PIN_PLATES = {
    "B": ("lower_arm", "upper_arm"),
    "C": ("crank", "coupler"),
    "D": ("coupler", "upper_arm"),
}
#: Each link's angle source: motor 1 turns the lower arm, motor 2 the crank.
HUB_LINKS = {1: "lower_arm", 2: "crank"}
#: How far (mm) a part moves along the axis onto its spigot, pin or shaft, plus 2 mm.
STROKE_MM = 12.0


def poses(design: np.ndarray, kit_pose_deg: list[float], theta1_deg: tuple, t2_min: float):
    """The kit's pose and one per :data:`POSE_FRACTIONS` where the loop closes (rad)."""
    out = [tuple(math.radians(a) for a in kit_pose_deg)]
    for f in POSE_FRACTIONS:
        t1 = math.radians(theta1_deg[0] + f * (theta1_deg[1] - theta1_deg[0]))
        try:
            out.append(kl.working_pose(design, (math.degrees(t1),) * 2, t2_min))
        except ValueError:
            continue
    return out


def placed_solids(record: dict[str, Any], design, parts, angles) -> dict[str, tuple[Prism, ...]]:
    """Every part's prisms with the links at motor ``angles`` (rad): the layout's fixed parts,
    the links, the tool flange at E, the table under the base plate and the hardware, each
    piece carried by its link from the layout's pose."""
    layout = record["layout"]
    out = solids(layout)
    start = kl.link_frames(design, *np.radians(layout["pose_deg"]))
    now = kl.link_frames(design, *angles)
    for name, part in layout.get("hardware", {}).items():
        link, prisms = layout["moves_with"][name], hardware_prisms(part)
        if link != "base":
            prisms = tuple(moved_prism(p, start[link], now[link]) for p in prisms)
        out[name] = prisms
    links = kl.link_plates(design, parts, record["stack_mm"], angles)
    out |= {name: (plate_prism(p),) for name, p in links.items()}
    if "tool_flange" in layout["turned"]:
        e = np.asarray(pose(design, *angles).E) * 1e3
        flange = dict(layout["turned"]["tool_flange"]) | {"at_mm": e.tolist()}
        out["tool_flange"] = solids({"plates": {}, "turned": {"f": flange}})["f"]
    base = out["base_plate"][0]
    out["table"] = (Prism("y", base.shape.buffer(200.0), base.lo - 100.0, base.lo),)
    return out


#: A socket spanner on a threaded rod's nut: its wall (mm) and length along the axis (mm).
SOCKET_WALL_MM, SOCKET_LENGTH_MM = 2.0, 100.0


def _key(screw: str) -> fs.HexKey:
    """The key of an order line ``ISO 4762 M5 x 50`` or ``ISO 7379 8 x 80 - M6``; for a DIN
    976-1 rod, the socket spanner on its nut, as a key as wide as the socket."""
    standard, size = " ".join(screw.split()[:2]), screw.split()[2]
    if standard == "DIN 976-1":
        across = fs.nut_across_corners_mm(size) * math.cos(math.pi / 6)
        return fs.HexKey(across + 2 * SOCKET_WALL_MM, SOCKET_LENGTH_MM, SOCKET_LENGTH_MM / 4)
    thread = size if standard == "ISO 4762" else screw.split()[-1]
    d = float(size) if standard == "ISO 7379" else float(thread[1:])
    return fs.hex_key(fs.Fastener(standard, "", thread, d, 0.0, ""))


def _torque(thread: str, printed_MPa: float | None = None) -> float:
    """The tightening torque (N m) of an 8.8 screw of ``thread`` in a clearance hole, its
    preload at most ``printed_MPa`` over its washer's face where it clamps a printed plate."""
    hole = fs.clearance_hole_mm(thread)
    limit = math.inf
    if printed_MPa is not None:
        inner, outer, _ = fs.washer_mm(thread)
        limit = printed_MPa * math.pi / 4 * (outer**2 - inner**2)
    return fs.tightening_torque_Nm(thread, hole, limit)[0]


def _screw_tool(screw: str, printed_MPa: float | None = None) -> Tool:
    """The key (or a rod's socket spanner) of ``screw`` and its tightening torque."""
    key = _key(screw)
    thread = screw.split()[-1] if screw.startswith("ISO 7379") else screw.split()[2]
    torque = round(_torque(thread, printed_MPa), 2)
    if screw.startswith("DIN 976-1"):
        return Tool("socket spanner", f"socket spanner {key.key_mm - 4:g} mm", torque)
    return Tool("hexagon key", key.name, torque)


def keys_on(points, z: float, sign: float, screw: str) -> tuple[Prism, ...]:
    """The key paths of ``screw`` at each of ``points`` (mm), socket tops at ``z``."""
    key = _key(screw)
    return tuple(p for x, y in points for p in key_path(x, y, z, sign, key))


def _placing(name: str, placed, direction, stroke: float) -> tuple:
    """A part's way in: its prisms at each pose swept back along ``direction`` by ``stroke``."""
    return tuple(
        (i, tuple(p.swept(direction, stroke) for p in at_pose[name]))
        for i, at_pose in enumerate(placed)
        if name in at_pose
    )


def pinned_to(link: str) -> tuple[str, ...]:
    """The links ``link`` is pinned to (:data:`PIN_PLATES`)."""
    return tuple(b if a == link else a for a, b in PIN_PLATES.values() if link in (a, b))


def _z(sign: float) -> tuple[float, float, float]:
    return (0.0, 0.0, float(sign))


def _y_keys(points, top: float, sign: float, screw: str) -> tuple[Prism, ...]:
    """Key paths along y of ``screw`` at (x, z) ``points``, socket tops at ``top``."""
    key = _key(screw)
    end = top + sign * key.long_arm_mm
    d = key.key_mm / 0.866 + 1.0
    return tuple(Prism("y", disc(x, z, d), min(top, end), max(top, end)) for x, z in points)


def table_screw_points(plate: dict[str, Any]) -> list[tuple[float, float]]:
    """The table screws' places (x, z; mm): 15 mm in from the base ``plate``'s corners."""
    w, (z0, z1) = plate["size_mm"][0], (plate["outline"][0][1], plate["outline"][2][1])
    return [(x, z) for x in (-w / 2 + 15, w / 2 - 15) for z in (z0 + 15, z1 - 15)]


def cheek_screw_points(record: dict[str, Any], k: int) -> list[tuple[float, float]]:
    """Cheek ``k``'s fixing screws' places (x, z; mm): at :func:`kit_layout.fixing_x_mm
    <qsm.realization.kit.kit_layout.fixing_x_mm>`, in the middle of its thickness."""
    cheek = record["base"]["cheeks"][k - 1]
    t = cheek["thickness_mm"]
    z = -t / 2 if k == 1 else record["stack_mm"]["cheek_2"] + t / 2
    return [(x, z) for x in kl.fixing_x_mm(cheek)]


def base_steps(record: dict[str, Any]) -> list[Step]:
    """The base plate, and the plate onto the table (its four screws from above)."""
    plate = record["layout"]["plates"]["base_plate"]
    screw = record["base"]["table_screws"]["screw"]
    corners = table_screw_points(plate)
    top = plate["origin"][1] + fs.washer_mm("M8")[2] + fs.screw_head_mm("M8")[1]
    return [
        Step(
            "base plate",
            "Lay the base plate (dxf/base_plate.dxf) on the bench.",
            ("base_plate",),
            (),
            (0.0, -1.0, 0.0),
            Tool("hand", "by hand"),
        ),
        Step(
            "table",
            f"Set the base plate on the table and bolt it: 4 x {screw}, with ISO 7089 M8 washers.",
            ("table",),
            ("base plate",),
            (0.0, -1.0, 0.0),
            _screw_tool(screw),
            ((0, _y_keys(corners, top, 1.0, screw)),),
        ),
    ]


def cheek_screw_step(record: dict[str, Any], k: int, after: str) -> Step:
    """Cheek ``k``'s three screws from below the base plate into its bottom edge."""
    plate = record["layout"]["plates"]["base_plate"]
    cheek = record["base"]["cheeks"][k - 1]
    screw = cheek["fixing"]["screw"]
    bottom = plate["origin"][1] - plate["thickness_mm"]
    thread = screw.split()[2]
    top = bottom - fs.washer_mm(thread)[2] - fs.screw_head_mm(thread)[1]
    points = cheek_screw_points(record, k)
    return Step(f"cheek {k} screws", f"Bolt cheek {k} to the base plate from below: 3 x "
                f"{screw}, with ISO 7089 {thread} washers.", (), (after,), (0.0, 1.0, 0.0),
                _screw_tool(screw), ((0, _y_keys(points, top, -1.0, screw)),))  # fmt: skip


def link_faces(record: dict[str, Any], k: int) -> tuple[float, float, float]:
    """Motor ``k``'s link: its face toward the drive, its far face (z, mm), and its cheek's
    inner face."""
    stack, t = record["stack_mm"], record["layout"]["plates"][HUB_LINKS[k]]["thickness_mm"]
    near = stack["lower_arm"] if k == 1 else stack["crank_end"]
    inner = 0.0 if k == 1 else stack["cheek_2"]
    return near, near - TOWARD[k] * t, inner


def _per_pose(angles, k: int, build) -> tuple:
    """``build(link angle)`` -> prisms, at each pose (motor ``k``'s link angle)."""
    return tuple((i, build(a[k - 1])) for i, a in enumerate(angles))


def mount_screws(record: dict[str, Any], k: int) -> tuple[str, list[tuple[float, float]]]:
    """Drive ``k``'s mounting screw (an order line, through its cheek's web) and where each
    goes (mm about A: a square pattern of 4 turned by 45 degrees)."""
    iface, cheek = record["drives"][k - 1], record["base"]["cheeks"][k - 1]
    screw = fs.cap_screw(iface["mount_thread"], cheek["pocket"]["web_mm"], True, "").name
    start = math.radians(45.0 if iface["mount_bolts"] == 4 else 0.0)
    return screw, kl.ring(iface["mount_pcd_mm"], iface["mount_bolts"], start)


def mount_step(record: dict[str, Any], k: int, needs: tuple, group: str = "") -> Step:
    """Drive ``k``'s mounting screws through its cheek, heads on the cheek's inner face."""
    iface = record["drives"][k - 1]
    screw, points = mount_screws(record, k)
    top = link_faces(record, k)[2] - TOWARD[k] * fs.screw_head_mm(iface["mount_thread"])[1]
    reach = ((0, keys_on(points, top, -TOWARD[k], screw)),)
    return Step(f"drive {k} screws", f"Bolt drive {k} ({iface['drive']}) to cheek {k}: "
                f"{iface['mount_bolts']} x {screw} from the cheek's inner face.", (), needs,
                _z(TOWARD[k]), _screw_tool(screw), reach, group)  # fmt: skip


def link_screw_step(record: dict[str, Any], k: int, angles, needs: tuple, allow_MPa: float) -> Step:
    """Hub ``k``'s six screws to its link: from the link's far face into the hub's tapped
    flange, or from the hub's side into the link's inserts (the printed link bears
    ``allow_MPa`` under the washers or the hub's flange)."""
    hub, link = record["hubs"][k - 1], HUB_LINKS[k]
    s = hub["link_screws"]
    near, far, _ = link_faces(record, k)
    head = fs.washer_mm(s["thread"])[2] + fs.screw_head_mm(s["thread"])[1]
    if s["side"] == "link":
        top, sign = far - TOWARD[k] * head, -TOWARD[k]
        where = f"from the {link.replace('_', ' ')}'s far face"
    else:
        top = near + TOWARD[k] * (jt.FLANGE_MM + head)
        sign, where = TOWARD[k], f"from the hub's side into the {link.replace('_', ' ')}'s inserts"
    reach = _per_pose(
        angles,
        k,
        lambda a: keys_on(
            kl.ring(s["pcd_mm"], jt.HUB_SCREWS, a + math.radians(30)), top, sign, s["screw"]
        ),
    )
    return Step(f"hub {k} screws", f"Bolt hub {k} and the {link.replace('_', ' ')} together, "
                f"{where}: {jt.HUB_SCREWS} x {s['screw']}, with ISO 7089 {s['thread']} washers.",
                (), needs, _z(-sign), _screw_tool(s["screw"], allow_MPa), reach)  # fmt: skip


def flange_drive_steps(
    record: dict[str, Any], k: int, placed, angles, allow: float, bench: str = ""
) -> list:
    """Motor ``k`` with an output flange: cheek, drive and its screws, hub and its screws to
    the drive, link, and the link's screws into the hub's tapped flange; in place, or (``bench``:
    the module's name) on the bench, the module then brought onto the arm along the axis."""
    hub, link, iface = record["hubs"][k - 1], HUB_LINKS[k], record["drives"][k - 1]
    near = link_faces(record, k)[0]
    flange = hub["flange_screw"]
    reach = _per_pose(
        angles,
        k,
        lambda a: keys_on(
            kl.ring(iface["flange_pcd_mm"], iface["flange_bolts"], a), near, -TOWARD[k], flange
        ),
    )
    toward, away = _z(TOWARD[k]), _z(-TOWARD[k])
    where = "upright" if bench else "on the base plate"
    core = [
        Step(f"cheek {k}", f"Stand cheek {k} (dxf/cheek_{k}.dxf) {where}.", (f"cheek_{k}",),
             () if bench else ("base plate",), (0.0, -1.0, 0.0), Tool("hand", "by hand"),
             _placing(f"cheek_{k}", placed, (0.0, -1.0, 0.0), 10.0)),
        Step(f"drive {k}", f"Put drive {k} ({iface['drive']}) against cheek {k}'s outer face, "
             "its pilot in the bore.", (f"drive_{k}",), (f"cheek {k}",), away,
             Tool("hand", "by hand"), _placing(f"drive_{k}", placed, away, STROKE_MM)),
        mount_step(record, k, (f"drive {k}",)),
        Step(f"hub {k}", f"Put hub {k} on drive {k}'s output flange from the arm's side, its "
             "boss through the cheek's bore.", (f"hub_{k}",), (f"drive {k}",), toward,
             Tool("hand", "by hand"), _placing(f"hub_{k}", placed, toward, STROKE_MM)),
        Step(f"hub {k} to drive", f"Bolt hub {k} to drive {k}'s flange: "
             f"{iface['flange_bolts']} x {flange}, heads in the hub's counterbores.", (),
             (f"hub {k}",), toward, _screw_tool(flange), reach),
        Step(link, f"Put the {link.replace('_', ' ')} on hub {k}'s spigot.", (link,),
             (f"hub {k}",), toward, Tool("hand", "by hand"),
             _placing(link, placed, toward, STROKE_MM), aside=pinned_to(link)),
        link_screw_step(record, k, angles, (link,), allow),
    ]  # fmt: skip
    if not bench:
        return [*core, cheek_screw_step(record, k, f"cheek {k}")]
    parts = (f"cheek_{k}", f"drive_{k}", f"hub_{k}", link)
    module = Step(
        bench,
        f"Bring the module (cheek {k}, drive {k}, hub {k} and the "
        f"{link.replace('_', ' ')}, built on the bench) onto the base plate along the "
        "axis.",
        parts,
        (core[-1].key, core[2].key, core[4].key, "base plate"),
        away,
        Tool("hand", "by hand"),
        _module_way(parts, placed, away),
        aside=pinned_to(link),
    )
    return [*(replace(s, group=bench) for s in core), module, cheek_screw_step(record, k, bench)]


def _module_way(parts: tuple[str, ...], placed, direction) -> tuple:
    """A module's way in: each of its ``parts`` swept along ``direction`` by its stroke."""
    return tuple(
        (i, sum((tuple(p.swept(direction, STROKE_MM) for p in at[n]) for n in parts), ()))
        for i, at in enumerate(placed)
    )


def shaft_drive_steps(record: dict[str, Any], k: int, placed, angles, allow: float) -> list:
    """Motor ``k`` with a shaft: link, hub and its screws into the link's inserts; on the bench
    drive and cheek; the module slid onto the hub; the cheek's screws; the set screw."""
    hub, link, iface = record["hubs"][k - 1], HUB_LINKS[k], record["drives"][k - 1]
    module, away = f"drive module {k}", _z(-TOWARD[k])
    stroke = iface["shaft_length_mm"] + 2.0
    near, _, inner = link_faces(record, k)
    thread = hub["set_screw"].split()[2]
    key = fs.hex_key(fs.Fastener("ISO 4029", "", thread, float(thread[1:]), 0.0, ""))
    mid = jt.set_screw_z_mm(near, TOWARD[k], inner)
    set_reach = _per_pose(
        angles,
        k,
        lambda a: (
            spanner_slab(
                0.0,
                0.0,
                mid - key.key_mm,
                mid + key.key_mm,
                key.key_mm / 0.866 + 1,
                a + kl.SET_SCREW_RAD,
                hub["boss_d_mm"] / 2,
            ),
        ),
    )
    return [
        Step(link, f"Lay the {link.replace('_', ' ')} in its place.", (link,), (),
             (0.0, -1.0, 0.0), Tool("hand", "by hand"),
             _placing(link, placed, (0.0, -1.0, 0.0), 400.0), aside=pinned_to(link)),
        Step(f"hub {k}", f"Put hub {k}'s spigot into the {link.replace('_', ' ')}'s bore at A.",
             (f"hub_{k}",), (link,), away, Tool("hand", "by hand"),
             _placing(f"hub_{k}", placed, away, STROKE_MM)),
        link_screw_step(record, k, angles, (f"hub {k}",), allow),
        mount_step(record, k, (), group=module),
        Step(module, f"Slide drive {k} with cheek {k} (bolted together on the bench) onto hub "
             f"{k}: its shaft and key into the hub's bore.", (f"cheek_{k}", f"drive_{k}"),
             (f"drive {k} screws", f"hub {k}", "base plate"), away, Tool("hand", "by hand"),
             tuple((i, sum((tuple(p.swept(away, stroke) for p in at[n]) for n in
                            (f"cheek_{k}", f"drive_{k}")), ())) for i, at in enumerate(placed))),
        Step(f"hub {k} set screw", f"Tighten hub {k}'s {hub['set_screw']} onto the shaft "
             "through the gap between the hub's flange and the cheek.", (), (module,),
             (0.0, 0.0, 0.0), Tool("hexagon key", key.name), set_reach),
        cheek_screw_step(record, k, module),
    ]  # fmt: skip


def pin_faces(record: dict[str, Any], j: str) -> tuple[float, float, float, float]:
    """Pin ``j``'s head face and direction (its plate's outer face, away from the seat), and
    its nut's face and direction (the seat's outer face), z mm."""
    seat, other = PIN_PLATES[j]
    stack, plates = record["stack_mm"], record["layout"]["plates"]
    up = stack[other] > stack[seat]
    head = stack[other] + plates[other]["thickness_mm"] if up else stack[other]
    nut = stack[seat] if up else stack[seat] + plates[seat]["thickness_mm"]
    return head, 1.0 if up else -1.0, nut, -1.0 if up else 1.0


def _pin_keys(x: float, y: float, head_z: float, up: float, pin: dict[str, Any]) -> list:
    """The ways a key can turn pin ``pin``'s head at (x, y) mm: its long arm in the socket
    along the axis, or its short arm in it and the long arm as a handle in the plane, in four
    directions (none for a made pin)."""
    if pin["screw"] is None:
        return [()]
    key = _key(pin["screw"])
    top = head_z + up * fs.shoulder_head_mm(pin["shoulder_d_mm"])[1]
    short = [short_key_path(x, y, top, up, key, t * math.pi / 2) for t in range(4)]
    return [key_path(x, y, top, up, key), *short]


def pin_step(
    record: dict[str, Any], j: str, design, angles, allow: float, needs: tuple[str, ...]
) -> Step:
    """Pin ``j``: its shoulder screw through both plates (a key on the head) and its nut (an
    open spanner, the best of four directions), once ``needs`` have put its plates on the
    arm."""
    pin = record["pins"][j]
    screw = pin["screw"]
    head_z, up, nut_z, down = pin_faces(record, j)
    thread = pin["nut"].split()[-1]
    nut_h = fs.washer_mm(thread)[2] + fs.nut_height_mm(thread)
    across = fs.nut_across_corners_mm(thread) + 10.0
    reach = []
    for i, a in enumerate(angles):
        x, y = (1e3 * np.asarray(getattr(pose(design, *a), j))).tolist()
        for keys in _pin_keys(x, y, head_z, up, pin):
            for turn in range(4):
                slab = spanner_slab(x, y, nut_z, nut_z + down * nut_h, across, turn * math.pi / 2)
                reach.append((i, (*keys, slab)))
    a, b = (n.replace("_", " ") for n in PIN_PLATES[j])
    name = screw or pin["made"]
    tool = Tool("hexagon key and open spanner", _key(screw).name if screw else "spanners",
                round(_torque(thread, allow), 2))  # fmt: skip
    return Step(f"pin {j}", f"Join the {b} to the {a} at {j}: {name} through the {b}, the "
                f"{pin['spacers']} x {pin['spacer']} spacer and the bearing"
                + (f", {pin['shim']} beside it" if pin["shim"] else "")
                + f"; {pin['nut']} on an ISO 7089 washer.",
                (), needs, _z(-up), tool, tuple(reach))  # fmt: skip


def press_steps(record: dict[str, Any], bearings: Mapping[str, BearingLoad]) -> list[Step]:
    """On the bench: each pin joint's bearing pressed into its seat, and a hub's heat-set
    inserts pressed into its link with a soldering iron."""
    out = [
        Step(f"bearing {j}", f"Press the {b.designation} bearing into the "
             f"{PIN_PLATES[j][0].replace('_', ' ')}'s seat at {j}, flush with the face toward "
             f"the {PIN_PLATES[j][1].replace('_', ' ')}.", (), (), (0.0, 0.0, 0.0),
             Tool("press", "arbor press, on the outer ring"))
        for j, b in bearings.items() if j in PIN_PLATES
    ]  # fmt: skip
    for hub in record["hubs"]:
        s = hub["link_screws"]
        if s["thread"] and s["side"] == "hub":
            link = hub["link"].replace("_", " ")
            out.append(Step(f"inserts {hub['motor']}", f"Press {jt.HUB_SCREWS} {s['insert']} "
                            f"heat-set inserts into the {link} from the hub's side.", (), (),
                            (0.0, 0.0, 0.0), Tool("soldering iron", "soldering iron with an "
                                                  "insert tip")))  # fmt: skip
    return out


def _flange_reach(record: dict[str, Any], design, angles, placed) -> tuple:
    """The tool flange's way in (up under the upper arm) and its centre screw's key from the
    arm's far face at E, at each pose."""
    screw = record["tool_flange"]["centre_screw"]
    thread = screw.split()[2]
    face = record["stack_mm"]["upper_arm"] + record["layout"]["plates"]["upper_arm"]["thickness_mm"]
    top = face + fs.washer_mm(thread)[2] + fs.screw_head_mm(thread)[1]
    out = []
    for (i, way), a in zip(
        _placing("tool_flange", placed, _z(1.0), STROKE_MM), angles, strict=True
    ):
        e = 1e3 * np.asarray(pose(design, *a).E)
        out.append((i, (*way, *keys_on([tuple(e)], top, 1.0, screw))))
    return tuple(out)


def arm_steps(record: dict[str, Any], design, angles, placed, allow: float) -> list[Step]:
    """The upper arm on the lower arm and the coupler on the upper arm (each along the axis
    onto its neighbour), and the tool flange under the upper arm at E with its centre screw
    from the arm's far face (the printed arm bears ``allow`` MPa under its washer)."""
    down, up = _z(-1.0), _z(1.0)
    steps = [
        Step("upper_arm", "Put the upper arm on the lower arm, B over B.", ("upper_arm",),
             ("lower_arm",), down, Tool("hand", "by hand"),
             _placing("upper_arm", placed, down, STROKE_MM), aside=pinned_to("upper_arm")),
        Step("coupler", "Put the coupler on the upper arm, D over D.", ("coupler",),
             ("upper_arm",), down, Tool("hand", "by hand"),
             _placing("coupler", placed, down, STROKE_MM), aside=pinned_to("coupler")),
    ]  # fmt: skip
    flange = record["tool_flange"]
    if flange.get("pattern"):
        screw = flange["centre_screw"]
        steps.append(
            Step("tool_flange", f"Fix the tool flange under the upper arm at E: {screw} from "
                 "the arm's face, with an ISO 7089 M8 washer.", ("tool_flange",),
                 ("upper_arm",), up, _screw_tool(screw, allow),
                 _flange_reach(record, design, angles, placed)))  # fmt: skip
    return steps


def assembly_steps(
    record: dict[str, Any],
    design,
    angles,
    placed,
    allow: dict,
    bearings: Mapping[str, BearingLoad],
) -> list[Step]:
    """Every step of the kit in a natural order (the sort keeps it where it may), ``allow``
    each link's allowable stress (MPa) under a washer, ``bearings`` the joints' bearings."""
    base, table = base_steps(record)
    motors = []
    for k in (1, 2):
        a = allow[HUB_LINKS[k]]
        if record["drives"][k - 1]["output"] == "shaft":
            motors.append(shaft_drive_steps(record, k, placed, angles, a))
        else:  # motor 2's side is closed from the arm's side: its module is built on the bench
            bench = "" if k == 1 else f"motor {k} module"
            motors.append(flange_drive_steps(record, k, placed, angles, a, bench))
    steps = [*press_steps(record, bearings), base, *motors[0],
             *arm_steps(record, design, angles, placed, allow["upper_arm"]),
             *motors[1]]  # fmt: skip
    arm = {part: s.key for s in steps if not s.group for part in s.places}
    pins = [
        pin_step(record, j, design, angles, allow[PIN_PLATES[j][0]],
                 tuple(arm[p] for p in PIN_PLATES[j]))
        for j in "BDC"
    ]  # fmt: skip
    return [*steps, *pins, table]


def kit_sequence(
    record: dict[str, Any],
    design,
    parts,
    theta1_deg,
    t2_min,
    allow: dict,
    bearings: Mapping[str, BearingLoad],
    hardware_step: dict[str, str] | None = None,
):
    """The assembly sequence (:func:`qsm.realization.kit.kit_sequence.sequence`) of the kit
    ``record`` of ``design`` with its holed ``parts``, checked at :func:`poses`, the hardware
    in the layout put in by the steps ``hardware_step`` names."""
    layout = record["layout"]
    angles = poses(np.asarray(design), layout["pose_deg"], theta1_deg, t2_min)
    placed = [placed_solids(record, design, parts, a) for a in angles]
    steps = assembly_steps(record, design, angles, placed, allow, bearings)
    hardware = {n: (k, layout["moves_with"][n]) for n, k in (hardware_step or {}).items()}
    return sequence(steps, placed, hardware)
