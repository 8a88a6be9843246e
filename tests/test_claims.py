"""The evaluator of finding specifications: claims, their probes and the verdict of each row."""

import dataclasses

import pandas as pd

from qsm.design_rules.claims import Claim, Evidence, Probe, Study, evaluate

ALPHA = 4.0  # the claims below compare their value with multiples of alpha


def evidence(with_study: bool) -> Evidence:
    """Evidence whose only numbers the claims read: 5 designs, and a study with x = 9 and 7
    distinct designs."""
    empty = pd.DataFrame()
    study = Study(
        lengths={"x": 9.0},
        elasticity=pd.Series(dtype=float),
        distinct=empty,
        n_distinct=7,
        table3=empty,
        table3_run={},
        payload_to_link_mass=0.0,
    )
    frames = dict.fromkeys(("sobol", "correlations", "gradients", "pareto", "dataset"), empty)
    return Evidence(
        **frames,
        n_sobol=0,
        first_splits={},
        n_designs=5,
        n_unique=5,
        study=study if with_study else None,
    )


def above(factor: float):
    return lambda v, alpha: v > factor * alpha


X = Probe("x probe", lambda st: "x drawn", lambda st: st.lengths["x"], lambda st, v: f"x {v}")
#: A probe with its own test: seven distinct designs hold, whatever the claim's test says.
N = Probe(
    "n probe",
    lambda st: f"{st.n_distinct} distinct",
    lambda st: st.n_distinct,
    lambda st, v: f"n {v}",
    holds=lambda v, _: v == 7,
)
NEVER = dataclasses.replace(N, name="never", holds=lambda v, _: False)


def designs(ev: Evidence) -> int:
    return ev.n_designs


def shown(ev: Evidence, v: int) -> str:
    return f"{v} designs"


CLAIMS = (
    Claim("agrees", "more than 4", designs, above(1.0), shown, (X,)),  # 5 > 4
    Claim("rescued", "more than 8", designs, above(2.0), shown, (X, N)),  # x: 9 > 8
    Claim("refuted", "more than 12", designs, above(3.0), shown, (X, NEVER)),  # x: 9 < 12
    Claim("study only", "more than 8", designs, above(2.0), shown, (N,), needs_study=True),
)


def test_each_claim_gives_its_row_and_the_probes_decide_the_verdict():
    table = evaluate(CLAIMS, evidence(True), ALPHA).set_index("finding")
    assert list(table.index) == ["agrees", "rescued", "refuted", "study only"]
    assert list(table["agree"]) == ["agree", "disagree", "disagree", "disagree"]
    assert table.loc["agrees", "verdict"] == "agrees in this run"
    assert table.loc["agrees", "experiment"] == "x probe"
    assert table.loc["agrees", "this run"] == "5 designs"
    rescued = table.loc["rescued"]
    assert rescued["verdict"] == "reproduced under: x drawn; 7 distinct"
    assert rescued["measured outcome"] == "x 9.0; n 7"
    assert table.loc["refuted", "verdict"] == "not reproduced under any condition tried"
    assert table.loc["study only", "verdict"] == "reproduced under: 7 distinct"


def test_without_the_study_no_probe_runs_and_study_claims_are_left_out():
    table = evaluate(CLAIMS, evidence(False), ALPHA).set_index("finding")
    assert list(table.index) == ["agrees", "rescued", "refuted"]
    assert (table["experiment"] == "").all() and (table["measured outcome"] == "").all()
    assert table.loc["agrees", "verdict"] == "agrees in this run"
    assert table.loc["rescued", "verdict"].startswith("unexplained: no experiment was run")
