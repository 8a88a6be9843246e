"""``results/summary.md``: the headline numbers of a run, for reading without a browser."""

from __future__ import annotations

import math
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import pandas as pd

from qsm.prose import fixed
from qsm.report.accuracy_report import accuracy_lines
from qsm.report.cycle_report import cycle_lines
from qsm.report.drive_text import use_text
from qsm.report.headline_tables import (
    drive_failures,
    drive_rows,
    strength_rows,
    topology_rows,
)
from qsm.report.readiness import failures, verdict_lines, verdict_sentence


def _pct(x: float) -> str:
    return f"{100 * x:.1f} %"


def _drive_mass(kg: float | None) -> str:
    """The median drive mass in brackets, nothing when no design has drives (None)."""
    return f" ({kg:.2f} kg)" if kg is not None and math.isfinite(kg) else ""


def _ratio(counts: Mapping[str, Any]) -> float:
    return counts["hold_loads"] / counts["with_dynamics"] if counts["with_dynamics"] else 0.0


#: How the links' sections came about (the strength record's ``section``), in words.
SECTION_ORIGINS = {
    "fixed": "configured",
    "sized": "sized by strength",
    "grown": "the configured section grown for the tolerance",
    "sized and grown": "sized by strength, at least as large as the tolerance asks",
}


def _build_section(selected: Mapping[str, Any], topology: Mapping[str, Any], bom: str) -> list[str]:
    """The design to build: lengths (mm), link masses, bearings, drawing, parts and BOM."""
    names = ("l1", "l2", "l3", "l4", "EE_x", "EE_y")
    lengths = ", ".join(
        f"{n} {1e3 * v:.1f}" for n, v in zip(names, selected["design_m"], strict=True)
    )
    parts = topology["parts"]
    masses = ", ".join(f"{k} {v:.3f}" for k, v in parts["masses_kg"].items())
    sections = ", ".join(f"{k} {w:.1f} x {t:.1f}" for k, (w, t) in parts["section_mm"].items())
    how = SECTION_ORIGINS.get(selected["strength"].get("section"), "configured")
    bearings = "; ".join(
        f"{j} {b['designation'] or 'NONE FITS'} ({b['peak_force_N']:.0f} N peak at theta "
        f"{b['at_theta_deg'][0]:.0f} / {b['at_theta_deg'][1]:.0f} deg"
        + (f", C0 / F = {b['static_safety']:.1f})" if b.get("static_safety") else ")")
        for j, b in selected["strength"]["bearings"].items()
    )
    holes = ", ".join(f"{k} {v}" for k, v in parts["holes"].items())
    return [
        "## The design to build",
        f"- lengths (mm): {lengths}.",
        f"- the task disk keeps {1e3 * selected['clearance_m']:.2f} mm from the edge of the "
        "workspace (Euclidean clearance).",
        f"- link sections (width x thickness, mm; {how}): {sections}.",
        f"- printed link masses (kg, as built: the optimised plate with its bores; the topology "
        f"table's masses are the analysed plates, without bores): {masses}.",
        f"- bearings: {bearings}. The bearing at A sizes the links' bore there, which takes "
        "the hub's spigot; the drives' own output bearings carry joint A (the builder's kit).",
        "- through holes per printed link (its joint bores, and the openings the topology "
        f"optimisation left in an optimised plate): {holes}.",
        f"- drawing: {parts['drawing']['svg']} ({parts['drawing']['png']}); parts to print: "
        f"{Path(parts['bom']['csv']).parent}/stl/after/*.stl; bill of materials: "
        f"{parts['bom']['csv']}; the builder's kit: {Path(parts['bom']['csv']).parent}/kit/.",
        "- EE_x and EE_y place the end effector along and across the upper arm from B; the "
        "drawing shows E at (EE_x, -EE_y) in the upper arm's frame, whose y axis points away "
        "from E.",
        "",
        bom.rstrip(),
        "",
    ]


def _verdict_counts(findings: pd.DataFrame) -> str:
    """How many findings got each kind of verdict: agrees, reproduced under a condition, not
    reproduced, unexplained."""
    kinds = findings["verdict"].astype(str).str.split(":").str[0].str.strip()
    counts = kinds.value_counts()
    return ", ".join(f"{n} {kind}" for kind, n in counts.items())


def _mirror_lines(task: Mapping[str, Any]) -> list[str]:
    """The statement that the design is mirrored, with the user's points (none when not)."""
    if not task.get("mirrored"):
        return []
    points = ", ".join(f"({x:g}, {y:g})" for x, y in task["points_m"])
    return [f"**Mirrored:** your task points {points} m: {task['note']}.", ""]


def headline_markdown(
    filters: Mapping[str, Any],
    status: Mapping[str, Any],
    metrics: Mapping[str, Any],
    comparison: Mapping[str, Any],
    findings: pd.DataFrame,
    selected: Mapping[str, Any],
    torques: Mapping[str, Any],
    payload: Mapping[str, Any],
    topology: Mapping[str, Any],
    bom: str,
) -> str:
    """One page of Markdown with the overall verdict and the figures of every stage."""
    lines = [
        "# qsm-design: summary of this run",
        "",
        "**" + verdict_sentence(selected, topology, payload) + "**",
        "",
        *verdict_lines(failures(selected, topology, payload)),
        *_mirror_lines(selected.get("task", {})),
        *_build_section(selected, topology, bom),
        *accuracy_lines(selected.get("stiffness")),
        *cycle_lines(selected.get("cycle")),
        *_dataset_lines(filters, status, metrics),
        *_front_lines(comparison),
        "",
        "## Stage 5: design rules",
        f"- the paper's {len(findings)} findings: {_verdict_counts(findings)} "
        "(the table and each verdict's experiment: results/design_rules/summary.md).",
        "",
        *_realization_lines(selected, topology),
    ]
    for key in ("tau1_Nm", "tau2_Nm"):
        b, a = torques["before"][key], torques["after"][key]
        lines.append(
            f"- {key.removesuffix('_Nm')}: {fixed(b, 2)} -> {fixed(a, 2)} N m after topology "
            f"optimisation ({_pct((b - a) / b)} lower)."
        )
    lines.append(_payload_line(payload))
    return "\n".join(lines) + "\n"


def _dataset_lines(
    filters: Mapping[str, Any], status: Mapping[str, Any], metrics: Mapping[str, Any]
) -> list[str]:
    """The summary's Stages 1-3: the samples and filters, the dynamics, the surrogate."""
    r2 = metrics["test"]["r2"]
    return [
        "## Stage 1: mechanisms",
        f"- {filters['samples']:,} LHS samples; crank-rocker {filters['crank_rocker']:,}; loop "
        f"closes {filters['loop_closes']:,}; task fits {filters['task_fits']:,} of the first "
        f"{filters['task_fit_examined']:,} candidates examined; kept "
        f"{filters['selected']:,} of {filters['requested']:,} requested "
        f"(shortfall {filters['shortfall']}).",
        "",
        "## Stage 2: dynamics",
        f"- {status['mechanisms']:,} mechanisms, status "
        + ", ".join(f"{k} {v:,}" for k, v in status["status"].items())
        + ".",
        f"- {status['strength']['hold_loads']:,} of {status['strength']['with_dynamics']:,} "
        f"hold their loads ({_pct(_ratio(status['strength']))}); weakest link: "
        + ", ".join(f"{k} {v:,}" for k, v in status["strength"]["weakest_link"].items())
        + ".",
        *(
            [
                f"- {status['drives']['have_drives']:,} of "
                f"{status['drives']['with_dynamics']:,} have a drive in the catalogue for each "
                f"motor (motor 1: {status['drives']['motor1_has_drive']:,}, motor 2: "
                f"{status['drives']['motor2_has_drive']:,})."
            ]
            if "drives" in status
            else []
        ),
        "",
        "## Stage 3: surrogate",
        f"- test R^2 eta {r2['eta']:.4f}, tau1 {r2['tau1']:.4f}, tau2 {r2['tau2']:.4f} "
        f"(all {r2['all']:.4f}; paper 0.987); fit {metrics['fit_seconds']:.1f} s, on "
        f"{metrics['n_train']:,} training and {metrics['n_test']:,} test designs.",
        "- The surrogate's figures do not enter the verdict: the optimiser's fronts are verified "
        "and the realised design is checked against the true physics (MuJoCo, the strength, "
        "stiffness and drive checks).",
        "",
    ]


def _front_lines(comparison: Mapping[str, Any]) -> list[str]:
    """The summary's Stage 4: each front checked against the physics, a row each."""
    lines = [
        "## Stage 4: optimisation, checked against the physics",
        "| front | objectives | constraints | designs | truly hold the task | printable "
        "| links hold | have drives (median drive mass) | median error eta / tau1 / tau2 "
        "| true HV |",
        "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |",
    ]
    for name, e in comparison["fronts"].items():
        err = " / ".join(_pct(e["median_rel_error"][k]) for k in ("eta", "tau1", "tau2"))
        lines.append(
            f"| {name} | {', '.join(e.get('objectives', ['eta', 'tau1', 'tau2']))} "
            f"| {e['constraints']} | {e['n']} | {_pct(e['holds_task_share'])} "
            f"| {_pct(e['printable_share'])} | {_pct(e['holds_loads_share'])} "
            f"| {_pct(e.get('has_drives_share', float('nan')))}"
            f"{_drive_mass(e.get('median_drive_mass_kg'))} | {err} "
            f"| {e['true_hypervolume']:.3f} |"
        )
    return lines


def _realization_lines(selected: Mapping[str, Any], topology: Mapping[str, Any]) -> list[str]:
    """The summary's Stage 6: the selected design, its verdict, strength, drives and plates."""
    drives = selected.get("drives", {})
    return [
        "## Stage 6: realisation",
        f"- selected ({selected['selection_rule']}, from the {selected['source']}"
        f"{'' if selected['source'] == 'dataset' else ' front'}, "
        f"{selected['n_candidates']} candidates): l1 {selected['scale_m']:.3f} m, "
        f"as the optimiser's candidate (the configured section): eta "
        f"{selected['candidate']['eta_true']:.3f}, true peak torques "
        f"{selected['candidate']['tau1_true_Nm']:.1f} / "
        f"{selected['candidate']['tau2_true_Nm']:.1f} N m.",
        f"- verdict: {selected['verdict']}",
        *(f"- fell back past: {line}" for line in selected["fallback"]),
        "",
        f"Strength of the solid links ({selected['strength']['material']}, "
        f"{selected['strength']['payload_kg']:g} kg payload, over the duty):",
        "",
        "| link | peak stress (MPa) | allowable (MPa) | safety factor | buckling factor | holds |",
        "| --- | --- | --- | --- | --- | --- |",
        *strength_rows(selected["strength"]),
        "",
        f"Drives ({drives.get('rule', '')} of the catalogue that meet each "
        "motor's duty, reflected inertia included; margins 1 - utilisation):",
        "",
        "| motor | drive | ratio | mass (kg) | peak torque (N m) | RMS torque (N m) "
        "| peak speed (rad/s) | peak power (W) | margins |",
        "| --- | --- | --- | --- | --- | --- | --- | --- | --- |",
        *drive_rows(drives),
        *drive_failures(drives),
        "",
        "Topology-optimised plates (plane-stress FE of the printed plate):",
        "",
        "| link | mass (kg) | peak von Mises (MPa) | allowable (MPa) | printed part |",
        "| --- | --- | --- | --- | --- |",
        *topology_rows(topology),
        "",
    ]


def _payload_line(payload: Mapping[str, Any]) -> str:
    """The summary's line of the payload test: passed or why not, tracking error, torques and
    the limits they met (the drives' envelopes with each motor's peak use, or fixed limits)."""
    peak = ", ".join(fixed(v, 1) for v in payload["peak_torque_Nm"])
    limit = ", ".join(f"{v:.0f}" for v in payload["limit_Nm"])
    if payload.get("drives"):
        used = use_text(payload["peak_torque_over_available"])
        limits = (
            f"on the drives' torque-speed envelopes ({'; '.join(payload['drives'])}; "
            f"{limit} N m at standstill, peak use {used})"
        )
    else:
        limits = f"fixed limits {limit} N m"
    note = payload.get("drive_note")
    return (
        f"- payload test ({payload['payload_kg']:g} kg): "
        f"{'passed' if payload['passed'] else 'FAILED: ' + payload.get('reason', '')}, max "
        f"tracking error {fixed(payload['max_tracking_error_deg'], 3)} deg, peak torques {peak} "
        f"N m ({limits})." + (f" {note[0].upper()}{note[1:]}." if note else "")
    )
