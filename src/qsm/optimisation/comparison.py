"""Stage 4 summaries of verified fronts (shares, prediction errors, true hypervolume) and their
comparison across formulations: tables only, no physics."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
import pandas as pd
from pymoo.indicators.hv import HV


def _share(mask: pd.Series) -> float:
    return float(mask.mean()) if len(mask) else float("nan")


def summary(table: pd.DataFrame) -> dict[str, Any]:
    """Shares of designs that truly hold the task, are feasible, are printable, whose links hold
    their loads, whose motors have drives in the catalogue (and all of these), and the relative
    errors of the predictions on the truly
    feasible ones."""
    ok = table["feasible"] & table["dynamics_status"].eq("ok")
    out: dict[str, Any] = {
        "n": len(table),
        "holds_task_share": _share(table["task_contained"].astype(bool)),
        "feasible_share": _share(table["feasible"].astype(bool)),
        "printable_share": _share(table["printable"].astype(bool)),
        "feasible_and_printable_share": _share(ok & table["printable"].astype(bool)),
        "holds_loads_share": _share(table["holds_loads"].astype(bool)),
        "feasible_printable_and_holds_share": _share(
            ok & table["printable"].astype(bool) & table["holds_loads"].astype(bool)
        ),
        "has_drives_share": _share(table["has_drives"].astype(bool))
        if "has_drives" in table
        else float("nan"),
        "feasible_printable_holds_and_drives_share": _share(
            ok
            & table["printable"].astype(bool)
            & table["holds_loads"].astype(bool)
            & table["has_drives"].astype(bool)
        )
        if "has_drives" in table
        else float("nan"),
        "in_table1_share": _share(table["in_table1"].astype(bool)),
        "n_feasible_with_dynamics": int(ok.sum()),
        "infeasible_reasons": {
            "crank_rocker": int((~table["crank_rocker"]).sum()),
            "loop_open": int((~table["loop_closes"]).sum()),
            "transmission_angle": int((table["loop_closes"] & ~table["transmission_ok"]).sum()),
            "task_not_contained": int((table["loop_closes"] & ~table["task_contained"]).sum()),
        },
        "median_rel_error": {},
        "max_rel_error": {},
    }
    for key, pred, true in [
        ("eta", "eta_pred", "eta_true"),
        ("tau1", "tau1_pred_Nm", "tau1_true_Nm"),
        ("tau2", "tau2_pred_Nm", "tau2_true_Nm"),
    ]:
        rel = (table.loc[ok, pred] - table.loc[ok, true]).abs() / table.loc[ok, true].abs()
        out["median_rel_error"][key] = float(rel.median()) if len(rel) else float("nan")
        out["max_rel_error"][key] = float(rel.max()) if len(rel) else float("nan")
    return out


def true_hypervolume(table: pd.DataFrame, lower: np.ndarray, upper: np.ndarray) -> float:
    """Hypervolume of the truly feasible designs' true (eta, tau1, tau2), normalised to
    [lower, upper] with reference point 1.1 in every objective (larger is better)."""
    ok = table["feasible"] & table["dynamics_status"].eq("ok")
    f = table.loc[ok, ["eta_true", "tau1_true_Nm", "tau2_true_Nm"]].to_numpy()
    if not len(f):
        return 0.0
    return float(HV(ref_point=np.full(3, 1.1))((f - lower) / (upper - lower)))


def compare(
    fronts: dict[str, pd.DataFrame],
    dataset: pd.DataFrame,
    primary: str,
    constraints: Mapping[str, str] | None = None,
) -> dict[str, Any]:
    """Each verified front's shares (task held, feasible, printable), prediction errors and true
    hypervolume; ``constraints`` labels each front's constraint set.

    The hypervolume uses one normalisation for all fronts: the range of the dataset's labels.
    """
    labels = dataset[["eta", "tau1_Nm", "tau2_Nm"]].to_numpy()
    lower, upper = labels.min(axis=0), labels.max(axis=0)
    out: dict[str, Any] = {"primary": primary, "fronts": {}}
    for name, table in fronts.items():
        entry = summary(table)
        entry["constraints"] = (constraints or {}).get(name, "")
        entry["true_hypervolume"] = true_hypervolume(table, lower, upper)
        out["fronts"][name] = entry
    return out


def comparison_markdown(result: dict[str, Any]) -> str:
    """The comparison as a short Markdown summary."""
    lines = [
        "| formulation | constraints | designs | truly hold the task | truly feasible "
        "| printable | feasible and printable | median rel. error eta / tau1 / tau2 "
        "| hypervolume of true values |",
        "| --- | --- | --- | --- | --- | --- | --- | --- | --- |",
    ]
    for name, e in result["fronts"].items():
        err = " / ".join(f"{100 * e['median_rel_error'][k]:.2f} %" for k in ("eta", "tau1", "tau2"))
        shares = " | ".join(
            f"{100 * e[k]:.0f} %" for k in ("holds_task_share", "feasible_share", "printable_share")
        )
        lines.append(
            f"| {name} | {e.get('constraints', '')} | {e['n']} | {shares} "
            f"| {100 * e['feasible_and_printable_share']:.0f} % | {err} "
            f"| {e['true_hypervolume']:.4f} |"
        )
    best = max(result["fronts"], key=lambda k: result["fronts"][k]["true_hypervolume"])
    lines += [
        "",
        f"The {best} formulation's front has the larger hypervolume on true values (objectives "
        "normalised by the dataset's label ranges, reference point 1.1; only truly feasible "
        "designs count). Errors are over the truly feasible designs whose dynamics succeeded. "
        f"The {result['primary']} front feeds the later stages (optimization.formulation).",
    ]
    return "\n".join(lines) + "\n"
