"""Settings of the links: material, strength requirements, section sizing and bored parts."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from qsm.config.settings.physics import cad
from qsm.embodiment.parts.link_parts import PartSettings
from qsm.embodiment.stiffness.sag_check import SagCheck
from qsm.embodiment.strength.link_checks import StrengthCheck
from qsm.embodiment.strength.material import Material, StrengthSettings
from qsm.embodiment.strength.sizing import SizingSettings
from qsm.physics.duty import DutySettings, duty_cycle

Section = Mapping[str, Any]


def material(section: Section) -> Material:
    """``material``: the printed material of every link."""
    return Material(**section)


def parts(
    cad_section: Section, material_section: Section, strength_section: Section
) -> PartSettings:
    """The bored parts: the link solids and ``strength.boss_wall_m`` around the bearing seats."""
    return PartSettings(
        cad(cad_section, material_section), boss_wall_m=strength_section["boss_wall_m"]
    )


def strength(section: Section) -> StrengthSettings:
    """``strength``: what every link must hold."""
    return StrengthSettings(**section)


def strength_check(
    cad_section: Section,
    material_section: Section,
    strength_section: Section,
    payload_kg: float,
    duty_settings: DutySettings,
) -> StrengthCheck:
    """The link check of a design: section, material, requirements, payload (kg) and duty."""
    return StrengthCheck(
        cad(cad_section, material_section),
        material(material_section),
        strength(strength_section),
        float(payload_kg),
        duty_cycle(duty_settings),
        sizing=sizing(cad_section),
    )


def sizing(section: Section) -> SizingSettings | None:
    """``cad.section`` and ``cad.sized``: None for the fixed section, else the sizing bounds."""
    if section.get("section", "fixed") == "fixed":
        return None
    sized = section["sized"]
    return SizingSettings(
        width_m=tuple(sized["width_m"]),
        thickness_m=tuple(sized["thickness_m"]),
        max_iterations=sized["max_iterations"],
        tolerance=sized["tolerance"],
    )


def sag_check(
    cad_section: Section,
    material_section: Section,
    payload_kg: float,
    points: Sequence[Sequence[float]],
    operating_range: Section,
    tolerance_mm: float | None = None,
) -> SagCheck:
    """The tool's sag at the task ``points`` (m) under ``payload_kg`` (g15 against
    ``tolerance_mm``; the schema's default when None, for the dataset's column alone)."""
    extra = {} if tolerance_mm is None else {"tolerance_mm": float(tolerance_mm)}
    return SagCheck(
        points=tuple((float(x), float(y)) for x, y in points),
        cad=cad(cad_section, material_section),
        material=material(material_section),
        payload_kg=float(payload_kg),
        theta1_range_deg=tuple(operating_range["theta1_deg"]),
        theta2_min_deg=float(operating_range["theta2_min_deg"]),
        **extra,
    )
