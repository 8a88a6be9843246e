"""The realised machine as one record: :class:`~qsm.realization.selection.pipeline.Realization` to
JSON and back.

The rule ``select_design`` realises the chosen design once
(:func:`~qsm.realization.selection.pipeline.realize`) and writes :func:`machine_record` to
``realization/machine.json``. Every later rule (the plates, the kit, the cycle, the final budget)
rebuilds the same realisation from that file
with :func:`realization_from_record` instead of realising again: the record holds what the
realisation computed (sections, strength, bearings, drives, the tolerance's choice), and the
settings the rule is given hold the rest. The bored solid parts are rebuilt from the record's
bearings and sections (geometry, no check). Floats travel as their shortest repr, so the
rebuilt realisation equals the one realised; a non-finite figure is written as null and read
back as NaN.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import replace
from typing import Any

import numpy as np

from qsm.embodiment.drives.report import report_json, report_of
from qsm.embodiment.kit.joints import ToolFlange
from qsm.embodiment.parts.link_parts import link_parts
from qsm.embodiment.strength.record import strength_json, strength_of
from qsm.embodiment.strength.sizing import SizedSections, SizingSettings
from qsm.realization.accuracy.accuracy_sizing import AccuracyChoice
from qsm.realization.selection.pipeline import (
    FixedPoint,
    Realization,
    RealizationSettings,
    carrying,
)

#: The record's version: a reader refuses a record of another.
VERSION = 3


def _finite_or_none(value: float) -> float | None:
    return float(value) if math.isfinite(value) else None


def _nan_if_none(value: float | None) -> float:
    return math.nan if value is None else float(value)


def _sizing_record(sizing: SizingSettings | None) -> dict[str, Any] | None:
    """The sizing bounds the realisation ended with (m), its floor (section scales) included."""
    if sizing is None:
        return None
    return {
        "width_m": list(sizing.width_m),
        "thickness_m": list(sizing.thickness_m),
        "max_iterations": sizing.max_iterations,
        "tolerance": sizing.tolerance,
        "target": sizing.target,
        "floor": None if sizing.floor is None else list(sizing.floor),
    }


def _sizing_of(data: Mapping[str, Any] | None) -> SizingSettings | None:
    if data is None:
        return None
    floor = data["floor"]
    return SizingSettings(
        width_m=tuple(data["width_m"]),
        thickness_m=tuple(data["thickness_m"]),
        max_iterations=int(data["max_iterations"]),
        tolerance=float(data["tolerance"]),
        target=float(data["target"]),
        floor=None if floor is None else tuple(float(f) for f in floor),
    )


def _accuracy_record(choice: AccuracyChoice) -> dict[str, Any]:
    return {
        "section_scale": choice.scale.tolist(),
        "min_gearbox_stiffness_Nm_rad": list(choice.min_stiffness_Nm_rad),
        "structure_mm": _finite_or_none(choice.structure_mm),
        "target_mm": _finite_or_none(choice.target_mm),
        "meets_target": choice.meets,
        "stopped_at": list(choice.stopped_at),
    }


def _accuracy_of(data: Mapping[str, Any]) -> AccuracyChoice:
    k1, k2 = (float(k) for k in data["min_gearbox_stiffness_Nm_rad"])
    return AccuracyChoice(
        scale=np.asarray(data["section_scale"], dtype=float),
        min_stiffness_Nm_rad=(k1, k2),
        structure_mm=_nan_if_none(data["structure_mm"]),
        target_mm=_nan_if_none(data["target_mm"]),
        meets=data["meets_target"],
        stopped_at=tuple(data["stopped_at"]),
    )


def machine_record(done: Realization) -> dict[str, Any]:
    """``machine.json``: the realised design ``done`` as JSON-ready values (lengths m, section
    scales on the configured section, bearings as rows of the bearing table, joints A-D)."""
    sections = done.sections
    return {
        "version": VERSION,
        "design_m": done.design.tolist(),
        "section_scale": None if done.scale is None else list(done.scale),
        "sizing": _sizing_record(done.strength_check.sizing),
        "sizing_iterations": None if sections is None else int(sections.iterations[0]),
        "bearing_rows": [int(r) for r in done.bearing_rows],
        "tolerance_choice": _accuracy_record(done.accuracy),
        "strength": strength_json(done.strength),
        "drives": report_json(done.drives),
        "tool_flange": {} if done.tool_flange is None else done.tool_flange.record(),
        "fixed_point": fixed_point_record(done.fixed_point),
        "torque_limits_Nm": list(done.torque_limits_Nm),
    }


def fixed_point_record(point: FixedPoint) -> dict[str, Any]:
    """The realisation loop's end: the tool flange's mass (kg) each realisation carried, their
    number, and whether the last flange changed it by at most the tolerance."""
    return {
        "tool_kg": list(point.tool_kg),
        "iterations": point.iterations,
        "converged": point.converged,
    }


def realization_from_record(data: Mapping[str, Any], settings: RealizationSettings) -> Realization:
    """The :class:`Realization` that :func:`machine_record` wrote, under the same ``settings``
    the realisation ran with; ``ValueError`` for a record of another version."""
    if data.get("version") != VERSION:
        raise ValueError(
            f"machine.json is of version {data.get('version')}, this code reads {VERSION}: "
            "rerun the rule select_design"
        )
    d = np.asarray(data["design_m"], dtype=float)
    scale = None if data["section_scale"] is None else tuple(map(float, data["section_scale"]))
    tool_kg = [float(m) for m in data["fixed_point"]["tool_kg"]]
    carried = carrying(settings, tool_kg[-1]).strength  # the check ran with the tool flange
    check = replace(carried, sizing=_sizing_of(data["sizing"]))
    sections = None
    if scale is not None:
        iterations = np.array([int(data["sizing_iterations"])], dtype=np.intp)
        sections = SizedSections(np.asarray(scale, dtype=float)[None], iterations)
    part_settings = replace(settings.parts, scale=scale)
    rows = [int(r) for r in data["bearing_rows"]]
    return Realization(
        design=d,
        scale=scale,
        strength=strength_of(data["strength"]),
        drives=report_of(data["drives"]),
        bearing_rows=rows,
        part_settings=part_settings,
        parts=link_parts(d, rows, part_settings),
        accuracy=_accuracy_of(data["tolerance_choice"]),
        strength_check=check,
        sections=sections,
        tool_flange=ToolFlange.of(data["tool_flange"]) if data["tool_flange"] else None,
        fixed_point=FixedPoint(tuple(tool_kg), bool(data["fixed_point"]["converged"])),
        torque_limits_Nm=tuple(float(t) for t in data["torque_limits_Nm"]),
    )
