"""Stage 4: NSGA-II (pymoo) on the surrogate with the paper's constraints g1..g10 (Section 2.4)
and four of ours, g11 (the task lies in the workspace), g12 (every link fits the printer),
g13 (every link holds its loads) and g14 (each motor has a drive you can buy).

Objectives, all minimised (``optimization.objectives``): ``torques``, (eta', tau1', tau2'), the
surrogate's predictions (the paper's); or ``drive_mass``, (eta', total mass of both motors'
drives in kg), the drives chosen on the true closed-chain duty with g14's loads
(:meth:`qsm.embodiment.drives.drive_checks.DriveCheck.mass_objective`: a design without a drive for
each motor gets a penalty mass plus its g14 violation). Every evaluation also records the
surrogate's predictions as ``P`` (N, 3), which the front's tables keep. Constraints in pymoo's ``G
<= 0`` form:

* g1..g3: eta' > 0, tau1' > 0, tau2' > 0  ->  ``-eta'``, ``-tau1'``, ``-tau2'``;
* g4: crank-rocker l3 + l2 < l1 + l4      ->  ``l3 + l2 - l1 - l4``;
* g5..g10: each prediction within mean +- z std of its training labels (z = 1.95)
  ->  ``(mean - z std) - y'`` and ``y' - (mean + z std)``.

* g11 (paper formulation, ``constraints.containment``): the task disk grown by
  ``containment_tolerance_m`` lies in the workspace at scale l1, so the task keeps that Euclidean
  clearance from the workspace's edge; the violation is the arc-length margin of the grown disk
  (:mod:`qsm.optimization.constraints`, metres; its sign is exact, its size a measure);
* g12 (every formulation, ``constraints.printable``): every link's box fits the build volume
  (:mod:`qsm.optimization.constraints`, millimetres);
* g13 (every formulation, ``constraints.strong``): every link holds its loads over the duty, the
  largest strength utilisation less 1, from the true closed-chain loads of the design
  (:mod:`qsm.embodiment.strength.link_checks`);
* g14 (every formulation, ``constraints.drives``): each motor has a drive in the catalogue that
  meets its duty, the larger motor's least violation over the catalogue
  (:mod:`qsm.embodiment.drives.drive_checks`, from the same true torques).

g13, g14 and the drive mass are the costly ones (the closed-chain loads of every duty sample):
they are evaluated only for the candidates that meet every other constraint (about half of a
default run's), and the rest, infeasible already, read a large violation there
(:data:`qsm.optimization.constraint_set.NOT_EVALUATED`).

With these switches off the paper formulation is the paper's g1..g10 exactly.

Two formulations: ``paper`` optimises the 6 scaled lengths (the scale l1 free, as in the paper);
``ratios`` optimises the 5 ratios in Table 1 and computes the scale and eta exactly with Stage 1
(task containment guaranteed by the scale, so it has no g11), taking only the torques from the
surrogate.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray
from pymoo.core.problem import Problem

from qsm.mechanisms.filters import kinematic_checks
from qsm.mechanisms.scale import FitSettings, fit_rows
from qsm.optimization.constraint_set import PAPER_CONSTRAINTS, ExtraConstraints
from qsm.physics.kinematics import design_from_ratios
from qsm.surrogate.model import Surrogate


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
    """NSGA-II on the surrogate with g1..g10 and, as ``extra`` says, g11..g14 and the drive-mass
    objective."""

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
        n_obj = 2 if extra is not None and extra.drive_mass is not None else 3
        super().__init__(n_var=len(lower), n_obj=n_obj, n_ieq_constr=n_constr, xl=lower, xu=upper)
        self.model = model
        self.stats = stats
        self.extra = extra

    def fill(self, out: dict, design: NDArray, pred: NDArray, g: NDArray) -> None:
        """Set ``out``'s F (objectives), G (``g``, i.e. g1..g10, with the g11..g14 columns of the
        scaled designs appended) and P (the predictions ``pred``)."""
        out["P"], out["F"], out["G"] = pred, pred, g
        if self.extra is not None:
            cols, mass = self.extra.evaluate(self.formulation, design, g)
            out["G"] = np.column_stack([g, *cols])
            if mass is not None:
                out["F"] = np.column_stack([pred[:, 0], mass])


class PaperProblem(_SurrogateProblem):
    """The paper's problem over the 6 scaled lengths, vectorised over the population; g11 and g12
    as ``extra`` says (none: the paper's g1..g10 exactly)."""

    formulation = "paper"

    def _evaluate(self, x: NDArray, out: dict, *args: Any, **kwargs: Any) -> None:
        pred = self.model.predict(x)
        self.fill(out, x, pred, paper_constraints(x, pred, self.stats))


class RatiosProblem(_SurrogateProblem):
    """Ratios (5) in Table 1; scale and eta exact from Stage 1, torques from the surrogate.

    A design whose loop does not close or whose workspace holds the task at no scale is made
    infeasible through g4 (violation 1), with finite stand-in objectives (eta = 1, torques at the
    training means, the drive mass that of the unit-scale design). ``extra`` adds g12..g14 if on
    (g11 holds by construction).
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
        rows = np.flatnonzero(ok)
        for i, result in zip(rows, fit_rows(ratios[rows], self.fit), strict=True):
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
        self.fill(out, design, pred, g)
