"""Strict JSON files: numpy values as plain numbers and lists, and no NaN or Infinity.

JavaScript's, jq's and every other strict JSON parser rejects ``NaN`` and ``Infinity``, which
Python's :mod:`json` writes by default. Every JSON output of the workflow and of ``qsm export``
goes through :func:`write_json`: a non-finite number is written as ``null``. The code that makes
such a number says why in a field of its own beside it (for example ``median_drive_mass_note``).
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np


def plain(value: Any) -> Any:
    """``value`` as JSON types: mappings with string keys, lists, numpy scalars and arrays as
    Python numbers and lists, and every non-finite float as None."""
    if isinstance(value, Mapping):
        return {str(k): plain(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [plain(v) for v in value]
    if isinstance(value, np.ndarray):
        return plain(value.tolist())
    if isinstance(value, np.generic):
        return plain(value.item())
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def dumps(value: Any, indent: int | None = 2) -> str:
    """Strict JSON text of ``value`` (:func:`plain`; raises on anything else not JSON)."""
    return json.dumps(plain(value), indent=indent, allow_nan=False)


def write_json(path: str | Path, value: Any, indent: int | None = 2) -> None:
    """Write ``value`` to ``path`` as strict JSON (:func:`dumps`), with a final newline."""
    Path(path).write_text(dumps(value, indent) + "\n")
