"""Standard fasteners of the kit, from the tables in ``data/`` (each file names its standard and
source): ISO 4762 socket head cap screws, ISO 7379 shoulder screws, ISO 7089 washers, ISO 10511
thin lock nuts and the ISO 2936 keys that turn them. A screw's length is the shortest preferred
length that spans its grip and, where it ends in a nut, the washer and the nut; where it ends in
a tapped hole, 1.5 d of engagement. Tightening torques follow VDI 2230-1:2015.
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from functools import cache
from pathlib import Path

DATA = Path(__file__).parent / "data"
#: Thread engagement of a screw in a tapped metal part, in diameters.
TAPPED_ENGAGEMENT = 1.5
#: Friction coefficient in the thread and under the head (VDI 2230-1:2015 table A5: steel,
#: zinc plated, dry or lightly oiled, 0.10-0.16).
FRICTION = 0.12
#: Share of the yield strength the tightening may use in the thread's combined stress (VDI
#: 2230-1:2015, nu = 0.9).
YIELD_SHARE = 0.9


#: ISO 273 medium-series clearance holes (mm) by thread.
CLEARANCE_HOLE_MM = {
    "M3": 3.4,
    "M4": 4.5,
    "M5": 5.5,
    "M6": 6.6,
    "M8": 9.0,
    "M10": 11.0,
    "M12": 13.5,
    "M16": 17.5,
}


#: Hexagon socket size s (mm) of ISO 4026-4029 set screws by thread: the FreeCAD Fasteners
#: Workbench data (github.com/shaise/FreeCAD_FastenersWB, FsData/iso4026def.csv at 918dc6a).
SET_SCREW_KEY_MM = {"M3": 1.5, "M4": 2.0, "M5": 2.5, "M6": 3.0, "M8": 4.0}


class FastenerError(ValueError):
    """No standard fastener fits (the message names the size and the grip)."""


@cache
def table(name: str) -> tuple[dict[str, str], ...]:
    """The rows of ``data/<name>.csv`` (comment lines starting with ``#`` skipped)."""
    with open(DATA / f"{name}.csv", newline="") as fh:
        return tuple(csv.DictReader(line for line in fh if not line.startswith("#")))


def _row(name: str, key: str, value: str) -> dict[str, str]:
    for row in table(name):
        if row[key] == value:
            return row
    raise FastenerError(f"{name}: no row with {key} = {value}")


@dataclass(frozen=True)
class Fastener:
    """One standard part: its ``standard`` (e.g. ``ISO 4762``), ``designation`` (e.g.
    ``M6 x 30``), thread, nominal diameter and length (mm; 0 for washers and nuts) and what it
    is for."""

    standard: str
    designation: str
    thread: str
    d_mm: float
    length_mm: float
    purpose: str

    @property
    def name(self) -> str:
        """The order line: standard, designation."""
        return f"{self.standard} {self.designation}"


def _preferred(lengths: str, needed_mm: float, what: str) -> float:
    """The shortest preferred length (mm) of the space-separated ``lengths`` >= ``needed_mm``."""
    for length in (float(x) for x in lengths.split()):
        if length >= needed_mm - 1e-9:
            return length
    raise FastenerError(f"{what}: no preferred length of at least {needed_mm:.1f} mm")


def washer_mm(thread: str) -> tuple[float, float, float]:
    """ISO 7089 washer of ``thread``: inner and outer diameter, thickness (mm)."""
    row = _row("iso7089", "thread", thread)
    return float(row["inner_d_mm"]), float(row["outer_d_mm"]), float(row["thickness_mm"])


def nut_height_mm(thread: str) -> float:
    """Height (mm) of the ISO 10511 thin lock nut of ``thread``."""
    return float(_row("iso10511", "thread", thread)["height_mm"])


def cap_screw(
    thread: str, grip_mm: float, tapped: bool, purpose: str, depth_mm: float | None = None
) -> Fastener:
    """The ISO 4762 screw of ``thread`` through a grip of ``grip_mm`` (washer under the head
    included by the caller), into a tapped hole (``tapped``: at least 1.5 d of thread, and no
    more than ``depth_mm`` where the tapped part is that thick) or through into a washer and
    nut. Where no preferred length fits: a DIN 976-1 threaded rod with a washer and nut at the
    head's end, in 5 mm steps, or cut to the tap's depth."""
    row = _row("iso4762", "thread", thread)
    d = float(row["d_mm"])
    nut_end = washer_mm(thread)[2] + nut_height_mm(thread) + 1
    tail = TAPPED_ENGAGEMENT * d if tapped else nut_end
    try:
        length = _preferred(row["lengths_mm"], grip_mm + tail, f"ISO 4762 {thread}")
        if tapped and depth_mm is not None and length > grip_mm + depth_mm:
            raise FastenerError(f"ISO 4762 {thread}: none within the {depth_mm:g} mm tap")
        return Fastener("ISO 4762", f"{thread} x {length:g}", thread, d, length, purpose)
    except FastenerError:
        length = 5 * math.ceil((grip_mm + tail + nut_end) / 5)
        if tapped and depth_mm is not None:
            length = min(length, round(grip_mm + depth_mm + nut_end, 1))
        return Fastener("DIN 976-1", f"{thread} x {length:g}", thread, d, length, purpose)


def clearance_hole_mm(thread: str) -> float:
    """ISO 273 medium clearance hole (mm) of ``thread``."""
    return CLEARANCE_HOLE_MM.get(thread, math.ceil(float(thread[1:]) * 1.1))


def screw_head_mm(thread: str) -> tuple[float, float]:
    """Head diameter and height (mm) of the ISO 4762 screw of ``thread``."""
    row = _row("iso4762", "thread", thread)
    return float(row["head_d_mm"]), float(row["head_h_mm"])


def screw_yield_N(thread: str) -> float:
    """Tensile force (N) at which the ISO 4762 class 8.8 screw of ``thread`` yields: As Rp0.2."""
    row = _row("iso4762", "thread", thread)
    return float(row["stress_area_mm2"]) * float(row["yield_MPa"])


def shoulder_screw(shoulder_d_mm: float, grip_mm: float, purpose: str) -> Fastener | None:
    """The ISO 7379 shoulder screw of shoulder ``shoulder_d_mm`` whose shoulder spans
    ``grip_mm``; None where the table has no such shoulder or no shoulder that long."""
    for row in table("iso7379"):
        if math.isclose(float(row["shoulder_d_mm"]), shoulder_d_mm):
            try:
                length = _preferred(row["lengths_mm"], grip_mm, "ISO 7379")
            except FastenerError:
                return None
            return Fastener(
                "ISO 7379",
                f"{shoulder_d_mm:g} x {length:g} - {row['thread']}",
                row["thread"],
                shoulder_d_mm,
                length,
                purpose,
            )
    return None


def shoulder_yield_MPa(shoulder_d_mm: float) -> float:
    """Yield strength (MPa) of the ISO 7379 screw's material (class 12.9)."""
    for row in table("iso7379"):
        if math.isclose(float(row["shoulder_d_mm"]), shoulder_d_mm):
            return float(row["yield_MPa"])
    return float(table("iso7379")[0]["yield_MPa"])


def shoulder_thread_mm(shoulder_d_mm: float) -> float:
    """Length (mm) of the ISO 7379 screw's thread beyond its shoulder."""
    return float(_row("iso7379", "shoulder_d_mm", f"{shoulder_d_mm:g}")["thread_length_mm"])


def shoulder_head_mm(shoulder_d_mm: float) -> tuple[float, float]:
    """Head diameter and height (mm) of the ISO 7379 screw of ``shoulder_d_mm``."""
    row = _row("iso7379", "shoulder_d_mm", f"{shoulder_d_mm:g}")
    return float(row["head_d_mm"]), float(row["head_h_mm"])


def insert(thread: str) -> tuple[float, float, str]:
    """The heat-set insert of ``thread``: length, hole diameter (mm) and designation."""
    row = _row("inserts", "thread", thread)
    return float(row["length_mm"]), float(row["hole_mm"]), row["designation"]


def key_hub_depth_mm(w_mm: float, h_mm: float) -> float:
    """The depth (mm) of the DIN 6885-1 keyway in a hub beyond its bore, for a ``w_mm`` x
    ``h_mm`` key."""
    for row in table("din6885"):
        if float(row["w_mm"]) == w_mm and float(row["h_mm"]) == h_mm:
            return float(row["t2_mm"])
    raise FastenerError(f"DIN 6885-1: no {w_mm:g} x {h_mm:g} key")


def insert_threads() -> list[str]:
    """The threads of the insert table, smallest first."""
    return [row["thread"] for row in table("inserts")]


def nut_across_corners_mm(thread: str) -> float:
    """Across corners (mm) of the ISO 10511 nut of ``thread``: its across flats / cos 30."""
    return float(_row("iso10511", "thread", thread)["across_flats_mm"]) / math.cos(math.pi / 6)


@dataclass(frozen=True)
class HexKey:
    """An ISO 2936 L-shaped hexagon key: its size across flats, long and short arm (mm)."""

    key_mm: float
    long_arm_mm: float
    short_arm_mm: float

    @property
    def name(self) -> str:
        """The order line."""
        return f"ISO 2936 hexagon key {self.key_mm:g} mm"


def hex_key(fastener: Fastener) -> HexKey:
    """The ISO 2936 key that turns ``fastener`` (an ISO 4762 cap screw, an ISO 4029 set screw,
    or an ISO 7379 shoulder screw by its shoulder); a DIN 976-1 rod's nut takes a spanner
    instead (FastenerError)."""
    if fastener.standard == "ISO 4762":
        size = _row("iso4762", "thread", fastener.thread)["key_mm"]
    elif fastener.standard == "ISO 4029":
        size = f"{SET_SCREW_KEY_MM[fastener.thread]:g}"
    elif fastener.standard == "ISO 7379":
        size = _row("iso7379", "shoulder_d_mm", f"{fastener.d_mm:g}")["key_mm"]
    else:
        raise FastenerError(f"{fastener.name} takes no hexagon key")
    row = _row("iso2936", "key_mm", size)
    return HexKey(float(size), float(row["long_arm_mm"]), float(row["short_arm_mm"]))


def tightening_torque_Nm(
    thread: str, hole_mm: float, clamp_limit_N: float = math.inf
) -> tuple[float, float]:
    """The tightening torque (N m) of the class 8.8 ISO 4762 screw of ``thread`` seated over a
    hole of ``hole_mm``, and its preload (N): the preload that uses :data:`YIELD_SHARE` of the
    yield strength under tension and the thread's torsion (VDI 2230-1:2015, R7), at most
    ``clamp_limit_N`` (what the clamped part bears, e.g. a printed plate under a washer), turned
    into a torque by ``F (0.16 P + 0.58 d2 mu + mu D_Km / 2)`` (R13) with :data:`FRICTION`."""
    row = _row("iso4762", "thread", thread)
    d, p = float(row["d_mm"]), float(row["pitch_mm"])
    d2, d3 = d - 0.64952 * p, d - 1.22687 * p
    d0, area = (d2 + d3) / 2, float(row["stress_area_mm2"])
    twist = 1.5 * d2 / d0 * (p / (math.pi * d2) + 1.155 * FRICTION)
    preload = YIELD_SHARE * float(row["yield_MPa"]) * area / math.sqrt(1 + 3 * twist**2)
    preload = min(preload, clamp_limit_N)
    bearing_d = (float(row["head_d_mm"]) + hole_mm) / 2
    torque = preload * (0.16 * p + 0.58 * d2 * FRICTION + FRICTION * bearing_d / 2) / 1e3
    return torque, preload
