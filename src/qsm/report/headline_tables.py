"""The rows of the tables in ``results/summary.md`` (markdown): link strength (MPa), the drives
(N m, rad/s, W, kg) and the topology-optimised links (kg, MPa), from the run's JSON reports.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from qsm.embodiment.drives.report import drive_of
from qsm.report.drive_text import drive_sentences


def factor_text(x: float | None) -> str:
    """A factor with two decimals, "inf" for None (never loaded)."""
    return "inf" if x is None else f"{x:.2f}"


def strength_rows(strength: Mapping[str, Any]) -> list[str]:
    """One row per link of ``selected.json``'s ``strength``: stress, allowable (MPa), factors."""
    return [
        f"| {link} | {r['stress_peak_MPa']:.1f} | {r['allowable_MPa']:.1f} "
        f"| {r['safety_factor']:.2f} | {factor_text(r['buckling_factor'])} "
        f"| {'yes' if r['holds'] else 'NO'} |"
        for link, r in strength["links"].items()
    ]


def drive_rows(drives: Mapping[str, Any]) -> list[str]:
    """One row per motor of ``selected.json``'s ``drives``: the drive and what it must do."""
    rows = []
    for key, m in drives.get("motors", {}).items():
        d = drive_of(m)
        r = m["required"]
        margins = ", ".join(
            f"{k.replace('_', ' ')} {100 * v:.0f} %" for k, v in m["margins"].items()
        )
        rows.append(
            f"| {key.removeprefix('motor')} ({m['drives']}) | {d['motor']} + {d['gearbox']}"
            f"{'' if d['chosen'] else ' (NONE meets the duty: nearest)'} | {d['ratio']:.4g} "
            f"| {d['mass_kg']:.2f} | {r['peak_torque_Nm']:.1f} | {r['rms_torque_Nm']:.1f} "
            f"| {r['peak_speed_rad_s']:.2f} | {r['peak_power_W']:.0f} | {margins} |"
        )
    return rows


def drive_failures(drives: Mapping[str, Any]) -> list[str]:
    """A bullet per motor without a drive: by how much the nearest drive fails and what the
    strongest drive offers (:func:`qsm.report.drive_text.drive_sentences`)."""
    motors = drives.get("motors", {})
    if not motors:
        return []
    lines = drive_sentences(dict(drives))
    return [
        f"- {line}" for m, line in zip(motors.values(), lines, strict=True) if not m["has_drive"]
    ]


def topology_rows(topology: Mapping[str, Any]) -> list[str]:
    """One row per optimised link of ``topology.json``: mass (kg), peak and allowed stress."""
    rows = []
    for link, r in topology["links"].items():
        part = (
            "solid (no lighter plate held)"
            if r["kept_solid"]
            else (f"optimised, {100 * r['attempts'][-1]['volume_fraction']:.0f} % material kept")
        )
        rows.append(
            f"| {link} | {r['mass_before_kg']:.3f} -> {r['mass_after_kg']:.3f} "
            f"| {r['max_von_mises_after_MPa']:.1f} | {r['allowable_stress_MPa']:.1f} | {part} |"
        )
    return rows
