"""The order in which a verified front offers its designs: ``rank`` 1 is the knee.

A front's designs are all non-dominated, so a *rank* here is a position in a fixed order that
the interactive front shows and ``python -m qsm export --front F --rank K`` takes:

1. designs that truly hold the task, whose dynamics succeeded and whose every link fits the
   printer, by the ``knee`` score of :func:`rule_scores` (distance to
   the ideal point of the true eta, tau1 and tau2, each min-max normalised over the truly
   feasible designs);
2. the truly feasible designs that do not fit the printer, by the same score;
3. the rest, in table order.

So rank 1 is the design ``printing.selection_rule: knee`` picks from this front when any of its
designs is printable.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
from numpy.typing import NDArray

#: Selection rules of :func:`rule_scores` (and ``printing.selection_rule``).
RULES: tuple[str, ...] = ("min_tau1", "min_tau2", "min_torque_sum", "min_eta", "knee")
#: The true objectives a verified table holds, all minimised.
OBJECTIVES: tuple[str, ...] = ("eta_true", "tau1_true_Nm", "tau2_true_Nm")


def rule_scores(df: pd.DataFrame, rule: str) -> np.ndarray:
    """Score of every row of a verified table under selection ``rule`` (smaller is better):
    ``min_tau1``, ``min_tau2``, ``min_torque_sum`` (their sum), ``min_eta`` (the true values), or
    ``knee``, the distance to the ideal point of the three true objectives, each min-max
    normalised over the rows."""
    if rule == "min_tau1":
        return df["tau1_true_Nm"].to_numpy(float)
    if rule == "min_tau2":
        return df["tau2_true_Nm"].to_numpy(float)
    if rule == "min_torque_sum":
        return (df["tau1_true_Nm"] + df["tau2_true_Nm"]).to_numpy(float)
    if rule == "min_eta":
        return df["eta_true"].to_numpy(float)
    if rule == "knee":
        obj = df.loc[:, list(OBJECTIVES)].to_numpy(float)
        lo, hi = obj.min(axis=0), obj.max(axis=0)
        span = np.where(hi > lo, hi - lo, 1.0)
        return np.linalg.norm((obj - lo) / span, axis=1)
    raise ValueError(f"unknown selection rule {rule!r}; choose one of {RULES}")


def front_ranks(verified: pd.DataFrame) -> NDArray[np.int64]:
    """1-based rank of every row of a verified front (see the module docstring)."""
    ok = verified["feasible"].astype(bool) & verified["dynamics_status"].eq("ok")
    ok &= np.isfinite(verified.loc[:, list(OBJECTIVES)].to_numpy(float)).all(axis=1)
    score = np.full(len(verified), np.inf)
    if ok.any():
        score[ok.to_numpy()] = rule_scores(verified[ok], "knee")
    group = np.where(ok & verified["printable"].astype(bool), 0, np.where(ok, 1, 2))
    order = np.lexsort((np.arange(len(verified)), score, group))
    ranks = np.empty(len(verified), dtype=np.int64)
    ranks[order] = np.arange(1, len(verified) + 1)
    return ranks
