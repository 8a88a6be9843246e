"""A design's strength as a typed record: each link's stresses and factors, each joint's
bearing and its load, and the verdict's figures; turned into JSON and back here.

Every number comes from :class:`qsm.embodiment.strength.link_checks.StrengthCheck` run on the
design (:func:`strength_record`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import asdict, dataclass, fields
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike

from qsm.embodiment.strength.link_checks import StrengthCheck
from qsm.embodiment.strength.sizing import SizedSections
from qsm.physics.kinematics import LINK_NAMES

#: The joints whose bearings the record holds, in order.
JOINTS = ("A", "B", "C", "D")


@dataclass(frozen=True)
class LinkStrength:
    """One link over the duty: peak stress and allowable (MPa), safety factor against yield and
    the required one, buckling factor (None: never compressed) and the required one, whether it
    holds, and its section (mm)."""

    stress_peak_MPa: float
    allowable_MPa: float
    safety_factor: float
    required_safety_factor: float
    buckling_factor: float | None
    required_buckling_factor: float
    holds: bool
    width_mm: float
    thickness_mm: float


@dataclass(frozen=True)
class BearingLoad:
    """One joint's bearing: its designation ('' where none of the table fits), its peak force
    (N) and where (theta1, theta2 in deg); for a bearing of the table its bore ``d_mm``, outer
    diameter ``D_mm`` and width ``B_mm`` (mm), ratings (kN), static rating over the peak force
    (None: no force), maker and source (None where none fits)."""

    designation: str
    peak_force_N: float
    at_theta_deg: tuple[float, float]
    d_mm: float | None = None
    D_mm: float | None = None
    B_mm: float | None = None
    C_kN: float | None = None
    C0_kN: float | None = None
    static_safety: float | None = None
    maker: str | None = None
    source: str | None = None


@dataclass(frozen=True)
class StrengthRecord:
    """A design's strength: its links and bearings, the bearings' required static safety, the
    largest utilisation, the weakest link and check, whether every link and bearing holds, the
    material, the payload (kg) it was checked with, how the sections came about (``fixed``,
    ``sized``; the realisation adds ``grown`` and ``sized and grown`` for the tolerance) and
    the sizing's iterations, and the tool flange's mass (kg) beside the payload (None: no
    flange was carried)."""

    links: Mapping[str, LinkStrength]
    bearings: Mapping[str, BearingLoad]
    required_bearing_safety: float
    utilisation: float
    weakest_link: str
    weakest_check: str
    holds_loads: bool
    material: str
    payload_kg: float
    section: str
    section_iterations: int
    tool_flange_kg: float | None = None

    @property
    def required_safety_factor(self) -> float:
        """The links' largest required safety factor against yield."""
        return max(link.required_safety_factor for link in self.links.values())


def _finite(x: float) -> float | None:
    return float(x) if math.isfinite(x) else None


def _bearing(row: pd.Series, joint: str, check: StrengthCheck) -> BearingLoad:
    """Joint ``joint``'s bearing in a design's strength row (at A the more loaded of the two
    links' bores), with the catalogue's figures."""
    name = str(row[f"bearing_{joint}"])
    column = "A_lower_arm" if joint == "A" else joint
    if joint == "A" and row["joint_force_peak_A_crank_N"] > row["joint_force_peak_A_lower_arm_N"]:
        column = "A_crank"
    force = float(row[f"joint_force_peak_{column}_N"])
    theta = (
        float(row[f"joint_force_peak_{column}_theta1_deg"]),
        float(row[f"joint_force_peak_{column}_theta2_deg"]),
    )
    if not name:
        return BearingLoad(name, force, theta)
    table = check.bearings
    b = table.row(int(np.flatnonzero(table.designation == name)[0]))
    return BearingLoad(
        name,
        force,
        theta,
        d_mm=1e3 * b["d_m"],
        D_mm=1e3 * b["D_m"],
        B_mm=1e3 * b["B_m"],
        C_kN=b["C_N"] / 1e3,
        C0_kN=b["C0_N"] / 1e3,
        static_safety=b["C0_N"] / force if force > 0 else None,
        maker=b["maker"],
        source=b["source"],
    )


def _link(row: pd.Series, link: str, check: StrengthCheck) -> LinkStrength:
    stress, buckling = float(row[f"stress_peak_{link}_MPa"]), row[f"buckling_factor_{link}"]
    allow, s = check.allowable_stress_pa / 1e6, check.strength
    return LinkStrength(
        stress_peak_MPa=stress,
        allowable_MPa=allow,
        safety_factor=float(row[f"safety_factor_{link}"]),
        required_safety_factor=s.safety_factor,
        buckling_factor=_finite(float(buckling)),
        required_buckling_factor=s.buckling_safety_factor,
        holds=bool(
            stress <= allow * (1 + 1e-12)
            and buckling >= s.buckling_safety_factor * (1 - 1e-12)
            and (bool(row["holds_loads"]) or str(row["weakest_link"]) != link)
        ),
        width_mm=float(row[f"section_width_{link}_mm"]),
        thickness_mm=float(row[f"section_thickness_{link}_mm"]),
    )


def strength_record(
    design: ArrayLike, check: StrengthCheck, sized: SizedSections | None = None
) -> StrengthRecord:
    """The strength of ``design`` (6 lengths, m) under ``check``; ``sized``: the design's
    sections when not the check's own."""
    d = np.atleast_2d(np.asarray(design, dtype=float))
    row = check.evaluate_with_torques(d, sized)[0].iloc[0]
    return StrengthRecord(
        links={link: _link(row, link, check) for link in LINK_NAMES},
        bearings={joint: _bearing(row, joint, check) for joint in JOINTS},
        required_bearing_safety=check.strength.bearing_safety_factor,
        utilisation=float(row["strength_utilisation"]),
        weakest_link=str(row["weakest_link"]),
        weakest_check=str(row["weakest_check"]),
        holds_loads=bool(row["holds_loads"]),
        material=check.material.name,
        payload_kg=check.payload_kg,
        section="fixed" if check.sizing is None else "sized",
        section_iterations=int(row["section_iterations"]),
    )


def bearing_json(bearing: BearingLoad) -> dict[str, Any]:
    """A bearing as JSON: the catalogue's figures only where one of the table fits."""
    out = asdict(bearing)
    out["at_theta_deg"] = list(bearing.at_theta_deg)
    if not bearing.designation:
        out = {k: out[k] for k in ("designation", "peak_force_N", "at_theta_deg")}
    return out


def strength_json(record: StrengthRecord) -> dict[str, Any]:
    """``record`` as JSON-ready values (the tool flange's mass only where one was carried)."""
    out = {f.name: getattr(record, f.name) for f in fields(record)}
    out["links"] = {name: asdict(link) for name, link in record.links.items()}
    out["bearings"] = {joint: bearing_json(b) for joint, b in record.bearings.items()}
    if record.tool_flange_kg is None:
        del out["tool_flange_kg"]
    return out


def strength_of(data: Mapping[str, Any]) -> StrengthRecord:
    """The :class:`StrengthRecord` that :func:`strength_json` wrote."""
    bearings = {
        joint: BearingLoad(**{**b, "at_theta_deg": tuple(b["at_theta_deg"])})
        for joint, b in data["bearings"].items()
    }
    links = {name: LinkStrength(**link) for name, link in data["links"].items()}
    return StrengthRecord(**{**data, "links": links, "bearings": bearings})
