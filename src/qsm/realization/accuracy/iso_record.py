"""The ISO 9283 figures of a realised arm for ``selected.json``: its random terms taken from the
chosen drives, the catalogue and the payload test, each with where it comes from
(:func:`random_terms`), and the JSON record with the repeatability check (:func:`iso_record`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from qsm.embodiment.drives.catalogue import Catalogue
from qsm.embodiment.drives.compliance import ARCMIN_RAD
from qsm.embodiment.drives.report import DriveReport, MotorReport
from qsm.realization.accuracy.iso9283 import RANDOM_TERMS, PoseCharacteristics, RandomTerms


@dataclass(frozen=True)
class IsoSettings:
    """``cycles`` per point and the Monte Carlo's ``seed``; ``encoder_counts``, counts per motor
    turn where the catalogue's row has none; ``kp_Nm_rad`` (2,), the servo's stiffness at the
    joints (the payload test's proportional gains); ``repeatability_mm``, the task's largest RP
    (None: no requirement)."""

    cycles: int
    seed: int
    encoder_counts: float
    kp_Nm_rad: tuple[float, float]
    repeatability_mm: float | None = None


def _number(row: Mapping[str, Any], key: str) -> float:
    value = row.get(key)
    return math.nan if value is None else float(value)


def _motor_terms(
    motor: MotorReport, catalogue: Catalogue, kp: float, counts: float, opens: bool
) -> tuple[tuple[float, float, float], dict[str, str]]:
    """One motor's backlash (where its play ``opens``), encoder quantum and friction
    deflection (rad at the joint) and where each comes from."""
    d = motor.drive
    row = catalogue.motors.loc[d.motor_key].to_dict()
    ratio = d.ratio
    own = _number(row, "encoder_counts")
    n = own if np.isfinite(own) and own > 0 else counts
    friction_Nm = _number(row, "I_nl") * _number(row, "k_t") * ratio
    known = np.isfinite(friction_Nm)
    play = d.backlash_arcmin
    values = (play * ARCMIN_RAD if opens else 0.0, 2 * math.pi / (n * ratio),
              friction_Nm / kp if known else 0.0)  # fmt: skip
    sources = {
        "backlash": (
            f"{play:g} arcmin"
            if opens
            else f"0: the joint's torque keeps one sign along the task and at the five points, so "
            f"gravity holds its {play:g} arcmin of play closed"
        )
        + f" ({d.backlash_from})",
        "encoder": f"{n:g} counts per motor turn over {ratio:g}:1, "
        + ("motors.csv's encoder_counts" if n == own else "assumed: iso9283.encoder_counts"),
        "friction": (
            f"no-load friction I_nl x k_t = {friction_Nm / ratio * 1e3:.1f} mN m at the motor "
            f"(motors.csv), x {ratio:g} at the joint, over the servo's {kp:g} N m/rad"
            if known
            else "motors.csv gives no I_nl for this motor: not counted"
        ),
    }
    return values, sources


def random_terms(
    drives: DriveReport, catalogue: Catalogue, payload: Mapping[str, Any],
    settings: IsoSettings, opens: Sequence[bool] = (True, True),
) -> tuple[RandomTerms, dict[str, list[str]]]:  # fmt: skip
    """The random terms of the arm's chosen drives (``drives``: the drive report), its
    ``catalogue`` and its ``payload`` test (the settling error: its largest at the end of a
    hold), and what each was taken from, per motor; a gearbox's backlash only where its play
    ``opens`` (:func:`qsm.realization.accuracy.iso9283.play_opens`)."""
    values, sources = [], {k: [] for k in RANDOM_TERMS}
    motors = zip(drives.motors.values(), settings.kp_Nm_rad, opens, strict=True)
    for motor, kp, open_ in motors:
        v, s = _motor_terms(motor, catalogue, float(kp), settings.encoder_counts, bool(open_))
        values.append(v)
        for key, text in s.items():
            sources[key].append(text)
    settle = float(max(payload.get("point_error_mm") or [0.0]))
    sources["settling"] = [
        f"{settle:.4f} mm: the payload test's largest tool error at the end of a hold, its "
        "controller and plant (the same gains), random in direction and size within it"
    ]
    b, e, f = (np.array(col) for col in zip(*values, strict=True))
    return RandomTerms(b, e, f, settle), sources


def iso_record(
    pc: PoseCharacteristics, sources: Mapping[str, Sequence[str]], payload_kg: float,
    repeatability_mm: float | None, mirrored: bool,
) -> dict[str, Any]:  # fmt: skip
    """JSON-ready ISO 9283 record of ``pc``: the plane (in the user's frame, mirrored back when
    the task was designed ``mirrored``), AP and RP per point with their terms, the main random
    term, and whether RP meets ``repeatability_mm``."""
    sign = np.array([-1.0 if mirrored else 1.0, 1.0])
    worst = int(np.argmax(pc.rp_mm))
    meets = None if repeatability_mm is None else bool(pc.rp_mm.max() <= repeatability_mm)
    return {
        "standard": "ISO 9283:1998, pose accuracy (AP) and pose repeatability (RP)",
        "plane_centre_m": (np.asarray(pc.plane.centre_m) * sign).tolist(),
        "plane_side_m": pc.plane.side_m,
        "points_m": (pc.plane.points_m * sign).tolist(),
        "payload_kg": payload_kg,
        "cycles": pc.cycles,
        "seed": pc.seed,
        "ap_mm": pc.ap_mm.tolist(),
        "rp_mm": pc.rp_mm.tolist(),
        "static_sag_mm": pc.static_sag_mm.tolist(),
        "base_mm": pc.base_mm.tolist(),
        "random_mean_mm": pc.random_mean_mm.tolist(),
        "compensated_ap_mm": pc.compensated_ap_mm.tolist(),
        "creep_mm": pc.creep_mm.tolist(),
        "service_ap_mm": pc.service_ap_mm.tolist(),
        "service_time_h": pc.service_time_h,
        "rp_alone_mm": {k: v.tolist() for k, v in zip(RANDOM_TERMS, pc.rp_alone_mm, strict=True)},
        "main_random_term": pc.main_random_term,
        "worst_point": worst + 1,
        "sources": {k: list(v) for k, v in sources.items()},
        "repeatability_mm": repeatability_mm,
        "meets_repeatability": meets,
    }
