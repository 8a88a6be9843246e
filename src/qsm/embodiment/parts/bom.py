"""Bill of materials of one design: printed links, bearings and pins per joint, motors, gearboxes.

One row per item kind and place (:data:`BOM_COLUMNS`). The motors and gearboxes rows are always
there (both motors sit at the base joint A: motor 1 turns theta1 and the lower arm, motor 2 turns
theta2 and the crank) and stay empty until a drive is chosen (pass ``drives``). Pins are steel
dowels of the bearing's bore through both plates of the joint (length: the sum of the two links'
thicknesses); at A the motor shafts take the place of pins, and each shaft runs in its own bearing
in the base (2 at A). Each printed part's thickness is its own section's
(:attr:`qsm.embodiment.parts.link_parts.LinkPart.section`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from qsm.embodiment.parts.bearings import JOINTS, BearingTable, load_catalogue
from qsm.embodiment.parts.link_parts import LinkPart
from qsm.physics.cad import MassProperties
from qsm.physics.kinematics import LINK_NAMES

BOM_COLUMNS: tuple[str, ...] = (
    "item",
    "category",
    "where",
    "quantity",
    "designation",
    "material",
    "mass_kg",
    "bbox_x_mm",
    "bbox_y_mm",
    "bbox_z_mm",
    "topology_optimised",
    "d_mm",
    "D_mm",
    "B_mm",
    "C_kN",
    "C0_kN",
    "maker",
    "source",
    "notes",
)
#: The bill's drive rows, filled with the chosen drives when given: (item, where).
DRIVE_ROWS: tuple[tuple[str, str], ...] = (
    ("motor 1", "A, theta1 (lower arm)"),
    ("gearbox 1", "A, theta1 (lower arm)"),
    ("motor 2", "A, theta2 (crank)"),
    ("gearbox 2", "A, theta2 (crank)"),
)


def bill_of_materials(
    parts: Mapping[str, LinkPart],
    masses: Mapping[str, MassProperties],
    bearing_index: Sequence[int],
    table: BearingTable | None = None,
    material: str = "ABS-M30",
    topology_optimized: Mapping[str, bool] | None = None,
    drives: Mapping[str, Mapping[str, Any]] | None = None,
    kit: Sequence[Mapping[str, Any]] | None = None,
) -> pd.DataFrame:
    """The BOM as a DataFrame with :data:`BOM_COLUMNS`.

    ``parts`` and ``masses`` of the links (:func:`qsm.embodiment.parts.link_parts.link_parts`,
    :func:`qsm.embodiment.parts.part_mass.part_mass_properties`, or the topology-optimised links'
    masses); ``bearing_index`` the catalogue rows at A, B, C, D (-1: none fits, the row says so);
    ``topology_optimised`` per link (default all False); ``drives`` optional values per drive
    item (``"motor 1"`` ...) for the columns ``designation``, ``maker``, ``mass_kg``, ``source``,
    ``notes``; ``kit`` the builder's kit's rows
    (:func:`qsm.realization.kit.builders_kit.builders_kit`), which bring the pins of B, C and D
    themselves and carry A on the drives' output bearings (no bearing at A).
    """
    t = table if table is not None else load_catalogue()
    topo = topology_optimized or {}
    rows = [
        _part_row(name, parts[name], masses[name], material, topo.get(name, False))
        for name in LINK_NAMES
    ]
    for joint, i in zip(JOINTS, np.asarray(bearing_index, dtype=int), strict=True):
        joint_rows = _joint_rows(joint, int(i), t, parts)
        if kit is not None:  # the kit's hubs and shoulder screws instead
            joint_rows = [
                r for r in joint_rows if r["item"] != "bearing A" and r["category"] != "pin"
            ]
        rows += joint_rows
    for item, where in DRIVE_ROWS:
        row = {"item": item, "category": item.split()[0], "where": where, "quantity": 1}
        row.update(dict((drives or {}).get(item, {})))
        rows.append(row)
    rows += [dict(r) for r in kit or ()]
    return pd.DataFrame(rows, columns=list(BOM_COLUMNS))


def _part_row(
    name: str, part: LinkPart, mass: MassProperties, material: str, optimized: bool
) -> dict[str, Any]:
    """The BOM row of the printed link ``name``: its mass (kg), box (mm) and bores."""
    x0, y0, x1, y1 = part.polygon.bounds
    bores = ", ".join(f"{b.joint} {b.kind} {1e3 * b.diameter_m:.1f} mm" for b in part.bores)
    return {
        "item": name,
        "category": "printed part",
        "where": name,
        "quantity": 1,
        "material": material,
        "mass_kg": float(mass.mass_kg),
        "bbox_x_mm": round(1e3 * (x1 - x0), 1),
        "bbox_y_mm": round(1e3 * (y1 - y0), 1),
        "bbox_z_mm": round(1e3 * part.section.thickness_m, 1),
        "topology_optimised": bool(optimized),
        "notes": f"printed flat (layers in the plate's plane); bores: {bores}",
    }


def _joint_rows(
    joint: str, i: int, t: BearingTable, parts: Mapping[str, LinkPart]
) -> list[dict[str, Any]]:
    """The BOM rows of a joint: its bearing (row ``i`` of ``t``; two at A, one per motor shaft;
    -1: none fits, and the row says so) and, at B, C and D, the pin through both plates."""
    count = 2 if joint == "A" else 1
    where = "A (one per motor shaft, in the base)" if joint == "A" else joint
    if i < 0:
        return [
            {
                "item": f"bearing {joint}",
                "category": "bearing",
                "where": where,
                "quantity": count,
                "notes": "no bearing of the catalogue carries the joint's peak load",
            }
        ]
    b = t.row(i)
    rows = [
        {
            "item": f"bearing {joint}",
            "category": "bearing",
            "where": where,
            "quantity": count,
            "designation": f"{b['maker']} {b['designation']}",
            "d_mm": 1e3 * b["d_m"],
            "D_mm": 1e3 * b["D_m"],
            "B_mm": 1e3 * b["B_m"],
            "C_kN": 1e-3 * b["C_N"],
            "C0_kN": 1e-3 * b["C0_N"],
            "maker": b["maker"],
            "source": b["source"],
            "notes": "deep groove ball bearing",
        }
    ]
    if joint != "A":
        d_mm = 1e3 * b["d_m"]
        length = 1e3 * sum(
            p.section.thickness_m for p in parts.values() if any(x.joint == joint for x in p.bores)
        )
        rows.append(
            {
                "item": f"pin {joint}",
                "category": "pin",
                "where": joint,
                "quantity": 1,
                "designation": f"dowel pin {d_mm:g} x {length:g} mm",
                "material": "steel",
                "d_mm": d_mm,
                "notes": "through both plates of the joint, held in the pin link",
            }
        )
    return rows


def _cell(value: Any) -> str:
    if value is None or (isinstance(value, float) and np.isnan(value)):
        return ""
    if isinstance(value, float):
        return f"{value:.4g}"
    text = str(value).replace("\r", " ").replace("\n", " ")
    return text.replace("\\", "\\\\").replace("|", "\\|")


def markdown_table(frame: pd.DataFrame, columns: Sequence[str] | None = None) -> str:
    """A GitHub-flavoured Markdown table of ``frame`` (``|`` in cells escaped, empty cells
    blank)."""
    cols = list(columns or frame.columns)
    lines = [
        "| " + " | ".join(_cell(c) for c in cols) + " |",
        "| " + " | ".join("---" for _ in cols) + " |",
    ]
    for _, row in frame.iterrows():
        lines.append("| " + " | ".join(_cell(row[c]) for c in cols) + " |")
    return "\n".join(lines) + "\n"


#: Columns of the summary's BOM table (the CSV has them all).
SUMMARY_COLUMNS: tuple[str, ...] = tuple(
    c for c in BOM_COLUMNS[: BOM_COLUMNS.index("topology_optimised") + 1] if c != "category"
)


def write_bom(frame: pd.DataFrame, directory: str | Path) -> tuple[Path, Path]:
    """Write ``bom.csv`` (every column, numbers to 10 significant digits) and ``bom.md``
    (:data:`SUMMARY_COLUMNS`) into ``directory``; returns both paths."""
    out = Path(directory)
    out.mkdir(parents=True, exist_ok=True)
    csv, md = out / "bom.csv", out / "bom.md"
    frame.to_csv(
        csv, index=False, float_format="%.10g"
    )  # no float noise: 0.6, not 0.6000000000000001
    md.write_text(markdown_table(frame, SUMMARY_COLUMNS))
    return csv, md
