"""Design-rule extraction: Sobol through SALib, trees, correlations, eta derivatives, findings."""

import dataclasses

import numpy as np
import pandas as pd
import pytest
from SALib.test_functions import Ishigami

from qsm.design_rules.claims import Evidence
from qsm.design_rules.correlations import FEATURES_MM, correlations
from qsm.design_rules.eta_derivatives import (
    batch_gradients,
    eta_gradient,
    sampled_rows,
    true_etas,
)
from qsm.design_rules.findings import findings, summary_markdown
from qsm.design_rules.sensitivity import ranking, sobol_indices
from qsm.design_rules.trees import fit_tree, mining_designs, rule_sentence
from qsm.physics.kinematics import DESIGN_NAMES
from qsm.physics.task import Disk
from qsm.physics.workspace import OperatingRange, Resolution

OP = OperatingRange.from_degrees([45.0, 180.0], -37.5)
DISK = Disk((-0.72, 0.11), 0.1345)


def test_paper_sample_size():
    calls = []

    def model(x):
        calls.append(len(x))
        return np.column_stack([x.sum(axis=1), x[:, 0], x[:, 1] ** 2])

    bounds = np.array([[0.0, 1.0]] * 6)
    result = sobol_indices(model, list(DESIGN_NAMES), bounds, ["a", "b", "c"], 1024, seed=1)
    assert calls == [14336] and result.n_evaluations == 14336
    # a model of x1 alone: all of its variance is x1's
    b = result.indices[result.indices["output"] == "b"].set_index(["index", "variable"])["value"]
    assert b[("ST", "l1")] == pytest.approx(1.0, abs=0.02)
    assert abs(b[("ST", "l2")]) < 0.02


def test_ishigami_reference_values_through_the_same_code_path():
    """Analytic indices of the Ishigami function (a = 7, b = 0.1), as SALib documents them."""
    bounds = np.array([[-np.pi, np.pi]] * 3)
    result = sobol_indices(
        lambda x: Ishigami.evaluate(x)[:, None], ["x1", "x2", "x3"], bounds, ["f"], 4096, seed=2
    )
    idx = result.indices.set_index(["index", "variable"])["value"]
    for (kind, var), ref in {
        ("S1", "x1"): 0.3139, ("S1", "x2"): 0.4424, ("S1", "x3"): 0.0,
        ("ST", "x1"): 0.5576, ("ST", "x2"): 0.4424, ("ST", "x3"): 0.2437,
        ("S2", "x1:x3"): 0.2437, ("S2", "x1:x2"): 0.0,
    }.items():  # fmt: skip
        assert idx[(kind, var)] == pytest.approx(ref, abs=0.03), (kind, var)
    assert ranking(result.indices, "f") == ["x1", "x2", "x3"]


def fake_front(n, rng, start=0):
    lengths = rng.uniform([0.3, 0.1, 0.3, 0.1, 0.4, 0.1], [0.5, 0.2, 0.5, 0.3, 0.6, 0.3], (n, 6))
    table = pd.DataFrame(lengths, columns=[f"{c}_m" for c in DESIGN_NAMES])
    table["scale_m"] = lengths[:, 0]
    table["eta_pred"] = 0.2 - 0.1 * (lengths[:, 4] > 0.5) + rng.normal(0, 0.001, n)
    table["tau1_pred_Nm"] = 50 + 40 * lengths[:, 4] + 10 * lengths[:, 0]
    table["tau2_pred_Nm"] = 10 + 30 * lengths[:, 4] + rng.normal(0, 0.1, n)
    return table


def test_trees_and_correlations_use_exactly_the_400_designs():
    rng = np.random.default_rng(0)
    pareto, gens = fake_front(100, rng), fake_front(300, rng).assign(generation=1, feasible=True)
    designs = mining_designs(pareto, gens)
    assert len(designs) == 400 and (designs["source"] == "pareto").sum() == 100
    np.testing.assert_allclose(designs["ee_x_mm"], np.r_[pareto["ee_x_m"], gens["ee_x_m"]] * 1e3)
    tree = fit_tree(designs, "eta_pred", depth=2, seed=0)
    assert tree.first_split == "ee_x" and tree.threshold_mm == pytest.approx(500, abs=5)
    assert rule_sentence(tree).startswith("ee_x <= ") and "higher eta" in rule_sentence(tree)
    table = correlations(designs, FEATURES_MM, ["eta_pred", "tau1_pred_Nm", "tau2_pred_Nm"])
    row = table[(table["a"] == "ee_x_mm") & (table["b"] == "tau1_pred_Nm")].iloc[0]
    assert row["pearson"] == pytest.approx(
        np.corrcoef(designs["ee_x_mm"], designs["tau1_pred_Nm"])[0, 1], rel=1e-12
    )
    assert row["spearman"] > 0.9 and row["pearson_p"] < 1e-10
    assert len(table) == 6 * 3 + 3


def test_eta_derivatives_satisfy_eulers_theorem():
    """eta is homogeneous of degree -2 in the lengths, so sum_i x_i d eta / d x_i = -2 eta.

    This checks the finite differences (their steps, signs and the one-sided fallback), not the
    area itself: the pixel-reference tests in test_workspace.py do that."""
    for design in ([0.4, 0.12, 0.4, 0.2, 0.48, 0.16], [0.45, 0.1, 0.5, 0.22, 0.55, 0.2]):
        d = np.array(design)
        grad = eta_gradient(d, OP, DISK, Resolution())
        eta = true_etas(d, OP, DISK, Resolution())[0]
        assert float(d @ grad) == pytest.approx(-2 * eta, rel=1e-4)
        half = eta_gradient(d, OP, DISK, Resolution(), rel_step=5e-4)
        np.testing.assert_allclose(grad, half, rtol=1e-2, atol=1e-3)


def test_designs_differentiated_together_give_each_design_s_own_derivatives():
    designs = np.array([[0.4, 0.12, 0.4, 0.2, 0.48, 0.16], [0.45, 0.1, 0.5, 0.22, 0.55, 0.2]])
    one_by_one = [eta_gradient(d, OP, DISK, Resolution()) for d in designs]
    np.testing.assert_allclose(batch_gradients(designs, OP, DISK, Resolution()), one_by_one,
                               rtol=1e-12)  # fmt: skip


def test_the_derivatives_stop_growing_with_the_dataset():
    """Up to the bound every row, beyond it that many distinct rows, the same for a seed."""
    np.testing.assert_array_equal(sampled_rows(1500, 2000, 7), np.arange(1500))
    rows = sampled_rows(110_800, 20_000, 7)
    assert len(np.unique(rows)) == 20_000 and np.all(np.diff(rows) > 0) and rows[-1] < 110_800
    np.testing.assert_array_equal(rows, sampled_rows(110_800, 20_000, 7))
    assert not np.array_equal(rows, sampled_rows(110_800, 20_000, 8))


def agreeing_evidence():
    names = list(DESIGN_NAMES)
    rows = []
    order = {
        "eta": ["ee_x", "l3", "l1"],
        "tau1": ["ee_x", "l1", "l4"],
        "tau2": ["ee_x", "l4", "l3"],
    }
    for out, top in order.items():
        for name in names:
            value = 1.0 - 0.1 * top.index(name) if name in top else 0.01
            rows.append((out, "ST", name, value, 0.0))
    sobol = pd.DataFrame(rows, columns=["output", "index", "variable", "value", "conf"])
    objectives = ["eta_pred", "tau1_pred_Nm", "tau2_pred_Nm"]
    corr = []
    for v in FEATURES_MM:
        for o in objectives:
            r = {"eta_pred": -0.8, "tau1_pred_Nm": 0.8, "tau2_pred_Nm": 0.7}[o]
            if v not in ("ee_x_mm", "l1_mm"):
                r = 0.0
            corr.append((v, o, r, 1e-6, r, 1e-6))
    corr.append(("tau1_pred_Nm", "tau2_pred_Nm", 0.96, 0.0, 0.95, 0.0))
    corr_table = pd.DataFrame(
        corr, columns=["a", "b", "spearman", "spearman_p", "pearson", "pearson_p"]
    )
    grads = pd.DataFrame(
        {
            f"deta_d{n}_per_m": [s]
            for n, s in zip(names, [-0.5, 0.01, -0.6, 0.02, -0.9, 0.03], strict=True)
        }
    )
    scale = np.linspace(0.3, 0.5, 20)
    pareto = pd.DataFrame(
        {"scale_m": scale, "eta_pred": -scale, "tau1_pred_Nm": scale, "tau2_pred_Nm": 2 * scale}
    )
    splits = {"eta": "ee_x", "tau1": "ee_x", "tau2": "ee_x"}
    x = np.linspace(0.0, 1.0, 30)
    dataset = pd.DataFrame(
        {"ee_x_m": x, "l1_m": x, "scale_m": x, "eta": -x, "tau1_Nm": x, "tau2_Nm": x**2}
    )
    return Evidence(
        sobol=sobol,
        n_sobol=14336,
        first_splits=splits,
        n_designs=400,
        n_unique=120,
        correlations=corr_table,
        gradients=grads,
        pareto=pareto,
        dataset=dataset,
    )


def test_findings_agree_and_a_disagreement_carries_its_verdict():
    ev = agreeing_evidence()
    table = findings(ev, alpha=0.05)
    assert len(table) == 10
    assert (table["agree"] == "agree").all(), table
    assert (table["verdict"] == "agrees in this run").all()
    scale_row = table.set_index("finding").loc[
        "Larger scale factor: lower eta, higher torques (Pareto front)", "this run"
    ]
    assert "all mechanisms: eta -1.00, tau1 +1.00, tau2 +1.00" in scale_row
    assert "120 distinct designs" in summary_markdown(table, ev, "paper")
    flipped = dataclasses.replace(ev, first_splits={**ev.first_splits, "tau2": "l4"})
    again = findings(flipped, alpha=0.05).set_index("finding")
    row = again.loc["EE_x splits first in every tree"]
    assert row["agree"] == "disagree" and row["verdict"].startswith("unexplained")


def test_derivative_at_the_edge_of_loop_closure_is_one_sided():
    # l3 + l4 = 1 + l2 exactly: the loop just closes at theta1 - theta2 = 180 deg
    d = np.array([1.0, 0.25, 0.85, 0.4, 1.2, 0.4]) * 0.4
    grad = eta_gradient(d, OP, DISK, Resolution())
    assert np.isfinite(grad).all()
    up = d.copy()
    up[2] *= 1.001  # a longer coupler keeps the loop closed: the one-sided side
    one_sided = (
        true_etas(up, OP, DISK, Resolution())[0] - true_etas(d, OP, DISK, Resolution())[0]
    ) / (0.001 * d[2])
    assert grad[2] == pytest.approx(one_sided, rel=1e-9)
    shrunk = d.copy()
    shrunk[2] *= 0.999
    assert np.isnan(true_etas(shrunk, OP, DISK, Resolution())[0])
