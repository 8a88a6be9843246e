"""The task points of a configuration: ``task.points``, or a CSV file named by ``task.points_file``.

A task of thousands of points reads fastest from a CSV file (header ``x_m,y_m``, one point a row,
metres; the path relative to the working directory): :func:`resolve_points_file` reads it once
into ``task.points``, so everything downstream sees one kind of task. Long inline ``task.points``
are checked here with numpy rather than pair by pair by the JSON schema
(:func:`plain_points`).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from qsm.config.errors import ConfigError

#: The header a points file starts with.
POINTS_HEADER = ("x_m", "y_m")

_NUMBER = (int, float)


def plain_points(value: Any) -> bool:
    """Whether ``value`` is a non-empty list of [x, y] number pairs (what the schema asks of
    ``task.points``), checked without the schema."""
    return (
        isinstance(value, list)
        and len(value) > 0
        and all(
            type(p) is list and len(p) == 2 and type(p[0]) in _NUMBER and type(p[1]) in _NUMBER
            for p in value
        )
    )


def check_finite_points(points: Any) -> None:
    """``ConfigError`` unless every coordinate of ``task.points`` is a finite number."""
    if not np.isfinite(np.asarray(points, dtype=float)).all():
        raise ConfigError("config key 'task.points': every coordinate must be a finite number")


def read_points_file(path: str | Path) -> list[list[float]]:
    """The points (n, 2) m of the CSV file ``path`` (header ``x_m,y_m``); ``ConfigError`` naming
    ``task.points_file``, the file and, for a bad cell, its line."""
    key = f"config key 'task.points_file': file '{path}'"
    try:
        lines = Path(path).read_text(encoding="utf-8-sig").splitlines()
    except OSError as exc:
        raise ConfigError(f"{key} cannot be read: {exc.strerror or exc}") from exc
    header = tuple(cell.strip() for cell in lines[0].split(",")) if lines else ()
    if header != POINTS_HEADER:
        raise ConfigError(
            f"{key}: the first line must be the header '{','.join(POINTS_HEADER)}' (x and y in "
            f"metres), not '{lines[0] if lines else ''}'"
        )
    points = []
    for k, line in enumerate(lines[1:], start=2):
        if not line.strip():
            continue
        try:
            x, y = (float(cell) for cell in line.split(","))
        except ValueError:
            raise ConfigError(
                f"{key}, line {k}: '{line}' is not two numbers x_m,y_m (metres)"
            ) from None
        if not (math.isfinite(x) and math.isfinite(y)):
            raise ConfigError(f"{key}, line {k}: every coordinate must be a finite number")
        points.append([x, y])
    if not points:
        raise ConfigError(f"{key} holds no points below its header")
    return points


def resolve_points_file(config: dict[str, Any], default_points: list[list[float]]) -> None:
    """Replace ``task.points_file`` in the schema-valid ``config`` by the file's points in
    ``task.points``, in place; ``ConfigError`` naming both keys when ``task.points`` holds other
    points than ``default_points`` (the two keys exclude each other; config/config.yaml's default
    task gives way to the file)."""
    task = config["task"]
    path = task.pop("points_file", None)
    if path is None:
        return
    if task["points"] != default_points:
        raise ConfigError(
            f"config keys 'task.points' and 'task.points_file' are both given (points_file "
            f"'{path}'): give the task's points one way, the points or the file"
        )
    task["points"] = read_points_file(path)
