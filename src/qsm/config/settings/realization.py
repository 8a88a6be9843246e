"""Settings of the realisation of a chosen design (Stage 6, ``qsm export``)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import replace
from typing import Any

from qsm.config.settings.actuation import drive_check
from qsm.config.settings.links import parts, strength_check
from qsm.config.settings.physics import duty
from qsm.config.settings.simulation import payload_test
from qsm.realization.accuracy_budget import AccuracySettings
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
    task: Section | None = None,
    payload_test_section: Section | None = None,
) -> RealizationSettings:
    """The link check, drive check and bored parts of the ``cad``, ``material``, ``strength``
    and ``drives`` sections, ``task.payload_kg`` and the duty (``dynamics.duty`` over
    ``operating_range``); the accuracy ``task`` needs and its motion (``payload_test``), for
    the accuracy budget (None: the schema's defaults, for rules that do not make it)."""
    duty_settings = duty(duty_section, operating_range)
    done = RealizationSettings(
        strength=strength_check(cad, material, strength, payload_kg, duty_settings),
        drives=drive_check(drives, cad, material, payload_kg, duty_settings),
        parts=parts(cad, material, strength),
    )
    if task is not None:
        done = replace(done, accuracy=accuracy(task))
    if payload_test_section is not None:
        motion = payload_test(payload_test_section, payload_kg, operating_range)
        done = replace(done, motion=motion)
    return done


def accuracy(task: Section) -> AccuracySettings:
    """``task.tolerance_mm`` and ``task.min_first_mode_hz``: what the design's accuracy must
    meet."""
    return AccuracySettings(
        tolerance_mm=float(task["tolerance_mm"]), min_first_mode_hz=task["min_first_mode_hz"]
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
        config["task"],
        config["payload_test"],
    )
