"""The study's physics runs: designs at a scale drawn apart from their ratios (the paper's Sobol box
varies the 6 scaled lengths independently, while every mechanism here sits at its minimal scale,
which ties l1 to the ratios and the task), and Table 3's torque reduction against the payload /
link-mass ratio with the links optimised in the run. :mod:`qsm.design_rules.study` analyses them.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from qsm.dataset.evaluation import evaluate_table
from qsm.physics.cad import CadSettings, MassProperties, mass_properties
from qsm.physics.duty import Duty
from qsm.physics.kinematics import DESIGN_NAMES, RATIO_NAMES, design_from_ratios
from qsm.realization.motion.torques import torques_before_after

#: Columns of results/study/independent_lengths.parquet and their units.
INDEPENDENT_COLUMNS: dict[str, str] = {
    "mechanism_id": "the dataset design whose ratios are used (-)",
    "scale_min_m": "its minimal scale (m)",
    "scale_m": "the scale drawn for the experiment, independent of the ratios (m)",
    **{f"{n}_m": "scaled length at the drawn scale (m)" for n in DESIGN_NAMES},
    "eta": "task-disk area / workspace area at the drawn scale (-)",
    "tau1_Nm": "peak |tau1| at the drawn scale (N m)",
    "tau2_Nm": "peak |tau2| at the drawn scale (N m)",
}


def independent_lengths(
    dataset: pd.DataFrame,
    n_designs: int,
    seed: int,
    duty: Duty,
    cad: CadSettings,
    payload_kg: float,
) -> pd.DataFrame:
    """Up to ``n_designs`` distinct dataset designs (ratios), each at a scale drawn uniformly over
    the dataset's scale range independently of its ratios, with the true eta and peak torques.

    Workspace area scales with the square of the scale, so eta at the drawn scale is the
    dataset's eta times (minimal scale / drawn scale)^2 (tested against the kinematics). Designs
    whose dynamics fail at the drawn scale (a link too short for its bosses) are dropped.
    """
    rng = np.random.default_rng(seed)
    distinct = dataset.drop_duplicates(subset=list(RATIO_NAMES)).sort_values("mechanism_id")
    rows = distinct.iloc[np.sort(rng.permutation(len(distinct))[:n_designs])]
    lo, hi = dataset["scale_m"].min(), dataset["scale_m"].max()
    scale = rng.uniform(lo, hi, len(rows))
    design = design_from_ratios(rows[list(RATIO_NAMES)].to_numpy(), scale)
    out = pd.DataFrame(design, columns=[f"{n}_m" for n in DESIGN_NAMES])
    out.insert(0, "scale_m", scale)
    out.insert(0, "scale_min_m", rows["scale_m"].to_numpy())
    out.insert(0, "mechanism_id", rows["mechanism_id"].to_numpy())
    out["eta"] = rows["eta"].to_numpy() * (out["scale_min_m"] / out["scale_m"]) ** 2
    dyn = evaluate_table(out, duty, cad, payload_kg, log_every=max(1, len(out) // 4))
    out["tau1_Nm"], out["tau2_Nm"] = dyn["tau1_Nm"].to_numpy(), dyn["tau2_Nm"].to_numpy()
    return out.loc[dyn["status"].to_numpy() == "ok"].reset_index(drop=True)[
        list(INDEPENDENT_COLUMNS)
    ]


def table3_sweep(
    design: NDArray[np.float64],
    cad: CadSettings,
    duty: Duty,
    optimized: dict[str, MassProperties],
    payloads_kg: list[float],
) -> pd.DataFrame:
    """Peak torques with the CAD links and with the optimised ones at each payload (kg), the
    reduction (%) and the payload / CAD-link mass ratio. The links stay as optimised in the run."""
    link_mass = sum(p.mass_kg for p in mass_properties(design, cad).values())
    rows = []
    for payload in payloads_kg:
        t = torques_before_after(design, cad, payload, duty, optimized)
        rows.append(
            {
                "payload_kg": payload,
                "link_mass_kg": link_mass,
                "payload_to_link_mass": payload / link_mass,
                **{f"{k}_before": v for k, v in t["before"].items()},
                **{f"{k}_after": v for k, v in t["after"].items()},
                "tau1_reduction_pct": -t["change"]["tau1_change_pct"],
                "tau2_reduction_pct": -t["change"]["tau2_change_pct"],
            }
        )
    return pd.DataFrame(rows)
