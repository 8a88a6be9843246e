"""The parts of a validated config that a stage reads, picked in one place for the rules' params
and the library's calls alike. Light: the Snakefile imports it."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

Section = Mapping[str, Any]


#: The ``task`` keys the realisation's accuracy reads.
ACCURACY_KEYS = ("tolerance_mm", "min_first_mode_hz", "grow_for_tolerance")


def accuracy_section(config: Section) -> dict[str, Any]:
    """What :func:`qsm.config.settings.realization.accuracy` reads of a validated config:
    :data:`ACCURACY_KEYS` of ``task``, ``topology.min_stiffness_factor`` and the
    ``printed_material`` section (the rules' ``task`` param; the task's points and cycle arrive
    by other params)."""
    section = {k: config["task"][k] for k in ACCURACY_KEYS}
    return section | {
        "min_stiffness_factor": config["topology"]["min_stiffness_factor"],
        "printed_material": config["printed_material"],
    }


def iso_section(config: Section) -> dict[str, Any]:
    """What :func:`qsm.config.settings.realization.iso` reads: ``iso9283``, the task's
    ``repeatability_mm`` and the servo's proportional gains (``payload_test.kp_Nm_rad``)."""
    return {
        **config["iso9283"],
        "repeatability_mm": config["task"]["repeatability_mm"],
        "kp_Nm_rad": config["payload_test"]["kp_Nm_rad"],
    }
