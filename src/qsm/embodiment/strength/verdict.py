"""A design's link strength as a record for outputs, and the verdict sentence that states it.

Every number comes from :class:`qsm.embodiment.strength.link_checks.StrengthCheck` run on the
design.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike

from qsm.embodiment.strength.link_checks import StrengthCheck
from qsm.embodiment.strength.sizing import SizedSections
from qsm.physics.kinematics import LINK_NAMES


def _finite(x: float) -> float | None:
    return float(x) if math.isfinite(x) else None


def _bearing_entry(row: pd.Series, joint: str, check: StrengthCheck) -> dict[str, Any]:
    """Joint ``joint``'s bearing in a design's strength row: its designation, peak force (N) and
    where (deg; at A the more loaded of the two links' bores), and the catalogue's figures."""
    name = str(row[f"bearing_{joint}"])
    column = "A_lower_arm" if joint == "A" else joint
    if joint == "A" and row["joint_force_peak_A_crank_N"] > row["joint_force_peak_A_lower_arm_N"]:
        column = "A_crank"
    force = float(row[f"joint_force_peak_{column}_N"])
    entry: dict[str, Any] = {
        "designation": name,
        "peak_force_N": force,
        "at_theta_deg": [
            float(row[f"joint_force_peak_{column}_theta1_deg"]),
            float(row[f"joint_force_peak_{column}_theta2_deg"]),
        ],
    }
    if name:
        table = check.bearings
        b = table.row(int(np.flatnonzero(table.designation == name)[0]))
        entry.update(
            d_mm=1e3 * b["d_m"],
            D_mm=1e3 * b["D_m"],
            B_mm=1e3 * b["B_m"],
            C_kN=b["C_N"] / 1e3,
            C0_kN=b["C0_N"] / 1e3,
            static_safety=b["C0_N"] / force if force > 0 else None,
            maker=b["maker"],
            source=b["source"],
        )
    return entry


def strength_record(
    design: ArrayLike, check: StrengthCheck, sized: SizedSections | None = None
) -> dict[str, Any]:
    """Per link: peak stress and allowable (MPa), safety factor and the required one, buckling
    factor (None: never compressed) and the required one, whether it holds; then the largest
    utilisation, the weakest link and check, and whether every link holds. ``sized``: the
    design's sections when not the check's own."""
    d = np.atleast_2d(np.asarray(design, dtype=float))
    row = check.evaluate_with_torques(d, sized)[0].iloc[0]
    allow = check.allowable_stress_pa / 1e6
    links = {}
    for link in LINK_NAMES:
        stress, buckling = float(row[f"stress_peak_{link}_MPa"]), row[f"buckling_factor_{link}"]
        links[link] = {
            "stress_peak_MPa": stress,
            "allowable_MPa": allow,
            "safety_factor": float(row[f"safety_factor_{link}"]),
            "required_safety_factor": check.strength.safety_factor,
            "buckling_factor": _finite(float(buckling)),
            "required_buckling_factor": check.strength.buckling_safety_factor,
            "holds": bool(
                stress <= allow * (1 + 1e-12)
                and buckling >= check.strength.buckling_safety_factor * (1 - 1e-12)
                and (bool(row["holds_loads"]) or str(row["weakest_link"]) != link)
            ),
            "width_mm": float(row[f"section_width_{link}_mm"]),
            "thickness_mm": float(row[f"section_thickness_{link}_mm"]),
        }
    bearings = {joint: _bearing_entry(row, joint, check) for joint in ("A", "B", "C", "D")}
    return {
        "links": links,
        "bearings": bearings,
        "required_bearing_safety": check.strength.bearing_safety_factor,
        "utilisation": float(row["strength_utilisation"]),
        "weakest_link": str(row["weakest_link"]),
        "weakest_check": str(row["weakest_check"]),
        "holds_loads": bool(row["holds_loads"]),
        "material": check.material.name,
        "payload_kg": check.payload_kg,
        "section": "fixed" if check.sizing is None else "sized",
        "section_iterations": int(row["section_iterations"]),
    }


def _text(x: float | None) -> str:
    return "-" if x is None else f"{x:.2f}"


def strength_verdict(record: Mapping[str, Any]) -> str:
    """One sentence: how the weakest link fares, in MPa or as a buckling factor."""
    link = record["weakest_link"]
    if link.startswith("bearing "):
        b = record["bearings"][link.split()[-1]]
        text = (
            f"the {link} ({b['designation'] or 'none fits'}) carries "
            f"{b['peak_force_N']:.0f} N, its static rating over that "
            f"{_text(b.get('static_safety'))} ({record['required_bearing_safety']:g} required)"
        )
        return f"{'weakest' if record['holds_loads'] else 'NOT STRONG ENOUGH'}: {text}"
    r = record["links"][link]
    name = link.replace("_", " ")
    if record["weakest_check"] == "buckling":
        factor = f"{r['buckling_factor']:.2f}" if r["buckling_factor"] is not None else "inf"
        text = (
            f"the {name}'s Euler load is {factor} x its peak compression "
            f"({r['required_buckling_factor']:g} required)"
        )
    else:
        required = r["required_safety_factor"]
        text = (
            f"the {name} reaches {r['stress_peak_MPa']:.1f} MPa, {r['allowable_MPa']:.1f} MPa "
            f"allowed (yield {r['allowable_MPa'] * required:.1f} MPa / {required:g}; safety "
            f"factor against yield {r['safety_factor']:.2f}) (at the {record['weakest_check']})"
        )
    if record["holds_loads"]:
        return f"weakest: {text}"
    return f"NOT STRONG ENOUGH: {text}"
