"""Settings of Stage 2, the dataset's dynamics, strength, drives and tool sag (the rule
``dynamics``, ``qsm evaluate``)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from qsm.config.settings.actuation import drive_check
from qsm.config.settings.links import load_case_of, sag_check, strength_check
from qsm.dataset.evaluation import DatasetSettings
from qsm.physics.task_points import design_task


def dataset_of(config: Mapping[str, Any]) -> DatasetSettings:
    """Stage 2's settings from a validated config, or from its share of one
    (:func:`qsm.config.sections.dataset_section`, the rule's param): the load case, the link
    check with the ``strength`` section, the drive check with ``drives`` and the tool's sag at the
    task's design points (the schema's tolerance: the dataset's column is the sag alone)."""
    case = load_case_of(config)
    return DatasetSettings(
        case=case,
        strength=strength_check(case, config["strength"]),
        drives=drive_check(config["drives"], case),
        sag=sag_check(case, design_task(config["task"]["points"])[1]),
    )
