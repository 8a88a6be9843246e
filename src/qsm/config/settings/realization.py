"""Settings of the realisation of a chosen design (Stage 6, ``qsm export``)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from qsm.config.sections import accuracy_section
from qsm.config.settings.actuation import drive_check
from qsm.config.settings.links import load_case_of, parts, strength_check
from qsm.config.settings.simulation import task_motion
from qsm.embodiment.load_case import LoadCase
from qsm.embodiment.strength.printed import PrintedMaterial
from qsm.physics.task_points import design_task
from qsm.physics.workspace import OperatingRange
from qsm.realization.accuracy.accuracy_budget import AccuracySettings
from qsm.realization.accuracy.iso_record import IsoSettings
from qsm.realization.kit.builders_kit import KitSettings
from qsm.realization.selection.pipeline import KitSizing, RealizationSettings

Section = Mapping[str, Any]


def kit_sizing(section: Section) -> KitSizing:
    """The ``kit`` section's keys of the loop that adds the tool flange's mass."""
    return KitSizing(
        tool_offset_m=float(section["tool_offset_m"]),
        max_iterations=int(section["fixed_point_iterations"]),
        tolerance=float(section["fixed_point_tolerance"]),
        torque_margin=float(section["torque_limit_margin"]),
    )


def accuracy(
    task: Section,
    case: LoadCase,
    points: Sequence[Sequence[float]],
    build_volume_mm: Sequence[float],
) -> AccuracySettings:
    """``task`` (:func:`accuracy_section`): ``tolerance_mm`` and ``min_first_mode_hz``, what the
    design's accuracy must meet; where the realisation builds the design for it
    (``grow_for_tolerance``), the design ``points`` (m), the largest section it may give a link
    (``cad.sized``'s) and the optimised plates' least stiffness factor it sizes them at."""
    return AccuracySettings(
        tolerance_mm=float(task["tolerance_mm"]),
        min_first_mode_hz=task["min_first_mode_hz"],
        points_m=tuple((float(x), float(y)) for x, y in points)
        if task["grow_for_tolerance"]
        else (),
        max_section_scale=case.largest_scale,
        build_volume_mm=tuple(float(v) for v in build_volume_mm),
        plate_factor=float(task["min_stiffness_factor"]),
        printed=printed_material(task["printed_material"]),
    )


def printed_material(section: Section) -> PrintedMaterial:
    """``printed_material``: the orientation, the across-layer factor and the creep law."""
    creep = section["creep"]
    return PrintedMaterial(
        build_orientation=section["build_orientation"],
        across_layers_strength_factor=float(section["across_layers_strength_factor"]),
        service_time_h=float(creep["service_time_h"]),
        creep_coefficient_1000h=float(creep["coefficient_1000h"]),
        creep_exponent=float(creep["exponent"]),
        payload_share=float(creep["payload_share"]),
    )


def realization_of(config: Section) -> RealizationSettings:
    """The realisation's settings from a validated config, or from its share of one
    (:func:`qsm.config.sections.realization_section`, the Stage 6 rules' param): the link check,
    drive check and bored parts of a design under the config's load case, with the ``strength``
    and ``drives`` sections; the accuracy the task needs at its design points (m) and the task's
    motion through them (``payload_test``'s :data:`~qsm.physics.task_points.MOTION_KEYS`), which
    the realisation meets (``task.grow_for_tolerance``, within the printer's build volume) and
    the accuracy budget reports; the ``kit`` section's loop that adds the tool flange's mass."""
    case = load_case_of(config)
    points = design_task(config["task"]["points"])[1]
    return RealizationSettings(
        strength=strength_check(case, config["strength"]),
        drives=drive_check(config["drives"], case),
        parts=parts(case, config["strength"]),
        accuracy=accuracy(
            accuracy_section(config), case, points, config["printing"]["build_volume_mm"]
        ),
        motion=task_motion(config["payload_test"], case.payload_kg, case.operating_range),
        task_points_m=tuple((float(x), float(y)) for x, y in points),
        kit_sizing=kit_sizing(config["kit"]),
    )


def kit(op: OperatingRange, drives: Section, accuracy: AccuracySettings) -> KitSettings:
    """The builder's kit's settings: the motors' operating range ``op``, the ``drives`` section's
    catalogue (where ``interfaces.csv`` is read), and the task's tolerance and the printed
    material of ``accuracy`` (the tool flange is the realisation's: :func:`kit_sizing`)."""
    return KitSettings(
        op,
        drives["catalogue"],
        accuracy.tolerance_mm,
        accuracy.printed,
    )


def iso(section: Section) -> IsoSettings:
    """The ISO 9283 figures' settings from the rules' ``iso`` param (:func:`iso_section`)."""
    return IsoSettings(
        cycles=int(section["cycles"]),
        seed=int(section["seed"]),
        encoder_counts=float(section["encoder_counts"]),
        kp_Nm_rad=tuple(float(k) for k in section["kp_Nm_rad"]),
        repeatability_mm=section["repeatability_mm"],
    )
