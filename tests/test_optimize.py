"""NSGA-II problem: the paper's constraints by hand, determinism, what is recorded."""

import numpy as np
import pytest

from qsm.config.reading import load_config
from qsm.config.settings import physics
from qsm.mechanisms.scale import fit_design
from qsm.optimization.nsga import run_nsga2
from qsm.optimization.problems import LabelStats, PaperProblem, RatiosProblem, paper_constraints
from qsm.surrogate.model import SurrogateSettings, train


def test_constraints_by_hand():
    design = np.array([[1.0, 0.3, 1.0, 0.5, 1.2, 0.4]])
    pred = np.array([[0.1, 50.0, 20.0]])
    stats = LabelStats(np.array([0.1, 60.0, 18.0]), np.array([0.02, 5.0, 4.0]), z=1.95)
    g = paper_constraints(design, pred, stats)[0]
    expected = [
        -0.1, -50.0, -20.0,           # g1..g3: the predictions are positive
        1.0 + 0.3 - 1.0 - 0.5,        # g4: l3 + l2 - l1 - l4
        (0.1 - 0.039) - 0.1,          # g5: eta > mean - z std
        0.1 - (0.1 + 0.039),          # g6: eta < mean + z std
        (60 - 9.75) - 50.0,           # g7: violated, tau1 too low for the data
        50.0 - (60 + 9.75),           # g8
        (18 - 7.8) - 20.0,            # g9
        20.0 - (18 + 7.8),            # g10
    ]  # fmt: skip
    np.testing.assert_allclose(g, expected, atol=1e-12)
    assert (g <= 0).sum() == 9  # only g7 is violated


def test_crank_rocker_violation_is_positive():
    bad = np.array([[1.0, 0.6, 1.3, 0.3, 1.2, 0.4]])
    stats = LabelStats(np.zeros(3), np.ones(3))
    assert paper_constraints(bad, np.ones((1, 3)), stats)[0, 3] == pytest.approx(0.6)


@pytest.fixture(scope="module")
def model():
    rng = np.random.default_rng(0)
    x = rng.uniform([0.3, 0.06, 0.25, 0.1, 0.35, 0.07], [0.5, 0.3, 0.6, 0.3, 0.7, 0.35], (800, 6))
    y = np.column_stack([0.05 + 0.1 * x[:, 0], 40 + 30 * x[:, 4], 10 + 20 * x[:, 3]])
    return train(x, y, SurrogateSettings(max_epochs=100)).model, x


def test_same_seed_same_front_and_three_generations_kept(model):
    surrogate, x = model
    stats = LabelStats.of(surrogate, 1.95)
    problem = PaperProblem(surrogate, x.min(axis=0), x.max(axis=0), stats)
    span = (np.array([0.0, 30.0, 10.0]), np.array([0.2, 80.0, 40.0]))
    a = run_nsga2(problem, 24, 12, 5, span)
    b = run_nsga2(problem, 24, 12, 5, span)
    np.testing.assert_array_equal(a.pareto_x, b.pareto_x)
    assert len(a.hypervolume) == 12 and len(a.last_populations) == 3
    assert all(len(p["X"]) == 24 for p in a.last_populations)
    c = run_nsga2(problem, 24, 12, 6, span)
    assert not np.array_equal(a.pareto_x, c.pareto_x)


def test_ratios_problem_uses_the_exact_scale_and_eta(model):
    surrogate, _ = model
    config = load_config()
    fit = physics.fit(
        config["operating_range"], config["task"]["points"], config["scale"], config["workspace"]
    )
    problem = RatiosProblem(surrogate, np.zeros(5), np.ones(5), LabelStats.of(surrogate, 1.95), fit)
    ratios = np.array([[0.3, 1.0, 0.5, 1.2, 0.4], [0.6, 1.3, 0.3, 1.2, 0.4]])
    out = {}
    problem._evaluate(ratios, out)
    exact = fit_design(ratios[0], fit)
    assert out["F"][0, 0] == pytest.approx(exact["eta"], rel=1e-12)
    design, _, feasible = problem.designs(ratios)
    assert design[0, 0] == pytest.approx(exact["scale_m"]) and feasible.tolist() == [True, False]
    assert out["G"][1, 3] == 1.0  # the crossed design is infeasible


def test_the_least_violation_of_g13_counts_only_designs_where_it_was_evaluated():
    """g13 / g14 read 0 where the cheaper constraints fail (not evaluated there); their least
    violation is over the designs that met the others, so a task nothing holds drops g13."""
    from qsm.optimization.nsga import InfeasibleProblem

    names = ("g1", "g12", "g13", "g14")
    violation = np.array(
        [
            [0.5, 0.0, 0.0, 0.0],  # fails g1: g13 and g14 not evaluated
            [0.0, 0.0, 0.3, 0.0],  # meets g1 and g12, too weak
            [0.0, 0.0, 0.7, 0.1],
        ]
    )
    least = InfeasibleProblem(violation).least(names, ("g13", "g14"))
    assert least == {"g1": 0.0, "g12": 0.0, "g13": 0.3, "g14": 0.0}
    none_held = InfeasibleProblem(violation[:1]).least(names, ("g13", "g14"))
    assert none_held == {"g1": 0.5, "g12": 0.0, "g13": 0.0, "g14": 0.0}
