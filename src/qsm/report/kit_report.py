"""``summary.md``'s section on the builder's kit: its files, the arrangement, the base's and the
joints' checks with their numbers, what was assumed or not checked, and the assembly steps."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

#: The kit's files, relative to results/realization/kit.
KIT_FILES = (
    "kit.json (every part, check and fastener)",
    "step/*.step (one closed solid per part) and step/assembly.step (the arm assembled)",
    "dxf/*.dxf (every plate's outline with its holes and openings, mm)",
    "exploded.png (the exploded assembly view; its numbers are the steps below)",
)


def _cheek_rows(kit: Mapping[str, Any]) -> list[str]:
    rows = [
        "| cheek | drive | plate (mm) | height (mm) | root stress (MPa) | safety factor "
        "| tool error in the plane (mm) | tilt (mrad), its tool error (mm) | fixing |",
        "| --- | --- | --- | --- | --- | --- | --- | --- | --- |",
    ]
    for c in kit["base"]["cheeks"]:
        rows.append(
            f"| {c['motor']} | {c['drive']} | {c['width_mm']:g} x {c['thickness_mm']:g} "
            f"| {c['height_mm']:.0f} | {c['root_stress_MPa']:.1f} (yield {c['yield_MPa']:g}) "
            f"| {c['safety_factor']:.1f} ({c['required_safety_factor']:g} required) "
            f"| {c['tool_error_mm']:.3f} | {1e3 * c['tilt_rad']:.2f}, {c['tilt_error_mm']:.3f} "
            f"({c['allowed_tilt_error_mm']:.3f} allowed) | 3 x {c['fixing']['screw']} |"
        )
    return rows


def _joint_rows(kit: Mapping[str, Any]) -> list[str]:
    rows = ["| joint | part | load | safety factor |", "| --- | --- | --- | --- |"]
    for j, p in kit["pins"].items():
        rows.append(
            f"| {j} | {p['screw'] or p['made']} | {p['peak_force_N']:.0f} N "
            f"| {p['safety_factor']:.1f} ({p['required_safety_factor']:g} required) |"
        )
    for h in kit["hubs"]:
        s = h["link_screws"]
        text = (
            f"6 x {s['thread']} on {s['pcd_mm']:.0f} mm, {s['bearing_MPa']:.1f} MPa bearing"
            if s["thread"]
            else "no insert and screw fit the boss at A"
        )
        key = h.get("key_safety_factor")
        sf = f"key {key:.1f}" if key is not None else "the drive's flange pattern"
        rows.append(
            f"| A (hub {h['motor']}) | {text} | {h['torque_Nm']:.1f} N m (torque limit) | {sf} |"
        )
    f = kit["tool_flange"]
    if f.get("pattern"):
        rows.append(
            f"| E | {f['pattern']} | {f['payload_force_N']:.0f} N at {1e3 * f['offset_m']:g} mm "
            f"| {f['safety_factor']:.1f} ({f['required_safety_factor']:g} required) |"
        )
    return rows


def kit_markdown(kit: Mapping[str, Any]) -> str:
    """The section (Markdown)."""
    verdict = (
        "Every part of the kit holds."
        if kit["holds"]
        else ("THE KIT DOES NOT HOLD: " + "; ".join(kit["problems"]) + ".")
    )
    assumed = [f"{d['drive']}: {d['assumed']}" for d in kit["drives"] if d["assumed"]]
    sources = [f"{d['drive']}: {d['status']} ({d['source']})" for d in kit["drives"]]
    lines = [
        "## The builder's kit",
        "",
        verdict,
        "",
        "Files in results/realization/kit: " + "; ".join(KIT_FILES) + ".",
        "",
        "**Arrangement.** " + kit["base"]["arrangement"],
        "",
        f"**Base.** The links reach {kit['base']['links_lowest_mm']:.0f} mm below A over the "
        f"operating range; the cheeks are cut from {kit['base']['material']['name']} and move "
        f"the tool by {kit['base']['tool_error_mm']:.2f} mm in all, in the plane and from their "
        "tilt across their thickness (the accuracy budget's base term).",
        "",
        *_cheek_rows(kit),
        "",
        "**Joints.**",
        "",
        *_joint_rows(kit),
        "",
    ]
    if assumed:
        lines += [
            "**Assumed** (no maker's value in the catalogue): " + "; ".join(assumed) + ".",
            "",
        ]
    lines += ["**The drives' interfaces:** " + "; ".join(sources) + ".", ""]
    lines += ["**Not checked:** " + "; ".join(dict.fromkeys(kit["not_checked"])) + ".", ""]
    lines += ["### Assembly", ""]
    lines += [f"{k}. {step}" for k, step in enumerate(kit["assembly_steps"], 1)]
    return "\n".join(lines) + "\n"
