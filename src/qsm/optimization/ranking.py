"""The order in which a verified front offers its designs: ``rank`` 1 is the knee.

A front's designs are all non-dominated, so a *rank* here is a position in a fixed order that
the interactive front shows and ``python -m qsm export --front F --rank K`` takes:

1. designs that truly hold the task, whose dynamics succeeded and whose every link fits the
   printer, by the ``knee`` score of :func:`rule_scores` (distance to the ideal point of the
   true values of the objectives the front was optimised on, :func:`objectives_of`, each min-max
   normalised over the truly feasible designs);
2. the truly feasible designs that do not fit the printer, by the same score;
3. the rest, in table order.

So rank 1 is the design ``printing.selection_rule: knee`` picks from this front when any of its
designs is printable.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from qsm.physics.kinematics import DESIGN_COLUMNS

#: Selection rules of :func:`rule_scores` (and ``printing.selection_rule``).
RULES: tuple[str, ...] = ("min_tau1", "min_tau2", "min_torque_sum", "min_eta", "knee", "fastest")


@dataclass(frozen=True)
class Objective:
    """One minimised objective: its ``name``, the column of a front holding the value NSGA-II
    minimised (``predicted``), the column of a verified front holding the true value, the
    dataset's column (which normalises the hypervolume) and an axis ``label`` with the unit."""

    name: str
    predicted: str
    true: str
    dataset: str
    label: str


ETA = Objective("eta", "eta_pred", "eta_true", "eta", "eta (-)")
TAU1 = Objective("tau1", "tau1_pred_Nm", "tau1_true_Nm", "tau1_Nm", "tau1 (N m)")
TAU2 = Objective("tau2", "tau2_pred_Nm", "tau2_true_Nm", "tau2_Nm", "tau2 (N m)")
#: The mass of both motors' drives (Stage 2's selection, drive_checks); NSGA-II's value comes
#: from the selection on the loop's coarse duty, the true one on the full duty.
DRIVE_MASS = Objective(
    "drive_mass", "drive_mass_pred_kg", "drive_mass_kg", "drive_mass_kg", "drive mass (kg)"
)
#: NSGA-II's objectives for each ``optimization.objectives`` setting, in its order.
OBJECTIVE_SETS: dict[str, tuple[Objective, ...]] = {
    "torques": (ETA, TAU1, TAU2),
    "drive_mass": (ETA, DRIVE_MASS),
}
#: The dataset's columns the optimisation and the fronts' comparison read (its designs, labels,
#: objectives and tool sag): at 100x the paper a job holds these, not the whole dataset.
OPTIMISATION_COLUMNS: tuple[str, ...] = tuple(dict.fromkeys([
    "status", *DESIGN_COLUMNS, "eta", "tau1_Nm", "tau2_Nm", "tool_sag_mm",
    *(o.dataset for objectives in OBJECTIVE_SETS.values() for o in objectives),
]))  # fmt: skip
#: The surrogate's predictions every front holds, whatever it was optimised on.
PREDICTION_COLUMNS: tuple[str, ...] = tuple(o.predicted for o in OBJECTIVE_SETS["torques"])
#: The true values every verified table holds (eta, tau1, tau2), all minimised.
OBJECTIVES: tuple[str, ...] = tuple(o.true for o in OBJECTIVE_SETS["torques"])


def objectives_of(table: pd.DataFrame) -> tuple[Objective, ...]:
    """The objectives a front (or its verified table) was optimised on: ``drive_mass`` when it
    holds NSGA-II's drive-mass column, else ``torques`` (also for the dataset's rows)."""
    return OBJECTIVE_SETS["drive_mass" if DRIVE_MASS.predicted in table else "torques"]


def drawn_objectives(table: pd.DataFrame) -> tuple[Objective, ...]:
    """Three objectives to draw a front on: its own (:func:`objectives_of`), then tau1 and tau2
    to make three."""
    own = objectives_of(table)
    return (*own, *(o for o in OBJECTIVE_SETS["torques"] if o not in own))[:3]


def true_columns(table: pd.DataFrame) -> list[str]:
    """The true values a design of ``table`` needs to be ranked: eta, tau1, tau2 and the
    objectives of :func:`objectives_of`."""
    return list(dict.fromkeys([*OBJECTIVES, *(o.true for o in objectives_of(table))]))


def rule_scores(df: pd.DataFrame, rule: str) -> np.ndarray:
    """Score of every row of a verified table under selection ``rule`` (smaller is better):
    ``min_tau1``, ``min_tau2``, ``min_torque_sum`` (their sum), ``min_eta`` (the true values), or
    ``knee``, the distance to the ideal point of the true values of the objectives the table was
    optimised on (:func:`objectives_of`), each min-max normalised over the rows, or ``fastest``,
    the task's time-optimal cycle (s, ``time_optimal_cycle_s``,
    :mod:`qsm.realization.motion.front_cycles`; the knee on a table without it)."""
    if rule == "min_tau1":
        return df["tau1_true_Nm"].to_numpy(float)
    if rule == "min_tau2":
        return df["tau2_true_Nm"].to_numpy(float)
    if rule == "min_torque_sum":
        return (df["tau1_true_Nm"] + df["tau2_true_Nm"]).to_numpy(float)
    if rule == "min_eta":
        return df["eta_true"].to_numpy(float)
    cycles = df["time_optimal_cycle_s"] if "time_optimal_cycle_s" in df else None
    if rule == "fastest" and cycles is not None and cycles.notna().any():
        return np.nan_to_num(cycles.to_numpy(float), nan=np.inf)
    if rule in ("knee", "fastest"):  # fastest without any cycle (the dataset's): the knee
        obj = df.loc[:, [o.true for o in objectives_of(df)]].to_numpy(float)
        lo, hi = obj.min(axis=0), obj.max(axis=0)
        span = np.where(hi > lo, hi - lo, 1.0)
        return np.linalg.norm((obj - lo) / span, axis=1)
    raise ValueError(f"unknown selection rule {rule!r}; choose one of {RULES}")


def front_ranks(verified: pd.DataFrame) -> NDArray[np.int64]:
    """1-based rank of every row of a verified front (see the module docstring)."""
    ok = verified["feasible"].astype(bool) & verified["dynamics_status"].eq("ok")
    ok &= np.isfinite(verified.loc[:, true_columns(verified)].to_numpy(float)).all(axis=1)
    score = np.full(len(verified), np.inf)
    if ok.any():
        score[ok.to_numpy()] = rule_scores(verified[ok], "knee")
    group = np.where(ok & verified["printable"].astype(bool), 0, np.where(ok, 1, 2))
    order = np.lexsort((np.arange(len(verified)), score, group))
    ranks = np.empty(len(verified), dtype=np.int64)
    ranks[order] = np.arange(1, len(verified) + 1)
    return ranks
