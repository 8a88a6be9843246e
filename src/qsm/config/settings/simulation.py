"""Settings of the simulated payload test (Stage 6) and of the front's cycles."""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from typing import Any

from qsm.config.settings.actuation import drive_check
from qsm.config.settings.links import load_case_of, strength_check
from qsm.embodiment.drives.catalogue import Catalogue
from qsm.embodiment.strength.link_checks import StrengthCheck
from qsm.physics.workspace import OperatingRange
from qsm.realization.motion.payload import PayloadSettings

Section = Mapping[str, Any]


def payload_test(section: Section, payload_kg: float, op: OperatingRange) -> PayloadSettings:
    """``payload_test`` with ``task.payload_kg`` and the motors' operating range ``op``."""
    return PayloadSettings(
        payload_kg=payload_kg,
        torque_limits_Nm=(
            None if section["torque_limits_Nm"] is None else tuple(section["torque_limits_Nm"])
        ),
        segment_duration_s=section["segment_duration_s"],
        dwell_s=section["dwell_s"],
        return_to_start=section["return_to_start"],
        kp_Nm_rad=tuple(section["kp_Nm_rad"]),
        kd_Nms_rad=tuple(section["kd_Nms_rad"]),
        ki_Nm_rad_s=tuple(section["ki_Nm_rad_s"]),
        tracking_tolerance_deg=section["tracking_tolerance_deg"],
        plant_mass_error=section["plant_mass_error"],
        operating_range=op,
    )


def task_motion(section: Section, payload_kg: float, op: OperatingRange) -> PayloadSettings:
    """The task's motion: the :data:`qsm.physics.task_points.MOTION_KEYS` of ``payload_test``
    (the others' defaults, which it does not read), with ``task.payload_kg`` and
    ``operating_range``."""
    return PayloadSettings(
        payload_kg=payload_kg,
        segment_duration_s=section["segment_duration_s"],
        dwell_s=section["dwell_s"],
        return_to_start=section["return_to_start"],
        operating_range=op,
    )


@dataclasses.dataclass(frozen=True)
class CycleSettings:
    """What the time-optimal cycle of a front's design needs: its links' check, the drive
    catalogue and the payload test's settings (payload, gains, operating range)."""

    strength: StrengthCheck
    catalogue: Catalogue
    test: PayloadSettings


def cycles_of(config: Section) -> CycleSettings:
    """The front's cycles' settings (the rule ``front_cycles``) from a validated config, or from
    its share of one (:func:`qsm.config.sections.cycles_section`, the rule's param)."""
    case = load_case_of(config)
    return CycleSettings(
        strength=strength_check(case, config["strength"]),
        catalogue=drive_check(config["drives"], case).catalogue,
        test=payload_test(config["payload_test"], case.payload_kg, case.operating_range),
    )
