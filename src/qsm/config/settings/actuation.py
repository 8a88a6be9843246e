"""Settings of the drives: the catalogue and the drive check of a design."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from qsm.embodiment.drives.catalogue import Catalogue, load_catalogue
from qsm.embodiment.drives.drive_checks import DriveCheck
from qsm.embodiment.load_case import LoadCase

Section = Mapping[str, Any]


def catalogue(section: Section) -> Catalogue:
    """``drives.catalogue``: the drive catalogue (null: the one shipped with qsm), read once per
    process (:func:`qsm.embodiment.drives.catalogue.load_catalogue`)."""
    return load_catalogue(section["catalogue"])


def drive_check(drives_section: Section, case: LoadCase) -> DriveCheck:
    """The drive check of a design under ``case``: the catalogue, rule and reflected inertia of
    ``drives``."""
    return DriveCheck(
        catalogue(drives_section),
        drives_section["rule"],
        bool(drives_section["reflected_inertia"]),
        case.cad,
        case.payload_kg,
        case.cycle(),
    )
