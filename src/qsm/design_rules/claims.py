"""Findings as claims checked against evidence: what a run offers to check them on
(:class:`Evidence`, with the study's :class:`Study`), a finding's specification (:class:`Claim`,
with the experiments that :class:`Probe` it again) and :func:`evaluate`, which turns a list of
claims into the findings table with a verdict per row."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd
from scipy import stats


def spearman(a: pd.Series, b: pd.Series) -> float:
    """Spearman coefficient of ``a`` and ``b``; NaN when either is constant."""
    return float(stats.spearmanr(a, b)[0]) if np.ptp(a) > 0 and np.ptp(b) > 0 else float("nan")


@dataclass(frozen=True)
class Study:
    """Outcomes of the study's experiments (:mod:`qsm.design_rules.study`)."""

    lengths: dict[str, Any]  # lengths_outcome of the scale-apart-from-ratios sample
    elasticity: pd.Series  # median |x / eta d eta / dx| per length, largest first
    distinct: pd.DataFrame  # correlations on the distinct designs among the 400 rows
    n_distinct: int
    table3: pd.DataFrame  # table3_sweep
    table3_run: dict[str, float]  # this run's reductions (%), "tau1" and "tau2"
    payload_to_link_mass: float  # this run's payload / CAD-link mass

    def corr(self, a: str, b: str) -> tuple[float, float]:
        """Pearson coefficient and p-value of ``a`` and ``b`` on the distinct designs."""
        d = self.distinct
        row = d[(d["a"] == a) & (d["b"] == b)].iloc[0]
        return float(row["pearson"]), float(row["pearson_p"])


@dataclass(frozen=True)
class Evidence:
    """What the findings are checked against."""

    sobol: pd.DataFrame
    n_sobol: int
    first_splits: dict[str, str]  # objective (eta, tau1, tau2) -> variable of the root split
    n_designs: int  # rows behind the trees and correlations
    n_unique: int  # distinct designs among them
    correlations: pd.DataFrame
    gradients: pd.DataFrame
    pareto: pd.DataFrame
    dataset: pd.DataFrame  # all mechanisms whose dynamics succeeded (true values)
    study: Study | None = None  # None when the study is off

    def corr(self, a: str, b: str, kind: str = "pearson") -> tuple[float, float]:
        """Coefficient (``kind``: pearson or spearman) and p-value of ``a`` and ``b`` on the
        designs behind the trees."""
        c = self.correlations
        row = c[(c["a"] == a) & (c["b"] == b)].iloc[0]
        return float(row[kind]), float(row[f"{kind}_p"])

    def spearman_all(self, a: str, b: str) -> float:
        """Spearman coefficient of columns ``a`` and ``b`` over all mechanisms (true values)."""
        return spearman(self.dataset[a], self.dataset[b])


@dataclass(frozen=True)
class Experiment:
    """One experiment's reading of a finding: what was run, what it measured, whether the
    paper's claim holds there, and under which condition."""

    name: str
    outcome: str
    holds: bool
    condition: str


@dataclass(frozen=True)
class Probe:
    """An experiment of the study that measures a finding again: ``measure`` gives the value the
    claim is judged on, ``outcome`` its text; ``holds`` replaces the claim's test when given."""

    name: str
    condition: Callable[[Study], str]
    measure: Callable[[Study], Any]
    outcome: Callable[[Study, Any], str]
    holds: Callable[[Any, float], bool] | None = None


@dataclass(frozen=True)
class Claim:
    """A finding of the paper: ``measure`` reads this run's value from the evidence, ``holds``
    judges a value at significance ``alpha``, ``shown`` writes this run's column; findings with
    ``needs_study`` are left out when the study is off."""

    finding: str
    paper: str
    measure: Callable[[Evidence], Any]
    holds: Callable[[Any, float], bool]
    shown: Callable[[Evidence, Any], str]
    probes: tuple[Probe, ...] = ()
    needs_study: bool = False


def evaluate(claims: Sequence[Claim], ev: Evidence, alpha: float) -> pd.DataFrame:
    """The table of ``claims``: finding, paper, this run, agree, experiment, measured outcome,
    verdict; the probes run only when ``ev`` has a study."""
    rows = []
    for c in claims:
        if c.needs_study and ev.study is None:
            continue
        value = c.measure(ev)
        experiments = []
        for p in c.probes if ev.study is not None else ():
            got = p.measure(ev.study)
            holds = (p.holds or c.holds)(got, alpha)
            experiments.append(
                Experiment(p.name, p.outcome(ev.study, got), holds, p.condition(ev.study))
            )
        rows.append(
            _row(c.finding, c.paper, c.shown(ev, value), c.holds(value, alpha), experiments)
        )
    return pd.DataFrame(rows)


def _row(
    finding: str, paper: str, ours: str, agree: bool, experiments: list[Experiment]
) -> dict[str, str]:
    if agree:
        verdict = "agrees in this run"
    elif not experiments:
        verdict = "unexplained: no experiment was run (study.enabled is false)"
    elif any(e.holds for e in experiments):
        verdict = "reproduced under: " + "; ".join(e.condition for e in experiments if e.holds)
    else:
        verdict = "not reproduced under any condition tried"
    return {
        "finding": finding,
        "paper": paper,
        "this run": ours,
        "agree": "agree" if agree else "disagree",
        "experiment": "; ".join(e.name for e in experiments),
        "measured outcome": "; ".join(e.outcome for e in experiments),
        "verdict": verdict,
    }
