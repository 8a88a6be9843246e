"""A design's link strength as a record for outputs, and the verdict sentence that states it.

Every number comes from :class:`qsm.embodiment.link_checks.StrengthCheck` run on the design.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from qsm.embodiment.link_checks import StrengthCheck
from qsm.physics.kinematics import LINK_NAMES


def _finite(x: float) -> float | None:
    return float(x) if math.isfinite(x) else None


def strength_record(design: ArrayLike, check: StrengthCheck) -> dict[str, Any]:
    """Per link: peak stress and allowable (MPa), safety factor and the required one, buckling
    factor (None: never compressed) and the required one, whether it holds; then the largest
    utilisation, the weakest link and check, and whether every link holds."""
    row = check.evaluate(np.asarray(design, dtype=float)).iloc[0]
    allow = check.allowable_stress_pa / 1e6
    links = {}
    for link in LINK_NAMES:
        stress, buckling = float(row[f"stress_peak_{link}_MPa"]), row[f"buckling_factor_{link}"]
        links[link] = {
            "stress_peak_MPa": stress,
            "allowable_MPa": allow,
            "safety_factor": float(row[f"safety_factor_{link}"]),
            "required_safety_factor": check.strength.safety_factor,
            "buckling_factor": _finite(float(buckling)),
            "required_buckling_factor": check.strength.buckling_safety_factor,
            "holds": bool(
                stress <= allow * (1 + 1e-12)
                and buckling >= check.strength.buckling_safety_factor * (1 - 1e-12)
            ),
        }
    return {
        "links": links,
        "utilisation": float(row["strength_utilisation"]),
        "weakest_link": str(row["weakest_link"]),
        "weakest_check": str(row["weakest_check"]),
        "holds_loads": bool(row["holds_loads"]),
        "material": check.material.name,
        "payload_kg": check.payload_kg,
    }


def strength_verdict(record: Mapping[str, Any]) -> str:
    """One sentence: how the weakest link fares, in MPa or as a buckling factor."""
    link = record["weakest_link"]
    r = record["links"][link]
    name = link.replace("_", " ")
    if record["weakest_check"] == "buckling":
        factor = f"{r['buckling_factor']:.2f}" if r["buckling_factor"] is not None else "inf"
        text = (
            f"the {name}'s Euler load is {factor} x its peak compression "
            f"({r['required_buckling_factor']:g} required)"
        )
    else:
        text = (
            f"the {name} reaches {r['stress_peak_MPa']:.1f} MPa, {r['allowable_MPa']:.1f} MPa "
            f"allowed (at the {record['weakest_check']})"
        )
    if record["holds_loads"]:
        return f"weakest: {text}"
    return f"NOT STRONG ENOUGH: {text}"
