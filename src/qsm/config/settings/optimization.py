"""Settings of the optimisation's extra constraints g11-g14 (Stage 4)."""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from typing import Any

from qsm.config.settings.actuation import drive_check
from qsm.config.settings.links import load_case, sag_check, strength_check
from qsm.embodiment.load_case import LoadCase
from qsm.mechanisms.scale import FitSettings
from qsm.optimization.constraint_set import (
    LOOP_ALLOWANCE,
    LOOP_SAG_POINTS,
    ExtraConstraints,
    loop_duty,
)
from qsm.physics.cad import DEFAULT_CAD
from qsm.physics.task_points import visited_points
from qsm.schema.defaults import default

Section = Mapping[str, Any]


def constraints(section: Section, fit_settings: FitSettings) -> ExtraConstraints:
    """``optimization.constraints`` as one formulation's rule passes it: ``containment``,
    ``printable``, ``strong``, ``drives``, ``stiff`` and, when on, ``tolerance_m``,
    ``load_case`` (:func:`qsm.config.settings.links.load_case`), ``build_volume_mm`` (g12),
    ``strength`` (g13), ``drives_section`` (g14), ``tolerance_mm`` and ``task_points`` (g15).
    g13 and g14 run on the optimisation's coarser duty
    (:func:`qsm.optimization.constraint_set.loop_duty`) and g15 on a coarse set of the task
    points, and the front's final check on the full duty and every point."""
    printable, strong = bool(section["printable"]), bool(section.get("strong", False))
    drives = bool(section.get("drives", False))
    case = load_case(section["load_case"]) if "load_case" in section else None
    checks: dict[str, Any] = {}  # g13 and g14 on the loop's duty, and on the full duty
    if strong or drives:
        for name, duty_settings in (("full", case.duty), ("loop", loop_duty(case.duty))):
            each = case.with_duty(duty_settings)
            if drives:
                checks[f"{name}_drives"] = drive_check(section["drives_section"], each)
            if strong:
                checks[f"{name}_strength"] = strength_check(each, section["strength"])
    check = checks.get("loop_strength")
    if check is not None and check.sizing is not None:  # sized within g13's allowance
        target = check.sizing.target / (1 + LOOP_ALLOWANCE)
        check = dataclasses.replace(check, sizing=dataclasses.replace(check.sizing, target=target))
    sags = _sag_checks(section, case) if section.get("stiff", False) else {}
    return ExtraConstraints(
        containment=bool(section["containment"]),
        printable=printable,
        fit=fit_settings,
        cad=case.cad if printable else DEFAULT_CAD,
        volume_mm=tuple(section.get("build_volume_mm", default("printing.build_volume_mm"))),
        tolerance_m=float(section.get("tolerance_m", 0.0)),
        strength=check,
        drives=checks.get("loop_drives"),
        full_strength=checks.get("full_strength"),
        full_drives=checks.get("full_drives"),
        **sags,
    )


def _sag_checks(section: Section, case: LoadCase) -> dict[str, Any]:
    """g15 on a coarse set of the task points (the loop's) and on all of them (the front's)."""
    points, tolerance = section["task_points"], section["tolerance_mm"]
    coarse = [points[k] for k in visited_points(points, LOOP_SAG_POINTS)]
    return {
        "sag": sag_check(case, coarse, tolerance),
        "full_sag": sag_check(case, points, tolerance),
    }
