"""Settings of the realisation of a chosen design (Stage 6, ``qsm export``)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from qsm.config.settings.actuation import drive_check
from qsm.config.settings.links import parts, strength_check
from qsm.config.settings.physics import duty
from qsm.realization.pipeline import RealizationSettings

Section = Mapping[str, Any]


def realization(
    cad: Section,
    material: Section,
    strength: Section,
    drives: Section,
    payload_kg: float,
    duty_section: Section,
    operating_range: Section,
) -> RealizationSettings:
    """The link check, drive check and bored parts of the ``cad``, ``material``, ``strength``
    and ``drives`` sections, ``task.payload_kg`` and the duty (``dynamics.duty`` over
    ``operating_range``)."""
    duty_settings = duty(duty_section, operating_range)
    return RealizationSettings(
        strength=strength_check(cad, material, strength, payload_kg, duty_settings),
        drives=drive_check(drives, cad, material, payload_kg, duty_settings),
        parts=parts(cad, material, strength),
    )


def realization_of(config: Section) -> RealizationSettings:
    """:func:`realization` of a whole validated config (``qsm export``, a notebook)."""
    return realization(
        config["cad"],
        config["material"],
        config["strength"],
        config["drives"],
        float(config["task"]["payload_kg"]),
        config["dynamics"]["duty"],
        config["operating_range"],
    )
