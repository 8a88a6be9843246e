"""Experiments that test why this run's design rules differ from the paper's (Section 4, Table 3).

* :func:`independent_lengths`: the paper's Sobol box varies the 6 scaled lengths independently,
  while every mechanism here sits at its minimal scale, which ties l1 to the ratios and the task.
  The experiment draws each distinct design's scale apart from its ratios and re-evaluates the true
  eta and torques: l1 then varies independently of the ratios (the lengths still share the scale,
  so they remain correlated with one another).
* :func:`given_data_sobol`: first-order Sobol indices from such a given sample (SALib's
  ``delta`` module, its Sobol estimator), checked on the Ishigami function.
* :func:`elasticities`: the eta derivatives made dimensionless (x / eta * d eta / dx), which no
  longer favour the short links by their units.
* :func:`distinct_rows`: the paper's 400 rows repeat designs; the correlations on distinct designs
  give p-values that do not count repeats.
* :func:`table3_sweep`: Table 3's torque reduction by topology optimisation against the payload to
  link-mass ratio, with the links optimised in the run.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import NDArray
from SALib.analyze import delta

from qsm.physics.cad import CadSettings, MassProperties
from qsm.physics.duty import Duty
from qsm.physics.dynamics import evaluate_table
from qsm.physics.kinematics import DESIGN_NAMES, RATIO_NAMES, design_from_ratios
from qsm.realisation.topology import torques_before_after

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
OUTPUTS: dict[str, str] = {"eta": "eta", "tau1_Nm": "tau1", "tau2_Nm": "tau2"}
#: Table 3 of the paper: torque reduction (%) by topology optimisation.
PAPER_TABLE3_PCT: dict[str, float] = {"tau1": 25.65, "tau2": 16.50}


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


def given_data_sobol(
    x: NDArray[np.float64], y: NDArray[np.float64], names: list[str], seed: int
) -> pd.Series:
    """First-order Sobol indices of ``y`` on the columns of ``x`` from a given (not Saltelli)
    sample: SALib's ``delta`` analysis with its Sobol estimator."""
    problem = {
        "num_vars": len(names),
        "names": names,
        "bounds": [[float(a), float(b)] for a, b in zip(x.min(axis=0), x.max(axis=0), strict=True)],
    }
    result = delta.analyze(problem, x, y, num_resamples=2, seed=seed, method="sobol")
    return pd.Series(np.asarray(result["S1"]), index=names)


def lengths_outcome(sample: pd.DataFrame, seed: int, tree_depth: int) -> dict[str, Any]:
    """What the independent-lengths sample says about each finding: first-order Sobol ranking,
    Spearman and Pearson (with p) of every length with each output, Pearson(tau1, tau2) and the
    first split of a regression tree per output."""
    from scipy import stats
    from sklearn.tree import DecisionTreeRegressor

    x = sample[[f"{n}_m" for n in DESIGN_NAMES]].to_numpy()
    out: dict[str, Any] = {"n_designs": len(sample), "sobol_s1": {}, "ranking": {}}
    out.update(spearman={}, pearson={}, pearson_p={}, first_split={})
    for column, name in OUTPUTS.items():
        y = sample[column].to_numpy()
        s1 = given_data_sobol(x, y, list(DESIGN_NAMES), seed)
        out["sobol_s1"][name] = s1.round(6).to_dict()
        out["ranking"][name] = list(s1.sort_values(ascending=False).index)
        out["spearman"][name] = {
            n: float(stats.spearmanr(x[:, i], y)[0]) for i, n in enumerate(DESIGN_NAMES)
        }
        pearson = [stats.pearsonr(x[:, i], y) for i in range(len(DESIGN_NAMES))]
        out["pearson"][name] = {n: float(r[0]) for n, r in zip(DESIGN_NAMES, pearson, strict=True)}
        out["pearson_p"][name] = {
            n: float(r[1]) for n, r in zip(DESIGN_NAMES, pearson, strict=True)
        }
        tree = DecisionTreeRegressor(max_depth=tree_depth, random_state=seed).fit(x, y)
        out["first_split"][name] = DESIGN_NAMES[tree.tree_.feature[0]]
    out["pearson_tau1_tau2"] = float(stats.pearsonr(sample["tau1_Nm"], sample["tau2_Nm"])[0])
    return out


def elasticities(gradients: pd.DataFrame, dataset: pd.DataFrame) -> pd.Series:
    """Median |x / eta * d eta / d x| (-) of every length over the mechanisms, largest first."""
    merged = gradients.merge(dataset[["mechanism_id", "eta", *(f"{n}_m" for n in DESIGN_NAMES)]])
    values = {
        n: np.nanmedian(np.abs(merged[f"{n}_m"] * merged[f"deta_d{n}_per_m"] / merged["eta"]))
        for n in DESIGN_NAMES
    }
    return pd.Series(values).sort_values(ascending=False)


def distinct_rows(designs: pd.DataFrame, features: list[str]) -> pd.DataFrame:
    """The rows of ``designs`` with distinct ``features``, first occurrence kept."""
    return designs.drop_duplicates(subset=features).reset_index(drop=True)


def table3_sweep(
    design: NDArray[np.float64],
    cad: CadSettings,
    duty: Duty,
    optimised: dict[str, MassProperties],
    payloads_kg: list[float],
) -> pd.DataFrame:
    """Peak torques with the CAD links and with the optimised ones at each payload (kg), the
    reduction (%) and the payload / CAD-link mass ratio. The links stay as optimised in the run."""
    from qsm.physics.cad import mass_properties

    link_mass = sum(p.mass_kg for p in mass_properties(design, cad).values())
    rows = []
    for payload in payloads_kg:
        t = torques_before_after(design, cad, payload, duty, optimised)
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


def ratio_reaching(x: NDArray[np.float64], y: NDArray[np.float64], target: float) -> float:
    """First ``x`` (in increasing ``x``) at which the piecewise-linear curve ``y(x)`` reaches
    ``target``; NaN if it never does in the range."""
    order = np.argsort(x)
    x, y = np.asarray(x, dtype=float)[order], np.asarray(y, dtype=float)[order] - target
    for i in range(len(x) - 1):
        if y[i] == 0.0:
            return float(x[i])
        if y[i] * y[i + 1] < 0.0:
            return float(x[i] - y[i] * (x[i + 1] - x[i]) / (y[i + 1] - y[i]))
    return float(x[-1]) if len(x) and y[-1] == 0.0 else float("nan")
