"""What would let a design's links hold their loads, each answer checked by the strength check.

For a design that does not hold (:class:`qsm.embodiment.strength.link_checks.StrengthCheck`), every
lever is searched by bisection with the full check (the link masses, and so the loads, follow the
section): the smallest boss that holds (room for larger bearings and shafts), the thinnest plate
that holds, the weakest material that holds, and the heaviest payload that holds. A lever that
cannot make the design hold within its range is None.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from qsm.embodiment.strength.link_checks import StrengthCheck

#: Largest multiple of the configured value a lever searches.
MAX_FACTOR = 8.0


def _bisect(holds: Callable[[float], bool], bad: float, good: float) -> float:
    """The point between ``bad`` (does not hold) and ``good`` (holds) where a monotone
    ``holds`` changes, on the side that holds (to 1e-4 of the interval)."""
    tol = 1e-4 * abs(good - bad)
    while abs(good - bad) > tol:
        mid = 0.5 * (bad + good)
        bad, good = (bad, mid) if holds(mid) else (mid, good)
    return good


def strength_advice(design: ArrayLike, check: StrengthCheck) -> dict[str, Any]:
    """Levers that make ``design`` (6 lengths, m) hold its loads under ``check``: the boss radius
    (m, room for larger bearings and shafts), the thickness (m), the yield strength (Pa) and the
    payload (kg) that would, each alone, within :data:`MAX_FACTOR` of (or, for the payload,
    below) the configured value; None where that lever alone cannot."""
    d = np.asarray(design, dtype=float)

    def holds_with(c: StrengthCheck) -> bool:
        return bool(c.violation(d)[0] <= 0)

    t0 = check.cad.thickness_m
    y0 = check.material.yield_strength_pa
    r0 = check.cad.boss_radius_m
    levers = {
        "boss_radius_m": (
            lambda r: holds_with(replace(check, cad=replace(check.cad, boss_radius_m=r))),
            r0,
            MAX_FACTOR * r0,
        ),
        "thickness_m": (
            lambda t: holds_with(replace(check, cad=replace(check.cad, thickness_m=t))),
            t0,
            MAX_FACTOR * t0,
        ),
        "yield_strength_pa": (
            lambda y: holds_with(
                replace(check, material=replace(check.material, yield_strength_pa=y))
            ),
            y0,
            MAX_FACTOR * y0,
        ),
        "payload_kg": (lambda p: holds_with(replace(check, payload_kg=p)), check.payload_kg, 0.0),
    }
    return {
        name: float(_bisect(holds, now, far)) if holds(far) else None
        for name, (holds, now, far) in levers.items()
    }


def advice_sentences(advice: dict[str, Any], check: StrengthCheck) -> list[str]:
    """The levers as plain sentences, every number from ``advice``."""
    lines = []
    r, r0 = advice["boss_radius_m"], check.cad.boss_radius_m
    lines.append(
        f"larger joint bosses: cad.boss_radius_m {1e3 * r:.1f} mm or more (now {1e3 * r0:g} mm)"
        if r is not None
        else f"no boss up to {1e3 * MAX_FACTOR * r0:g} mm radius alone"
    )
    t = advice["thickness_m"]
    t0 = check.cad.thickness_m
    lines.append(
        f"thicker links: cad.thickness_m {1e3 * t:.1f} mm or more (now {1e3 * t0:g} mm)"
        if t is not None
        else f"no plate up to {1e3 * MAX_FACTOR * t0:g} mm thick alone"
    )
    y = advice["yield_strength_pa"]
    y0 = check.material.yield_strength_pa
    lines.append(
        f"a stronger material: material.yield_strength_pa {y / 1e6:.1f} MPa or more "
        f"(now {y0 / 1e6:g} MPa)"
        if y is not None
        else f"no material up to {MAX_FACTOR * y0 / 1e6:g} MPa alone"
    )
    p = advice["payload_kg"]
    lines.append(
        f"a lighter payload: task.payload_kg {p:.2f} kg or less (now {check.payload_kg:g} kg)"
        if p is not None
        else "no payload: the links do not hold even their own weight and inertia"
    )
    return lines
