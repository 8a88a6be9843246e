"""The parts to build for the realised design: bored links (topology-optimised where the printed
plate holds its loads, solid otherwise), their mass properties and a bill of materials."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
import shapely
from numpy.typing import ArrayLike

from qsm.embodiment.drives.report import DriveReport
from qsm.embodiment.parts.bearings import BearingTable
from qsm.embodiment.parts.bom import bill_of_materials, write_bom
from qsm.embodiment.parts.link_parts import LinkPart, PartSettings, link_parts
from qsm.embodiment.parts.part_mass import part_mass_properties
from qsm.embodiment.parts.part_outlines import hole_polygon
from qsm.physics.cad import MassProperties


def bearing_rows(designations: Mapping[str, str], table: BearingTable) -> list[int]:
    """Catalogue rows of the bearings at A, B, C, D (-1 where none fits: an empty name)."""
    rows = []
    for joint in ("A", "B", "C", "D"):
        name = designations[joint]
        rows.append(int(np.flatnonzero(table.designation == name)[0]) if name else -1)
    return rows


def final_parts(
    design: ArrayLike,
    bearing_index: list[int],
    settings: PartSettings,
    optimized: Mapping[str, shapely.Geometry],
) -> dict[str, LinkPart]:
    """The bored links of ``design``; a link in ``optimised`` takes that printed plate (link
    frame, m) with the same bores cut through it."""
    parts = link_parts(design, bearing_index, settings)
    for name, plate in optimized.items():
        seg = parts[name].section.segments_per_circle
        holes = shapely.union_all(
            [
                shapely.Polygon(hole_polygon(b.centre_m, b.diameter_m, seg))
                for b in parts[name].bores
                if b.diameter_m > 0
            ]
        )
        polygon = shapely.make_valid(plate.difference(holes))
        if not isinstance(polygon, shapely.Polygon):
            polygon = max(getattr(polygon, "geoms", [polygon]), key=lambda g: g.area)
        parts[name] = LinkPart(name, polygon, parts[name].bores, parts[name].section)
    return parts


def drive_rows(report: DriveReport | None) -> dict[str, dict[str, Any]]:
    """BOM values of the motor and gearbox rows from a drives report
    (:meth:`qsm.embodiment.drives.drive_checks.DriveCheck.report`; None: none): the drive each
    motor is built with (the nearest, marked, where none meets its duty). A gearbox named after
    its motor (an actuator's own stage) is built in: quantity 0."""
    rows: dict[str, dict[str, Any]] = {}
    motors = {} if report is None else report.motors
    for k, motor in enumerate(motors.values(), start=1):
        drive = motor.drive
        mark = "" if motor.has_drive else "NONE of the catalogue meets its duty: the nearest; "
        rows[f"motor {k}"] = {
            "designation": drive.motor,
            "mass_kg": drive.mass_kg,
            "notes": f"{mark}with {drive.gearbox}; mass of motor and gearbox together",
        }
        built_in = drive.gearbox.startswith(drive.motor)  # e.g. the AK80-6's own stage
        rows[f"gearbox {k}"] = {
            "designation": drive.gearbox,
            "notes": f"ratio {drive.ratio:.2f}:1"
            + (f"; built into {drive.motor}: not a part to buy" if built_in else ""),
        } | ({"quantity": 0} if built_in else {})
    return rows


def write_parts(
    parts: Mapping[str, LinkPart],
    bearing_index: list[int],
    settings: PartSettings,
    material: str,
    optimized: Mapping[str, bool],
    directory: str | Path,
    drives: DriveReport | None = None,
    kit: Sequence[Mapping[str, Any]] | None = None,
) -> dict[str, Any]:
    """Write the BOM (``bom.csv`` / ``bom.md``, with the motors and gearboxes of the ``drives``
    report and the builder's ``kit`` rows when given) into ``directory``; return its paths, the
    parts' hole counts and mass properties."""
    out = Path(directory)
    masses: dict[str, MassProperties] = part_mass_properties(parts)
    bom = bill_of_materials(
        parts,
        masses,
        bearing_index,
        settings.table,
        material,
        optimized,
        drive_rows(drives),
        kit,
    )
    csv, md = write_bom(bom, out)
    return {
        "bom": {"csv": str(csv), "md": str(md)},
        "masses": masses,
        "holes": {name: p.holes for name, p in parts.items()},
    }
