"""The verdict sentence that states a design's strength, from its record as JSON
(:func:`qsm.embodiment.strength.record.strength_json`)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any


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
