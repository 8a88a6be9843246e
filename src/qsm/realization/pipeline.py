"""One realisation of a chosen design, built the same way by the workflow, ``qsm export`` and a
notebook: its link check and sections, bearings, bored parts and drives.

:func:`realize` runs the checks of :class:`RealizationSettings` on one design (6 lengths, m) and
returns a :class:`Realization`: the strength record (:func:`qsm.embodiment.strength.verdict
.strength_record`), the drive report (:meth:`qsm.embodiment.drives.drive_checks.DriveCheck.report`),
each link's section scale, the bearing rows and the solid bored parts. The rules
``select_design`` and ``topology_optimize`` and :func:`qsm.app.export.export_design` each take
what they write from it, so the command line cannot drift from the workflow.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from qsm.embodiment.drives.drive_checks import DriveCheck
from qsm.embodiment.parts.link_parts import LinkPart, PartSettings, link_parts
from qsm.embodiment.parts.part_mass import part_mass_properties
from qsm.embodiment.stiffness.frame import FrameSections
from qsm.embodiment.strength.link_checks import StrengthCheck
from qsm.embodiment.strength.loads import Inertials
from qsm.embodiment.strength.verdict import strength_record
from qsm.physics.cad import MassProperties, link_settings
from qsm.physics.kinematics import LINK_NAMES, as_design
from qsm.realization.accuracy_budget import (
    AccuracySettings,
    ArmModel,
    accuracy_record,
    drive_terms,
)
from qsm.realization.assembly import bearing_rows
from qsm.realization.payload import PayloadSettings


@dataclass(frozen=True)
class RealizationSettings:
    """What realising a design takes: the link check (section, material, strength, payload and
    duty), the drive check (catalogue, rule, payload and duty) and the bored parts (section and
    the wall around each bearing seat), the accuracy the task needs and the task's motion (the
    payload test's path through the points, along which the joints' torques are checked)."""

    strength: StrengthCheck
    drives: DriveCheck
    parts: PartSettings
    accuracy: AccuracySettings = field(default_factory=AccuracySettings)
    motion: PayloadSettings = field(default_factory=PayloadSettings)


@dataclass(frozen=True)
class Realization:
    """A design as realised: ``scale`` is each link's section factor on the configured one (None
    for the fixed section), ``part_settings`` the bored parts' settings at that scale, ``parts``
    the solid bored links with ``bearing_rows`` (rows of the bearing table, joints A, B, C, D)."""

    design: NDArray[np.float64]
    scale: tuple[float, ...] | None
    strength: dict[str, Any]
    drives: dict[str, Any]
    bearing_rows: list[int]
    part_settings: PartSettings
    parts: dict[str, LinkPart]

    @property
    def has_drives(self) -> bool:
        """Each motor has a drive of the catalogue that meets its duty."""
        return bool(self.drives["has_drives"])


def realize(design: ArrayLike, settings: RealizationSettings) -> Realization:
    """Check and embody ``design`` (6 lengths, m): the sections its links need (sized, or the
    configured one), their strength and bearings, the drives, and the solid bored parts (the
    accuracy budget at task points: :func:`budget_of`)."""
    d = np.asarray(as_design(design), dtype=float)
    sized = settings.strength.section_scales(d)
    scale = None if sized is None else tuple(float(f) for f in sized.scale[0])
    strength = strength_record(d, settings.strength)
    drives = settings.drives.report(d, None if sized is None else sized.scale)
    part_settings = replace(settings.parts, scale=scale)
    names = {joint: b["designation"] for joint, b in strength["bearings"].items()}
    rows = bearing_rows(names, part_settings.table)
    return Realization(
        design=d,
        scale=scale,
        strength=strength,
        drives=drives,
        bearing_rows=rows,
        part_settings=part_settings,
        parts=link_parts(d, rows, part_settings),
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
    sections = link_settings(settings.strength.cad, done.scale)
    material = settings.strength.material
    frame = FrameSections(
        width_m=np.array([sections[k].width_m for k in LINK_NAMES]),
        thickness_m=np.array([sections[k].thickness_m for k in LINK_NAMES]),
        youngs_pa=material.youngs_modulus_pa,
        poisson=material.poisson_ratio,
    )
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
    )


def budget_of(
    done: Realization,
    settings: RealizationSettings,
    points_m: ArrayLike,
    props: dict[str, MassProperties] | None = None,
    factor: ArrayLike | None = None,
    tracking_mm: ArrayLike | None = None,
) -> dict[str, Any]:
    """The accuracy budget (:func:`qsm.realization.accuracy_budget.accuracy_record`) of a
    realised design at task ``points_m``; ``props`` and ``factor`` for the optimised plates,
    ``tracking_mm`` the payload test's error per point."""
    model = arm_model(done, settings, props, factor)
    notes = drive_terms(done.drives)[-1]
    return accuracy_record(
        model,
        points_m,
        settings.motion,
        settings.strength.duty,
        settings.accuracy,
        tracking_mm,
        notes,
    )
