"""A one-page datasheet of the realised design, as an industrial arm's reads: payload, reach and
task region, cycles per hour, accuracy and first mode, masses, drives, bearings, material, print
time and filament per part, and power. Every figure comes from this run's records
(``selected.json``, the bill of materials); what a record does not hold is not stated.

Print time is estimated by one rule, stated on the page: a part's volume (its printed mass over
the material's density) over :data:`PRINT_RATE_MM3_S`, a typical volumetric rate of a 0.4 mm
nozzle at 0.2 mm layers with solid infill, plus :data:`PRINT_SETUP_MIN` per part.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
import pandas as pd

from qsm.embodiment.drives.selection import drive_of

#: Volumetric printing rate (mm^3/s) of the print-time rule.
PRINT_RATE_MM3_S = 10.0
#: Setup time (min) per printed part of the print-time rule (heating, first layer).
PRINT_SETUP_MIN = 10.0


def _row(name: str, value: str) -> str:
    return f"| {name} | {value} |"


def _pair(values: Sequence[float], digits: int, unit: str) -> str:
    return " / ".join(f"{v:.{digits}f}" for v in values) + f" {unit} (motor 1 / motor 2)"


def printed_parts(bom: pd.DataFrame, density_kg_m3: float) -> pd.DataFrame:
    """Each printed part's filament mass (g), volume (cm^3) and estimated print time (h)."""
    parts = bom.loc[bom["category"] == "printed part"]
    volume_mm3 = parts["mass_kg"].to_numpy(float) / density_kg_m3 * 1e9
    hours = (volume_mm3 / PRINT_RATE_MM3_S + 60 * PRINT_SETUP_MIN) / 3600
    return pd.DataFrame(
        {
            "part": parts["item"].to_numpy(),
            "filament_g": parts["mass_kg"].to_numpy(float) * 1e3,
            "volume_cm3": volume_mm3 / 1e3,
            "print_time_h": hours,
            "box_mm": [
                f"{x:.0f} x {y:.0f} x {z:.0f}"
                for x, y, z in parts[["bbox_x_mm", "bbox_y_mm", "bbox_z_mm"]].to_numpy(float)
            ],
        }
    )


def _machine_rows(selected: Mapping[str, Any], parts: pd.DataFrame) -> list[str]:
    """Payload, reach, task region, masses, drives, bearings and material."""
    d = selected["design_m"]
    reach = d[0] + float(np.hypot(d[4], d[5]))
    points = np.asarray(selected["task"]["points_m"], dtype=float)
    motors = selected["drives"]["motors"]
    drives = [drive_of(m) for m in motors.values()]
    link_kg = float(parts["filament_g"].sum()) / 1e3
    drive_kg = sum(float(x["mass_kg"]) for x in drives)
    bearings = ", ".join(f"{j} {b['designation'] or 'none fits'}"
                         for j, b in selected["strength"]["bearings"].items())  # fmt: skip
    return [
        _row("payload", f"{selected['strength']['payload_kg']:g} kg at the tool (gripper "
             "included)"),
        _row("reach", f"{reach:.3f} m from the base joint A (lower arm and upper arm in line)"),
        _row("task", f"{len(points)} points, x {points[:, 0].min():.3f} to "
             f"{points[:, 0].max():.3f} m, y {points[:, 1].min():.3f} to "
             f"{points[:, 1].max():.3f} m"),
        _row("mass", f"{link_kg + drive_kg:.2f} kg: printed links {link_kg:.2f} kg, drives "
             f"{drive_kg:.2f} kg (bearings, pins and fasteners not counted)"),
        *(
            _row(f"drive {j}", f"{x['motor']} + {x['gearbox']} ({x['ratio']:g}:1, "
                 f"{x['mass_kg']:.2f} kg; backlash {x.get('backlash_arcmin', '-')} arcmin, "
                 f"{x.get('torsional_stiffness_Nm_rad', '-')} N m/rad)")
            for j, x in enumerate(drives, start=1)
        ),
        _row("bearings", bearings),
        _row("material", f"{selected['strength']['material']}, printed"),
    ]  # fmt: skip


def _performance_rows(selected: Mapping[str, Any]) -> list[str]:
    """Cycles per hour, accuracy, first mode and power."""
    rows = []
    cycle = selected.get("cycle")
    if cycle and not cycle["planned"]:
        rows.append(_row("cycles per hour", f"none: no cycle could be planned ({cycle['reason']})"))
    elif cycle:
        rows += [
            _row("cycles per hour", f"{cycle['cycles_per_hour']:.0f} on the task "
                 f"({cycle['cycle_time_s']:.2f} s per cycle, {cycle['dwell_s']:g} s dwell at each "
                 f"point; {'checks passed' if cycle['ok'] else 'FAILS a check, see summary.md'})"),
            _row("mechanical power", f"peak {_pair(cycle['peak_power_W'], 0, 'W')}, RMS "
                 f"{_pair(cycle['rms_power_W'], 0, 'W')}; {cycle['energy_per_cycle_J']:.0f} J "
                 f"per cycle at the joints"),
            _row("electrical power", "; ".join(
                f"motor {j}: " + (e if isinstance(e, str) else
                                  f"peak {e['peak_W']:.0f} W, RMS {e['rms_W']:.0f} W, "
                                  f"{e['energy_per_cycle_J']:.0f} J per cycle")
                for j, e in enumerate(cycle["electrical"], start=1))),
        ]  # fmt: skip
    budget = selected.get("stiffness")
    if budget:
        w = budget["worst"]
        track = w["tracking_error_mm"]
        rows += [
            _row("placing accuracy", f"{w['error_budget_mm']:.2f} mm worst at the task points "
                 f"(sag {max(w['sag_mm'], w['dynamic_sag_mm']):.2f} mm, lost motion "
                 f"{w['lost_motion_mm']:.2f} mm, tracking "
                 f"{'-' if track is None else f'{track:.2f}'} mm; "
                 f"tolerance {budget['tolerance_mm']:g} mm)"),
            _row("first mode", f"{w['first_mode_hz']:.1f} Hz (loaded, lowest at the task points)"),
        ]  # fmt: skip
    return rows


def datasheet_markdown(
    selected: Mapping[str, Any], bom: pd.DataFrame, density_kg_m3: float, verdict: str
) -> str:
    """The datasheet page (Markdown) of the realised design ``selected`` with its ``bom`` and
    the printed material's density (kg/m^3); ``verdict`` is the run's overall sentence."""
    parts = printed_parts(bom, density_kg_m3)
    table = [
        "| part | filament (g) | volume (cm3) | print time (h) | box (mm) |",
        "| --- | --- | --- | --- | --- |",
        *(
            f"| {r.part} | {r.filament_g:.0f} | {r.volume_cm3:.0f} | {r.print_time_h:.1f} | "
            f"{r.box_mm} |"
            for r in parts.itertuples()
        ),
    ]
    return "\n".join(
        [
            "# Datasheet of the realised design",
            "",
            f"**{verdict}**",
            "",
            "| | |",
            "| --- | --- |",
            *_machine_rows(selected, parts),
            *_performance_rows(selected),
            "",
            "## Printed parts",
            "",
            *table,
            "",
            f"Print time: the part's volume (printed mass / {density_kg_m3:g} kg/m3) at "
            f"{PRINT_RATE_MM3_S:g} mm3/s, plus {PRINT_SETUP_MIN:g} min per part (an estimate; "
            f"a slicer gives the printer's own).",
            "",
        ]
    )
