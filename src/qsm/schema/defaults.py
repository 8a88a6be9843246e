"""Every setting's default value, read from the config schema, its one source.

The library's settings dataclasses take their field defaults from here (``width_m: float =
default("cad.width_m")``), so a call without arguments, in a notebook or a test, uses the values
of a run whose config leaves the key out. README's and ``config/README.md``'s tables describe
the keys; ``config/config.yaml`` spells the defaults out for users to edit (a test keeps it
equal to the schema).
"""

from __future__ import annotations

from functools import cache
from importlib import resources
from typing import Any

import yaml

SCHEMA_FILE = "config.schema.yaml"


@cache
def schema() -> dict[str, Any]:
    """The configuration schema shipped with the package."""
    text = resources.files("qsm.schema").joinpath(SCHEMA_FILE).read_text()
    return yaml.load(text, Loader=getattr(yaml, "CSafeLoader", yaml.SafeLoader))


def _frozen(value: Any) -> Any:
    """``value`` with every list made a tuple (dataclass defaults must be immutable)."""
    return tuple(_frozen(v) for v in value) if isinstance(value, list) else value


def default(key: str) -> Any:
    """The schema's default of config key ``key``, dotted (``"cad.width_m"``); lists read as
    tuples. Raises ``KeyError`` naming the key when the schema has no such key with a default."""
    node = schema()
    for part in key.split("."):
        node = node.get("properties", {}).get(part, {})
    if "default" not in node:
        raise KeyError(f"config key '{key}' has no default in the schema")
    return _frozen(node["default"])
