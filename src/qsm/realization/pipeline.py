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

from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from qsm.embodiment.drives.drive_checks import DriveCheck
from qsm.embodiment.parts.link_parts import LinkPart, PartSettings, link_parts
from qsm.embodiment.strength.link_checks import StrengthCheck
from qsm.embodiment.strength.verdict import strength_record
from qsm.physics.kinematics import as_design
from qsm.realization.assembly import bearing_rows


@dataclass(frozen=True)
class RealizationSettings:
    """What realising a design takes: the link check (section, material, strength, payload and
    duty), the drive check (catalogue, rule, payload and duty) and the bored parts (section and
    the wall around each bearing seat)."""

    strength: StrengthCheck
    drives: DriveCheck
    parts: PartSettings


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
    configured one), their strength and bearings, the drives, and the solid bored parts."""
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
