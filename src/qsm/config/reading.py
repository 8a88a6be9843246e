"""Configuration: JSON-schema validation with defaults, and a hash of the settings a stage uses."""

from __future__ import annotations

import copy
import math
from collections.abc import Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any

import jsonschema
import numpy as np
import yaml

from qsm.config.checks import check_config
from qsm.config.errors import ConfigError
from qsm.config.points import check_finite_points, plain_points, resolve_points_file
from qsm.schema.defaults import schema


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


def _yaml_hint(err: Any) -> str:
    """Why a number may have been read as text: YAML 1.1 reads ``5e-1`` (no dot) as a string."""
    if err.validator != "type" or not isinstance(err.instance, str):
        return ""
    try:
        value = float(err.instance)
    except ValueError:
        return ""
    return (
        f" (YAML reads {err.instance} as text, not a number: write it with a dot and a signed "
        f"exponent, {np.format_float_scientific(value, trim='0')}, or as "
        f"{np.format_float_positional(value, trim='-')})"
    )


def _key(path: Any) -> str:
    return ".".join(str(p) for p in path) or "<top level>"


def validate_config(config: dict[str, Any]) -> dict[str, Any]:
    """Validate ``config`` in place, fill in defaults and return it.

    Raises ``ConfigError`` naming the offending key (dotted path) for the first problem found.
    ``task.points_file`` is read into ``task.points`` (:mod:`qsm.config.points`).
    """
    task = config.get("task")
    points = task.get("points") if isinstance(task, dict) else None
    plain = plain_points(points)
    if plain:  # checked already: the schema sees one pair, not thousands
        task["points"] = points[:1]
    try:
        errors = sorted(
            _Validator(schema()).iter_errors(config), key=lambda e: list(e.absolute_path)
        )
    finally:
        if plain:
            task["points"] = points
    if errors:
        err = errors[0]
        if err.validator == "additionalProperties":
            known = set(err.schema.get("properties", {}))
            unknown = sorted(set(err.instance) - known)
            path = [*err.absolute_path, unknown[0]]
            raise ConfigError(
                f"config key '{_key(path)}' is unknown; known keys here: {', '.join(sorted(known))}"
            )
        raise ConfigError(f"config key '{_key(err.absolute_path)}': {err.message}{_yaml_hint(err)}")
    resolve_points_file(config, schema()["properties"]["task"]["properties"]["points"]["default"])
    _coerce_whole_numbers(config, schema())
    check_finite_points(config["task"]["points"])
    _check_finite(config)
    check_config(config)
    return config


def _coerce_whole_numbers(value: Any, sub_schema: dict[str, Any]) -> Any:
    """``value`` with every whole float (30000.0, 2.0e5) where the schema wants an integer made
    an int, in place; the schema has already rejected fractional ones."""
    if isinstance(value, dict):
        for name, prop in sub_schema.get("properties", {}).items():
            if name in value:
                value[name] = _coerce_whole_numbers(value[name], prop)
    elif isinstance(value, list) and isinstance(sub_schema.get("items"), dict):
        value[:] = [_coerce_whole_numbers(item, sub_schema["items"]) for item in value]
    elif sub_schema.get("type") == "integer" and isinstance(value, float) and value.is_integer():
        return int(value)
    return value


def _check_finite(value: Any, path: tuple[str, ...] = ()) -> None:
    """Every number in the config is finite (JSON schema bounds let NaN through); not
    ``task.points`` (:func:`qsm.config.points.check_finite_points`)."""
    if isinstance(value, dict):
        for key, item in value.items():
            if (*path, key) != ("task", "points"):
                _check_finite(item, (*path, str(key)))
    elif isinstance(value, list):
        for k, item in enumerate(value):
            _check_finite(item, (*path, str(k)))
    elif isinstance(value, float) and not math.isfinite(value):
        raise ConfigError(f"config key '{_key(path)}': {value} is not a finite number")


def read_config_file(path: str | Path) -> dict[str, Any]:
    """The mapping in the YAML (or JSON) file ``path``; ``ConfigError`` naming the file, and the
    line and column of a syntax error. Read with libyaml where PyYAML has it (10,000 task points
    in about a second, several times faster than pure Python)."""
    if not Path(path).exists():
        raise ConfigError(f"config file '{path}' does not exist")
    try:
        text = Path(path).read_text()
    except OSError as exc:
        raise ConfigError(f"cannot read config file '{path}': {exc}") from exc
    try:
        data = yaml.load(text, Loader=getattr(yaml, "CSafeLoader", yaml.SafeLoader))
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark or exc.context_mark
        where = f", line {mark.line + 1}, column {mark.column + 1}" if mark else ""
        line = text.splitlines()[mark.line] if mark and mark.line < len(text.splitlines()) else ""
        tab = " (YAML indents with spaces, never tabs)" if "\t" in line else ""
        raise ConfigError(
            f"config file '{path}'{where}: not valid YAML: {exc.problem or exc}{tab}"
        ) from exc
    except yaml.YAMLError as exc:
        raise ConfigError(f"config file '{path}': not valid YAML: {exc}") from exc
    if data is None:
        raise ConfigError(
            f"config file '{path}' is empty: it must hold a mapping of config keys (for example "
            f"'task: {{payload_kg: 2.0}}'); config/README.md lists them"
        )
    if not isinstance(data, dict):
        raise ConfigError(
            f"config file '{path}' must hold a mapping of config keys, not a "
            f"{type(data).__name__} (for example 'task: {{payload_kg: 2.0}}')"
        )
    return data


def configfile_errors(argv: Sequence[str]) -> list[str]:
    """The errors of the files that ``--configfile`` / ``--configfiles`` name in a Snakemake
    command line ``argv``: missing, empty, not a mapping, or a YAML error (file, line, column).
    The workflow profile prints them and stops, since Snakemake reads those files before the
    Snakefile runs and names neither file nor line (a missing one ends in a traceback)."""
    files, taking = [], False
    for arg in argv:
        name, eq, value = arg.partition("=")
        if name in ("--configfile", "--configfiles"):
            taking = not eq
            files += [value] if eq else []
        elif arg.startswith("-"):
            taking = False
        elif taking:
            files.append(arg)
    errors = []
    for path in files:
        try:
            read_config_file(path)
        except ConfigError as exc:
            errors.append(str(exc))
    return errors


def merge_config(base: dict[str, Any], update: Mapping[str, Any]) -> dict[str, Any]:
    """Merge ``update`` into ``base`` in place as Snakemake merges --configfile files: mappings
    key by key, anything else replaced."""
    for key, value in update.items():
        if isinstance(value, Mapping) and isinstance(base.get(key), dict):
            merge_config(base[key], value)
        else:
            base[key] = copy.deepcopy(value)
    return base


def load_config(*paths: str | Path | None) -> dict[str, Any]:
    """Read YAML config files (none: all defaults), each merged over the ones before as
    ``snakemake --configfile a.yaml b.yaml`` does, then validate and fill in defaults."""
    data: dict[str, Any] = {}
    for path in paths:
        if path is not None:
            merge_config(data, read_config_file(path))
    return validate_config(data)
