"""Settings of the realisation of a chosen design (Stage 6, ``qsm export``)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from qsm.config.settings.actuation import drive_check
from qsm.config.settings.links import load_case_of, parts, strength_check
from qsm.config.settings.simulation import task_motion
from qsm.embodiment.load_case import LoadCase
from qsm.physics.task_points import design_task
from qsm.realization.accuracy.accuracy_budget import AccuracySettings
from qsm.realization.kit.builders_kit import KitSettings
from qsm.realization.selection.pipeline import RealizationSettings

Section = Mapping[str, Any]


def realization(
    case: LoadCase,
    strength: Section,
    drives: Section,
    task: Section,
    motion: Section,
    points: Sequence[Sequence[float]],
    build_volume_mm: Sequence[float],
) -> RealizationSettings:
    """The link check, drive check and bored parts of a design under ``case``, with the
    ``strength`` and ``drives`` sections; the accuracy the ``task`` needs at its design
    ``points`` (m) and the task's ``motion`` through them (``payload_test``'s
    :data:`~qsm.physics.task_points.MOTION_KEYS`), which the realisation meets
    (``task.grow_for_tolerance``, within the printer's ``build_volume_mm``) and the accuracy
    budget reports."""
    (lo, hi), theta2_min = case.operating_range_deg
    op = {"theta1_deg": [lo, hi], "theta2_min_deg": theta2_min}
    return RealizationSettings(
        strength=strength_check(case, strength),
        drives=drive_check(drives, case),
        parts=parts(case, strength),
        accuracy=accuracy(task, case, points, build_volume_mm),
        motion=task_motion(motion, case.payload_kg, op),
        task_points_m=tuple((float(x), float(y)) for x, y in points),
    )


def accuracy(
    task: Section,
    case: LoadCase,
    points: Sequence[Sequence[float]],
    build_volume_mm: Sequence[float],
) -> AccuracySettings:
    """``task.tolerance_mm`` and ``task.min_first_mode_hz``: what the design's accuracy must
    meet; where the realisation builds the design for it (``task.grow_for_tolerance``), the
    design ``points`` (m) and the largest section it may give a link (``cad.sized``'s)."""
    return AccuracySettings(
        tolerance_mm=float(task["tolerance_mm"]),
        min_first_mode_hz=task["min_first_mode_hz"],
        points_m=tuple((float(x), float(y)) for x, y in points)
        if task["grow_for_tolerance"]
        else (),
        max_section_scale=case.largest_scale,
        build_volume_mm=tuple(float(v) for v in build_volume_mm),
    )


def realization_of(config: Section) -> RealizationSettings:
    """:func:`realization` of a whole validated config (``qsm export``, a notebook)."""
    return realization(
        load_case_of(config),
        config["strength"],
        config["drives"],
        config["task"],
        config["payload_test"],
        design_task(config["task"]["points"])[1],
        config["printing"]["build_volume_mm"],
    )


def kit(
    section: Section, operating_range: Section, drives: Section, tolerance_mm: float
) -> KitSettings:
    """The builder's kit's settings: the ``kit`` section, the motors' ``operating_range``, the
    ``drives`` section's catalogue (where ``interfaces.csv`` is read) and the task's
    ``tolerance_mm``."""
    return KitSettings(
        section["tool_offset_m"],
        tuple(operating_range["theta1_deg"]),
        operating_range["theta2_min_deg"],
        drives["catalogue"],
        tolerance_mm,
    )
