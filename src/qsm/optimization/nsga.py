"""Stage 4: NSGA-II (pymoo) on the surrogate in one formulation (the problems are in
:mod:`qsm.optimization.problems`) and on one set of objectives
(:data:`qsm.optimization.ranking.OBJECTIVE_SETS`), with the hypervolume recorded per generation,
and the tables a run writes."""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import NDArray
from pymoo.algorithms.moo.nsga2 import NSGA2
from pymoo.core.callback import Callback
from pymoo.core.problem import Problem
from pymoo.indicators.hv import HV
from pymoo.optimize import minimize

from qsm.mechanisms.scale import FitSettings
from qsm.optimization.constraint_set import (
    G12,
    G13,
    G14,
    G15,
    LOOP_ALLOWANCE,
    ExtraConstraints,
)
from qsm.optimization.problems import LabelStats, PaperProblem, RatiosProblem
from qsm.optimization.ranking import OBJECTIVE_SETS, PREDICTION_COLUMNS, Objective
from qsm.physics.kinematics import RATIO_NAMES
from qsm.surrogate.model import INPUTS, Surrogate


@dataclass
class Recorder(Callback):
    """Per generation: hypervolume of the feasible non-dominated set (normalised objectives);
    the last ``keep`` populations (X, F, G and the predictions P). Replaces pymoo's
    ``save_history``, which deep-copies the algorithm every generation."""

    lower: NDArray[np.float64]
    upper: NDArray[np.float64]
    keep: int = 3
    progress: Callable[[int, float], None] | None = None
    hypervolume: list[float] = field(default_factory=list)
    populations: list[dict[str, NDArray]] = field(default_factory=list)

    def __post_init__(self) -> None:
        super().__init__()
        self._hv = HV(ref_point=np.full(len(self.lower), 1.1))

    def notify(self, algorithm: Any) -> None:
        pop = algorithm.pop
        x, f, g = pop.get("X"), pop.get("F"), pop.get("G")
        feasible = np.all(g <= 0, axis=1)
        norm = (f[feasible] - self.lower) / (self.upper - self.lower)
        self.hypervolume.append(float(self._hv(norm)) if len(norm) else 0.0)
        self.populations.append({"X": x.copy(), "F": f.copy(), "G": g.copy(), "P": pop.get("P")})
        del self.populations[: -self.keep]
        if self.progress is not None:
            self.progress(algorithm.n_gen, self.hypervolume[-1])


@dataclass(frozen=True)
class OptimizationResult:
    """Pareto designs (variables, objectives, the surrogate's predictions), the last populations
    and the hypervolume history."""

    pareto_x: NDArray[np.float64]
    pareto_f: NDArray[np.float64]
    pareto_p: NDArray[np.float64]
    last_populations: list[dict[str, NDArray]]
    hypervolume: list[float]


class InfeasibleProblem(RuntimeError):
    """NSGA-II ended with no feasible design; ``violation`` holds each constraint's violation
    (``G`` clipped at 0) for each design of the last population."""

    def __init__(
        self, violation: NDArray[np.float64], message: str = "NSGA-II found no feasible design"
    ) -> None:
        super().__init__(message)
        self.violation = violation

    def least(self, names: tuple[str, ...], expensive: tuple[str, ...]) -> dict[str, float]:
        """The smallest violation of each constraint in the last population (0 where some design
        met it). The ``expensive`` ones are evaluated only for the designs that meet all the
        others (:meth:`ExtraConstraints.evaluate`), so theirs is the least over those designs,
        and 0 when there are none (nothing is known of them then)."""
        g = self.violation
        least = dict(zip(names, g.min(axis=0), strict=False))
        late = [k for k, n in enumerate(names) if n in expensive]
        early = [k for k in range(len(names)) if k not in late]
        held = (g[:, early] <= 0).all(axis=1)
        for k in late:
            least[names[k]] = float(g[held, k].min()) if held.any() else 0.0
        return least


def run_nsga2(
    problem: Problem,
    pop_size: int,
    generations: int,
    seed: int,
    objective_range: tuple[NDArray, NDArray],
    progress: Callable[[int, float], None] | None = None,
    initial: NDArray | None = None,
) -> OptimizationResult:
    """Run NSGA-II for ``generations`` with a recorder; ``objective_range`` normalises the HV;
    ``initial`` (pop_size, n_var): the first population (None: pymoo's random sampling)."""
    recorder = Recorder(*objective_range, progress=progress)
    algorithm = NSGA2(pop_size=pop_size) if initial is None else NSGA2(pop_size, sampling=initial)
    result = minimize(
        problem,
        algorithm,
        ("n_gen", generations),
        seed=seed,
        callback=recorder,
        verbose=False,
    )
    if result.opt is None or result.X is None:
        g = recorder.populations[-1]["G"]
        raise InfeasibleProblem(np.clip(g, 0.0, None))
    return OptimizationResult(
        pareto_x=np.atleast_2d(result.opt.get("X")),
        pareto_f=np.atleast_2d(result.opt.get("F")),
        pareto_p=np.atleast_2d(result.opt.get("P")),
        last_populations=recorder.populations,
        hypervolume=recorder.hypervolume,
    )


def bounds_from(
    table: Mapping[str, NDArray], columns: tuple[str, ...], override: Mapping[str, Any]
) -> tuple[NDArray, NDArray]:
    """Lower and upper bounds per column: the data's min and max unless ``override`` names it."""
    lo, hi = [], []
    for name in columns:
        given = override.get(name)
        if given is not None:
            lo.append(float(given[0]))
            hi.append(float(given[1]))
        else:
            lo.append(float(np.min(table[name])))
            hi.append(float(np.max(table[name])))
    return np.array(lo), np.array(hi)


@dataclass(frozen=True)
class FrontTables:
    """What an optimisation writes: the Pareto designs, the last generations, the HV history."""

    pareto: pd.DataFrame
    last_generations: pd.DataFrame
    hypervolume: pd.DataFrame
    constraints: str = ""
    population: NDArray | None = None  # the last population's variables, to start again from


def _design_table(
    design: NDArray, pred: NDArray, f: NDArray, objectives: tuple[Objective, ...]
) -> pd.DataFrame:
    """Lengths, scale, ratios, the predictions ``pred`` and the objectives ``f`` NSGA-II
    minimised that are not predictions."""
    table = pd.DataFrame(design, columns=list(INPUTS))
    table.insert(0, "scale_m", design[:, 0])
    for j, name in enumerate(RATIO_NAMES, start=1):
        table[name] = design[:, j] / design[:, 0]
    for j, name in enumerate(PREDICTION_COLUMNS):
        table[name] = pred[:, j]
    for j, o in enumerate(objectives):
        if o.predicted not in PREDICTION_COLUMNS:
            table[o.predicted] = f[:, j]
    return table


def _relaxed(
    extra: ExtraConstraints, unmet: str, least: Mapping[str, float]
) -> tuple[ExtraConstraints, str]:
    """``extra`` without the constraint ``unmet`` (g12, g15, g14 or g13) that no design met, and
    the sentence that says so with the least violation of the last generation."""
    if unmet == G15:
        return replace(extra, sag=None, full_sag=None), (
            f"g15 dropped: no design keeps the tool's sag within {extra.sag.tolerance_mm:g} mm "
            f"(least excess in the last generation {least[G15]:.1f} mm)"
        )
    if unmet == G12:
        volume = " x ".join(f"{v:g}" for v in extra.volume_mm)
        return replace(extra, printable=False), (
            f"g12 dropped: no design printable on {volume} mm (least excess in the last "
            f"generation {least[G12]:.0f} mm)"
        )
    if unmet == G14:
        return replace(extra, drives=None), (
            "g14 dropped: no design has a drive for each motor in the catalogue (least drive "
            f"utilisation in the last generation {1 + least[G14] - LOOP_ALLOWANCE:.2f}, on the "
            "loop's coarser duty)"
        )
    return replace(extra, strength=None), (
        "g13 dropped: no design whose links hold their loads (least strength utilisation in the "
        f"last generation {1 + least[G13]:.2f}, the links' with the loop's "
        f"{100 * LOOP_ALLOWANCE:g} % allowance)"
    )


def _stiffness_in_reach(
    extra: ExtraConstraints | None, dataset: pd.DataFrame
) -> tuple[ExtraConstraints | None, list[str]]:
    """``extra`` without g15 when no design of the dataset keeps the tool's sag within the
    tolerance (its ``tool_sag_mm``), with the sentence that says so; as it is otherwise."""
    if extra is None or extra.sag is None or "tool_sag_mm" not in dataset:
        return extra, []
    sag = dataset["tool_sag_mm"].to_numpy(float)
    least = float(np.nanmin(sag)) if np.isfinite(sag).any() else float("inf")
    if least <= extra.sag.tolerance_mm:
        return extra, []
    return replace(extra, sag=None, full_sag=None), [
        f"g15 dropped: no design of the dataset keeps the tool's sag within "
        f"{extra.sag.tolerance_mm:g} mm (least {least:.1f} mm at the configured section)"
    ]


def _full_duty_check(
    extra: ExtraConstraints | None, front: NDArray[np.float64]
) -> tuple[NDArray[np.bool_], list[str]]:
    """The front's designs to keep after g13 and g14 on the full duty (the loop ran them on a
    coarser one), and what the constraint label says of it."""
    keep = np.ones(len(front), dtype=bool)
    if extra is None:
        return keep, []
    fails = extra.full_duty_failures(front)
    if fails.all():
        return keep, [
            f"none of the front's {len(fails)} designs passes g13 / g14 / g15 on the full duty "
            "and task: the front is kept as found"
        ]
    if fails.any():
        return ~fails, [
            f"{int(fails.sum())} of the front's {len(fails)} designs removed: they fail "
            "g13, g14 or g15 on the full duty and task"
        ]
    return keep, []


def _search_space(
    formulation: str,
    dataset: pd.DataFrame,
    section: Mapping[str, Any],
    ratio_bounds: Mapping[str, Any],
    fit: FitSettings,
    extra: ExtraConstraints | None,
) -> tuple[NDArray[np.float64], NDArray[np.float64], FitSettings]:
    """NSGA-II's bounds in ``formulation``: the dataset's lengths (m) for ``paper`` (unless
    ``section["bounds"]`` overrides them), the sampled ratios for ``ratios``, whose scale-up
    then holds the task disk grown by the containment tolerance."""
    if formulation == "paper":
        lo, hi = bounds_from(dataset, INPUTS, section["bounds"])
        return lo, hi, fit
    if formulation == "ratios":
        lo = np.array([ratio_bounds[n][0] for n in RATIO_NAMES], dtype=float)
        hi = np.array([ratio_bounds[n][1] for n in RATIO_NAMES], dtype=float)
        if extra is not None:
            fit = replace(fit, safety_margin=fit.safety_margin + extra.tolerance_m)
        return lo, hi, fit
    raise ValueError(f"config key 'optimization.formulations': unknown '{formulation}'")


def _paper_infeasible(n_designs: int) -> str:
    """Why NSGA-II may find no design that meets the paper's g1..g10, and what to change."""
    return (
        f"NSGA-II found no design that meets the paper's g1..g10 (the surrogate's predictions "
        f"positive and within optimization.z standard deviations of the mean of its training "
        f"labels) after optimization.generations: with {n_designs} designs in the dataset the "
        f"surrogate and that band may be too poor; raise config key 'sampling.n_mechanisms' "
        f"(or optimization.generations)"
    )


def _with_drive_mass(
    extra: ExtraConstraints | None, objectives: Sequence[Any]
) -> ExtraConstraints | None:
    """``extra`` with the drive check as the drive-mass objective's, where the objectives ask
    for it (fewer than three: ``drive_mass``); an error naming the key where no check is on."""
    if len(objectives) >= 3:
        return extra
    if extra is None or extra.drives is None:
        raise ValueError(
            "config key 'optimization.objectives': drive_mass needs the drive check of "
            "optimization.constraints.drives"
        )
    return replace(extra, drive_mass=extra.drives)


def _objective_range(
    dataset: pd.DataFrame, objectives: Sequence[Any]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The dataset's lowest and highest value of each objective (a constant spans 1): the
    hypervolume's normalisation."""
    labels = dataset[[o.dataset for o in objectives]].to_numpy(float)
    lower, upper = np.nanmin(labels, axis=0), np.nanmax(labels, axis=0)
    return lower, np.where(upper > lower, upper, lower + 1.0)


def optimize(
    formulation: str,
    model: Surrogate,
    dataset: pd.DataFrame,
    section: Mapping[str, Any],
    fit: FitSettings,
    ratio_bounds: Mapping[str, Any],
    extra: ExtraConstraints | None = None,
    progress: Callable[[int, float], None] | None = None,
    start: tuple[NDArray, int] | None = None,
) -> FrontTables:
    """Run NSGA-II in the given formulation (``paper`` or ``ratios``) and tabulate the results.

    ``dataset`` (status-ok rows) gives the paper formulation's bounds (unless ``section["bounds"]``
    overrides them) and the objective range that normalises the hypervolume. ``extra`` switches
    g11..g14 on (None: the paper's g1..g10 only); when no design meets them, g12, g14 and then
    g13 are dropped and the constraint label says so. ``section["objectives"]`` (default
    ``torques``) picks the objectives; ``drive_mass`` takes its drives from ``extra.drives``.
    ``start``: a first population (a former run's ``population``) and the generations to run
    from it (None: random, ``section["generations"]``).
    """
    stats = LabelStats.of(model, section["z"])
    objectives = OBJECTIVE_SETS[section.get("objectives", "torques")]
    extra = _with_drive_mass(extra, objectives)
    objective_range = _objective_range(dataset, objectives)
    lo, hi, fit = _search_space(formulation, dataset, section, ratio_bounds, fit, extra)

    def make(extra: ExtraConstraints | None) -> Problem:
        if formulation == "paper":
            return PaperProblem(model, lo, hi, stats, extra)
        return RatiosProblem(model, lo, hi, stats, fit, extra)

    initial, n_gen = (None, section["generations"]) if start is None else start

    def run(problem: Problem) -> OptimizationResult:
        return run_nsga2(
            problem, section["pop_size"], n_gen, section["seed"], objective_range, progress,
            initial,
        )  # fmt: skip

    label = extra.label(formulation) if extra is not None else "g1..g10 (the paper's)"
    extra, dropped = _stiffness_in_reach(extra, dataset)
    result, problem, extra = _relaxing(make, run, extra, formulation, dropped, len(dataset))

    def lengths(x: NDArray) -> NDArray:
        return problem.designs(x)[0] if isinstance(problem, RatiosProblem) else x

    front = lengths(result.pareto_x)
    keep, notes = _full_duty_check(extra, front)
    dropped += notes
    if dropped:
        label = "; ".join([extra.label(formulation), *dropped])
    pareto = _design_table(front[keep], result.pareto_p[keep], result.pareto_f[keep], objectives)
    generations = _generation_tables(result, n_gen, lengths, objectives)
    n = len(result.hypervolume)
    history = pd.DataFrame({"generation": np.arange(1, n + 1), "hypervolume": result.hypervolume})
    return FrontTables(pareto, generations, history, label, result.last_populations[-1]["X"])


def _relaxing(
    make: Callable[[ExtraConstraints | None], Problem],
    run: Callable[[Problem], OptimizationResult],
    extra: ExtraConstraints | None,
    formulation: str,
    dropped: list[str],
    n_designs: int,
) -> tuple[OptimizationResult, Problem, ExtraConstraints | None]:
    """NSGA-II on ``make(extra)``; where no design met g12 (a far task, a small printer), g15,
    g14 (a task no drive of the catalogue serves) or g13 (a heavy task), again without it (in
    that order, the least important first), each note appended to ``dropped``. Returns the
    result, the problem it solved and the constraints it kept."""
    problem = make(extra)
    while True:
        try:
            return run(problem), problem, extra
        except InfeasibleProblem as exc:
            names = extra.names(formulation) if extra is not None else ()
            least = exc.least(names, (G13, G14, G15))
            unmet = [n for n in (G12, G15, G14, G13) if least.get(n, 0.0) > 0]
            if extra is None or not unmet:
                raise InfeasibleProblem(exc.violation, _paper_infeasible(n_designs)) from None
            extra, note = _relaxed(extra, unmet[0], least)
            dropped.append(note)
            problem = make(extra)


def _generation_tables(
    result: OptimizationResult,
    n_generations: int,
    lengths: Callable[[NDArray], NDArray],
    objectives: tuple[Objective, ...],
) -> pd.DataFrame:
    """The last populations of ``result`` as one table: each design's lengths (m), predictions
    and objectives, its generation, whether it was feasible and its total violation."""
    generations = []
    first = n_generations - len(result.last_populations) + 1
    for offset, pop in enumerate(result.last_populations):
        table = _design_table(lengths(pop["X"]), pop["P"], pop["F"], objectives)
        table.insert(0, "generation", first + offset)
        table["feasible"] = np.all(pop["G"] <= 0, axis=1)
        table["constraint_violation"] = np.clip(pop["G"], 0.0, None).sum(axis=1)
        generations.append(table)
    return pd.concat(generations, ignore_index=True)
