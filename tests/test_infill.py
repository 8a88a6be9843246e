"""The adaptive infill loop (qsm.optimization.infill) on an analytic stand-in with a known front:
the truth is a smooth function of the six lengths, the "surrogate" a nearest-neighbour fit of
its training data, and the "optimiser" keeps the designs of a fixed pool with the lowest
predicted sum. Infill must drive the front's errors below the goals within its rounds, and 0
rounds must give the one-shot front unchanged."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from sklearn.neighbors import KNeighborsRegressor

from qsm.optimization.infill import (
    InfillSettings,
    Steps,
    front_errors,
    infill,
    meets_goals,
    refit_rows,
)
from qsm.optimization.nsga import FrontTables
from qsm.optimization.ranking import OBJECTIVE_SETS, PREDICTION_COLUMNS
from qsm.surrogate.model import INPUTS

TRUE = [o.true for o in OBJECTIVE_SETS["torques"]]
RNG = np.random.default_rng(7)
POOL = RNG.uniform(0.1, 1.0, size=(400, 6))  # the designs the stand-in optimiser may pick
SEED = RNG.uniform(0.1, 1.0, size=(60, 6))  # the stand-in's "dataset"


def truth_of(x: np.ndarray) -> np.ndarray:
    """A smooth, positive (eta, tau1, tau2) of the six lengths: the known physics."""
    return np.column_stack(
        [
            0.05 + 0.1 * x[:, 0] * x[:, 1],
            10 + 20 * x[:, 2] ** 2 + x[:, 3],
            3 + 5 * x[:, 4] + x[:, 5],
        ]
    )


class Neighbour:
    """The stand-in surrogate: the true value of the nearest training design."""

    def __init__(self, x: np.ndarray, y: np.ndarray) -> None:
        self.fit = KNeighborsRegressor(n_neighbors=1).fit(x, y)

    def predict(self, x: np.ndarray) -> np.ndarray:
        return self.fit.predict(x)


def optimize(model: Neighbour, start: tuple[np.ndarray, int] | None) -> FrontTables:
    """The stand-in optimiser: the 20 pool designs of least predicted sum of normalised
    objectives, the next 30 as its last generation."""
    pred = model.predict(POOL)
    order = np.argsort((pred / pred.max(axis=0)).sum(axis=1))
    table = pd.DataFrame(POOL, columns=list(INPUTS))
    for k, name in enumerate(PREDICTION_COLUMNS):
        table[name] = pred[:, k]
    pareto = table.iloc[order[:20]].reset_index(drop=True)
    last = table.iloc[order[:50]].assign(generation=1).reset_index(drop=True)
    return FrontTables(pareto, last, pd.DataFrame(), "", POOL[order[:50]])


def truth(designs: pd.DataFrame) -> pd.DataFrame:
    """The stand-in verification: the true values beside the predictions."""
    out = designs.reset_index(drop=True).copy()
    out[TRUE] = truth_of(out[list(INPUTS)].to_numpy(float))
    out["feasible"] = True
    out["dynamics_status"] = "ok"
    return out


def steps() -> Steps:
    seed_y = truth_of(SEED)
    return Steps(
        optimize,
        truth,
        lambda x, y: Neighbour(np.vstack([SEED, x]), np.vstack([seed_y, y])),
    )


def test_infill_drives_the_front_s_errors_below_the_goals():
    settings = InfillSettings(
        rounds=6, offspring=10, generations=1, median_goal=0.01, p90_goal=0.03
    )
    model = Neighbour(SEED, truth_of(SEED))
    result = infill(model, steps(), settings, lambda t: float(len(t)))
    first, last = result.rounds[0], result.rounds[-1]
    assert not meets_goals({"median": first["median_rel_error"], "p90": first["p90_rel_error"]},
                           settings)  # fmt: skip
    assert meets_goals({"median": last["median_rel_error"], "p90": last["p90_rel_error"]}, settings)
    assert len(result.rounds) <= settings.rounds + 1
    counts = [r["true_evaluations"] for r in result.rounds]
    assert counts == sorted(counts) and counts[-1] == len(result.evaluations)
    # the final front's own errors, measured afresh, are the last round's
    errors = front_errors(truth(result.tables.pareto))
    assert errors["median"] == pytest.approx(last["front_median_rel_error"])


def test_no_rounds_is_the_one_shot_front():
    model = Neighbour(SEED, truth_of(SEED))
    result = infill(model, steps(), InfillSettings(rounds=0), lambda t: 0.0)
    pd.testing.assert_frame_equal(result.tables.pareto, optimize(model, None).pareto)
    assert result.rounds == [] and result.evaluations.empty


def test_the_rounds_stop_at_the_budget():
    settings = InfillSettings(rounds=1, offspring=0, generations=1, median_goal=1e-9, p90_goal=1e-9)
    result = infill(Neighbour(SEED, truth_of(SEED)), steps(), settings, lambda t: 0.0)
    assert [r["round"] for r in result.rounds] == [0, 1]


def test_a_refit_takes_the_true_designs_neighbourhood_and_a_bounded_sample():
    """Up to the bound, every training row; beyond it, exactly the bound: each true design's
    nearest rows (found here by brute force) and a seeded sample of the rest."""
    rng = np.random.default_rng(0)
    train = rng.uniform([0.2, 0.05, 0.2, 0.1, 0.2, 0.05], [0.8, 0.3, 0.8, 0.4, 1.0, 0.4],
                        (5000, 6))  # fmt: skip
    near = train[[10, 20]] + 1e-4
    np.testing.assert_array_equal(refit_rows(train, near, 5000, 1), np.arange(5000))
    rows = refit_rows(train, near, 1000, 1)
    assert len(rows) == 1000 and np.all(np.diff(rows) > 0)
    scaled = (train - train.min(0)) / np.ptp(train, 0)
    for point in (near - train.min(0)) / np.ptp(train, 0):
        nearest = np.argsort(np.linalg.norm(scaled - point, axis=1))[:250]
        assert set(nearest) <= set(rows)  # 500 / 2 designs: 250 neighbours each
    np.testing.assert_array_equal(rows, refit_rows(train, near, 1000, 1))
    assert not np.array_equal(rows, refit_rows(train, near, 1000, 2))
