"""``results/summary.md``: the headline numbers of a run, for reading without a browser."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import pandas as pd


def _pct(x: float) -> str:
    return f"{100 * x:.1f} %"


def headline_markdown(
    filters: Mapping[str, Any],
    status: Mapping[str, Any],
    metrics: Mapping[str, Any],
    comparison: Mapping[str, Any],
    findings: pd.DataFrame,
    selected: Mapping[str, Any],
    torques: Mapping[str, Any],
    payload: Mapping[str, Any],
) -> str:
    """One page of Markdown with the figures of every stage."""
    r2 = metrics["test"]["r2"]
    lines = [
        "# qsm-design: summary of this run",
        "",
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
        "",
        "## Stage 3: surrogate",
        f"- test R^2 eta {r2['eta']:.4f}, tau1 {r2['tau1']:.4f}, tau2 {r2['tau2']:.4f} "
        f"(all {r2['all']:.4f}; paper 0.98700); fit {metrics['fit_seconds']:.1f} s.",
        "",
        "## Stage 4: optimisation, checked against the physics",
        "| front | constraints | designs | truly hold the task | printable "
        "| median error eta / tau1 / tau2 | true HV |",
        "| --- | --- | --- | --- | --- | --- | --- |",
    ]
    for name, e in comparison["fronts"].items():
        err = " / ".join(_pct(e["median_rel_error"][k]) for k in ("eta", "tau1", "tau2"))
        lines.append(
            f"| {name} | {e['constraints']} | {e['n']} | {_pct(e['holds_task_share'])} "
            f"| {_pct(e['printable_share'])} | {err} | {e['true_hypervolume']:.3f} |"
        )
    agree = int((findings["agree"] == "agree").sum())
    lines += [
        "",
        "## Stage 5: design rules",
        f"- {agree} of {len(findings)} of the paper's findings agree "
        "(results/design_rules/summary.md).",
        "",
        "## Stage 6: realisation",
        f"- selected ({selected['selection_rule']}, from the {selected['source']}"
        f"{'' if selected['source'] == 'dataset' else ' front'}, "
        f"{selected['n_candidates']} candidates): l1 {selected['scale_m']:.3f} m, "
        f"eta {selected['eta_true']:.3f}, true peak torques {selected['tau1_true_Nm']:.1f} / "
        f"{selected['tau2_true_Nm']:.1f} N m.",
        f"- verdict: {selected['verdict']}",
        *(f"- fell back past: {line}" for line in selected["fallback"]),
    ]
    for key in ("tau1_Nm", "tau2_Nm"):
        b, a = torques["before"][key], torques["after"][key]
        lines.append(
            f"- {key.removesuffix('_Nm')}: {b:.2f} -> {a:.2f} N m after topology optimisation "
            f"({_pct((b - a) / b)} lower)."
        )
    peak = ", ".join(f"{v:.1f}" for v in payload["peak_torque_Nm"])
    limit = ", ".join(f"{v:.0f}" for v in payload["limit_Nm"])
    lines.append(
        f"- payload test ({payload['payload_kg']:g} kg): "
        f"{'passed' if payload['passed'] else 'FAILED'}, max tracking error "
        f"{payload['max_tracking_error_deg']:.3f} deg, peak torques {peak} N m "
        f"(limits {limit} N m)."
    )
    return "\n".join(lines) + "\n"
