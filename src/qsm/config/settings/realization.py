"""Settings of the realisation of a chosen design (Stage 6, ``qsm export``)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import replace
from typing import Any

from qsm.config.settings.actuation import drive_check
from qsm.config.settings.links import load_case_of, parts, strength_check
from qsm.config.settings.simulation import payload_test
from qsm.embodiment.load_case import LoadCase
from qsm.realization.accuracy_budget import AccuracySettings
from qsm.realization.pipeline import RealizationSettings

Section = Mapping[str, Any]


def realization(
    case: LoadCase,
    strength: Section,
    drives: Section,
    task: Section | None = None,
    payload_test_section: Section | None = None,
) -> RealizationSettings:
    """The link check, drive check and bored parts of a design under ``case``, with the
    ``strength`` and ``drives`` sections; the accuracy ``task``
    needs and its motion (``payload_test``), for the accuracy budget (None: the schema's
    defaults, for rules that do not make it)."""
    done = RealizationSettings(
        strength=strength_check(case, strength),
        drives=drive_check(drives, case),
        parts=parts(case, strength),
    )
    if task is not None:
        done = replace(done, accuracy=accuracy(task))
    if payload_test_section is not None:
        (lo, hi), theta2_min = case.operating_range_deg
        op = {"theta1_deg": [lo, hi], "theta2_min_deg": theta2_min}
        done = replace(done, motion=payload_test(payload_test_section, case.payload_kg, op))
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
        load_case_of(config),
        config["strength"],
        config["drives"],
        config["task"],
        config["payload_test"],
    )
