"""Correlations on the designs near the Pareto front (paper Section 4.3), and the names of the
mined features and objectives."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pandas as pd
from scipy import stats

from qsm.optimization.ranking import OBJECTIVE_SETS
from qsm.physics.kinematics import DESIGN_NAMES

#: The paper's objectives as the surrogate predicts them (every front holds these) and their
#: display names.
OBJECTIVES: dict[str, str] = {o.predicted: o.name for o in OBJECTIVE_SETS["torques"]}
FEATURES_MM: tuple[str, ...] = tuple(f"{n}_mm" for n in DESIGN_NAMES)


def correlations(
    designs: pd.DataFrame, variables: Sequence[str], objectives: Sequence[str]
) -> pd.DataFrame:
    """Spearman and Pearson coefficients with p-values for every variable-objective pair, and
    between the objectives."""
    rows = []
    pairs = [(v, o) for v in variables for o in objectives]
    pairs += [(a, b) for i, a in enumerate(objectives) for b in objectives[i + 1 :]]
    for a, b in pairs:
        x, y = designs[a].to_numpy(), designs[b].to_numpy()
        constant = np.ptp(x) == 0 or np.ptp(y) == 0
        sp = (np.nan, np.nan) if constant else stats.spearmanr(x, y)
        pe = (np.nan, np.nan) if constant else stats.pearsonr(x, y)
        rows.append((a, b, float(sp[0]), float(sp[1]), float(pe[0]), float(pe[1])))
    columns = ["a", "b", "spearman", "spearman_p", "pearson", "pearson_p"]
    return pd.DataFrame(rows, columns=columns)
