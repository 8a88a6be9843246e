"""The parts of a validated config that a stage reads, picked in one place for the rules' params
and the library's calls alike. Light: the Snakefile imports it."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from qsm.config.drive_limits import catalogue_folder
from qsm.physics.task_points import MOTION_KEYS, design_task

Section = Mapping[str, Any]


#: The ``task`` keys the realisation's accuracy reads.
ACCURACY_KEYS = ("tolerance_mm", "min_first_mode_hz", "grow_for_tolerance")


def canonical(value: Any) -> Any:
    """``value`` with every mapping's keys sorted, at every depth. A rule compares its params with
    the last run's by their ``repr``: a share must not change with the order in which the config
    files were merged (an override file puts its keys first)."""
    if isinstance(value, Mapping):
        return {k: canonical(value[k]) for k in sorted(value)}
    if isinstance(value, list | tuple):
        return [canonical(v) for v in value]
    return value


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
    return canonical(
        {
            **config["iso9283"],
            "repeatability_mm": config["task"]["repeatability_mm"],
            "kp_Nm_rad": config["payload_test"]["kp_Nm_rad"],
        }
    )


def drives_section(config: Section) -> dict[str, Any]:
    """``drives`` with ``catalogue_sha256``, a digest of the catalogue's CSV files as they are
    read (:func:`qsm.embodiment.drives.catalogue.catalogue_digest`): editing a value reruns the
    rules that choose drives, which a config value alone would not; a re-save that keeps every
    value does not."""
    from qsm.embodiment.drives.catalogue import catalogue_digest

    digest = catalogue_digest(catalogue_folder(config))
    return {**config["drives"], "catalogue_sha256": digest}


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
    return canonical(
        {
            **_checked_loads(config),
            "task": {k: task[k] for k in ("points", "payload_kg", *ACCURACY_KEYS)},
            "topology": {"min_stiffness_factor": topology["min_stiffness_factor"]},
            "printed_material": config["printed_material"],
            "payload_test": {k: config["payload_test"][k] for k in MOTION_KEYS},
            "printing": {"build_volume_mm": config["printing"]["build_volume_mm"]},
            "kit": config["kit"],
        }
    )


def dataset_section(config: Section) -> dict[str, Any]:
    """Stage 2's share of a validated config, in the config's shape: every key
    :func:`qsm.config.settings.dataset.dataset_of` reads (the rule ``dynamics``'s one param)."""
    return canonical(
        {
            **_checked_loads(config),
            "task": {k: config["task"][k] for k in ("points", "payload_kg")},
        }
    )


#: The ``workspace`` keys of the scale-up (its slicing and scale scan), not the shard count.
FIT_KEYS = ("n_delta", "n_levels", "n_scan")


def mechanisms_section(config: Section) -> dict[str, Any]:
    """Stage 1's share of a validated config: ``sampling``, ``operating_range``, ``filters``,
    ``scale``, the scale-up's ``workspace`` keys (:data:`FIT_KEYS`, not the shard count) and
    ``task_points``, the task's points as every stage designs for them
    (:func:`qsm.physics.task_points.design_task`). The rules ``fit_task``'s and
    ``select_mechanisms``'s param, and what the mechanism table records it was made with."""
    return canonical(
        {
            **{k: config[k] for k in ("sampling", "operating_range", "filters", "scale")},
            "workspace": {k: config["workspace"][k] for k in FIT_KEYS},
            "task_points": design_task(config["task"]["points"])[1],
        }
    )


def dataset_provenance(config: Section, drives: Section) -> dict[str, Any]:
    """What the dataset depends on (the rule ``gather_dataset``'s param, recorded in the
    dataset): :func:`mechanisms_section` and Stage 2's keys, with the ``drives`` section as
    :func:`drives_section` gives it (its catalogue's hash included); not the shard counts."""
    return canonical(
        {
            **mechanisms_section(config),
            "duty": config["dynamics"]["duty"],
            **{k: config[k] for k in ("cad", "material", "strength")},
            "drives": drives,
            "payload_kg": config["task"]["payload_kg"],
        }
    )


def surrogate_section(config: Section) -> dict[str, Any]:
    """Stage 3's share: ``surrogate``, the network and its training, without the infill (which
    only the optimisation runs)."""
    return canonical({k: v for k, v in config["surrogate"].items() if k != "infill"})


def applied_constraints(section: Section, formulation: str) -> dict[str, Any]:
    """``optimization.constraints`` as they apply to ``formulation``: g11 (``containment``) only
    in the paper formulation, and ``containment_tolerance_m`` only where the task is contained
    (g11, or the ratios formulation's scale-up); the other keys as they are."""
    out = {k: section[k] for k in ("printable", "strong", "drives", "stiff")}
    out["containment"] = formulation == "paper" and bool(section["containment"])
    if formulation == "ratios" or out["containment"]:
        out["containment_tolerance_m"] = section["containment_tolerance_m"]
    return out


def optimization_section(config: Section, formulation: str) -> dict[str, Any]:
    """Stage 4's share of a validated config for ``formulation``'s front, in the config's shape:
    every key :func:`qsm.config.settings.optimization.front_of` reads (the rules ``optimize``'s
    and ``verify_pareto``'s one param), the constraints as they apply to it."""
    optimization = config["optimization"]
    return canonical(
        {
            **_checked_loads(config),
            "task": {k: config["task"][k] for k in ("points", "payload_kg", "tolerance_mm")},
            "scale": config["scale"],
            "workspace": {k: config["workspace"][k] for k in FIT_KEYS},
            "filters": config["filters"],
            "sampling": {"bounds": config["sampling"]["bounds"]},
            "printing": {"build_volume_mm": config["printing"]["build_volume_mm"]},
            "surrogate": config["surrogate"],
            "optimization": {
                **{
                    k: v
                    for k, v in optimization.items()
                    if k not in ("formulation", "formulations")
                },
                "constraints": applied_constraints(optimization["constraints"], formulation),
            },
        }
    )


def cycles_section(config: Section) -> dict[str, Any]:
    """The front's cycles' share of a validated config (the rule ``front_cycles``'s param): the
    keys :func:`qsm.config.settings.simulation.cycles_of` reads."""
    return canonical(
        {
            **_checked_loads(config),
            "task": {"payload_kg": config["task"]["payload_kg"]},
            "payload_test": config["payload_test"],
        }
    )
