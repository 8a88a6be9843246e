"""Stage 4: NSGA-II (pymoo) on the surrogate with the paper's constraints g1..g10 (Section 2.4)
and two of ours, g11 (the task lies in the workspace) and g12 (every link fits the printer).

Objectives, all minimised: (eta', tau1', tau2'), the surrogate's predictions. Constraints in
pymoo's ``G <= 0`` form:

* g1..g3: eta' > 0, tau1' > 0, tau2' > 0  ->  ``-eta'``, ``-tau1'``, ``-tau2'``;
* g4: crank-rocker l3 + l2 < l1 + l4      ->  ``l3 + l2 - l1 - l4``;
* g5..g10: each prediction within mean +- z std of its training labels (z = 1.95)
  ->  ``(mean - z std) - y'`` and ``y' - (mean + z std)``.

* g11 (paper formulation, ``constraints.containment``): the task disk lies in the workspace at
  scale l1 with ``containment_tolerance_m`` of arc to spare (:mod:`qsm.optimisation.constraints`,
  metres);
* g12 (every formulation, ``constraints.printable``): every link's box fits the build volume
  (:mod:`qsm.optimisation.constraints`, millimetres).

With both switches off the paper formulation is the paper's g1..g10 exactly.

Two formulations: ``paper`` optimises the 6 scaled lengths (the scale l1 free, as in the paper);
``ratios`` optimises the 5 ratios in Table 1 and computes the scale and eta exactly with Stage 1
(task containment guaranteed by the scale, so it has no g11), taking only the torques from the
surrogate.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
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

from qsm.mechanisms.dataset import cad_settings
from qsm.mechanisms.filters import kinematic_checks
from qsm.mechanisms.scale import FitSettings, fit_design
from qsm.optimisation.constraints import containment_margin_m, printability_violation_mm
from qsm.physics.cad import CadSettings
from qsm.physics.kinematics import RATIO_NAMES, design_from_ratios
from qsm.surrogate.model import INPUTS, Surrogate

PAPER_CONSTRAINTS: tuple[str, ...] = (
    "g1_eta_positive",
    "g2_tau1_positive",
    "g3_tau2_positive",
    "g4_crank_rocker",
    "g5_eta_low",
    "g6_eta_high",
    "g7_tau1_low",
    "g8_tau1_high",
    "g9_tau2_low",
    "g10_tau2_high",
)
G11 = "g11_task_contained"
G12 = "g12_printable"


@dataclass(frozen=True)
class ExtraConstraints:
    """g11 and g12: which are on and what they need.

    ``containment`` (g11, paper formulation only) with ``tolerance_m`` of arc to spare (m) on the
    task disk of ``fit`` (the ratios formulation holds the task by its scale, fitted to the disk
    grown by ``tolerance_m``); ``printable`` (g12) for the link section ``cad`` and the printer
    ``volume_mm`` (W, L, H in mm).
    """

    containment: bool
    printable: bool
    fit: FitSettings
    cad: CadSettings
    volume_mm: tuple[float, float, float]
    tolerance_m: float = 0.001

    @classmethod
    def from_settings(cls, settings: Mapping[str, Any], fit: FitSettings) -> ExtraConstraints:
        """From the rule's ``constraints`` params: ``containment``, ``printable`` and, when on,
        ``tolerance_m``, ``cad`` (config section) and ``build_volume_mm``."""
        printable = bool(settings["printable"])
        return cls(
            containment=bool(settings["containment"]),
            printable=printable,
            fit=fit,
            cad=cad_settings(settings["cad"]) if printable else CadSettings(),
            volume_mm=tuple(settings.get("build_volume_mm", (600.0, 350.0, 350.0))),
            tolerance_m=float(settings.get("tolerance_m", 0.0)),
        )

    def names(self, formulation: str) -> tuple[str, ...]:
        """Constraint columns of ``formulation`` in order: g1..g10, then g11 and g12 if on."""
        extra = (G11,) if self.containment and formulation == "paper" else ()
        return PAPER_CONSTRAINTS + extra + ((G12,) if self.printable else ())

    def label(self, formulation: str) -> str:
        """Human-readable constraint set, e.g. 'g1..g10 (the paper's) + g12 printable'."""
        names = self.names(formulation)
        text = "g1..g10 (the paper's)"
        spare = f"{1e3 * self.tolerance_m:g} mm to spare"
        if G11 in names:
            text += f" + g11 task contained ({spare})"
        elif formulation == "ratios":
            text += f" + task contained by the scale ({spare})"
        if G12 in names:
            volume = " x ".join(f"{v:g}" for v in self.volume_mm)
            text += f" + g12 printable on {volume} mm"
        return text

    def columns(self, formulation: str, design: NDArray[np.float64]) -> list[NDArray]:
        """The g11 / g12 columns (``G <= 0``) for scaled designs (N, 6)."""
        cols = []
        if self.containment and formulation == "paper":
            disk = self.fit.disk
            inflated = type(disk)(disk.centre, disk.radius + self.fit.safety_margin)
            margin = containment_margin_m(
                design, self.fit.op, inflated, self.fit.resolution.n_delta
            )
            cols.append(self.tolerance_m - margin)
        if self.printable:
            cols.append(printability_violation_mm(design, self.cad, self.volume_mm))
        return cols


@dataclass(frozen=True)
class LabelStats:
    """Mean and standard deviation of the training labels (eta, tau1, tau2) and z."""

    mean: NDArray[np.float64]
    std: NDArray[np.float64]
    z: float = 1.95

    @classmethod
    def of(cls, model: Surrogate, z: float) -> LabelStats:
        """The statistics of the labels ``model`` was trained on."""
        return cls(model.label_mean, model.label_std, z)


def paper_constraints(
    design: NDArray[np.float64], pred: NDArray[np.float64], stats: LabelStats
) -> NDArray[np.float64]:
    """g1..g10 as ``G <= 0`` for designs (N, 6) of lengths and predictions (N, 3)."""
    l1, l2, l3, l4 = design[:, 0], design[:, 1], design[:, 2], design[:, 3]
    lo = stats.mean - stats.z * stats.std
    hi = stats.mean + stats.z * stats.std
    cols = [-pred[:, 0], -pred[:, 1], -pred[:, 2], l3 + l2 - l1 - l4]
    for j in range(3):
        cols += [lo[j] - pred[:, j], pred[:, j] - hi[j]]
    return np.column_stack(cols)


class _SurrogateProblem(Problem):
    """NSGA-II on the surrogate with g1..g10 and, as ``extra`` says, g11 / g12."""

    formulation = ""

    def __init__(
        self,
        model: Surrogate,
        lower: NDArray,
        upper: NDArray,
        stats: LabelStats,
        extra: ExtraConstraints | None = None,
    ) -> None:
        n_constr = len(extra.names(self.formulation)) if extra else len(PAPER_CONSTRAINTS)
        super().__init__(n_var=len(lower), n_obj=3, n_ieq_constr=n_constr, xl=lower, xu=upper)
        self.model = model
        self.stats = stats
        self.extra = extra

    def with_extra(self, design: NDArray, g: NDArray) -> NDArray:
        """``g`` (g1..g10) with the g11 / g12 columns of the scaled designs appended."""
        if self.extra is None:
            return g
        return np.column_stack([g, *self.extra.columns(self.formulation, design)])


class PaperProblem(_SurrogateProblem):
    """The paper's problem over the 6 scaled lengths, vectorised over the population; g11 and g12
    as ``extra`` says (none: the paper's g1..g10 exactly)."""

    formulation = "paper"

    def _evaluate(self, x: NDArray, out: dict, *args: Any, **kwargs: Any) -> None:
        pred = self.model.predict(x)
        out["F"] = pred
        out["G"] = self.with_extra(x, paper_constraints(x, pred, self.stats))


class RatiosProblem(_SurrogateProblem):
    """Ratios (5) in Table 1; scale and eta exact from Stage 1, torques from the surrogate.

    A design whose loop does not close or whose workspace holds the task at no scale is made
    infeasible through g4 (violation 1), with finite stand-in objectives (eta = 1, torques at the
    training means). ``extra`` adds g12 if on (g11 holds by construction).
    """

    formulation = "ratios"

    def __init__(
        self,
        model: Surrogate,
        lower: NDArray,
        upper: NDArray,
        stats: LabelStats,
        fit: FitSettings,
        extra: ExtraConstraints | None = None,
    ) -> None:
        super().__init__(model, lower, upper, stats, extra)
        self.fit = fit

    def designs(self, ratios: NDArray) -> tuple[NDArray, NDArray, NDArray]:
        """Scaled designs (N, 6), exact eta (N,) and a feasibility mask for ratios (N, 5)."""
        n = len(ratios)
        scale = np.full(n, np.nan)
        eta = np.full(n, np.nan)
        checks = kinematic_checks(ratios, self.fit.op, self.fit.min_transmission_angle_deg)
        ok = np.logical_and.reduce(list(checks.values()))
        for i in np.flatnonzero(ok):
            result = fit_design(ratios[i], self.fit)
            if result["feasible"]:
                scale[i], eta[i] = result["scale_m"], result["eta"]
        feasible = np.isfinite(scale)
        return design_from_ratios(ratios, np.where(feasible, scale, 1.0)), eta, feasible

    def _evaluate(self, x: NDArray, out: dict, *args: Any, **kwargs: Any) -> None:
        design, eta, feasible = self.designs(x)
        pred = self.model.predict(design)
        pred[:, 0] = np.where(feasible, eta, 1.0)
        pred[~feasible, 1:] = self.stats.mean[1:]
        g = paper_constraints(design, pred, self.stats)
        g[:, 3] = np.where(feasible, g[:, 3], 1.0)
        out["F"] = pred
        out["G"] = self.with_extra(design, g)


@dataclass
class Recorder(Callback):
    """Per generation: hypervolume of the feasible non-dominated set (normalised objectives);
    the last ``keep`` populations (X, F, G). Replaces pymoo's ``save_history``, which deep-copies
    the algorithm every generation."""

    lower: NDArray[np.float64]
    upper: NDArray[np.float64]
    keep: int = 3
    progress: Callable[[int, float], None] | None = None
    hypervolume: list[float] = field(default_factory=list)
    populations: list[dict[str, NDArray]] = field(default_factory=list)

    def __post_init__(self) -> None:
        super().__init__()
        self._hv = HV(ref_point=np.full(3, 1.1))

    def notify(self, algorithm: Any) -> None:
        pop = algorithm.pop
        x, f, g = pop.get("X"), pop.get("F"), pop.get("G")
        feasible = np.all(g <= 0, axis=1)
        norm = (f[feasible] - self.lower) / (self.upper - self.lower)
        self.hypervolume.append(float(self._hv(norm)) if len(norm) else 0.0)
        self.populations.append({"X": x.copy(), "F": f.copy(), "G": g.copy()})
        del self.populations[: -self.keep]
        if self.progress is not None:
            self.progress(algorithm.n_gen, self.hypervolume[-1])


@dataclass(frozen=True)
class OptimisationResult:
    """Pareto designs, the last populations and the hypervolume history."""

    pareto_x: NDArray[np.float64]
    pareto_f: NDArray[np.float64]
    last_populations: list[dict[str, NDArray]]
    hypervolume: list[float]


class InfeasibleProblem(RuntimeError):
    """NSGA-II ended with no feasible design; ``least`` is the smallest violation of each
    constraint in the last population (0 where some design met it)."""

    def __init__(self, least: NDArray[np.float64]) -> None:
        super().__init__("NSGA-II found no feasible design")
        self.least = least


def run_nsga2(
    problem: Problem,
    pop_size: int,
    generations: int,
    seed: int,
    objective_range: tuple[NDArray, NDArray],
    progress: Callable[[int, float], None] | None = None,
) -> OptimisationResult:
    """Run NSGA-II for ``generations`` with a recorder; ``objective_range`` normalises the HV."""
    recorder = Recorder(*objective_range, progress=progress)
    result = minimize(
        problem,
        NSGA2(pop_size=pop_size),
        ("n_gen", generations),
        seed=seed,
        callback=recorder,
        verbose=False,
    )
    if result.opt is None or result.X is None:
        g = recorder.populations[-1]["G"]
        raise InfeasibleProblem(np.clip(g, 0.0, None).min(axis=0))
    return OptimisationResult(
        pareto_x=np.atleast_2d(result.opt.get("X")),
        pareto_f=np.atleast_2d(result.opt.get("F")),
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


PREDICTION_COLUMNS: tuple[str, ...] = ("eta_pred", "tau1_pred_Nm", "tau2_pred_Nm")


@dataclass(frozen=True)
class FrontTables:
    """What an optimisation writes: the Pareto designs, the last generations, the HV history."""

    pareto: pd.DataFrame
    last_generations: pd.DataFrame
    hypervolume: pd.DataFrame
    constraints: str = ""


def _design_table(design: NDArray, objectives: NDArray) -> pd.DataFrame:
    table = pd.DataFrame(design, columns=list(INPUTS))
    table.insert(0, "scale_m", design[:, 0])
    for j, name in enumerate(RATIO_NAMES, start=1):
        table[name] = design[:, j] / design[:, 0]
    for j, name in enumerate(PREDICTION_COLUMNS):
        table[name] = objectives[:, j]
    return table


def optimise(
    formulation: str,
    model: Surrogate,
    dataset: pd.DataFrame,
    section: Mapping[str, Any],
    fit: FitSettings,
    ratio_bounds: Mapping[str, Any],
    extra: ExtraConstraints | None = None,
    progress: Callable[[int, float], None] | None = None,
) -> FrontTables:
    """Run NSGA-II in the given formulation (``paper`` or ``ratios``) and tabulate the results.

    ``dataset`` (status-ok rows) gives the paper formulation's bounds (unless ``section["bounds"]``
    overrides them) and the objective range that normalises the hypervolume. ``extra`` switches
    g11 / g12 on (None: the paper's g1..g10 only).
    """
    stats = LabelStats.of(model, section["z"])
    labels = dataset[["eta", "tau1_Nm", "tau2_Nm"]].to_numpy()
    objective_range = (labels.min(axis=0), labels.max(axis=0))
    if formulation == "paper":
        lo, hi = bounds_from(dataset, INPUTS, section["bounds"])
    elif formulation == "ratios":
        lo = np.array([ratio_bounds[n][0] for n in RATIO_NAMES], dtype=float)
        hi = np.array([ratio_bounds[n][1] for n in RATIO_NAMES], dtype=float)
        if extra is not None:  # the scale holds the task disk grown by the tolerance
            fit = replace(fit, safety_margin=fit.safety_margin + extra.tolerance_m)
    else:
        raise ValueError(f"config key 'optimization.formulations': unknown '{formulation}'")

    def make(extra: ExtraConstraints | None) -> Problem:
        if formulation == "paper":
            return PaperProblem(model, lo, hi, stats, extra)
        return RatiosProblem(model, lo, hi, stats, fit, extra)

    def run(problem: Problem) -> OptimisationResult:
        n_gen, seed = section["generations"], section["seed"]
        return run_nsga2(problem, section["pop_size"], n_gen, seed, objective_range, progress)

    label = extra.label(formulation) if extra is not None else "g1..g10 (the paper's)"
    problem = make(extra)
    try:
        result = run(problem)
    except InfeasibleProblem as exc:
        if extra is None or not extra.printable:
            raise
        # no design met g12 (a far task, a small printer): optimise without it, and say so
        excess = float(exc.least[extra.names(formulation).index(G12)])
        extra = replace(extra, printable=False)
        problem = make(extra)
        result = run(problem)
        label = (
            f"{extra.label(formulation)}; g12 dropped: no design printable on "
            f"{' x '.join(f'{v:g}' for v in extra.volume_mm)} mm (least excess in the last "
            f"generation {excess:.0f} mm)"
        )

    def lengths(x: NDArray) -> NDArray:
        return problem.designs(x)[0] if isinstance(problem, RatiosProblem) else x

    pareto = _design_table(lengths(result.pareto_x), result.pareto_f)
    generations = []
    first = section["generations"] - len(result.last_populations) + 1
    for offset, pop in enumerate(result.last_populations):
        table = _design_table(lengths(pop["X"]), pop["F"])
        table.insert(0, "generation", first + offset)
        table["feasible"] = np.all(pop["G"] <= 0, axis=1)
        table["constraint_violation"] = np.clip(pop["G"], 0.0, None).sum(axis=1)
        generations.append(table)
    history = pd.DataFrame(
        {
            "generation": np.arange(1, len(result.hypervolume) + 1),
            "hypervolume": result.hypervolume,
        }
    )
    return FrontTables(pareto, pd.concat(generations, ignore_index=True), history, label)
