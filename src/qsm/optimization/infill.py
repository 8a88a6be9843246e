"""Adaptive infill: the surrogate made right where the optimiser goes.

After NSGA-II on the surrogate, :func:`infill` checks its front with the true physics (out of
sample: none of those designs is in the training data yet), and while an objective's median
relative error on the front exceeds ``median_goal`` or its 90th percentile ``p90_goal``, it adds
the front and up to ``offspring`` further designs of the last population to the training data,
refits the surrogate (:func:`qsm.surrogate.model.refit`: from scratch, or warm where its
normalisation holds the new designs) and runs NSGA-II again from the last population, for at
most ``rounds`` rounds. ``rounds: 0`` is the paper's one-shot method, unchanged.

The loop is given its three steps as functions (:class:`Steps`), so the workflow runs it on the
MuJoCo physics and the tests on an analytic stand-in with a known front.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any, NamedTuple

import numpy as np
import pandas as pd
from numpy.typing import NDArray
from sklearn.neighbors import NearestNeighbors

from qsm.optimization.nsga import FrontTables
from qsm.optimization.ranking import OBJECTIVE_SETS
from qsm.schema.defaults import default
from qsm.surrogate.model import INPUTS, Surrogate

#: The surrogate's objectives whose predictions the infill makes right.
OBJECTIVES = OBJECTIVE_SETS["torques"]


@dataclass(frozen=True)
class InfillSettings:
    """``rounds`` (0: one-shot), ``offspring`` (designs of the last population added per round
    beside the front), ``generations`` (NSGA-II's from the last population in each round) and
    the goals on the front's relative errors: each objective's median and 90th percentile;
    ``refit_rows``, the most training rows a refit takes (:func:`refit_rows`)."""

    rounds: int = default("surrogate.infill.rounds")
    offspring: int = default("surrogate.infill.offspring")
    generations: int = default("surrogate.infill.generations")
    median_goal: float = default("surrogate.infill.median_goal")
    p90_goal: float = default("surrogate.infill.p90_goal")
    refit_rows: int = default("surrogate.infill.refit_rows")


class Steps(NamedTuple):
    """The loop's steps: ``optimize(model, start)`` NSGA-II on a surrogate (``start``: None, or
    the last population and the generations to run from it); ``truth(designs)`` the verified
    table of designs (their lengths and predictions); ``refit(x, y)`` a surrogate trained on
    the data plus the true designs ``x`` (N, 6) m with labels ``y`` (N, 3)."""

    optimize: Callable[[Surrogate, tuple[NDArray, int] | None], FrontTables]
    truth: Callable[[pd.DataFrame], pd.DataFrame]
    refit: Callable[[NDArray, NDArray], Surrogate]


class InfillResult(NamedTuple):
    """The final front's tables, the record of each round and every true evaluation made."""

    tables: FrontTables
    rounds: list[dict[str, Any]]
    evaluations: pd.DataFrame


def truly_ok(table: pd.DataFrame) -> pd.Series:
    """The verified designs whose true objectives are defined: feasible, dynamics ok."""
    return table["feasible"].astype(bool) & table["dynamics_status"].eq("ok")


def front_errors(table: pd.DataFrame) -> dict[str, dict[str, float | None]]:
    """Each objective's median and 90th-percentile relative error of the predictions on the
    verified ``table``'s truly ok designs (None where there is none)."""
    ok = truly_ok(table)
    out: dict[str, dict[str, float | None]] = {"median": {}, "p90": {}}
    for o in OBJECTIVES:
        true = table.loc[ok, o.true].to_numpy(float)
        rel = np.abs(table.loc[ok, o.predicted].to_numpy(float) - true) / np.abs(true)
        out["median"][o.name] = float(np.median(rel)) if len(rel) else None
        out["p90"][o.name] = float(np.percentile(rel, 90)) if len(rel) else None
    return out


def meets_goals(errors: dict[str, dict[str, float | None]], settings: InfillSettings) -> bool:
    """Every objective's median and 90th percentile within the goals."""
    goal = {"median": settings.median_goal, "p90": settings.p90_goal}
    return all(
        v is not None and v <= goal[kind] for kind, per in errors.items() for v in per.values()
    )


def _offspring(tables: FrontTables, n: int) -> pd.DataFrame:
    """Up to ``n`` designs of the last generation that are not on the front, evenly spread over
    it in its order (deterministic)."""
    gens = tables.last_generations
    last = gens[gens["generation"] == gens["generation"].max()]
    on_front = (
        last[list(INPUTS)]
        .apply(tuple, axis=1)
        .isin(tables.pareto[list(INPUTS)].apply(tuple, axis=1))
    )
    rest = last.loc[~on_front.to_numpy(), list(tables.pareto.columns)]
    rest = rest.drop_duplicates(subset=list(INPUTS))
    if len(rest) <= n:
        return rest
    return rest.iloc[np.linspace(0, len(rest) - 1, n).round().astype(int)]


def _labelled(table: pd.DataFrame) -> tuple[NDArray, NDArray]:
    """The true designs (N, 6) m and labels (N, 3) of a verified table's truly ok rows."""
    table = table.drop_duplicates(subset=list(INPUTS))
    ok = truly_ok(table)
    x = table.loc[ok, list(INPUTS)].to_numpy(float)
    y = table.loc[ok, [o.true for o in OBJECTIVES]].to_numpy(float)
    good = np.isfinite(y).all(axis=1)
    return x[good], y[good]


def infill(
    model: Surrogate,
    steps: Steps,
    settings: InfillSettings,
    hypervolume: Callable[[pd.DataFrame], float],
    log: Callable[[str], None] | None = None,
) -> InfillResult:
    """NSGA-II on ``model``, then infill rounds until the front's errors meet the goals or the
    rounds are spent (:mod:`module docs <qsm.optimization.infill>`). Each round's record gives
    its errors on the front's designs not yet trained on (out of sample: the goals are judged on
    these) and, as ``front_*``, on the whole front (the verification's figures), the true
    ``hypervolume`` of the front's verified table, the front's size, how many of its designs
    are new and the true evaluations made so far."""
    tables = steps.optimize(model, None)
    rounds: list[dict[str, Any]] = []
    evaluated: list[pd.DataFrame] = []
    if settings.rounds == 0:
        return InfillResult(tables, rounds, pd.DataFrame())
    for r in range(settings.rounds + 1):
        checked = steps.truth(tables.pareto)
        new = _unseen(checked, evaluated)
        whole = front_errors(checked)
        errors = front_errors(checked[new]) if new.any() else whole  # out of sample
        evaluated.append(checked.assign(round=r, source="front"))
        record = _round_record(
            r, errors, hypervolume(checked), (len(checked), int(new.sum())), evaluated
        )
        rounds.append(record | {f"front_{k}": v for k, v in _as_record(whole).items()})
        if log is not None:
            log(f"infill round {r}: errors {errors}, true hypervolume {rounds[-1]['hypervolume']}")
        if r == settings.rounds or meets_goals(errors, settings):
            break
        offspring = _offspring(tables, settings.offspring)
        if len(offspring):
            evaluated.append(steps.truth(offspring).assign(round=r, source="offspring"))
        x, y = _labelled(pd.concat(evaluated, ignore_index=True))
        model = steps.refit(x, y)
        tables = _continued(
            tables, steps.optimize(model, (tables.population, settings.generations))
        )
    return InfillResult(tables, rounds, pd.concat(evaluated, ignore_index=True))


def refit_rows(
    train_x: NDArray[np.float64], near_x: NDArray[np.float64], most: int, seed: int
) -> NDArray[np.intp]:
    """The training rows (sorted) a refit takes beside the true designs ``near_x`` (M, 6): all
    of ``train_x`` (N, 6) up to ``most``; beyond it, the nearest to the true designs (in the
    inputs scaled to their range, up to half of ``most``) and a ``seed``-ed sample of the rest,
    so that a refit's work stops growing with the dataset while it keeps the front's
    neighbourhood."""
    n = len(train_x)
    if n <= most:
        return np.arange(n)
    lo, span = train_x.min(axis=0), np.ptp(train_x, axis=0)
    span = np.where(span > 0, span, 1.0)
    k = max(1, (most // 2) // max(len(near_x), 1))
    search = NearestNeighbors(n_neighbors=min(k, n)).fit((train_x - lo) / span)
    near = np.unique(search.kneighbors((near_x - lo) / span, return_distance=False))
    near = near[: most // 2]
    rest = np.setdiff1d(np.arange(n), near)
    fill = np.random.default_rng(seed).choice(rest, size=most - len(near), replace=False)
    return np.sort(np.concatenate([near, fill]))


def _continued(before: FrontTables, after: FrontTables) -> FrontTables:
    """``after`` (a rerun from ``before``'s last population) with ``before``'s hypervolume
    history ahead of its own and its generations numbered on from ``before``'s."""
    if before.hypervolume.empty:
        return after
    offset = int(before.hypervolume["generation"].max())
    later = after.hypervolume.assign(generation=after.hypervolume["generation"] + offset)
    gens = after.last_generations
    return replace(
        after,
        hypervolume=pd.concat([before.hypervolume, later], ignore_index=True),
        last_generations=gens.assign(generation=gens["generation"] + offset),
    )


def _unseen(checked: pd.DataFrame, evaluated: list[pd.DataFrame]) -> NDArray[np.bool_]:
    """Which designs of ``checked`` no table of ``evaluated`` holds (not trained on yet)."""
    if not evaluated:
        return np.ones(len(checked), bool)
    seen = pd.concat(evaluated)[list(INPUTS)].apply(tuple, axis=1)
    return ~checked[list(INPUTS)].apply(tuple, axis=1).isin(seen).to_numpy()


def _as_record(errors: dict[str, dict[str, float | None]]) -> dict[str, Any]:
    """``front_errors``' median and 90th percentile under the round record's keys."""
    return {"median_rel_error": errors["median"], "p90_rel_error": errors["p90"]}


def _round_record(
    r: int,
    errors: dict[str, dict[str, float | None]],
    hypervolume: float,
    front: tuple[int, int],
    evaluated: list[pd.DataFrame],
) -> dict[str, Any]:
    """One round's JSON-ready record: ``errors`` on the front's designs that no former round had
    evaluated (out of sample; the whole front's when there are none); ``front``: its size and
    how many of its designs those are."""
    n_front, n_new = front
    return {
        "round": r,
        **_as_record(errors),
        "hypervolume": hypervolume,
        "n_front": n_front,
        "n_front_new": n_new,
        "true_evaluations": int(sum(len(t) for t in evaluated)),
    }


def final_front(evaluations: pd.DataFrame, pareto: pd.DataFrame) -> pd.DataFrame | None:
    """The last round's verified front (the verification's table, made already) when it holds
    ``pareto``'s designs in order; None otherwise (no round ran)."""
    if evaluations.empty:
        return None
    last = evaluations[
        evaluations["source"].eq("front") & evaluations["round"].eq(evaluations["round"].max())
    ]
    cols = list(INPUTS)
    if len(last) != len(pareto) or not np.array_equal(
        last[cols].to_numpy(), pareto[cols].to_numpy()
    ):
        return None
    return last.drop(columns=["round", "source"]).reset_index(drop=True)
