"""Settings of the links: material, strength requirements, section sizing and bored parts."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from qsm.config.settings.physics import cad, duty
from qsm.embodiment.load_case import LoadCase
from qsm.embodiment.parts.link_parts import PartSettings
from qsm.embodiment.stiffness.sag_check import SagCheck
from qsm.embodiment.strength.link_checks import StrengthCheck
from qsm.embodiment.strength.material import Material, StrengthSettings
from qsm.embodiment.strength.sizing import SizingSettings

Section = Mapping[str, Any]


def material(section: Section) -> Material:
    """``material``: the printed material of every link."""
    return Material(**section)


def parts(case: LoadCase, strength_section: Section) -> PartSettings:
    """The bored parts: the link solids of ``case`` and ``strength.boss_wall_m`` around the
    bearing seats."""
    return PartSettings(case.cad, boss_wall_m=strength_section["boss_wall_m"])


def strength(section: Section) -> StrengthSettings:
    """``strength``: what every link must hold."""
    return StrengthSettings(**section)


def _largest_scale(section: Section, material_section: Section) -> float:
    """The largest factor on the ``cad`` section's that ``cad.sized`` allows (1 where its bounds
    admit none: a fixed section's config need not keep them consistent)."""
    try:
        return _bounds(section).bounds(cad(section, material_section))[1]
    except ValueError:
        return 1.0


def load_case_of(config: Section) -> LoadCase:
    """What the links and drives carry, from a validated config or a stage's share of one: the
    ``cad``, ``material``, ``dynamics.duty`` and ``operating_range`` sections and
    ``task.payload_kg``, as one value."""
    cad_section, material_section = config["cad"], config["material"]
    return LoadCase(
        cad=cad(cad_section, material_section),
        material=material(material_section),
        payload_kg=float(config["task"]["payload_kg"]),
        duty=duty(config["dynamics"]["duty"], config["operating_range"]),
        sizing=sizing(cad_section),
        largest_scale=_largest_scale(cad_section, material_section),
    )


def strength_check(case: LoadCase, strength_section: Section) -> StrengthCheck:
    """The link check of a design under ``case``, with the ``strength`` requirements."""
    return StrengthCheck(
        case.cad,
        case.material,
        strength(strength_section),
        case.payload_kg,
        case.cycle(),
        sizing=case.sizing,
    )


def sizing(section: Section) -> SizingSettings | None:
    """``cad.section`` and ``cad.sized``: None for the fixed section, else the sizing bounds."""
    return None if section.get("section", "fixed") == "fixed" else _bounds(section)


def _bounds(section: Section) -> SizingSettings:
    """``cad.sized`` as sizing settings."""
    sized = section["sized"]
    return SizingSettings(
        width_m=tuple(sized["width_m"]),
        thickness_m=tuple(sized["thickness_m"]),
        max_iterations=sized["max_iterations"],
        tolerance=sized["tolerance"],
    )


def sag_check(
    case: LoadCase, points: Sequence[Sequence[float]], tolerance_mm: float | None = None
) -> SagCheck:
    """The tool's sag at the task ``points`` (m) under ``case`` (g15 against ``tolerance_mm``;
    the schema's default when None, for the dataset's column alone)."""
    extra = {} if tolerance_mm is None else {"tolerance_mm": float(tolerance_mm)}
    return SagCheck(
        points=tuple((float(x), float(y)) for x, y in points),
        cad=case.cad,
        material=case.material,
        payload_kg=case.payload_kg,
        operating_range=case.operating_range,
        **extra,
    )
