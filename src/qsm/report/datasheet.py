"""A one-page datasheet of the realised design, as an industrial arm's reads: payload, reach and
task region, cycles per hour, accuracy and first mode, masses, drives, bearings, material, print
time and filament per part, and power. Every figure comes from this run's records
(``selected.json``, the bill of materials, the kit's hardware) or is computed from them (the
reach within the operating range); what a record does not hold is not stated.

Print time is estimated by one rule, stated on the page: a part's volume (its printed mass over
the material's density) over :data:`PRINT_RATE_MM3_S`, a typical volumetric rate of a 0.4 mm
nozzle at 0.2 mm layers with solid infill, plus :data:`PRINT_SETUP_MIN` per part.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
import pandas as pd

from qsm.embodiment.drives.report import drive_of
from qsm.physics.workspace import Reach
from qsm.prose import fixed
from qsm.realization.accuracy.accuracy_budget import term_phrases
from qsm.report.accuracy_report import stiffness_text
from qsm.report.cycle_report import cycle_problems, dwell_text, jerk_text

#: Volumetric printing rate (mm^3/s) of the print-time rule.
PRINT_RATE_MM3_S = 10.0
#: Setup time (min) per printed part of the print-time rule (heating, first layer).
PRINT_SETUP_MIN = 10.0


def _row(name: str, value: str) -> str:
    """A table row; a ``|`` in the value (a norm in a check's reason) escaped."""
    cell = value.replace("|", r"\|")
    return f"| {name} | {cell} |"


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


def _bom_masses_kg(bom: pd.DataFrame) -> dict[str, float]:
    """The BOM's weighed mass (kg, mass times quantity) by category, printed parts first; the
    rows without a mass (bearings, fasteners, inserts) are not in it."""
    weighed = bom.dropna(subset=["mass_kg"])
    kg = weighed["mass_kg"].astype(float) * weighed["quantity"].astype(float)
    return {str(k): float(v) for k, v in kg.groupby(weighed["category"], sort=False).sum().items()}


#: The BOM's categories whose parts move with the links: the printed links, the hubs on the
#: drives' outputs and the tool flange.
MOVING_CATEGORIES = ("printed part", "turned part")


def _mass_text(bom: pd.DataFrame, hardware_kg: tuple[float, float]) -> str:
    """The datasheet's mass line: the BOM's weighed parts, in total and by category, the
    bearings and fasteners (``hardware_kg``: all and those that move, weighed from their
    solids), and the moving mass."""
    by = _bom_masses_kg(bom)
    name = {"motor": "drives (motor and gearbox)"}
    parts = ", ".join(f"{name.get(k, k + 's')} {v:.2f} kg" for k, v in by.items())
    built = sum(by.values())
    hardware, moving_hw = hardware_kg
    moving = sum(by.get(k, 0.0) for k in MOVING_CATEGORIES) + moving_hw
    return (
        f"{built + hardware:.2f} kg in all: {built:.2f} kg as built ({parts}) and "
        f"{hardware:.2f} kg of bearings and fasteners, weighed from their solids in "
        f"assembly.step as steel; {moving:.2f} kg of it moves (the printed links, hubs and tool "
        f"flange, {moving_hw:.2f} kg of bearings and fasteners with them; the drives stand on "
        "the base), besides the payload"
    )


def _bearings_text(bom: pd.DataFrame) -> str:
    """The bearings as built, from the BOM: each joint's, and A's carried by the drives."""
    rows = bom.loc[bom["category"] == "bearing"]
    built = ", ".join(f"{w} {d}" for w, d in zip(rows["where"], rows["designation"], strict=True))
    return f"{built or 'none'}; A: the drives' output bearings"


def _reach_text(reach: Reach) -> str:
    """The datasheet's reach line: within the operating range, beside the arm in line."""
    return (
        f"{reach.reach_m:.3f} m from the base joint A within the operating range (at theta1 - "
        f"theta2 = {np.degrees(reach.delta_rad):.0f} deg; {reach.in_line_m:.3f} m with the "
        "lower and upper arm in line, outside it)"
        if reach.reach_m < reach.in_line_m - 5e-4
        else f"{reach.reach_m:.3f} m from the base joint A (lower arm and upper arm in line)"
    ) + "; figures/envelope.png draws the envelope"


def _machine_rows(
    selected: Mapping[str, Any], bom: pd.DataFrame, reach: Reach, hardware_kg: tuple[float, float]
) -> list[str]:
    """Payload, reach, task region, masses, drives, bearings and material."""
    points = np.asarray(selected["task"]["points_m"], dtype=float)
    motors = selected["drives"]["motors"]
    drives = [drive_of(m) for m in motors.values()]
    return [
        _row("payload", f"{selected['strength']['payload_kg']:g} kg at the tool (gripper "
             f"included), on a {selected['tool_flange_kg']:.3f} kg tool flange "
             f"({selected['tool_flange'].get('pattern') or 'none fits'})"),
        _row("reach", _reach_text(reach)),
        _row("task", f"{len(points)} points, x {points[:, 0].min():.3f} to "
             f"{points[:, 0].max():.3f} m, y {points[:, 1].min():.3f} to "
             f"{points[:, 1].max():.3f} m"),
        _row("mass", _mass_text(bom, hardware_kg)),
        *(
            _row(f"drive {j}", f"{x['motor']} + {x['gearbox']} ({x['ratio']:g}:1, "
                 f"{x['mass_kg']:.2f} kg; backlash {x.get('backlash_arcmin', '-')} arcmin, "
                 f"{stiffness_text(x)} N m/rad)")
            for j, x in enumerate(drives, start=1)
        ),
        _row("torque limits", _pair(selected["torque_limits_Nm"], 1, "N m") + " at the joints: "
             "each controller keeps its drive within it; the kit is sized for it, the cycle "
             "planned within it"),
        _row("bearings", _bearings_text(bom)),
        _row("material", f"{selected['strength']['material']}, printed"),
    ]  # fmt: skip


def _cycle_checks(cycle: Mapping[str, Any]) -> str:
    """What the cycle's own checks (the links' strength, the drives' heat, MuJoCo's run) say:
    that they pass, with the drives' thermal use, or what fails, with its numbers."""
    if cycle["ok"]:
        use = cycle.get("thermal_use")
        heat = f", thermal use {' / '.join(f'{u:.2f}' for u in use)}" if use else ""
        return f"the cycle's strength, heat and simulation checks pass{heat}"
    return "the cycle fails: " + "; ".join(cycle_problems(dict(cycle)))


def _performance_rows(selected: Mapping[str, Any]) -> list[str]:
    """Cycles per hour, accuracy, first mode and power."""
    rows = []
    cycle = selected.get("cycle")
    if cycle and not cycle["planned"]:
        rows.append(_row("cycles per hour", f"none: no cycle could be planned ({cycle['reason']})"))
    elif cycle:
        rows += [
            _row("cycles per hour", f"{cycle['cycles_per_hour']:,.0f} on the task "
                 f"({cycle['cycle_time_s']:.2f} s per cycle, {dwell_text(cycle)}, "
                 f"{jerk_text(cycle.get('jerk'))}; {_cycle_checks(cycle)})"),
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
        per = budget["per_point"]
        i = int(np.argmax(per["error_budget_mm"]))  # the worst point's own terms
        rows += [
            _row("placing error", f"{fixed(per['error_budget_mm'][i], 2)} mm worst, at task point "
                 f"{i + 1} ({', '.join(term_phrases(per, i))}; "
                 f"tolerance {budget['tolerance_mm']:g} mm)"),
            _row("first mode", f"{w['first_mode_hz']:.1f} Hz (loaded, lowest at the task points)"),
        ]  # fmt: skip
    return (
        rows + _iso_rows(selected.get("iso9283")) + _standard_rows(selected.get("standard_cycle"))
    )


def _standard_payload(c: Mapping[str, Any]) -> str:
    """One payload's standard cycle: its time, what its checks say and what slowed it."""
    if not c["planned"]:
        return f"at {c['payload_kg']:g} kg none could be planned ({c['reason']})"
    failed = [
        *([] if c["links_hold"] else [f"links at {c['strength_utilisation']:.2f} of strength"]),
        *([] if c["thermal_ok"] is not False else ["the drives' heat"]),
        *([] if c["simulation_passed"] else [c["simulation_reason"]]),
    ]
    checks = "its checks pass" if c["ok"] else "FAILS its checks: " + "; ".join(failed)
    slowed = (
        f"; its moves slowed {c['slowed_by']:g}x (the dwells kept) from the time-optimal "
        f"{c['time_optimal_s']:.2f} s for " + "; ".join(c["slowed_for"])
        if c["slowed_by"] > 1
        else ""
    )
    return f"{c['cycle_time_s']:.2f} s at {c['payload_kg']:g} kg ({checks}{slowed})"


def _standard_rows(std: Mapping[str, Any] | None) -> list[str]:
    """The standard pick-and-place cycle at each payload, and where it runs."""
    if std is None:
        return []
    if not std["planned"]:
        return [_row("standard cycle (25 / 305 / 25 mm)", f"none: {std['reason']}")]
    (x0, y0), (x1, _) = std["corners_m"][0], std["corners_m"][3]
    stroke = (
        f"a {std['stroke_mm']:.0f} mm stroke, the longest the arm makes (305 mm is the standard's)"
        if std["scaled"]
        else "the 305 mm stroke"
    )
    return [
        _row(f"standard cycle (25 / {std['stroke_mm']:.0f} / 25 mm)",
             "; ".join(_standard_payload(c) for c in std["payloads"])
             + f". Up {std['rise_mm']:.0f} mm, across, down and back, time-optimal from rest to "
             f"rest without dwell; {stroke} at y = {y0:.3f} m from x = {x0:.3f} to {x1:.3f} m, "
             "centred on the task disk, the rises vertical"),
    ]  # fmt: skip


def _iso_rows(iso: Mapping[str, Any] | None) -> list[str]:
    """ISO 9283 pose accuracy and repeatability: the worst point's, its terms, the plane."""
    if not iso:
        return []
    if not iso["simulated"]:
        return [
            _row("pose accuracy and repeatability (ISO 9283)", f"not simulated: {iso['reason']}")
        ]
    ap, rp = np.asarray(iso["ap_mm"]), np.asarray(iso["rp_mm"])
    i, k = int(np.argmax(ap)), iso["worst_point"] - 1
    side = 1e3 * iso["plane_side_m"]
    cx, cy = iso["plane_centre_m"]
    alone = iso["rp_alone_mm"]
    terms = ", ".join(
        f"{t} {v[k]:.3f} mm" for t, v in sorted(alone.items(), key=lambda x: -x[1][k])
    )
    required = iso["repeatability_mm"]
    check = (
        ""
        if required is None
        else (f"; {required:g} mm required: {'met' if iso['meets_repeatability'] else 'NOT met'}")
    )
    plane = (
        f"at the rated {iso['payload_kg']:g} kg (on the {iso['tool_flange_kg']:.3f} kg tool "
        f"flange), {iso['cycles']} cycles simulated at the five points of a "
        f"{side:.0f} x {side:.0f} mm square centred at ({cx:.3f}, {cy:.3f}) m in the arm's plane "
        "(the standard's test cube has no depth for a planar arm)"
    )
    return [
        _row("pose accuracy AP (ISO 9283)", f"{ap[i]:.2f} mm worst, at P{i + 1} (static sag "
             f"{iso['static_sag_mm'][i]:.2f} mm, base {iso['base_mm'][i]:.2f} mm along it, and the "
             f"{iso['cycles']} cycles' mean random error, {iso['random_mean_mm'][i]:.2f} mm in "
             "its own direction); "
             f"{iso['compensated_ap_mm'][i]:.2f} mm left once the controller takes out the "
             f"modelled static sag, which teaching the points removes too; {_aged(iso, i)}"
             f"{plane}"),
        _row("pose repeatability RP (ISO 9283)", f"±{rp[k]:.3f} mm worst, at P{k + 1} (main "
             f"random term {iso['main_random_term']}; each alone: {terms}{_uncounted(iso)})"
             f"{check}"),
    ]  # fmt: skip


def _aged(iso: Mapping[str, Any], i: int) -> str:
    """AP at point ``i`` once the printed links have crept over their service time."""
    if not iso.get("service_time_h"):
        return ""
    return (
        f"{iso['service_ap_mm'][i]:.2f} mm after {iso['service_time_h']:g} h of holding its "
        f"loads, as the printed links creep ({iso['creep_mm'][i]:.2f} mm of drift, by the "
        "assumed creep law of printed_material.creep); "
    )


def _uncounted(iso: Mapping[str, Any]) -> str:
    """Why a random term adds nothing to RP: its sources' words, once per distinct one."""
    zero = [t for t, v in iso["rp_alone_mm"].items() if max(v) < 1e-6]  # below 1 nm: none
    why = [f"{t}: {' / '.join(dict.fromkeys(iso['sources'][t]))}" for t in zero]
    return "".join(f"; {w}" for w in why)


def datasheet_markdown(
    selected: Mapping[str, Any],
    bom: pd.DataFrame,
    density_kg_m3: float,
    verdict: tuple[str, list[str]],
    reach: Reach,
    hardware_kg: tuple[float, float],
) -> str:
    """The datasheet page (Markdown) of the realised design ``selected`` with its ``bom`` and
    the printed material's density (kg/m^3); ``verdict`` is the run's overall sentence and the
    lines of what fails (:mod:`qsm.report.readiness`),
    ``reach`` the tool's within the operating range
    (:func:`qsm.physics.workspace.operating_reach`) and ``hardware_kg`` the bearings' and
    fasteners' mass, all and moving (:func:`qsm.realization.kit.kit_hardware.mass_kg`,
    :func:`~qsm.realization.kit.kit_hardware.moving_mass_kg`)."""
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
            f"**{verdict[0]}**",
            "",
            *verdict[1],
            "| quantity | value |",
            "| --- | --- |",
            *_machine_rows(selected, bom, reach, hardware_kg),
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
