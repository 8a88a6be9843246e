"""One realisation of a chosen design, built the same way by the workflow, ``qsm export`` and a
notebook: its link check and sections, bearings, bored parts and drives.

:func:`realize` runs the checks of :class:`RealizationSettings` on one design (6 lengths, m) and
returns a :class:`Realization`: the strength record (:func:`qsm.embodiment.strength.record
.strength_record`), the drive report (:meth:`qsm.embodiment.drives.drive_checks.DriveCheck.report`),
each link's section scale, the bearing rows and the solid bored parts. The rules
``select_design`` and ``topology_optimize`` and :func:`qsm.app.export.export_design` each take
what they write from it, so the command line cannot drift from the workflow.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from qsm.embodiment.drives.drive_checks import DriveCheck
from qsm.embodiment.drives.report import DriveReport
from qsm.embodiment.drives.torque_limits import torque_limits_Nm
from qsm.embodiment.kit.joints import ToolFlange, tool_flange
from qsm.embodiment.parts.link_parts import LinkPart, PartSettings, link_parts
from qsm.embodiment.parts.part_mass import part_mass_properties
from qsm.embodiment.strength.link_checks import StrengthCheck
from qsm.embodiment.strength.loads import Inertials
from qsm.embodiment.strength.record import StrengthRecord, strength_record
from qsm.embodiment.strength.sizing import SizedSections, SizingSettings
from qsm.physics.cad import CadSettings, MassProperties
from qsm.physics.duty import Duty
from qsm.physics.inverse_kinematics import joint_path
from qsm.physics.kinematics import as_design
from qsm.realization.accuracy.accuracy_budget import (
    AccuracySettings,
    ArmModel,
    accuracy_record,
    drive_terms,
    peak_payload_force_N,
    task_motion_duty,
)
from qsm.realization.accuracy.accuracy_sizing import (
    AccuracyChoice,
    accuracy_choice,
    as_realised,
    frame_sections,
)
from qsm.realization.motion.payload import PayloadSettings
from qsm.realization.selection.assembly import bearing_rows
from qsm.schema.defaults import default


@dataclass(frozen=True)
class KitSizing:
    """What the kit adds to the realisation: the loop that puts its moving masses into the
    dynamics (the tool flange at E, ``tool_offset_m`` the payload's centre of mass from its face,
    m; at most ``max_iterations`` realisations, until the mass at E changes by at most
    ``tolerance`` of the payload), and each drive's torque limit, ``torque_margin`` times the
    largest checked torque (:mod:`qsm.embodiment.drives.torque_limits`), which sizes the kit."""

    tool_offset_m: float = default("kit.tool_offset_m")
    max_iterations: int = default("kit.fixed_point_iterations")
    tolerance: float = default("kit.fixed_point_tolerance")
    torque_margin: float = default("kit.torque_limit_margin")


@dataclass(frozen=True)
class FixedPoint:
    """How the realisation's loop ended: the tool flange's mass (kg) each realisation carried at
    E, in order, and whether the flange of the last changed it by at most the tolerance."""

    tool_kg: tuple[float, ...]
    converged: bool

    @property
    def iterations(self) -> int:
        """The realisations the loop ran."""
        return len(self.tool_kg)


@dataclass(frozen=True)
class RealizationSettings:
    """What realising a design takes: the link check (section, material, strength, payload and
    duty), the drive check (catalogue, rule, payload and duty) and the bored parts (section and
    the wall around each bearing seat), the accuracy the task needs and the task's motion (the
    payload test's path through the design's ``task_points_m``, (x, y) m each, along which the
    joints' torques are checked and which the drives meet as well as the duty), and the loop
    that adds the kit's moving masses (``kit_sizing``)."""

    strength: StrengthCheck
    drives: DriveCheck
    parts: PartSettings
    accuracy: AccuracySettings = field(default_factory=AccuracySettings)
    motion: PayloadSettings = field(default_factory=PayloadSettings)
    task_points_m: tuple[tuple[float, float], ...] = ()
    kit_sizing: KitSizing = field(default_factory=KitSizing)


@dataclass(frozen=True)
class Realization:
    """A design as realised: ``scale`` is each link's section factor on the configured one (None
    for the fixed section), ``part_settings`` the bored parts' settings at that scale, ``parts``
    the solid bored links with ``bearing_rows`` (rows of the bearing table, joints A, B, C, D),
    ``accuracy`` what the tolerance asked of its sections and gearboxes, ``strength_check`` and
    ``sections`` the check and sections it was realised with (None: the fixed section), its
    ``tool_flange`` (:func:`qsm.embodiment.kit.joints.tool_flange`), the ``fixed_point`` that
    put the flange's mass into its dynamics and each drive's torque limit (N m at the joint)."""

    design: NDArray[np.float64]
    scale: tuple[float, ...] | None
    strength: StrengthRecord
    drives: DriveReport
    bearing_rows: list[int]
    part_settings: PartSettings
    parts: dict[str, LinkPart]
    accuracy: AccuracyChoice
    strength_check: StrengthCheck
    sections: SizedSections | None
    tool_flange: ToolFlange | None = None
    fixed_point: FixedPoint = FixedPoint((0.0,), True)
    torque_limits_Nm: tuple[float, float] = (0.0, 0.0)

    @property
    def has_drives(self) -> bool:
        """Each motor has a drive of the catalogue that meets its duty."""
        return self.drives.has_drives

    @property
    def tool_kg(self) -> float:
        """The mass (kg) at E beside the payload in the realisation's dynamics: the tool
        flange's."""
        return self.fixed_point.tool_kg[-1]


def carrying(settings: RealizationSettings, extra_kg: float) -> RealizationSettings:
    """``settings`` with ``extra_kg`` (kg) more at E, beside the payload, in the dynamics of the
    link check, the drive check and the task's motion."""

    def heavier(s: Any) -> Any:
        return replace(s, payload_kg=s.payload_kg + extra_kg)

    return replace(
        settings,
        strength=heavier(settings.strength),
        drives=heavier(settings.drives),
        motion=heavier(settings.motion),
    )


def realize(design: ArrayLike, settings: RealizationSettings) -> Realization:
    """:func:`realize_once` of ``design`` (6 lengths, m) with its tool flange at E: from the
    flange for the payload's force on the configured section, each realisation carries the
    flange the one before it chose (sized for the payload's and its own force, fitted to the
    realised boss at E), until the flange's mass changes by at most ``kit_sizing.tolerance`` of
    the payload, or for ``kit_sizing.max_iterations`` realisations (``fixed_point`` says which);
    then each drive's torque limit
    (:func:`qsm.embodiment.drives.torque_limits.torque_limits_Nm`)."""
    d = np.asarray(as_design(design), dtype=float)
    payload, loop = settings.motion.payload_kg, settings.kit_sizing
    flange = _tool_flange(d, settings, payload, math.inf, settings.strength.cad.thickness_m)
    carried: list[float] = []
    for _ in range(loop.max_iterations):
        carried.append(flange.moving_mass_kg)
        done = realize_once(d, carrying(settings, carried[-1]))
        upper = done.parts["upper_arm"]
        boss = next(b.boss_radius_m for b in upper.bores if b.joint == "E")
        flange = _tool_flange(d, settings, payload + carried[-1], boss, upper.section.thickness_m)
        change = abs(flange.moving_mass_kg - carried[-1])
        if change <= loop.tolerance * payload:
            break
    converged = change <= loop.tolerance * payload
    strength = replace(done.strength, payload_kg=payload, tool_flange_kg=carried[-1])
    point = FixedPoint(tuple(carried), converged)
    limits = _torque_limits(done, carrying(settings, carried[-1]))
    return replace(
        done, strength=strength, tool_flange=flange, fixed_point=point, torque_limits_Nm=limits
    )


def _torque_limits(done: Realization, settings: RealizationSettings) -> tuple[float, float]:
    """Each drive's torque limit (:func:`qsm.embodiment.drives.torque_limits.torque_limits_Nm`)
    over the duty and the task's motion of ``done``, with ``settings`` as it was realised."""
    d = done.design
    check = replace(settings.drives, task_duty=_task_duty(d, settings))
    scales = None if done.scale is None else np.asarray(done.scale)[None]
    margin = settings.kit_sizing.torque_margin
    return torque_limits_Nm(done.drives, check, d, scales, margin)


def _tool_flange(
    d: NDArray[np.float64],
    settings: RealizationSettings,
    mass_kg: float,
    boss_m: float,
    thickness_m: float,
) -> ToolFlange:
    """The tool flange (:func:`qsm.embodiment.kit.joints.tool_flange`) that carries ``mass_kg``
    over the duty at E on a boss of radius ``boss_m`` (m) of the upper arm ``thickness_m`` (m)
    thick, at the links' safety factor."""
    du = settings.strength.duty
    force = peak_payload_force_N(d, mass_kg, du.theta, du.dtheta, du.ddtheta)
    sf = settings.strength.strength.safety_factor
    offset = settings.kit_sizing.tool_offset_m
    return tool_flange(force, offset, 1e3 * boss_m, 1e3 * thickness_m, sf)


def realize_once(design: ArrayLike, settings: RealizationSettings) -> Realization:
    """Check and embody ``design`` (6 lengths, m): the sections its links need (sized, or the
    configured one) and the drives, both grown for the tolerance where it asks for more
    (:mod:`qsm.realization.accuracy.accuracy_sizing`), their strength and bearings, and the solid
    bored parts (the accuracy budget at task points: :func:`budget_of`)."""
    d = np.asarray(as_design(design), dtype=float)
    settings = replace(settings, drives=replace(settings.drives, task_duty=_task_duty(d, settings)))
    check, sized, accuracy = _for_accuracy(d, settings)
    scale = None if sized is None else tuple(float(f) for f in sized.scale[0])
    strength = replace(strength_record(d, check, sized), section=_section(settings.strength, check))
    drives = replace(settings.drives, min_stiffness_Nm_rad=accuracy.min_stiffness_Nm_rad)
    report = drives.report(d, None if sized is None else sized.scale)
    realised = np.ones(4) if scale is None else np.asarray(scale)
    accuracy = as_realised(accuracy, d, realised, report, check, settings.accuracy, settings.motion)
    part_settings = replace(settings.parts, scale=scale)
    names = {joint: b.designation for joint, b in strength.bearings.items()}
    rows = bearing_rows(names, part_settings.table)
    return Realization(
        design=d,
        scale=scale,
        strength=strength,
        drives=report,
        bearing_rows=rows,
        part_settings=part_settings,
        parts=link_parts(d, rows, part_settings),
        accuracy=accuracy,
        strength_check=check,
        sections=sized,
    )


def _section(configured: StrengthCheck, check: StrengthCheck) -> str:
    """How the links' sections came about: ``fixed`` (the configured section), ``sized`` (by
    strength), ``grown`` (the configured section grown for the tolerance) or ``sized and
    grown`` (by strength, at least as large as the tolerance asked)."""
    if check.sizing is None:
        return "fixed"
    if check.sizing.floor is None:
        return "sized"
    return "grown" if configured.sizing is None else "sized and grown"


def _task_duty(d: NDArray[np.float64], settings: RealizationSettings) -> Duty | None:
    """The task's motion through its points as a duty the drives must meet as well as the
    duty's (None: no task points, or one out of the design's reach)."""
    m = settings.motion
    if not settings.task_points_m:
        return None
    try:
        angles = joint_path(d, settings.task_points_m, *m.operating_range.degrees)
    except ValueError:
        return None
    return task_motion_duty(angles, m)


def _for_accuracy(
    d: NDArray[np.float64], settings: RealizationSettings
) -> tuple[StrengthCheck, SizedSections | None, AccuracyChoice]:
    """The strength check, the sections and the accuracy choice of design ``d``: the strength's
    sections, grown where the tolerance asks (as a floor of the sizing when the sections are
    sized, else within the grown sections' bounds)."""
    check = settings.strength
    sized = check.section_scales(d)
    base = np.ones(4) if sized is None else sized.scale[0]
    acc = settings.accuracy
    if not acc.points_m:
        return check, sized, AccuracyChoice(base, (0.0, 0.0), math.nan, math.nan, None)
    choice = accuracy_choice(d, base, check, settings.drives, acc, settings.motion)
    if np.array_equal(choice.scale, base):
        return check, sized, choice
    floor = tuple(float(f) for f in choice.scale)
    sizing = check.sizing or _sized_around(check.cad, choice.scale)
    check = replace(check, sizing=replace(sizing, floor=floor))
    return check, check.section_scales(d), choice


def _sized_around(cad: CadSettings, scale: NDArray[np.float64]) -> SizingSettings:
    """Sizing bounds from the smallest to the largest of ``scale`` (4,) on ``cad``: a fixed
    section grown for the tolerance keeps its growth, and the strength check chooses bearings
    for the grown bosses."""
    lo, hi = float(scale.min()), float(scale.max())
    return SizingSettings(
        width_m=(cad.width_m * lo, cad.width_m * hi),
        thickness_m=(cad.thickness_m * lo, cad.thickness_m * hi),
    )


def arm_model(
    done: Realization,
    settings: RealizationSettings,
    props: dict[str, MassProperties] | None = None,
    factor: ArrayLike | None = None,
) -> ArmModel:
    """The realised arm for its accuracy budget: each link's drawn section, the material, the
    masses of ``props`` (the optimised links; default the solid bored parts), each link's
    stiffness ``factor`` (4,) (default 1) and the chosen drives' stiffness and play."""
    scale = None if done.scale is None else np.asarray(done.scale)
    frame = frame_sections(settings.strength.cad, settings.strength.material, scale)
    stiffness, play, reflected, mass, _ = drive_terms(done.drives)
    return ArmModel(
        design=done.design,
        sections=frame,
        factor=np.ones(4) if factor is None else np.asarray(factor, dtype=float),
        inertials=Inertials.of(props or part_mass_properties(done.parts)),
        drive_stiffness=stiffness,
        backlash_rad=play,
        reflected_kgm2=reflected if settings.drives.reflected_inertia else np.zeros(2),
        drive_mass_kg=mass,
        printed=settings.accuracy.printed,
    )


def budget_of(
    done: Realization,
    settings: RealizationSettings,
    points_m: ArrayLike,
    props: dict[str, MassProperties] | None = None,
    factor: ArrayLike | None = None,
    tracking_mm: ArrayLike | None = None,
    cycle_load_N: float | None = None,
) -> dict[str, Any]:
    """The accuracy budget (:func:`qsm.realization.accuracy.accuracy_budget.accuracy_record`) of a
    realised design at task ``points_m``; ``props`` and ``factor`` for the optimised plates,
    ``tracking_mm`` the payload test's error per point, ``cycle_load_N`` the payload's peak
    force (N) over the task's cycle (the duty's is always counted)."""
    model = arm_model(done, settings, props, factor)
    notes = drive_terms(done.drives)[-1]
    du = settings.strength.duty
    loads = {"duty": peak_payload_force_N(done.design, settings.motion.payload_kg, du.theta,
                                          du.dtheta, du.ddtheta)}  # fmt: skip
    if cycle_load_N is not None:
        loads["cycle"] = float(cycle_load_N)
    return accuracy_record(
        model, points_m, settings.motion, loads, settings.accuracy, tracking_mm, notes
    )
