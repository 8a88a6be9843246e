"""The joints' hardware and its checks: a shoulder screw at each of B, C and D, a hub at A per
drive and the tool flange at E.

**Pins (B, C, D).** Each pin is an ISO 7379 shoulder screw whose shoulder is the joint bearing's
bore (the bearing sits in one plate, the shoulder runs through its inner ring and through the
other plate's bore) and spans both plates and the ISO 7089 washer between them; an ISO 10511
nut on its thread holds it. It is checked at the joint's peak force F, as a cantilever from the
printed bore: the plastic carries F over the length ``F / (sigma_allow d)``, sigma_allow across
the layers (it must fit in the plate), so the bending arm runs from the bearing's centre, across
the washer, to the middle of that length. Bending ``32 F a / (pi d^3)`` and shear
``4 F / (pi d^2)`` (von Mises with shear ``sqrt(3)``) must stay within the screw's yield over the
required safety factor.

**Hubs (A).** A steel hub (C45, :data:`HUB_YIELD_MPA`) per drive: a flange bolted to its link,
which it centres with a spigot in the link's bore at A, by six screws on the
largest bolt circle that keeps each hole :data:`EDGE_DISTANCE` diameters from the boss's edge,
and a boss that reaches through the cheek to the drive. Where the hub is bolted to a drive's
output flange, the hub goes on after the drive and the link after the hub's own screws, so the
link's screws come from the link's far face through clearance holes into threads tapped in the
hub's steel flange (:func:`hub_screws_through_link`); each shank bears on the printed plate,
``T / (6 r d t)``. Where a shaft drives the hub, hub and link are bolted together first and
slid onto the shaft, so the screws come from the hub's side into heat-set inserts pressed into
the link and nothing stands out of its far face (:func:`hub_screws`); the inserts carry the
torque in bearing on the printed plate, ``T / (6 r D L)``, D and L the insert's hole and
length; an ISO 4029 cup-point set screw through the hub's boss onto the shaft holds the hub
along it (:func:`set_screw`). Either bearing stress stays within the link material's
allowable. A shaft
output drives the hub through a DIN 6885 form A key (pressure ``2 T / (d (h - t1) (l - b))``
with ``h - t1 = 0.4 h`` in the hub and l the shaft's length in the hub, within the hub's yield
over the safety factor); a flange output is bolted to the hub's boss with its own pattern, the
heads counterbored into the hub's flange.

**Tool flange (E).** A steel adapter disc on the boss at E, held by one M8 screw through the
arm's tool hole, carries the smallest ISO 9409-1 pattern whose bolts carry the payload's peak
force F at its offset e from the face (config ``kit.tool_offset_m``): the most loaded bolt of n
on the circle of radius r takes ``2 F e / (n r) + F / n``, within its yield over the safety
factor (:func:`tool_flange`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from qsm.embodiment.kit import fasteners as fs
from qsm.embodiment.kit.interfaces import DriveInterface

if TYPE_CHECKING:
    from qsm.embodiment.strength.record import BearingLoad

#: Yield strength (MPa) of the hubs' and adapters' steel: C45+N, EN 10083-2 (d <= 16 mm).
HUB_YIELD_MPA = 340.0
#: Yield strength (MPa) of a made pin where no ISO 7379 screw fits: 42CrMo4+QT, EN 10083-3
#: (16 < d <= 40 mm).
PIN_YIELD_MPA = 750.0
#: Steps (mm) of the DIN 988 shim rings that close a pin's axial float (the rings come 0.1 mm
#: thick and up; DIN 988:1990): what float they leave is at most this.
SHIM_MM = 0.1
#: Screws joining a hub to its link.
HUB_SCREWS = 6
#: Thickness (mm) of a hub's flange.
FLANGE_MM = 8.0
#: Thickness (mm) of the tool flange's steel adapter disc (tapped for its M8 centre screw).
ADAPTER_MM = 16.0
#: Density (kg/m^3) of the turned steel parts and screws: EN 1993-1-1:2005, 3.2.6.
STEEL_KG_M3 = 7850.0
#: A hub's wall (mm) around a drive's shaft.
HUB_WALL_MM = 4.0
#: Distance, in hole diameters, from a hub screw's hole to the edge of the printed boss.
EDGE_DISTANCE = 2.0
#: ISO 9409-1 patterns, smallest first: (d1 pitch circle, d2 face, d3 recess, n, thread) mm.
#: Source: ISO 9409-1:2004 table 1 as transcribed in github.com/AndreNijman/softsense
#: (motor/interfaces/iso-9409-1.md), with robot makers' flanges (UR, Dobot, ABB, Kosmek) agreeing
#: for 31.5, 50 and 80; the 40 mm pattern's M6 as Robotiq's couplings (ISO 9409-1-40-4-M6) have it.
ISO9409 = (
    (31.5, 40.0, 20.0, 4, "M5"),
    (40.0, 50.0, 25.0, 4, "M6"),
    (50.0, 63.0, 31.5, 4, "M6"),
    (63.0, 80.0, 40.0, 6, "M6"),
    (80.0, 100.0, 50.0, 6, "M8"),
)


@dataclass(frozen=True)
class Plate:
    """A printed plate at a joint: the link's name, its thickness (mm), the material's
    allowable stress along the layers (MPa), the boss radius (mm) around the joint and the
    allowable of a load taken across the layers (MPa; default the in-plane one): the bearing
    pressure of a pin or a screw in its printed hole
    (:mod:`qsm.embodiment.strength.printed`)."""

    link: str
    thickness_mm: float
    allowable_MPa: float
    boss_mm: float
    across_MPa: float | None = None

    @property
    def bearing_allowable_MPa(self) -> float:
        """The allowable (MPa) of a pin's or a screw's bearing pressure in the plate."""
        return self.allowable_MPa if self.across_MPa is None else self.across_MPa


def pin(
    joint: str,
    bearing: BearingLoad,
    seat: Plate,
    other: Plate,
    required_sf: float,
    spacers: int = 1,
) -> dict[str, Any]:
    """The shoulder screw of ``joint`` through the ``bearing`` (``d_mm``, ``B_mm``,
    ``peak_force_N``), pressed flush with ``seat``'s face toward ``other``, ``spacers``
    washers and the bore of ``other``, and its check; the shoulder's length beyond the grip is
    filled with spacers, and the float they leave with DIN 988 shim rings to below
    :data:`SHIM_MM`."""
    d, force = float(bearing.d_mm), bearing.peak_force_N
    washer = _spacer(d)
    gap = spacers * washer[2]
    grip = seat.thickness_mm + gap + other.thickness_mm
    screw = fs.shoulder_screw(d, grip, f"pin of joint {joint}")
    thread = screw.thread if screw else _pin_thread(d)
    fill = int((screw.length_mm - grip) // washer[2]) if screw else 0
    float_mm = screw.length_mm - grip - fill * washer[2] if screw else 0.0
    shims = math.floor(float_mm / SHIM_MM + 1e-9) * SHIM_MM
    bore_mm = force / (other.bearing_allowable_MPa * d)  # printed length that carries F
    arm = float(bearing.B_mm) / 2 + gap + bore_mm / 2
    bending = 32 * force * arm / (math.pi * d**3)
    shear = 4 * force / (math.pi * d**2)
    von_mises = math.hypot(bending, math.sqrt(3) * shear)
    yield_mpa = fs.shoulder_yield_MPa(d) if screw else PIN_YIELD_MPA
    sf = yield_mpa / von_mises if von_mises > 0 else math.inf
    return {
        "joint": joint,
        "screw": screw.name if screw else None,
        "made": None if screw else f"pin {d:g} h8 x {math.ceil(grip):g} mm, {thread} end",
        "shoulder_d_mm": d,
        "grip_mm": grip,
        "spacer": f"ISO 7089 {washer[3]}",
        "spacers": spacers,
        "spacers_mm": gap,
        "fill_spacers": fill,
        "shims_mm": shims,
        "shim": f"DIN 988 shim rings {d:g} mm bore, {shims:.1f} mm in all" if shims else None,
        "axial_float_mm": float_mm - shims,
        "max_axial_float_mm": SHIM_MM,
        "nut": f"ISO 10511 {thread}",
        "peak_force_N": force,
        "bending_arm_mm": arm,
        "printed_bearing_length_mm": bore_mm,
        "bending_MPa": bending,
        "shear_MPa": shear,
        "yield_MPa": yield_mpa,
        "safety_factor": sf,
        "required_safety_factor": required_sf,
        "holds": sf >= required_sf and bore_mm <= other.thickness_mm,
        "plates": [seat.link, other.link],
    }


def _pin_thread(d_mm: float) -> str:
    """The largest thread of the nut table below a made pin's ``d_mm``."""
    threads = [r["thread"] for r in fs.table("iso10511")]
    return max((t for t in threads if float(t[1:]) < d_mm), key=lambda t: float(t[1:]))


def _spacer(shoulder_d_mm: float) -> tuple[float, float, float, str]:
    """The smallest ISO 7089 washer that slides over a shoulder of ``shoulder_d_mm``."""
    for row in fs.table("iso7089"):
        if float(row["inner_d_mm"]) >= shoulder_d_mm:
            return (*fs.washer_mm(row["thread"]), row["thread"])
    raise fs.FastenerError(f"no ISO 7089 washer over a {shoulder_d_mm:g} mm shoulder")


def hub_screws(plate: Plate, spigot_mm: float, torque_Nm: float) -> dict[str, Any]:
    """The smallest thread of six screws from the hub's side into heat-set inserts in
    ``plate`` (nothing stands out of its far face), on the largest bolt circle that keeps each
    insert's hole :data:`EDGE_DISTANCE` diameters from the edge of the boss (and clear of a
    spigot of ``spigot_mm``), whose inserts carry ``torque_Nm`` in bearing on the printed
    plate, ``T / (6 r D L)`` (D, L the insert's hole and length); the last tried when none does
    (``holds`` False)."""
    result: dict[str, Any] = {
        "thread": "",
        "pcd_mm": 0.0,
        "bearing_MPa": math.inf,
        "screw": None,
        "insert": None,
        "hole_mm": 0.0,
        "holds": False,
        "side": "hub",
    }
    for thread in fs.insert_threads():
        length, hole, name = fs.insert(thread)
        r = plate.boss_mm - EDGE_DISTANCE * hole
        if r - hole < spigot_mm / 2 + 2.0 or length > plate.thickness_mm - 1.0:
            break
        bearing = torque_Nm * 1e3 / (HUB_SCREWS * r * hole * length)
        grip = FLANGE_MM + fs.washer_mm(thread)[2]  # the hub's flange and the head's washer
        # the screw runs through its insert and on into the hole, short of the far face
        screw = fs.cap_screw(thread, grip, True, "hub to link", plate.thickness_mm - 1.0)
        if screw.standard != "ISO 4762" or length < fs.TAPPED_ENGAGEMENT * float(thread[1:]):
            continue
        result = {
            "thread": thread,
            "pcd_mm": 2 * r,
            "bearing_MPa": bearing,
            "screw": screw,
            "insert": name,
            "hole_mm": hole,
            "holds": bearing <= plate.bearing_allowable_MPa,
            "side": "hub",
        }
        if result["holds"]:
            break
    return result


def hub_screws_through_link(
    plate: Plate, spigot_mm: float, torque_Nm: float, tip_mm: float
) -> dict[str, Any]:
    """The smallest thread of six ISO 4762 screws from ``plate``'s far face through clearance
    holes (ISO 273 medium) into threads tapped through the hub's flange (:data:`FLANGE_MM`, at
    least 1.5 d of it), on the largest bolt circle that keeps each hole :data:`EDGE_DISTANCE`
    diameters from the edge of the boss (and clear of a spigot of ``spigot_mm``), whose shanks
    carry ``torque_Nm`` in bearing on the printed plate, ``T / (6 r d t)``; a screw's end stands
    at most ``tip_mm`` beyond the flange. The last tried when none holds (``holds`` False)."""
    result: dict[str, Any] = {"thread": "", "pcd_mm": 0.0, "bearing_MPa": math.inf,
                              "screw": None, "insert": None, "hole_mm": 0.0, "holds": False,
                              "side": "link"}  # fmt: skip
    for row in fs.table("iso4762"):
        thread, d = row["thread"], float(row["d_mm"])
        hole = fs.clearance_hole_mm(thread)
        r = plate.boss_mm - EDGE_DISTANCE * hole
        if r - hole < spigot_mm / 2 + 2.0 or fs.TAPPED_ENGAGEMENT * d > FLANGE_MM:
            break
        grip = plate.thickness_mm + fs.washer_mm(thread)[2]
        screw = fs.cap_screw(thread, grip, True, "link to hub", FLANGE_MM + tip_mm)
        if screw.standard != "ISO 4762":
            continue
        bearing = torque_Nm * 1e3 / (HUB_SCREWS * r * d * plate.thickness_mm)
        result |= {"thread": thread, "pcd_mm": 2 * r, "bearing_MPa": bearing, "screw": screw,
                   "hole_mm": hole, "holds": bearing <= plate.bearing_allowable_MPa}  # fmt: skip
        if result["holds"]:
            break
    return result


def set_screw() -> str:
    """The ISO 4029 cup-point set screw through a shaft hub's wall (:data:`HUB_WALL_MM`) onto
    the shaft: the largest thread the wall takes, M3 to M8, as long as the wall, so that it
    stands flush with the boss."""
    fits = [t for t in ("M3", "M4", "M5", "M6", "M8") if float(t[1:]) <= HUB_WALL_MM]
    thread = fits[-1] if fits else "M3"
    return f"ISO 4029 {thread} x {HUB_WALL_MM:g}"


def set_screw_z_mm(link_face_mm: float, toward: float, cheek_face_mm: float) -> float:
    """Where (z, mm) a shaft hub's set screw sits: halfway across the gap between the hub's
    flange (:data:`FLANGE_MM` from the link's face along ``toward``, the drive's side) and its
    cheek's inner face, where a key reaches it."""
    return (link_face_mm + toward * FLANGE_MM + cheek_face_mm) / 2


def hub_boss_mm(drive: DriveInterface) -> float:
    """The diameter (mm) of a hub's boss, which reaches through the cheek to the drive: around
    a shaft, the shaft and :data:`HUB_WALL_MM` each side; at a flange, its bolt circle and a
    head (the screws counterbored into the hub) and 2 mm."""
    if drive.output == "shaft":
        return drive.shaft_d_mm + 2 * HUB_WALL_MM
    return drive.flange_pcd_mm + fs.screw_head_mm(drive.flange_thread)[0] + 2.0


def hub(
    motor: int,
    drive: DriveInterface,
    plate: Plate,
    spigot_mm: float,
    torque_Nm: float,
    required_sf: float,
    boss_length_mm: float,
    screws: dict[str, Any],
) -> dict[str, Any]:
    """The hub of ``motor`` (1: lower arm, 2: crank) on ``drive``'s output: bolted to
    ``plate`` by ``screws`` (:func:`hub_screws`) around a spigot of ``spigot_mm`` in its bore,
    for the peak ``torque_Nm``, its boss ``boss_length_mm`` long to the drive's face. A shaft's
    key (DIN 6885 form A) bears over its engaged length less its width."""
    out: dict[str, Any] = {
        "motor": motor,
        "link": plate.link,
        "output": drive.output,
        "spigot_d_mm": spigot_mm,
        "boss_d_mm": hub_boss_mm(drive),
        "boss_length_mm": boss_length_mm,
        "torque_Nm": torque_Nm,
        "required_safety_factor": required_sf,
        "link_screws": {
            k: (v.name if isinstance(v, fs.Fastener) else v) for k, v in screws.items()
        },
    }
    holds = bool(screws["holds"])
    if drive.output == "shaft":
        w, h = drive.key_w_mm, drive.key_h_mm
        engaged = min(drive.shaft_length_mm, boss_length_mm + FLANGE_MM)
        bearing = max(engaged - w, 1e-9)  # form A: the rounded ends carry nothing
        pressure = 2 * torque_Nm * 1e3 / (drive.shaft_d_mm * 0.4 * h * bearing)
        out["key"] = {"w_mm": w, "h_mm": h, "length_mm": engaged, "pressure_MPa": pressure}
        out["key_safety_factor"] = HUB_YIELD_MPA / pressure
        out["set_screw"] = set_screw()
        out["retention"] = f"{out['set_screw']} cup point on the shaft's round, opposite the key"
        holds = holds and out["key_safety_factor"] >= required_sf
    else:
        out["flange"] = f"{drive.flange_bolts} x {drive.flange_thread} on {drive.flange_pcd_mm:g}"
        head_h = fs.screw_head_mm(drive.flange_thread)[1]
        grip = boss_length_mm + FLANGE_MM - head_h  # heads counterbored into the hub's flange
        out["flange_screw"] = fs.cap_screw(drive.flange_thread, grip, True, "").name
        out["retention"] = f"the {out['flange']} screws on the drive's output flange"
    out["holds"] = holds
    return out


def flange_mass_kg(face_d_mm: float, screw: fs.Fastener) -> float:
    """The mass (kg) the tool flange adds at E: its steel disc (``face_d_mm`` across,
    :data:`ADAPTER_MM` thick), its centre ``screw`` (head and shank as cylinders) and the washer
    under the head."""
    head_d, head_h = fs.screw_head_mm(screw.thread)
    inner, outer, washer_h = fs.washer_mm(screw.thread)
    volume_mm3 = (math.pi / 4) * (
        face_d_mm**2 * ADAPTER_MM
        + head_d**2 * head_h
        + screw.d_mm**2 * screw.length_mm
        + (outer**2 - inner**2) * washer_h
    )
    return volume_mm3 * 1e-9 * STEEL_KG_M3


#: What :func:`tool_flange` chooses by.
FLANGE_RULE = (
    "the smallest ISO 9409-1 pattern whose most loaded bolt, 2 F e / (n r) + F / n, and whose "
    "centre screw, F e / (d2 / 2) + F, stay within yield / the safety factor, and whose face "
    "fits the boss at E"
)


#: A chosen flange's figures in its record, in order.
_FLANGE_KEYS = (
    *("moving_mass_kg", "pattern", "pitch_circle_mm", "face_d_mm", "recess_d_mm", "bolts"),
    *("thread", "adapter_mm", "centre_screw", "payload_force_N", "offset_m", "bolt_force_N"),
    *("centre_screw_force_N", "safety_factor", "required_safety_factor"),
)


@dataclass(frozen=True)
class ToolFlange:
    """The tool flange at E (:func:`tool_flange`) for ``payload_force_N`` (N): its ISO 9409-1
    ``pattern`` (None: none holds and fits; ``tried``, the patterns tried), and for one that
    does its moving mass (kg), pitch circle, face and recess diameters (mm), bolts and thread,
    the adapter disc's thickness (mm), the centre screw, the payload's offset from the face (m),
    the most loaded bolt's and the centre screw's forces (N), and the safety factor against
    yield and the required one."""

    payload_force_N: float
    pattern: str | None = None
    tried: tuple[str, ...] = ()
    moving_mass_kg: float = 0.0
    pitch_circle_mm: float | None = None
    face_d_mm: float | None = None
    recess_d_mm: float | None = None
    bolts: int | None = None
    thread: str | None = None
    adapter_mm: float | None = None
    centre_screw: str | None = None
    offset_m: float = 0.0
    bolt_force_N: float | None = None
    centre_screw_force_N: float | None = None
    safety_factor: float | None = None
    required_safety_factor: float | None = None

    @property
    def holds(self) -> bool:
        """A pattern carries the force and fits the boss."""
        return self.pattern is not None

    def record(self) -> dict[str, Any]:
        """As JSON-ready values: a chosen flange's figures and its rule, else the patterns
        tried."""
        if not self.holds:
            tried = list(self.tried)
            return {"pattern": None, "tried": tried, "payload_force_N": self.payload_force_N,
                    "holds": False}  # fmt: skip
        return {k: getattr(self, k) for k in _FLANGE_KEYS} | {"holds": True, "rule": FLANGE_RULE}

    @classmethod
    def of(cls, data: Mapping[str, Any]) -> ToolFlange:
        """The flange :meth:`record` wrote."""
        kept = {k: v for k, v in data.items() if k not in ("holds", "rule")}
        return cls(**{**kept, "tried": tuple(data.get("tried", ()))})


def tool_flange(
    force_N: float, offset_m: float, boss_mm: float, plate_mm: float, required_sf: float
) -> ToolFlange:
    """The tool flange at E: a steel adapter disc (:data:`ADAPTER_MM` thick) held to the upper
    arm (``plate_mm`` thick) by one ISO 4762 M8 screw through the arm's tool hole into the disc,
    with the smallest ISO 9409-1 pattern (tapped) whose bolts carry ``force_N`` at ``offset_m``
    from the face and whose face fits the boss at E (radius ``boss_mm``). The centre screw takes
    the moment at the disc's joint with the arm, the disc's edge the pivot: ``F (e + t) / (d2 /
    2) + F``, t the disc's thickness."""
    moment = force_N * (offset_m * 1e3 + ADAPTER_MM)  # N mm, at the disc's joint with the arm
    tried = []
    for d1, d2, d3, n, thread in ISO9409:
        bolt = 2 * force_N * offset_m * 1e3 / (n * d1 / 2) + force_N / n
        centre = moment / (d2 / 2) + force_N
        sf = min(fs.screw_yield_N(thread) / bolt, fs.screw_yield_N("M8") / centre)
        tried.append(f"ISO 9409-1-{d1:g}-{n}-{thread}")
        if sf >= required_sf and d2 / 2 <= boss_mm:
            screw = fs.cap_screw(
                "M8", plate_mm + fs.washer_mm("M8")[2], True, "tool flange", ADAPTER_MM
            )
            return ToolFlange(
                payload_force_N=force_N, pattern=tried[-1],
                moving_mass_kg=flange_mass_kg(d2, screw), pitch_circle_mm=d1, face_d_mm=d2,
                recess_d_mm=d3, bolts=n, thread=thread, adapter_mm=ADAPTER_MM,
                centre_screw=screw.name, offset_m=offset_m, bolt_force_N=bolt,
                centre_screw_force_N=centre, safety_factor=sf, required_safety_factor=required_sf,
            )  # fmt: skip
    return ToolFlange(force_N, None, tuple(tried))
