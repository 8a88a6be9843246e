"""Analysis of the study's experiments (:mod:`qsm.design_rules.experiments` runs them): why this
run's design rules differ from the paper's (Section 4, Table 3).

* :func:`given_data_sobol`: first-order Sobol indices from a given sample (SALib's ``delta``
  module, its Sobol estimator), checked on the Ishigami function; :func:`lengths_outcome` reads
  rankings, correlations and tree splits from the scale-apart-from-ratios sample.
* :func:`elasticities`: the eta derivatives made dimensionless (x / eta * d eta / dx), which no
  longer favour the short links by their units.
* :func:`distinct_rows`: the paper's 400 rows repeat designs; the correlations on distinct designs
  give p-values that do not count repeats.
* :func:`ratio_reaching`: where the Table 3 sweep reaches the paper's reductions.

Physics-free, so the findings table does not rerun when the dynamics code changes.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import NDArray
from SALib.analyze import delta
from scipy import stats
from sklearn.tree import DecisionTreeRegressor

from qsm.physics.kinematics import DESIGN_NAMES, RATIO_NAMES

#: The dataset's columns the design-rule stage reads (:func:`elasticities`, the findings'
#: correlations over all mechanisms, the lengths study and its figure, the healthy-row filter):
#: its jobs read these, not the whole table.
RULE_COLUMNS: tuple[str, ...] = (
    "mechanism_id", "status", *RATIO_NAMES, "scale_m", *(f"{n}_m" for n in DESIGN_NAMES),
    "eta", "tau1_Nm", "tau2_Nm",
)  # fmt: skip
OUTPUTS: dict[str, str] = {"eta": "eta", "tau1_Nm": "tau1", "tau2_Nm": "tau2"}
#: Table 3 of the paper: torque reduction (%) by topology optimisation.
PAPER_TABLE3_PCT: dict[str, float] = {"tau1": 25.65, "tau2": 16.50}


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
