"""Stage 4 check: re-evaluate optimised designs with the true Stages 1 and 2."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
import pandas as pd
from pymoo.indicators.hv import HV

from qsm.mechanisms.filters import kinematic_checks
from qsm.mechanisms.scale import FitSettings
from qsm.optimisation.constraints import (
    containment_margin_m,
    printability_violation_mm,
    smallest_build_volume_mm,
)
from qsm.physics.cad import CadSettings
from qsm.physics.duty import Duty
from qsm.physics.dynamics import evaluate_mechanism
from qsm.physics.kinematics import RATIO_NAMES
from qsm.physics.task import Disk
from qsm.physics.workspace import slice_workspace
from qsm.realisation.printing import all_links_fit
from qsm.surrogate.model import INPUTS

#: Circles through the task disk on which containment is verified (g11 uses 64).
VERIFY_RADII = 128

TRUE_COLUMNS: dict[str, str] = {
    "crank_rocker": "l3 + l2 < l1 + l4 (-)",
    "loop_closes": "the loop closes over the whole operating range (-)",
    "transmission_ok": "the transmission angle stays within filters.min_transmission_angle_deg (-)",
    "containment_margin_m": "smallest arc-length slack of the task disk in the workspace at this "
    "scale, on 128 of the disk's own circles with twice the delta samples of the "
    "optimisation (qsm.optimisation.constraints; m, < 0: not held)",
    "task_contained": "the workspace at this scale holds the task disk: margin >= 0 (-)",
    "feasible": "all of the above (-)",
    "eta_true": "task-disk area / true workspace area at the design's scale (-)",
    "tau1_true_Nm": "peak |tau1| over the duty from the MuJoCo dynamics (N m)",
    "tau2_true_Nm": "peak |tau2| over the duty from the MuJoCo dynamics (N m)",
    "dynamics_status": "status of the dynamics (ok or the failure)",
    "in_table1": "every ratio to l1 lies within sampling.bounds, where the data were sampled (-)",
    "printable": "every link's bounding box fits printing.build_volume_mm (-)",
    "print_excess_mm": "largest excess of a link's box over the build volume, <= 0 fits (mm)",
    **{
        f"needed_volume_{k}_mm": f"{k} side of the smallest build volume holding every link (mm)"
        for k in ("long", "mid", "short")
    },
}


def verify_design(
    design: np.ndarray, fit: FitSettings, duty: Duty, cad: CadSettings, payload_kg: float
) -> dict[str, Any]:
    """True kinematics and dynamics of one design (6 lengths, m) at its own scale l1."""
    ratios = design[1:] / design[0]
    out: dict[str, Any] = dict.fromkeys(TRUE_COLUMNS, np.nan)
    checks = kinematic_checks(ratios, fit.op, fit.min_transmission_angle_deg)
    out.update({name: bool(ok[0]) for name, ok in checks.items()})
    out["task_contained"] = False
    out["dynamics_status"] = "not run: loop does not close"
    if out["loop_closes"]:
        disk = fit.disk
        slices = slice_workspace(ratios, fit.op, disk.angle, fit.resolution)
        inflated = Disk(disk.centre, disk.radius + fit.safety_margin)
        n_delta = 2 * fit.resolution.n_delta - 1  # twice as fine as the optimisation's g11
        margin = containment_margin_m(design, fit.op, inflated, n_delta, VERIFY_RADII)[0]
        out["containment_margin_m"] = float(margin)
        out["task_contained"] = bool(margin >= 0)
        out["eta_true"] = disk.area / (slices.area * design[0] ** 2)
        dyn = evaluate_mechanism(design, duty, cad, payload_kg)
        out["tau1_true_Nm"], out["tau2_true_Nm"] = dyn["tau1_Nm"], dyn["tau2_Nm"]
        out["dynamics_status"] = dyn["status"]
    out["feasible"] = all(
        out[k] for k in ("crank_rocker", "loop_closes", "transmission_ok", "task_contained")
    )
    return out


def verify_front(
    pareto: pd.DataFrame,
    fit: FitSettings,
    duty: Duty,
    cad: CadSettings,
    payload_kg: float,
    ratio_bounds: Mapping[str, Sequence[float]],
    volume_mm: Sequence[float],
) -> pd.DataFrame:
    """``pareto`` (lengths and predictions) with the true values beside the predictions, whether
    each design's ratios lie within ``ratio_bounds`` (Table 1, where the data were sampled) and
    whether its links fit the printer ``volume_mm`` (see :data:`TRUE_COLUMNS`)."""
    lengths = pareto[list(INPUTS)].to_numpy()
    rows = [verify_design(d, fit, duty, cad, payload_kg) for d in lengths]
    table = pd.concat([pareto.reset_index(drop=True), pd.DataFrame(rows)], axis=1)
    ratios = lengths[:, 1:] / lengths[:, :1]
    lo = np.array([ratio_bounds[n][0] for n in RATIO_NAMES])
    hi = np.array([ratio_bounds[n][1] for n in RATIO_NAMES])
    table["in_table1"] = np.all((ratios >= lo - 1e-12) & (ratios <= hi + 1e-12), axis=1)
    table["printable"] = [all_links_fit(d, cad, tuple(volume_mm)) for d in lengths]
    table["print_excess_mm"] = printability_violation_mm(lengths, cad, volume_mm)
    needed = smallest_build_volume_mm(lengths, cad)
    for k, side in enumerate(("long", "mid", "short")):
        table[f"needed_volume_{side}_mm"] = needed[:, k]
    return table


def _share(mask: pd.Series) -> float:
    return float(mask.mean()) if len(mask) else float("nan")


def summary(table: pd.DataFrame) -> dict[str, Any]:
    """Shares of designs that truly hold the task, are feasible, are printable (and both), and
    the relative errors of the predictions on the truly feasible ones."""
    ok = table["feasible"] & table["dynamics_status"].eq("ok")
    out: dict[str, Any] = {
        "n": len(table),
        "holds_task_share": _share(table["task_contained"].astype(bool)),
        "feasible_share": _share(table["feasible"].astype(bool)),
        "printable_share": _share(table["printable"].astype(bool)),
        "feasible_and_printable_share": _share(ok & table["printable"].astype(bool)),
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
