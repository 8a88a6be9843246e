"""Latin-hypercube sampling of the unit-mechanism ratios (paper Section 2.1, Table 1)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
import pandas as pd
from scipy.stats import qmc

from qsm.physics.kinematics import RATIO_NAMES


def latin_hypercube(
    n_samples: int, bounds: Mapping[str, Sequence[float]], seed: int
) -> pd.DataFrame:
    """``n_samples`` LHS rows of the ratios l2, l3, l4, ee_x, ee_y (l1 = 1) within ``bounds``.

    Columns: ``sample_id`` (row index, the stable id of a design) and one column per ratio.
    """
    lo = np.array([bounds[name][0] for name in RATIO_NAMES], dtype=float)
    hi = np.array([bounds[name][1] for name in RATIO_NAMES], dtype=float)
    unit = qmc.LatinHypercube(d=len(RATIO_NAMES), seed=seed).random(n_samples)
    values = qmc.scale(unit, lo, hi)
    table = pd.DataFrame(values, columns=list(RATIO_NAMES))
    table.insert(0, "sample_id", np.arange(n_samples, dtype=np.int64))
    return table
