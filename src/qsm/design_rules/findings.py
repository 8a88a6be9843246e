"""This run's design rules beside the paper's Section 4 findings and Table 3, one row per finding.

The findings are the list :data:`CLAIMS` of :class:`qsm.design_rules.claims.Claim`: what the
paper says, the measure that checks it on this run and the study's experiments that check it again
under another condition; :func:`findings` evaluates them into the table."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
import pandas as pd

from qsm.design_rules.claims import Claim, Evidence, Probe, Study, evaluate, spearman
from qsm.design_rules.correlations import OBJECTIVES as OBJ
from qsm.design_rules.sensitivity import ranking
from qsm.design_rules.study import PAPER_TABLE3_PCT, ratio_reaching
from qsm.report.markdown_pages import markdown_cell

#: This run's Table 3 agrees when both reductions are within this many percentage points.
TABLE3_TOLERANCE_PCT = 5.0
PairDict = dict[str, tuple[float, float]]


def _lengths(measure: Callable[[dict], Any], outcome: Callable[[dict, Any], str]) -> Probe:
    """The scale-apart-from-ratios experiment, reading ``Study.lengths``."""
    return Probe(
        "scale apart from ratios: true eta and torques at a scale drawn apart from the ratios",
        lambda st: (
            f"the scale drawn apart from the ratios ({st.lengths['n_designs']:,} distinct designs)"
        ),
        lambda st: measure(st.lengths),
        lambda st, v: outcome(st.lengths, v),
    )


def _distinct(measure: Callable[[Study], Any], shown: Callable[[Any], str]) -> Probe:
    """The correlations again on the distinct designs only."""
    return Probe(
        "distinct designs: the correlations without repeated rows",
        lambda st: f"the {st.n_distinct} distinct designs only",
        measure,
        lambda st, v: f"on {st.n_distinct} distinct designs: {shown(v)}",
    )


def _pair(rp: tuple[float, float]) -> str:
    return f"{rp[0]:+.2f} (p {rp[1]:.1g})"


def _pairs(pe: PairDict) -> str:
    return ", ".join(f"{k} {_pair(rp)}" for k, rp in pe.items())


def _signed(prefix: str, values: dict[str, float]) -> str:
    return prefix + ", ".join(f"{k} {v:+.2f}" for k, v in values.items())


def _lowers_eta_raises_torques(v: dict[str, float]) -> bool:
    return v["eta"] < 0 < v["tau1"] and v["tau2"] > 0


def _significant(pe: PairDict, alpha: float) -> bool:
    signs = {k: r for k, (r, _) in pe.items()}
    return _lowers_eta_raises_torques(signs) and all(p < alpha for _, p in pe.values())


def _lengths_spearman(length: str, prefix: str) -> Probe:
    """The scale-apart-from-ratios experiment's Spearman coefficients of ``length`` with each
    objective."""
    return _lengths(
        lambda lo: {o: lo["spearman"][o][length] for o in OBJ.values()},
        lambda _, v: _signed(prefix, v),
    )


def _sobol_claim(out: str, paper: str, holds: Callable[[list[str]], bool]) -> Claim:
    """The Sobol top three of objective ``out``."""
    return Claim(
        f"Sobol top three for {out}" + (" (total index)" if out == "eta" else ""),
        paper,
        lambda ev: ranking(ev.sobol, out)[:3],
        lambda top, _: holds(top),
        lambda _, top: ", ".join(top),
        (
            _lengths(
                lambda lo: lo["ranking"][out],
                lambda lo, rank: (
                    "first-order indices (given data; the lengths share the drawn "
                    "scale): " + ", ".join(f"{n} {lo['sobol_s1'][out][n]:.2f}" for n in rank[:3])
                ),
            ),
        ),
    )


def _reach(st: Study) -> dict[str, float]:
    """Payload / link mass at which the sweep first reaches each of the paper's reductions."""
    x = st.table3["payload_to_link_mass"].to_numpy()
    return {
        k: ratio_reaching(x, st.table3[f"{k}_reduction_pct"].to_numpy(), v)
        for k, v in PAPER_TABLE3_PCT.items()
    }


def _table3_outcome(st: Study, reach: dict[str, float]) -> str:
    x = st.table3["payload_to_link_mass"].to_numpy()
    cut = {k: st.table3[f"{k}_reduction_pct"] for k in PAPER_TABLE3_PCT}
    span = ", ".join(f"{k} {c.min():.1f}-{c.max():.1f} %" for k, c in cut.items())
    found = ", ".join(
        f"{k} {PAPER_TABLE3_PCT[k]:.2f} % at {r:.2f}" if np.isfinite(r) else f"{k} never"
        for k, r in reach.items()
    )
    return (
        f"payload / link mass {x.min():.2f}-{x.max():.2f}: reductions {span}; the paper's "
        f"values reached: {found} (this run: {st.payload_to_link_mass:.2f})"
    )


def _reductions(pct: dict[str, float]) -> str:
    return f"tau1 -{pct['tau1']:.2f} %, tau2 -{pct['tau2']:.2f} %"


def _largest_gradients(ev: Evidence) -> list[str]:
    """Lengths by their median |d eta / d x| over all mechanisms, largest first."""
    med = ev.gradients.filter(like="deta_d").abs().median()
    return [c.removeprefix("deta_d").removesuffix("_per_m") for c in med.sort_values().index[::-1]]


#: The paper's Section 4 findings and Table 3, in the order of the table.
CLAIMS: tuple[Claim, ...] = (
    _sobol_claim("eta", "EE_x, l3, l1", lambda t: t[:3] == ["ee_x", "l3", "l1"]),
    _sobol_claim(
        "tau1", "EE_x, l1, then l3/l4", lambda t: t[:2] == ["ee_x", "l1"] and t[2] in ("l3", "l4")
    ),
    _sobol_claim(
        "tau2", "EE_x, then l4 and l3", lambda t: t[0] == "ee_x" and set(t[1:3]) == {"l3", "l4"}
    ),
    Claim(
        "EE_x splits first in every tree",
        "EE_x first for eta, tau1, tau2",
        lambda ev: ev.first_splits,
        lambda splits, _: all(v == "ee_x" for v in splits.values()),
        lambda _, splits: ", ".join(f"{k}: {v}" for k, v in splits.items()),
        (
            _lengths(
                lambda lo: lo["first_split"],
                lambda _, v: "first splits " + ", ".join(f"{k}: {x}" for k, x in v.items()),
            ),
        ),
    ),
    Claim(
        "Decreasing EE_x improves all objectives",
        "lower EE_x: higher eta (the paper's trees maximise it), lower tau1 and tau2",
        lambda ev: {o: ev.corr("ee_x_mm", c, "spearman")[0] for c, o in OBJ.items()},
        lambda v, _: _lowers_eta_raises_torques(v),
        lambda ev, v: (
            _signed("Spearman(EE_x, .) ", v)
            + f"; all mechanisms: tau1 {ev.spearman_all('ee_x_m', 'tau1_Nm'):+.2f}"
        ),
        (_lengths_spearman("ee_x", "Spearman(EE_x, .) "),),
    ),
    Claim(
        "Pearson(tau1, tau2)",
        "0.95",
        lambda ev: ev.corr("tau1_pred_Nm", "tau2_pred_Nm")[0],
        lambda r, _: r >= 0.9,
        lambda _, r: f"{r:.2f}",
        (
            _lengths(
                lambda lo: lo["pearson_tau1_tau2"], lambda _, r: f"Pearson(tau1, tau2) {r:.2f}"
            ),
        ),
    ),
    Claim(
        "EE_x negative with eta, positive with tau1 and tau2 (Pearson, significant)",
        "negative, positive, positive",
        lambda ev: {o: ev.corr("ee_x_mm", c) for c, o in OBJ.items()},
        _significant,
        lambda _, pe: _pairs(pe),
        (
            _distinct(lambda st: {o: st.corr("ee_x_mm", c) for c, o in OBJ.items()}, _pairs),
            _lengths(
                lambda lo: {
                    o: (lo["pearson"][o]["ee_x"], lo["pearson_p"][o]["ee_x"]) for o in lo["pearson"]
                },
                lambda _, pe: f"scale apart from ratios: {_pairs(pe)}",
            ),
        ),
    ),
    Claim(
        "l1 negative with eta (Pearson)",
        "negative",
        lambda ev: ev.corr("l1_mm", "eta_pred"),
        lambda rp, alpha: rp[0] < 0 and rp[1] < alpha,
        lambda ev, rp: (
            f"{_pair(rp)}; all mechanisms (Spearman): {ev.spearman_all('l1_m', 'eta'):+.2f}"
        ),
        (
            _distinct(lambda st: st.corr("l1_mm", "eta_pred"), _pair),
            _lengths(
                lambda lo: (lo["pearson"]["eta"]["l1"], lo["pearson_p"]["eta"]["l1"]),
                lambda _, rp: f"scale apart from ratios: {_pair(rp)}",
            ),
        ),
    ),
    Claim(
        "Larger scale factor: lower eta, higher torques (Pareto front)",
        "eta down, tau1 and tau2 up",
        lambda ev: {o: spearman(ev.pareto["scale_m"], ev.pareto[c]) for c, o in OBJ.items()},
        lambda v, _: _lowers_eta_raises_torques(v),
        lambda ev, v: (
            _signed("front: Spearman(scale, .) ", v)
            + "; all mechanisms: "
            + ", ".join(
                f"{o} {ev.spearman_all('scale_m', c):+.2f}"
                for c, o in (("eta", "eta"), ("tau1_Nm", "tau1"), ("tau2_Nm", "tau2"))
            )
        ),
        (_lengths_spearman("l1", "Spearman(scale, .) "),),
    ),
    Claim(
        "Largest median abs(d eta / d x) (true eta, all mechanisms)",
        "EE_x, l3, l1",
        _largest_gradients,
        lambda order, _: order[:3] == ["ee_x", "l3", "l1"],
        lambda _, order: ", ".join(order[:3]),
        (
            Probe(
                "elasticities: |x / eta * d eta / dx|, free of the lengths' units",
                lambda _: "derivatives made dimensionless (elasticities)",
                lambda st: list(st.elasticity.index),
                lambda st, _: (
                    "median " + ", ".join(f"{n} {v:.2f}" for n, v in st.elasticity.iloc[:3].items())
                ),
            ),
        ),
    ),
    Claim(
        "Topology optimisation lowers the peak torques (Table 3)",
        _reductions(PAPER_TABLE3_PCT),
        lambda ev: ev.study.table3_run,
        lambda run, _: all(
            abs(run[k] - v) <= TABLE3_TOLERANCE_PCT for k, v in PAPER_TABLE3_PCT.items()
        ),
        lambda _, run: _reductions(run),
        (
            Probe(
                "Table 3 sweep: the payload varied, links as optimised in this run",
                lambda st: (
                    "payload / CAD-link mass of "
                    + " (tau1) and ".join(f"{r:.2f}" for r in _reach(st).values())
                    + " (tau2)"
                ),
                _reach,
                _table3_outcome,
                lambda reach, _: all(np.isfinite(r) for r in reach.values()),
            ),
        ),
        needs_study=True,
    ),
)


def findings(ev: Evidence, alpha: float) -> pd.DataFrame:
    """The table of the paper's findings (:data:`CLAIMS`) on ``ev`` at significance ``alpha``."""
    return evaluate(CLAIMS, ev, alpha)


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
