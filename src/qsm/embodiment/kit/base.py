"""The base: two cheeks that hold the drives coaxially at A, on a base plate fixed to a table.

**Arrangement.** Along the joint axis z, from drive 1 to drive 2: drive 1 bolted to the outer
face of cheek 1 | hub 1 | lower arm | upper arm | coupler | crank | hub 2 | cheek 2 with drive 2
on its outer face. Each pair of plates that share a joint lies side by side (B: lower and upper
arm, D: upper arm and coupler, C: coupler and crank), so no pin crosses a third plate and no
shaft crosses a link; the links swing between the cheeks. The cheeks stand on one base plate, as
tall as the links' lowest point over the operating range asks (plus :data:`CLEARANCE_MM`); the
plate has four M8 holes to fix it to a table. The cheeks and the plate are cut from aluminium
plate (:data:`ALUMINIUM`) from the DXF files.

**Check.** Each cheek is a cantilever from the base plate (height h, section b x t) under its
drive's share of the duty: the peak joint force F at A in any direction in the plane, the
drive's peak torque T reacted through its face, the drive's weight m g overhanging by c, and F
acting at the link's offset e from the cheek's mid-plane. At the root:
``sigma = 6 (F h + T) / (t b^2) + 6 (F e + m g c) / (b t^2) + (F + m g) / (b t)``, within the
plate's yield over the links' required safety factor; the thinnest plate of
:data:`PLATE_STOCK_MM` that holds and takes its three fixing screws (a thread of at most half its
thickness, tapped into its bottom edge) is taken. Its stiffness: the top's deflection in the
plane ``F h^3 / (3 E I) + T h^2 / (2 E I)`` and its turn about z ``(F h^2 / 2 + T h) / (E I)``, I =
t b^3 / 12, which moves the tool by the turn times the reach. Each cheek is made wide enough
that this stays within :data:`BASE_SHARE` of the tolerance, half of it each. Across its
thickness the moment ``F e + m g c`` tilts the top by ``M h / (E I)`` and moves it along the
axis by ``M h^2 / (2 E I)``, I = b t^3 / 12 (:func:`tilt`): the tool moves along the axis by
that move and the tilt times the reach, and in the plane by the tilt times its distance from
the cheek along the axis; their sum is held to :data:`TILT_SHARE` of the tolerance, half each,
by the cheek's thickness. The accuracy budget counts both cheeks' errors, in the plane and from
the tilt, as its ``base`` term (the move along the axis added as if it were in the plane: a
bound on the distance).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from qsm.embodiment.kit import fasteners as fs

#: Plate of the base: EN AW-6082 T651, EN 485-2:2016 (Rp0.2 >= 240 MPa for 12.5 < t <= 60 mm,
#: the lowest of its thickness ranges taken throughout); E and density: EN 1999-1-1, table 3.1.
ALUMINIUM = {
    "name": "EN AW-6082 T651 plate",
    "yield_MPa": 240.0,
    "E_MPa": 70000.0,
    "density_kg_m3": 2700.0,
    "source": "EN 485-2:2016 (Rp0.2); EN 1999-1-1:2007 table 3.1 (E, density)",
}
#: Plate thicknesses (mm) a cheek is cut from.
PLATE_STOCK_MM = (6.0, 8.0, 10.0, 12.0, 15.0, 20.0, 25.0, 30.0)
#: Thickness (mm) of the base plate.
BASE_PLATE_MM = 15.0
#: Share of the placing tolerance the base may take at the tool (both cheeks together).
BASE_SHARE = 0.02
#: Share of the placing tolerance the cheeks' tilt across their thickness may take at the tool
#: (both together): its move along the axis and, through the tool's offset along the axis from
#: the cheek, in the plane.
TILT_SHARE = 0.1
#: Least web (mm) a pocket leaves in a cheek under a drive's face.
MIN_WEB_MM = 6.0
#: Room (mm) between the links' lowest point and the base plate, and around each drive.
CLEARANCE_MM = 10.0
G = 9.81


@dataclass(frozen=True)
class CheekLoad:
    """One cheek's loads: peak joint force (N), peak drive torque (N m), drive mass (kg), and
    from the cheek's faces (mm): the drive's centre of mass outside, the link's mid-plane
    inside (c and e are these plus half the cheek's thickness)."""

    force_N: float
    torque_Nm: float
    drive_kg: float
    overhang_mm: float
    offset_mm: float


@dataclass(frozen=True)
class Pocket:
    """A pocket in a cheek's outer face about A: its diameter and depth (mm); none when 0."""

    d_mm: float = 0.0
    depth_mm: float = 0.0


def root_stress_MPa(load: CheekLoad, h: float, b: float, t: float) -> float:
    """The cheek's largest stress (MPa) at its root (module docs), h, b, t in mm."""
    w = load.drive_kg * G
    in_plane = 6 * (load.force_N * h + load.torque_Nm * 1e3) / (t * b**2)
    out_of_plane = 6 * out_of_plane_Nmm(load, t) / (b * t**2)
    return in_plane + out_of_plane + (load.force_N + w) / (b * t)


def out_of_plane_Nmm(load: CheekLoad, t: float) -> float:
    """The moment (N mm) about the cheek's root across its thickness ``t`` (mm): ``F e + m g
    c``."""
    e, c = load.offset_mm + t / 2, load.overhang_mm + t / 2
    return load.force_N * e + load.drive_kg * G * c


def top_motion(load: CheekLoad, h: float, b: float, t: float) -> tuple[float, float]:
    """The cheek top's deflection in the plane (mm) and its turn about z (rad)."""
    ei = ALUMINIUM["E_MPa"] * t * b**3 / 12  # N mm^2
    f, m = load.force_N, load.torque_Nm * 1e3
    return f * h**3 / (3 * ei) + m * h**2 / (2 * ei), (f * h**2 / 2 + m * h) / ei


def pocket_stress_MPa(load: CheekLoad, b: float, t: float, pocket: Pocket) -> float:
    """The cheek's largest stress (MPa) at its pocket's lowest edge, ``D / 2`` below A, on the
    two full-thickness strips beside the pocket (module docs); 0 without a pocket."""
    d = pocket.d_mm
    if pocket.depth_mm <= 0:
        return 0.0
    in_plane = (load.force_N * d / 2 + load.torque_Nm * 1e3) * 6 * b / (t * (b**3 - d**3))
    out_of_plane = 6 * out_of_plane_Nmm(load, t) / ((b - d) * t**2)
    return in_plane + out_of_plane + (load.force_N + load.drive_kg * G) / ((b - d) * t)


def tilt(
    load: CheekLoad, h: float, b: float, t: float, pocket: Pocket = Pocket()
) -> tuple[float, float]:
    """The cheek top's tilt across its thickness (rad) and its move along the axis (mm) under
    the moment ``F e + m g c`` (:func:`out_of_plane_Nmm`), the same over its height:
    ``M h / (E I)`` and ``M h^2 / (2 E I)``, I = b t^3 / 12; over a ``pocket``'s lower half
    (``D / 2`` below A) I is the strips' ``(b - D) t^3 / 12``."""
    m, e = out_of_plane_Nmm(load, t), ALUMINIUM["E_MPa"]
    curve = m / (e * b * t**3 / 12)
    angle, along = curve * h, curve * h**2 / 2
    if pocket.depth_mm > 0:
        extra = m / (e * (b - pocket.d_mm) * t**3 / 12) - curve
        band = min(pocket.d_mm / 2, h)
        angle, along = angle + extra * band, along + extra * band**2 / 2
    return angle, along


def cheek(
    load: CheekLoad,
    h: float,
    b: float,
    required_sf: float,
    reach: tuple[float, float],
    t: float,
    allow: tuple[float, float],
    pocket: Pocket = Pocket(),
) -> dict:
    """The cheek of thickness ``t`` (mm) at height ``h``: at least ``b`` wide (and the
    ``pocket`` and 10 mm each side), and as wide as keeps its tool error (deflection plus turn
    times the reach ``reach[0]``, mm) within ``allow[0]`` (mm); its stress under ``load`` (at
    the root and the pocket) against yield over ``required_sf``, its stiffness, and its tilt's
    error at the tool (the top's move along the axis, plus the tilt times the reach and times
    the tool's distance ``reach[1]`` (mm) from the cheek along the axis), against
    ``allow[1]``."""
    if pocket.depth_mm > 0:
        b = max(b, math.ceil(pocket.d_mm + 20.0))
    deflection, turn = top_motion(load, h, b, t)
    error = deflection + turn * reach[0]
    if error > allow[0]:  # both terms fall with b^3
        b = math.ceil(b * (error / allow[0]) ** (1 / 3))
        deflection, turn = top_motion(load, h, b, t)
    sigma = max(root_stress_MPa(load, h, b, t), pocket_stress_MPa(load, b, t, pocket))
    sf = ALUMINIUM["yield_MPa"] / sigma
    angle, along = tilt(load, h, b, t, pocket)
    tilted = along + angle * (reach[0] + reach[1])
    return {
        "thickness_mm": t,
        "width_mm": b,
        "height_mm": h,
        "root_stress_MPa": sigma,
        "yield_MPa": ALUMINIUM["yield_MPa"],
        "safety_factor": sf,
        "required_safety_factor": required_sf,
        "holds": sf >= required_sf,
        "deflection_at_A_mm": deflection,
        "turn_at_A_rad": turn,
        "tool_error_mm": deflection + turn * reach[0],
        "allowed_tool_error_mm": allow[0],
        "tilt_rad": angle,
        "top_along_axis_mm": along,
        "tilt_error_mm": tilted,
        "allowed_tilt_error_mm": allow[1],
        "pocket": {"d_mm": pocket.d_mm, "depth_mm": pocket.depth_mm, "web_mm": t - pocket.depth_mm},
        "loads": {
            "force_N": load.force_N,
            "torque_Nm": load.torque_Nm,
            "drive_kg": load.drive_kg,
            "overhang_mm": load.overhang_mm,
            "offset_mm": load.offset_mm,
        },
    }


def fixing_screws(load: CheekLoad, part: dict[str, Any], required_sf: float) -> dict:
    """The three screws of a cheek, at -s, 0 and s (s = b / 2 - 10 mm), through the base plate
    (and a washer) into the cheek's tapped bottom edge: the smallest thread of at most half the
    cheek's thickness whose most loaded screw, ``M_out / (3 t / 2) + M_in / (2 s)`` (moments
    at the root), stays within yield over ``required_sf``."""
    h, b, t = part["height_mm"], part["width_mm"], part["thickness_mm"]
    m_in = load.force_N * h + load.torque_Nm * 1e3
    force = out_of_plane_Nmm(load, t) / (3 * t / 2) + m_in / (b - 20)
    for thread in ("M5", "M6", "M8", "M10", "M12"):
        if float(thread[1:]) > t / 2:
            break
        sf = fs.screw_yield_N(thread) / force
        if sf >= required_sf:
            grip = BASE_PLATE_MM + fs.washer_mm(thread)[2]
            screw = fs.cap_screw(thread, grip, True, "cheek to base plate")
            return {
                "screw": screw.name,
                "count": 3,
                "force_N": force,
                "safety_factor": sf,
                "holds": True,
            }
    return {"screw": None, "count": 3, "force_N": force, "holds": False}


def lowest_point_mm(joints: dict[str, NDArray], radii: dict[str, dict[str, float]]) -> float:
    """How far (mm) below A the links reach: ``joints`` the positions (..., 2) m of A-E over the
    poses, ``radii`` each link's boss radius (mm) at its joints (a link lies in the hull of its
    bosses)."""
    low = 0.0
    for per_joint in radii.values():
        for joint, r in per_joint.items():
            y = np.asarray(joints[joint])[..., 1] * 1e3 - r
            low = max(low, float(-np.nanmin(y)))
    return low


def table_screws(
    loads: list[CheekLoad], h: float, size: tuple[float, float], required_sf: float
) -> dict:
    """The four M8 screws (ISO 4762) at the base plate's corners (``size``: width across and
    length along the axis, mm; holes 15 mm in) into the table: the most loaded takes the
    overturning moments of both cheeks' ``loads``, ``F (h + t) + T`` across the width and ``F e
    + m g c`` along the length, each on two screws."""
    width, length = size
    m_in = sum(x.force_N * (h + BASE_PLATE_MM) + x.torque_Nm * 1e3 for x in loads)
    m_out = sum(out_of_plane_Nmm(x, 0.0) for x in loads)
    force = m_in / (2 * (width - 30)) + m_out / (2 * (length - 30))
    sf = fs.screw_yield_N("M8") / force
    screw = fs.cap_screw("M8", BASE_PLATE_MM + fs.washer_mm("M8")[2], True, "base plate to table")
    return {
        "screw": screw.name,
        "count": 4,
        "force_N": force,
        "safety_factor": sf,
        "holds": sf >= required_sf,
    }
