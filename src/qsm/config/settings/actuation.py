"""Settings of the drives: the catalogue and the drive check of a design."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from qsm.config.settings.physics import cad
from qsm.embodiment.drives.catalogue import Catalogue, load_catalogue
from qsm.embodiment.drives.drive_checks import DriveCheck
from qsm.physics.duty import DutySettings, duty_cycle

Section = Mapping[str, Any]


def catalogue(section: Section) -> Catalogue:
    """``drives.catalogue``: the drive catalogue (null: the one shipped with qsm), read once per
    process (:func:`qsm.embodiment.drives.catalogue.load_catalogue`)."""
    return load_catalogue(section["catalogue"])


def drive_check(
    drives_section: Section,
    cad_section: Section,
    material_section: Section,
    payload_kg: float,
    duty_settings: DutySettings,
) -> DriveCheck:
    """The drive check of a design: catalogue, rule, reflected inertia, link section, payload
    (kg) and duty."""
    return DriveCheck(
        catalogue(drives_section),
        drives_section["rule"],
        bool(drives_section["reflected_inertia"]),
        cad(cad_section, material_section),
        float(payload_kg),
        duty_cycle(duty_settings),
    )
