"""Stage 4 summaries of verified fronts (shares, prediction errors, true hypervolume) and their
comparison across formulations: tables only, no physics."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
import pandas as pd
from pymoo.indicators.hv import HV

from qsm.optimization.ranking import OBJECTIVE_SETS, Objective, objectives_of


def _share(mask: pd.Series) -> float:
    return float(mask.mean()) if len(mask) else float("nan")


def summary(table: pd.DataFrame) -> dict[str, Any]:
    """Shares of designs that truly hold the task, are feasible, are printable, whose links hold
    their loads, whose motors have drives in the catalogue (and all of these), the median true
    drive mass (kg) of the designs with drives, the objectives the front was optimised on, and
    the relative errors of the predictions on the truly feasible ones."""
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
        "within_tolerance_share": _share(table["within_tolerance"].astype(bool))
        if "within_tolerance" in table
        else float("nan"),
        **_median_drive_mass(table),
        "objectives": [o.name for o in objectives_of(table)],
        "in_table1_share": _share(table["in_table1"].astype(bool)),
        "n_feasible_with_dynamics": int(ok.sum()),
        "infeasible_reasons": {
            "crank_rocker": int((~table["crank_rocker"]).sum()),
            "loop_open": int((~table["loop_closes"]).sum()),
            "transmission_angle": int((table["loop_closes"] & ~table["transmission_ok"]).sum()),
            "task_not_contained": int((table["loop_closes"] & ~table["task_contained"]).sum()),
        },
        "median_rel_error": {},
        "p90_rel_error": {},
        "max_rel_error": {},
    }
    for key, pred, true in ((o.name, o.predicted, o.true) for o in OBJECTIVE_SETS["torques"]):
        rel = (table.loc[ok, pred] - table.loc[ok, true]).abs() / table.loc[ok, true].abs()
        out["median_rel_error"][key] = float(rel.median()) if len(rel) else float("nan")
        out["p90_rel_error"][key] = float(rel.quantile(0.9)) if len(rel) else float("nan")
        out["max_rel_error"][key] = float(rel.max()) if len(rel) else float("nan")
    return out


def _median_drive_mass(table: pd.DataFrame) -> dict[str, Any]:
    """``median_drive_mass_kg`` of the designs with drives; None, with a
    ``median_drive_mass_note`` saying why, when there is none."""
    if "has_drives" not in table:
        return {"median_drive_mass_kg": None, "median_drive_mass_note": "no drive check ran"}
    mass = table.loc[table["has_drives"].fillna(False).astype(bool), "drive_mass_kg"]
    if not len(mass):
        note = f"none of the {len(table)} designs has a drive for each motor in the catalogue"
        return {"median_drive_mass_kg": None, "median_drive_mass_note": note}
    return {"median_drive_mass_kg": float(mass.median())}


def drive_mass_text(kg: float | None) -> str:
    """A median drive mass for a table: kg, or "none" when no design has drives."""
    return "none" if kg is None or not np.isfinite(kg) else f"{kg:.2f} kg"


def true_hypervolume(
    table: pd.DataFrame,
    dataset: pd.DataFrame,
    objectives: tuple[Objective, ...] = OBJECTIVE_SETS["torques"],
) -> float:
    """Hypervolume of the truly feasible designs' true ``objectives`` (default eta, tau1, tau2;
    with the drive mass, only designs with drives count), each normalised by the range of its
    column in ``dataset`` (span 1 where it is constant), with reference point 1.1 in every
    objective (larger is better)."""
    ok = table["feasible"].astype(bool) & table["dynamics_status"].eq("ok")
    if any(o.true == "drive_mass_kg" for o in objectives):
        ok &= table["has_drives"].fillna(False).astype(bool)
    labels = dataset[[o.dataset for o in objectives]].to_numpy(float)
    lower, upper = np.nanmin(labels, axis=0), np.nanmax(labels, axis=0)
    span = np.where(upper > lower, upper - lower, 1.0)  # a constant column: span 1
    f = table.loc[ok, [o.true for o in objectives]].to_numpy(float)
    if not len(f):
        return 0.0
    return float(HV(ref_point=np.full(len(objectives), 1.1))((f - lower) / span))


def compare(
    fronts: dict[str, pd.DataFrame],
    dataset: pd.DataFrame,
    primary: str,
    constraints: Mapping[str, str] | None = None,
) -> dict[str, Any]:
    """Each verified front's shares (task held, feasible, printable, drives), prediction errors
    and true hypervolumes, on (eta, tau1, tau2) and, where the tables have drives, on (eta,
    drive mass); ``constraints`` labels each front's constraint set.

    The hypervolumes use one normalisation for all fronts: the range of the dataset's labels.
    """
    out: dict[str, Any] = {"primary": primary, "fronts": {}}
    for name, table in fronts.items():
        entry = summary(table)
        entry["constraints"] = (constraints or {}).get(name, "")
        entry["true_hypervolume"] = true_hypervolume(table, dataset)
        entry["true_hypervolume_drive_mass"] = (
            true_hypervolume(table, dataset, OBJECTIVE_SETS["drive_mass"])
            if "has_drives" in table
            else float("nan")
        )
        out["fronts"][name] = entry
    return out


def comparison_markdown(result: dict[str, Any]) -> str:
    """The comparison as a short Markdown summary."""
    lines = [
        "| formulation | objectives | constraints | designs | truly hold the task "
        "| truly feasible | printable | feasible and printable | have drives "
        "| median drive mass | median rel. error eta / tau1 / tau2 "
        "| hypervolume of true eta, tau1, tau2 | hypervolume of true eta, drive mass |",
        "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |",
    ]
    for name, e in result["fronts"].items():
        err = " / ".join(f"{100 * e['median_rel_error'][k]:.2f} %" for k in ("eta", "tau1", "tau2"))
        shares = " | ".join(
            f"{100 * e[k]:.0f} %" for k in ("holds_task_share", "feasible_share", "printable_share")
        )
        mass = drive_mass_text(e["median_drive_mass_kg"])
        lines.append(
            f"| {name} | {', '.join(e['objectives'])} | {e.get('constraints', '')} | {e['n']} "
            f"| {shares} | {100 * e['feasible_and_printable_share']:.0f} % "
            f"| {100 * e['has_drives_share']:.0f} % | {mass} | {err} "
            f"| {e['true_hypervolume']:.4f} | {e['true_hypervolume_drive_mass']:.4f} |"
        )
    best = max(result["fronts"], key=lambda k: result["fronts"][k]["true_hypervolume"])
    lines += [
        "",
        f"The {best} formulation's front has the larger hypervolume on true eta, tau1, tau2 "
        "(objectives normalised by the dataset's label ranges, reference point 1.1; only truly "
        "feasible designs count, and for the drive mass only those with drives). The drive mass "
        "is the median over the designs with drives. Errors are over the truly feasible designs "
        "whose dynamics succeeded. "
        f"The {result['primary']} front feeds the later stages (optimization.formulation).",
    ]
    return "\n".join(lines) + "\n"
