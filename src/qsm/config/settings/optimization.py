"""Settings of the optimisation's extra constraints g11-g14 (Stage 4)."""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from typing import Any

from qsm.config.defaults import default
from qsm.config.settings.actuation import drive_check
from qsm.config.settings.links import sag_check, strength_check
from qsm.config.settings.physics import cad, duty
from qsm.mechanisms.scale import FitSettings
from qsm.optimization.constraint_set import (
    LOOP_ALLOWANCE,
    LOOP_SAG_POINTS,
    ExtraConstraints,
    loop_duty,
)
from qsm.physics.cad import DEFAULT_CAD
from qsm.physics.task_points import visited_points

Section = Mapping[str, Any]


def constraints(section: Section, fit_settings: FitSettings) -> ExtraConstraints:
    """``optimization.constraints`` as one formulation's rule passes it: ``containment``,
    ``printable``, ``strong`` and, when on, ``tolerance_m``, ``cad`` and ``material`` (sections),
    ``build_volume_mm``, for g13 ``strength``, ``payload_kg``, ``duty`` and
    ``operating_range``, and for g14 (``drives``) the ``drives_section`` with ``cad``,
    ``material``, ``payload_kg``, ``duty`` and ``operating_range``, and for g15 (``stiff``)
    ``tolerance_mm`` and ``task_points`` besides. g13 and g14 run on the optimisation's coarser
    duty (:func:`qsm.optimization.constraint_set.loop_duty`) and g15 on a coarse set of the task
    points, and the front's final check on the full duty and every point."""
    printable, strong = bool(section["printable"]), bool(section.get("strong", False))
    drives = bool(section.get("drives", False))
    checks: dict[str, Any] = {}  # g13 and g14 on the loop's duty, and on the full duty
    if strong or drives:
        full = duty(section["duty"], section["operating_range"])
        for name, duty_settings in (("full", full), ("loop", loop_duty(full))):
            if drives:
                checks[f"{name}_drives"] = drive_check(
                    section["drives_section"],
                    section["cad"],
                    section["material"],
                    section["payload_kg"],
                    duty_settings,
                )
            if strong:
                checks[f"{name}_strength"] = strength_check(
                    section["cad"],
                    section["material"],
                    section["strength"],
                    section["payload_kg"],
                    duty_settings,
                )
    check = checks.get("loop_strength")
    if check is not None and check.sizing is not None:  # sized within g13's allowance
        target = check.sizing.target / (1 + LOOP_ALLOWANCE)
        check = dataclasses.replace(check, sizing=dataclasses.replace(check.sizing, target=target))
    sags = _sag_checks(section) if section.get("stiff", False) else {}
    return ExtraConstraints(
        containment=bool(section["containment"]),
        printable=printable,
        fit=fit_settings,
        cad=cad(section["cad"], section["material"]) if printable else DEFAULT_CAD,
        volume_mm=tuple(section.get("build_volume_mm", default("printing.build_volume_mm"))),
        tolerance_m=float(section.get("tolerance_m", 0.0)),
        strength=check,
        drives=checks.get("loop_drives"),
        full_strength=checks.get("full_strength"),
        full_drives=checks.get("full_drives"),
        **sags,
    )


def _sag_checks(section: Section) -> dict[str, Any]:
    """g15 on a coarse set of the task points (the loop's) and on all of them (the front's)."""
    points = section["task_points"]
    coarse = [points[k] for k in visited_points(points, LOOP_SAG_POINTS)]
    args = (section["cad"], section["material"], section["payload_kg"])
    tail = (section["operating_range"], section["tolerance_mm"])
    return {"sag": sag_check(*args, coarse, *tail), "full_sag": sag_check(*args, points, *tail)}
