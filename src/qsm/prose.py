"""Numbers in sentences: each value rounded and with its unit, written for a person (never a
Python list or an array's repr)."""

from __future__ import annotations

import math
from collections.abc import Sequence

from numpy.typing import ArrayLike


def per_motor(values: Sequence[float | None], digits: int, unit: str) -> str:
    """``motor 1 54.3 N m, motor 2 17.2 N m``; ``-`` where a motor has no value."""
    return ", ".join(
        f"motor {k} " + ("-" if v is None else f"{v:.{digits}f} {unit}".rstrip())
        for k, v in enumerate(values, start=1)
    )


def point(xy: ArrayLike, digits: int = 3, unit: str = "m") -> str:
    """A plane point: ``(-0.530, 0.170) m``."""
    x, y = (float(v) for v in xy)  # type: ignore[union-attr]
    return f"({x:.{digits}f}, {y:.{digits}f}) {unit}"


def listed(values: Sequence[float], digits: int, unit: str) -> str:
    """``297.0, 112.0 and 350.0 mm``."""
    text = [f"{float(v):.{digits}f}" for v in values]
    head = ", ".join(text[:-1])
    return f"{head} and {text[-1]} {unit}" if head else f"{text[-1]} {unit}"


def fixed(value: float, digits: int, significant: int = 4) -> str:
    """``value`` with ``digits`` decimals, fewer where that would show more than ``significant``
    significant digits: ``fixed(167.604, 2)`` is ``167.6``, ``fixed(0.4321, 2)`` is ``0.43``."""
    value = float(value)
    if not math.isfinite(value) or value == 0:
        return f"{value:.{digits}f}"
    whole = math.floor(math.log10(abs(value))) + 1
    places = max(0, min(digits, significant - whole))
    if places and abs(round(value, places)) >= 10.0**whole:  # 9.9996 rounds up to 10.000
        places -= 1
    return f"{value:.{places}f}"
