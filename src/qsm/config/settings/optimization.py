"""Settings of Stage 4: one formulation's front, its extra constraints g11-g15, its surrogate and
infill, and the true check of its designs (the rules ``optimize`` and ``verify_pareto``)."""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from typing import Any

import pandas as pd

from qsm.config.sections import applied_constraints, canonical
from qsm.config.settings.actuation import drive_check
from qsm.config.settings.links import load_case_of, sag_check, strength_check
from qsm.config.settings.physics import fit
from qsm.config.settings.surrogate import surrogate
from qsm.embodiment.drives.drive_checks import DriveCheck
from qsm.embodiment.load_case import LoadCase
from qsm.embodiment.stiffness.sag_check import SagCheck
from qsm.embodiment.strength.link_checks import StrengthCheck
from qsm.mechanisms.scale import FitSettings
from qsm.optimization.constraint_set import (
    LOOP_ALLOWANCE,
    LOOP_SAG_POINTS,
    ExtraConstraints,
    loop_duty,
)
from qsm.optimization.infill import InfillSettings
from qsm.optimization.verify import verify_front
from qsm.physics.cad import DEFAULT_CAD
from qsm.physics.task_points import design_task, visited_points
from qsm.surrogate.model import SurrogateSettings

Section = Mapping[str, Any]


def infill(section: Section) -> InfillSettings:
    """``surrogate.infill``: the rounds of true evaluations and refits after NSGA-II."""
    return InfillSettings(**section["infill"])


#: The ``optimization`` keys that are not NSGA-II's own: which fronts run, and g11-g15.
NOT_NSGA = ("formulation", "formulations", "constraints")


@dataclasses.dataclass(frozen=True)
class FrontSettings:
    """One formulation's front: NSGA-II's ``optimization`` keys (``nsga``), the scale-up
    (``fit``), the extra constraints, the surrogate's training and infill, and the true check
    of the front's designs (links, drives and the tool's sag at the task's design points;
    Table 1's ratio bounds; the printer's build volume in mm)."""

    formulation: str
    nsga: Mapping[str, Any]
    fit: FitSettings
    extra: ExtraConstraints
    training: SurrogateSettings
    infill: InfillSettings
    strength: StrengthCheck
    drives: DriveCheck
    sag: SagCheck
    ratio_bounds: Mapping[str, Any]
    build_volume_mm: tuple[float, ...]

    def verify(self, designs: pd.DataFrame) -> pd.DataFrame:
        """``designs`` (lengths in m and predictions) with their true values and checks
        (:func:`qsm.optimization.verify.verify_front`)."""
        return verify_front(
            designs,
            self.fit,
            self.strength,
            self.ratio_bounds,
            self.build_volume_mm,
            self.drives,
            self.sag,
        )


def front_of(config: Section, formulation: str) -> FrontSettings:
    """Stage 4's settings for ``formulation`` from a validated config, or from its share of one
    (:func:`qsm.config.sections.optimization_section`, the rules' param)."""
    points = design_task(config["task"]["points"])[1]
    scale_up = fit(
        config["operating_range"], points, config["scale"], config["workspace"], config["filters"]
    )
    case = load_case_of(config)
    tolerance_mm = config["task"]["tolerance_mm"]
    return FrontSettings(
        formulation=formulation,
        nsga=canonical({k: v for k, v in config["optimization"].items() if k not in NOT_NSGA}),
        fit=scale_up,
        extra=_extra(config, formulation, scale_up, case, points),
        training=surrogate(config["surrogate"]),
        infill=infill(config["surrogate"]),
        strength=strength_check(case, config["strength"]),
        drives=drive_check(config["drives"], case),
        sag=sag_check(case, points, tolerance_mm),
        ratio_bounds=canonical(config["sampling"]["bounds"]),
        build_volume_mm=tuple(config["printing"]["build_volume_mm"]),
    )


def _extra(
    config: Section, formulation: str, fit_settings: FitSettings, case: LoadCase, points: Any
) -> ExtraConstraints:
    """``optimization.constraints`` as they apply to ``formulation``
    (:func:`~qsm.config.sections.applied_constraints`). g13 and g14 run on the optimisation's
    coarser duty (:func:`qsm.optimization.constraint_set.loop_duty`) and g15 on a coarse set of
    the task ``points`` (m), and the front's final check on the full duty and every point."""
    section = applied_constraints(config["optimization"]["constraints"], formulation)
    strong, drives = section["strong"], section["drives"]
    checks: dict[str, Any] = {}  # g13 and g14 on the loop's duty, and on the full duty
    if strong or drives:
        for name, duty_settings in (("full", case.duty), ("loop", loop_duty(case.duty))):
            each = case.with_duty(duty_settings)
            if drives:
                checks[f"{name}_drives"] = drive_check(config["drives"], each)
            if strong:
                checks[f"{name}_strength"] = strength_check(each, config["strength"])
    check = checks.get("loop_strength")
    if check is not None and check.sizing is not None:  # sized within g13's allowance
        target = check.sizing.target / (1 + LOOP_ALLOWANCE)
        check = dataclasses.replace(check, sizing=dataclasses.replace(check.sizing, target=target))
    stiff = section["stiff"]
    sags = _sag_checks(case, points, config["task"]["tolerance_mm"]) if stiff else {}
    return ExtraConstraints(
        containment=section["containment"],
        printable=section["printable"],
        fit=fit_settings,
        cad=case.cad if section["printable"] else DEFAULT_CAD,
        volume_mm=tuple(config["printing"]["build_volume_mm"]),
        tolerance_m=float(section.get("containment_tolerance_m", 0.0)),
        strength=check,
        drives=checks.get("loop_drives"),
        full_strength=checks.get("full_strength"),
        full_drives=checks.get("full_drives"),
        **sags,
    )


def _sag_checks(case: LoadCase, points: Any, tolerance_mm: float) -> dict[str, Any]:
    """g15 on a coarse set of the task ``points`` (m; the loop's) and on all of them (the
    front's)."""
    coarse = [points[k] for k in visited_points(points, LOOP_SAG_POINTS)]
    return {
        "sag": sag_check(case, coarse, tolerance_mm),
        "full_sag": sag_check(case, points, tolerance_mm),
    }
