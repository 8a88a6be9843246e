"""The parts of a validated config that a stage reads, picked in one place for the rules' params
and the library's calls alike. Light: the Snakefile imports it."""

from __future__ import annotations

import hashlib
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from qsm.config.drive_limits import catalogue_folder
from qsm.physics.task_points import MOTION_KEYS

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


def drives_section(config: Section) -> dict[str, Any]:
    """``drives`` with ``catalogue_sha256``, a hash of the catalogue's CSV files (their paths in
    the folder and their bytes): editing the catalogue reruns the rules that choose drives, which
    a config value alone would not."""
    digest = hashlib.sha256()
    folder = Path(catalogue_folder(config))
    for path in sorted(folder.rglob("*.csv")):
        digest.update(str(path.relative_to(folder)).encode())
        digest.update(path.read_bytes())
    return {**config["drives"], "catalogue_sha256": digest.hexdigest()}


def _checked_loads(config: Section) -> dict[str, Any]:
    """The keys of the load case (:func:`qsm.config.settings.links.load_case_of`, the payload
    aside) and of the link and drive checks, in the config's shape."""
    return {
        "cad": config["cad"],
        "material": config["material"],
        "dynamics": {"duty": config["dynamics"]["duty"]},
        "operating_range": config["operating_range"],
        "strength": config["strength"],
        "drives": drives_section(config),
    }


def realization_section(config: Section) -> dict[str, Any]:
    """The realisation's share of a validated config, in the config's shape: every key that
    :func:`qsm.config.settings.realization.realization_of` and the Stage 6 rules read of it, and
    no other (so a rule's params change exactly when its settings do). The rules pass it as one
    param, and build their settings from it with the same function as ``qsm export`` does from
    the whole config."""
    task, topology = config["task"], config["topology"]
    return {
        **_checked_loads(config),
        "task": {k: task[k] for k in ("points", "payload_kg", *ACCURACY_KEYS)},
        "topology": {"min_stiffness_factor": topology["min_stiffness_factor"]},
        "printed_material": config["printed_material"],
        "payload_test": {k: config["payload_test"][k] for k in MOTION_KEYS},
        "printing": {"build_volume_mm": config["printing"]["build_volume_mm"]},
        "kit": config["kit"],
    }


def dataset_section(config: Section) -> dict[str, Any]:
    """Stage 2's share of a validated config, in the config's shape: every key
    :func:`qsm.config.settings.dataset.dataset_of` reads (the rule ``dynamics``'s one param)."""
    return {
        **_checked_loads(config),
        "task": {k: config["task"][k] for k in ("points", "payload_kg")},
    }
