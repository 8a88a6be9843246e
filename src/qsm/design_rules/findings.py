"""This run's design rules beside the paper's Section 4 findings, one row per finding."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd
from scipy import stats

from qsm.design_rules.correlations import OBJECTIVES as OBJ
from qsm.design_rules.sensitivity import ranking
from qsm.design_rules.study import PAPER_TABLE3_PCT, ratio_reaching
from qsm.report.markdown_pages import markdown_cell

#: This run's Table 3 agrees when both reductions are within this many percentage points.
TABLE3_TOLERANCE_PCT = 5.0


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


def _corr(ev: Evidence, a: str, b: str, kind: str = "pearson") -> tuple[float, float]:
    row = ev.correlations[(ev.correlations["a"] == a) & (ev.correlations["b"] == b)].iloc[0]
    return float(row[kind]), float(row[f"{kind}_p"])


def _all(ev: Evidence, a: str, b: str) -> float:
    """Spearman coefficient over all mechanisms (true values)."""
    return _spearman(ev.dataset[a], ev.dataset[b])


@dataclass(frozen=True)
class Experiment:
    """One experiment's reading of a finding: what was run, what it measured, whether the
    paper's claim holds there, and under which condition."""

    name: str
    outcome: str
    holds: bool
    condition: str


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


def _lengths_condition(study: Study) -> str:
    return (
        f"the scale drawn apart from the ratios ({study.lengths['n_designs']:,} distinct designs)"
    )


def _lengths(study: Study | None, outcome: str, holds: bool) -> list[Experiment]:
    if study is None:
        return []
    name = "scale apart from ratios: true eta and torques at a scale drawn apart from the ratios"
    return [Experiment(name, outcome, holds, _lengths_condition(study))]


def _top3(ranking: list[str], values: dict[str, float]) -> str:
    return ", ".join(f"{n} {values[n]:.2f}" for n in ranking[:3])


def _study_corr(study: Study, a: str, b: str) -> tuple[float, float]:
    d = study.distinct
    row = d[(d["a"] == a) & (d["b"] == b)].iloc[0]
    return float(row["pearson"]), float(row["pearson_p"])


def findings(ev: Evidence, alpha: float) -> pd.DataFrame:
    """The table of findings: finding, paper, this run, agree, experiment, measured outcome,
    verdict."""
    st = ev.study
    lo = st.lengths if st is not None else None
    rows = []
    top = {o: ranking(ev.sobol, o)[:3] for o in ("eta", "tau1", "tau2")}
    claims = {
        "eta": ("Sobol top three for eta (total index)", "EE_x, l3, l1"),
        "tau1": ("Sobol top three for tau1", "EE_x, l1, then l3/l4"),
        "tau2": ("Sobol top three for tau2", "EE_x, then l4 and l3"),
    }
    checks = {
        "eta": lambda t: t[:3] == ["ee_x", "l3", "l1"],
        "tau1": lambda t: t[:2] == ["ee_x", "l1"] and t[2] in ("l3", "l4"),
        "tau2": lambda t: t[0] == "ee_x" and set(t[1:3]) == {"l3", "l4"},
    }
    for out, (finding, paper) in claims.items():
        exp = (
            _lengths(
                st,
                "first-order indices (given data; the lengths share the drawn scale): "
                + _top3(lo["ranking"][out], lo["sobol_s1"][out]),
                checks[out](lo["ranking"][out]),
            )
            if lo
            else []
        )
        rows.append(_row(finding, paper, ", ".join(top[out]), checks[out](top[out]), exp))

    firsts = ev.first_splits
    exp = (
        _lengths(
            st,
            "first splits " + ", ".join(f"{k}: {v}" for k, v in lo["first_split"].items()),
            all(v == "ee_x" for v in lo["first_split"].values()),
        )
        if lo
        else []
    )
    rows.append(
        _row(
            "EE_x splits first in every tree",
            "EE_x first for eta, tau1, tau2",
            ", ".join(f"{k}: {v}" for k, v in firsts.items()),
            all(v == "ee_x" for v in firsts.values()),
            exp,
        )
    )

    def direction(signs: dict[str, float]) -> bool:
        return signs["eta"] < 0 and signs["tau1"] > 0 and signs["tau2"] > 0

    signs = {o: _corr(ev, "ee_x_mm", c, "spearman")[0] for c, o in OBJ.items()}
    exp = []
    if lo:
        sp = {o: lo["spearman"][o]["ee_x"] for o in ("eta", "tau1", "tau2")}
        outcome = "Spearman(EE_x, .) " + ", ".join(f"{k} {v:+.2f}" for k, v in sp.items())
        exp = _lengths(st, outcome, direction(sp))
    rows.append(
        _row(
            "Decreasing EE_x improves all objectives",
            "lower EE_x: higher eta (the paper's trees maximise it), lower tau1 and tau2",
            "Spearman(EE_x, .) "
            + ", ".join(f"{k} {v:+.2f}" for k, v in signs.items())
            + f"; all mechanisms: tau1 {_all(ev, 'ee_x_m', 'tau1_Nm'):+.2f}",
            direction(signs),
            exp,
        )
    )

    r12, _ = _corr(ev, "tau1_pred_Nm", "tau2_pred_Nm")
    exp = (
        _lengths(
            st,
            f"Pearson(tau1, tau2) {lo['pearson_tau1_tau2']:.2f}",
            lo["pearson_tau1_tau2"] >= 0.9,
        )
        if lo
        else []
    )
    rows.append(_row("Pearson(tau1, tau2)", "0.95", f"{r12:.2f}", r12 >= 0.9, exp))

    def significant(pe: dict[str, tuple[float, float]]) -> bool:
        return (
            pe["eta"][0] < 0 < pe["tau1"][0]
            and pe["tau2"][0] > 0
            and all(p < alpha for _, p in pe.values())
        )

    def fmt(pe: dict[str, tuple[float, float]]) -> str:
        return ", ".join(f"{k} {r:+.2f} (p {p:.1g})" for k, (r, p) in pe.items())

    pe = {o: _corr(ev, "ee_x_mm", c) for c, o in OBJ.items()}
    exp = []
    if st is not None:
        pd_ = {o: _study_corr(st, "ee_x_mm", c) for c, o in OBJ.items()}
        exp.append(
            Experiment(
                "distinct designs: the correlations without repeated rows",
                f"on {st.n_distinct} distinct designs: {fmt(pd_)}",
                significant(pd_),
                f"the {st.n_distinct} distinct designs only",
            )
        )
        pl = {o: (lo["pearson"][o]["ee_x"], lo["pearson_p"][o]["ee_x"]) for o in lo["pearson"]}
        exp += _lengths(st, f"scale apart from ratios: {fmt(pl)}", significant(pl))
    rows.append(
        _row(
            "EE_x negative with eta, positive with tau1 and tau2 (Pearson, significant)",
            "negative, positive, positive",
            fmt(pe),
            significant(pe),
            exp,
        )
    )

    r, p = _corr(ev, "l1_mm", "eta_pred")
    exp = []
    if st is not None:
        rd, pdist = _study_corr(st, "l1_mm", "eta_pred")
        exp.append(
            Experiment(
                "distinct designs: the correlations without repeated rows",
                f"on {st.n_distinct} distinct designs: {rd:+.2f} (p {pdist:.1g})",
                rd < 0 and pdist < alpha,
                f"the {st.n_distinct} distinct designs only",
            )
        )
        rl, pl1 = lo["pearson"]["eta"]["l1"], lo["pearson_p"]["eta"]["l1"]
        exp += _lengths(
            st, f"scale apart from ratios: {rl:+.2f} (p {pl1:.1g})", rl < 0 and pl1 < alpha
        )
    rows.append(
        _row(
            "l1 negative with eta (Pearson)",
            "negative",
            f"{r:+.2f} (p {p:.1g}); all mechanisms (Spearman): {_all(ev, 'l1_m', 'eta'):+.2f}",
            r < 0 and p < alpha,
            exp,
        )
    )

    def scale_claim(sc: dict[str, float]) -> bool:
        return sc["eta"] < 0 < sc["tau1"] and sc["tau2"] > 0

    sc = {o: _spearman(ev.pareto["scale_m"], ev.pareto[c]) for c, o in OBJ.items()}
    exp = []
    if lo:
        sl = {o: lo["spearman"][o]["l1"] for o in ("eta", "tau1", "tau2")}
        outcome = "Spearman(scale, .) " + ", ".join(f"{k} {v:+.2f}" for k, v in sl.items())
        exp = _lengths(st, outcome, scale_claim(sl))
    rows.append(
        _row(
            "Larger scale factor: lower eta, higher torques (Pareto front)",
            "eta down, tau1 and tau2 up",
            "front: Spearman(scale, .) "
            + ", ".join(f"{k} {v:+.2f}" for k, v in sc.items())
            + "; all mechanisms: "
            + ", ".join(
                f"{o} {_all(ev, 'scale_m', c):+.2f}"
                for c, o in (("eta", "eta"), ("tau1_Nm", "tau1"), ("tau2_Nm", "tau2"))
            ),
            scale_claim(sc),
            exp,
        )
    )

    med = ev.gradients.filter(like="deta_d").abs().median()
    order = [c.removeprefix("deta_d").removesuffix("_per_m") for c in med.sort_values().index[::-1]]
    exp = []
    if st is not None:
        el = st.elasticity
        exp.append(
            Experiment(
                "elasticities: |x / eta * d eta / dx|, free of the lengths' units",
                "median " + ", ".join(f"{n} {v:.2f}" for n, v in el.iloc[:3].items()),
                list(el.index[:3]) == ["ee_x", "l3", "l1"],
                "derivatives made dimensionless (elasticities)",
            )
        )
    rows.append(
        _row(
            "Largest median abs(d eta / d x) (true eta, all mechanisms)",
            "EE_x, l3, l1",
            ", ".join(order[:3]),
            order[:3] == ["ee_x", "l3", "l1"],
            exp,
        )
    )
    if st is not None:
        rows.append(_table3_row(st))
    return pd.DataFrame(rows)


def _table3_row(st: Study) -> dict[str, str]:
    """Table 3 of the paper against this run and the payload sweep."""
    run = st.table3_run
    agree = all(abs(run[k] - v) <= TABLE3_TOLERANCE_PCT for k, v in PAPER_TABLE3_PCT.items())
    x = st.table3["payload_to_link_mass"].to_numpy()
    reach = {
        k: ratio_reaching(x, st.table3[f"{k}_reduction_pct"].to_numpy(), v)
        for k, v in PAPER_TABLE3_PCT.items()
    }
    cut = {k: st.table3[f"{k}_reduction_pct"] for k in PAPER_TABLE3_PCT}
    span = ", ".join(f"{k} {c.min():.1f}-{c.max():.1f} %" for k, c in cut.items())
    found = ", ".join(
        f"{k} {PAPER_TABLE3_PCT[k]:.2f} % at {r:.2f}" if np.isfinite(r) else f"{k} never"
        for k, r in reach.items()
    )
    outcome = (
        f"payload / link mass {x.min():.2f}-{x.max():.2f}: reductions {span}; the paper's "
        f"values reached: {found} (this run: {st.payload_to_link_mass:.2f})"
    )
    holds = all(np.isfinite(r) for r in reach.values())
    condition = (
        "payload / CAD-link mass of "
        + " (tau1) and ".join(f"{r:.2f}" for r in reach.values())
        + " (tau2)"
    )
    exp = Experiment(
        "Table 3 sweep: the payload varied, links as optimised in this run",
        outcome,
        holds,
        condition,
    )
    return _row(
        "Topology optimisation lowers the peak torques (Table 3)",
        f"tau1 -{PAPER_TABLE3_PCT['tau1']:.2f} %, tau2 -{PAPER_TABLE3_PCT['tau2']:.2f} %",
        f"tau1 -{run['tau1']:.2f} %, tau2 -{run['tau2']:.2f} %",
        agree,
        [exp],
    )


def _spearman(a: pd.Series, b: pd.Series) -> float:
    return float(stats.spearmanr(a, b)[0]) if np.ptp(a) > 0 and np.ptp(b) > 0 else float("nan")


def summary_markdown(table: pd.DataFrame, ev: Evidence, primary: str) -> str:
    """``results/design_rules/summary.md``."""
    verdicts = table["verdict"].str.split(":").str[0].value_counts()
    head = (
        "# Design rules: this run against the paper's Section 4 and Table 3\n\n"
        f"Sobol analysis on {ev.n_sobol:,} surrogate evaluations (paper: 14,336). Trees and "
        f"correlations on the {ev.n_designs} rows (paper: 400) of the {primary} formulation's "
        f"front and last three generations (surrogate predictions, as in the paper), which hold "
        f"{ev.n_unique} distinct designs. Coefficients 'over all mechanisms' use the true values "
        f"of the whole dataset. {(table['agree'] == 'agree').sum()} of {len(table)} findings "
        "agree; verdicts: " + ", ".join(f"{k} {v}" for k, v in verdicts.items()) + ".\n\n"
    )
    lines = [_markdown(table)]
    if ev.study is not None:
        lines += ["", "## Table 3 sweep", "", _markdown(ev.study.table3.round(3))]
    return head + "\n".join(lines) + "\n"


def _markdown(table: pd.DataFrame) -> str:
    """``table`` as a Markdown table; each cell escaped (a ``|`` in it would split it)."""
    cols = [markdown_cell(c) for c in table.columns]
    lines = ["| " + " | ".join(cols) + " |", "|" + " --- |" * len(cols)]
    lines += [
        "| " + " | ".join(markdown_cell(v) for v in row) + " |"
        for row in table.itertuples(index=False)
    ]
    return "\n".join(lines)
