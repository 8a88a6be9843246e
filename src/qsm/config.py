"""Configuration: JSON-schema validation with defaults, and a hash of the settings a stage uses."""

from __future__ import annotations

import copy
import hashlib
import json
import math
from collections.abc import Iterator, Mapping
from functools import cache
from importlib import resources
from pathlib import Path
from typing import Any

import jsonschema
import numpy as np
import yaml

from qsm.physics.task import min_enclosing_circle

SCHEMA_FILE = "config.schema.yaml"


class ConfigError(ValueError):
    """A configuration value is missing, unknown, of the wrong type or out of range."""


@cache
def schema() -> dict[str, Any]:
    """The configuration schema shipped with the package."""
    text = resources.files("qsm").joinpath("schemas").joinpath(SCHEMA_FILE).read_text()
    return yaml.safe_load(text)


def _with_defaults(cls: type) -> type:
    """A jsonschema validator class that fills in ``default`` values while it validates."""
    validate_properties = cls.VALIDATORS["properties"]

    def properties(validator, props, instance, sub_schema) -> Iterator:
        if isinstance(instance, dict):
            for name, prop in props.items():
                if "default" in prop:
                    instance.setdefault(name, copy.deepcopy(prop["default"]))
        yield from validate_properties(validator, props, instance, sub_schema)

    return jsonschema.validators.extend(cls, {"properties": properties})


_Validator = _with_defaults(jsonschema.Draft202012Validator)


def _key(path: Any) -> str:
    return ".".join(str(p) for p in path) or "<top level>"


def validate_config(config: dict[str, Any]) -> dict[str, Any]:
    """Validate ``config`` in place, fill in defaults and return it.

    Raises ``ConfigError`` naming the offending key (dotted path) for the first problem found.
    """
    errors = sorted(_Validator(schema()).iter_errors(config), key=lambda e: list(e.absolute_path))
    if errors:
        err = errors[0]
        if err.validator == "additionalProperties":
            known = set(err.schema.get("properties", {}))
            unknown = sorted(set(err.instance) - known)
            path = [*err.absolute_path, unknown[0]]
            raise ConfigError(
                f"config key '{_key(path)}' is unknown; known keys here: {', '.join(sorted(known))}"
            )
        raise ConfigError(f"config key '{_key(err.absolute_path)}': {err.message}")
    for name, (lo, hi) in config["sampling"]["bounds"].items():
        if not lo < hi:
            raise ConfigError(
                f"config key 'sampling.bounds.{name}': min {lo} is not below max {hi}"
            )
    lo, hi = config["operating_range"]["theta1_deg"]
    if not lo < hi:
        raise ConfigError(
            f"config key 'operating_range.theta1_deg': min {lo} is not below max {hi}"
        )
    _check_finite(config)
    _check_task(config["task"]["points"])
    _check_cad(config)
    opt = config["optimization"]
    if opt["formulation"] not in opt["formulations"]:
        raise ConfigError(
            f"config key 'optimization.formulation': '{opt['formulation']}' is not among "
            f"optimization.formulations = {opt['formulations']}"
        )
    sampling = config["sampling"]
    if sampling["n_mechanisms"] > sampling["n_samples"]:
        raise ConfigError(
            f"config key 'sampling.n_mechanisms': {sampling['n_mechanisms']} exceeds "
            f"sampling.n_samples = {sampling['n_samples']}"
        )
    return config


#: Smallest radius (m) of the task circle: below it eta (task area / workspace area) is ~0.
MIN_TASK_RADIUS_M = 1e-3


def _check_task(points: list[list[float]]) -> None:
    """Finite task points spanning a circle of at least :data:`MIN_TASK_RADIUS_M`."""
    radius = min_enclosing_circle(np.asarray(points, dtype=float)).radius
    if radius < MIN_TASK_RADIUS_M:
        raise ConfigError(
            f"config key 'task.points': the points span a circle of radius {radius:.2g} m "
            f"(a single point); eta = task area / workspace area would be zero for every design "
            f"and could not rank them. Give the region the tool must cover: at least two points "
            f"{2e3 * MIN_TASK_RADIUS_M:g} mm or more apart (e.g. the point and the edge of its "
            f"positioning tolerance)"
        )


def _check_finite(value: Any, path: tuple[str, ...] = ()) -> None:
    """Every number in the config is finite (JSON schema bounds let NaN through)."""
    if isinstance(value, dict):
        for key, item in value.items():
            _check_finite(item, (*path, str(key)))
    elif isinstance(value, list):
        for k, item in enumerate(value):
            _check_finite(item, (*path, str(k)))
    elif isinstance(value, float) and not math.isfinite(value):
        if path[:2] == ("task", "points"):
            raise ConfigError("config key 'task.points': every coordinate must be a finite number")
        raise ConfigError(f"config key '{_key(path)}': {value} is not a finite number")


def _check_cad(config: dict[str, Any]) -> None:
    """A section that some design of the sampled ranges, at the largest scale, can carry."""
    cad = config["cad"]
    if not cad["boss_radius_m"] > cad["width_m"] / 2:
        raise ConfigError(
            f"config key 'cad.boss_radius_m': {cad['boss_radius_m']} m must exceed half the bar "
            f"width cad.width_m = {cad['width_m']} m"
        )
    bounds, scale = config["sampling"]["bounds"], config["scale"]["max_m"]
    shortest_bar = scale * min(1.0, bounds["l2"][1], bounds["l3"][1])
    needed = 2 * math.sqrt(cad["boss_radius_m"] ** 2 - (cad["width_m"] / 2) ** 2)
    if shortest_bar <= needed:
        raise ConfigError(
            f"config key 'cad.boss_radius_m': bosses of radius {cad['boss_radius_m']} m on bars "
            f"{cad['width_m']} m wide need links longer than {needed:.3g} m, but at scale.max_m "
            f"the sampled ranges give a crank or coupler of at most {shortest_bar:.3g} m"
        )


def load_config(path: str | Path | None = None) -> dict[str, Any]:
    """Read a YAML config file (or none: all defaults), validate it and fill in defaults."""
    data: dict[str, Any] = {}
    if path is not None:
        try:
            data = yaml.safe_load(Path(path).read_text()) or {}
        except (OSError, yaml.YAMLError) as exc:
            raise ConfigError(f"cannot read config file '{path}': {exc}") from exc
        if not isinstance(data, dict):
            raise ConfigError(f"config file '{path}' must hold a mapping of keys")
    return validate_config(data)


def settings_hash(settings: Mapping[str, Any]) -> str:
    """Short SHA-256 of the canonical JSON of ``settings`` (what a stage's output depends on)."""
    text = json.dumps(settings, sort_keys=True, separators=(",", ":"), default=str)
    return hashlib.sha256(text.encode()).hexdigest()[:16]
