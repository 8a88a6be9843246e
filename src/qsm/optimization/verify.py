"""Stage 4 check: re-evaluate optimised designs with the true Stages 1 and 2."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
import pandas as pd

from qsm.dataset.columns import DRIVE_COLUMNS, STIFFNESS_COLUMNS, STRENGTH_COLUMNS
from qsm.dataset.evaluation import with_embodiment
from qsm.embodiment.drives.drive_checks import DriveCheck
from qsm.embodiment.parts.printing import all_links_fit, needed_volume_mm, printability_violation_mm
from qsm.embodiment.stiffness.sag_check import SagCheck
from qsm.embodiment.strength.link_checks import StrengthCheck
from qsm.mechanisms.filters import kinematic_checks
from qsm.mechanisms.scale import FitSettings
from qsm.optimization.constraints import containment_margin_m
from qsm.physics.cad import CadSettings
from qsm.physics.clearance import disk_clearance_m
from qsm.physics.duty import Duty
from qsm.physics.dynamics import evaluate_mechanism
from qsm.physics.kinematics import RATIO_NAMES
from qsm.physics.task import Disk
from qsm.physics.workspace import slice_workspace
from qsm.surrogate.model import INPUTS

#: Circles through the task disk on which containment is verified (g11 uses 64).
VERIFY_RADII = 128

TRUE_COLUMNS: dict[str, str] = {
    "crank_rocker": "l3 + l2 < l1 + l4 (-)",
    "loop_closes": "the loop closes over the whole operating range (-)",
    "transmission_ok": "the transmission angle stays within filters.min_transmission_angle_deg (-)",
    "containment_margin_m": "smallest arc-length slack of the task disk in the workspace at this "
    "scale, on 128 of the disk's own circles with twice the delta samples of the "
    "optimisation (qsm.optimization.constraints; m, < 0: not held)",
    "task_contained": "the workspace at this scale holds the task disk: margin >= 0 (-)",
    "clearance_m": "Euclidean distance from the task disk to the nearest edge of the workspace at "
    "this scale (qsm.physics.clearance; m, < 0: not held); the arc-length margin above is an "
    "upper bound on it",
    "feasible": "all of the above (-)",
    "eta_true": "task-disk area / true workspace area at the design's scale (-)",
    "tau1_true_Nm": "peak |tau1| over the duty from the MuJoCo dynamics (N m)",
    "tau2_true_Nm": "peak |tau2| over the duty from the MuJoCo dynamics (N m)",
    "dynamics_status": "status of the dynamics (ok or the failure)",
    "mass_links_kg": "mass of the four links with their sections, payload excluded (kg)",
    "in_table1": "every ratio to l1 lies within sampling.bounds, where the data were sampled (-)",
    "printable": "every link's bounding box fits printing.build_volume_mm (-)",
    "print_excess_mm": "largest excess of a link's box over the build volume, <= 0 fits (mm)",
    **{
        f"needed_volume_{k}_mm": f"{k} side of the smallest build volume holding every link (mm)"
        for k in ("long", "mid", "short")
    },
    **STRENGTH_COLUMNS,
    **DRIVE_COLUMNS,
    **STIFFNESS_COLUMNS,
    "within_tolerance": "the tool's sag at every task point stays within task.tolerance_mm: g15 "
    "on the full task (-)",
}


def verify_design(
    design: np.ndarray,
    fit: FitSettings,
    duty: Duty,
    cad: CadSettings,
    payload_kg: float,
    scale: np.ndarray | None = None,
) -> dict[str, Any]:
    """True kinematics and dynamics of one design (6 lengths, m) at its own scale l1; ``scale``
    (4,): each link's section scale (sized sections)."""
    ratios = design[1:] / design[0]
    out: dict[str, Any] = {
        k: np.nan for k in TRUE_COLUMNS if k not in STRENGTH_COLUMNS and k not in DRIVE_COLUMNS
    }
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
        out["clearance_m"] = disk_clearance_m(design, fit.op, disk)
        out["task_contained"] = bool(margin >= 0)
        out["eta_true"] = disk.area / (slices.area * design[0] ** 2)
        dyn = evaluate_mechanism(design, duty, cad, payload_kg, scale)
        out["tau1_true_Nm"], out["tau2_true_Nm"] = dyn["tau1_Nm"], dyn["tau2_Nm"]
        out["mass_links_kg"] = sum(v for k, v in dyn.items() if k.startswith("mass_"))
        out["dynamics_status"] = dyn["status"]
    out["feasible"] = all(
        out[k] for k in ("crank_rocker", "loop_closes", "transmission_ok", "task_contained")
    )
    return out


def verify_front(
    pareto: pd.DataFrame,
    fit: FitSettings,
    check: StrengthCheck,
    ratio_bounds: Mapping[str, Sequence[float]],
    volume_mm: Sequence[float],
    drives: DriveCheck | None = None,
    sag: SagCheck | None = None,
) -> pd.DataFrame:
    """``pareto`` (lengths and predictions) with the true values beside the predictions, whether
    each design's ratios lie within ``ratio_bounds`` (Table 1, where the data were sampled),
    whether its links fit the printer ``volume_mm`` and whether they hold their loads over
    ``check``'s duty with its payload, section and material, and (with ``drives``) whether each
    motor has a drive in the catalogue, and (with ``sag``) the tool's sag at every task point
    (see :data:`TRUE_COLUMNS`)."""
    lengths = pareto[list(INPUTS)].to_numpy()
    cad, duty, payload_kg = check.cad, check.duty, check.payload_kg
    sized = check.section_scales(lengths)
    each = [None] * len(lengths) if sized is None else list(sized.scale)
    rows = [
        verify_design(d, fit, duty, cad, payload_kg, s) for d, s in zip(lengths, each, strict=True)
    ]
    true = pd.DataFrame(rows)
    true = with_embodiment(
        true.rename(columns={"dynamics_status": "status"}),
        lengths,
        check,
        drives or DriveCheck(cad=cad, payload_kg=payload_kg, duty=duty),
        sized,
    )
    true = true.rename(columns={"status": "dynamics_status"})
    table = pd.concat([pareto.reset_index(drop=True), true], axis=1)
    ratios = lengths[:, 1:] / lengths[:, :1]
    lo = np.array([ratio_bounds[n][0] for n in RATIO_NAMES])
    hi = np.array([ratio_bounds[n][1] for n in RATIO_NAMES])
    table["in_table1"] = np.all((ratios >= lo - 1e-12) & (ratios <= hi + 1e-12), axis=1)
    table["printable"] = [all_links_fit(d, cad, tuple(volume_mm)) for d in lengths]
    table["print_excess_mm"] = printability_violation_mm(lengths, cad, volume_mm)
    needed = needed_volume_mm(lengths, None, cad)
    for k, side in enumerate(("long", "mid", "short")):
        table[f"needed_volume_{side}_mm"] = needed[:, k]
    if sag is not None:
        table["tool_sag_mm"] = sag.sag_mm(lengths)  # g15's: the configured section
        table["within_tolerance"] = table["tool_sag_mm"] <= sag.tolerance_mm
    return table
