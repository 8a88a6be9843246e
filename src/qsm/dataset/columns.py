"""Stage 2's columns with their units: the mechanisms', dynamics', strength's, drives' and
stiffness's, each defined by its own domain and collected here.

Light on purpose (no MuJoCo, no trimesh): most later rules read the dataset through it and
:mod:`qsm.dataset.gathering`."""

from __future__ import annotations

from qsm.embodiment.drives.drive_columns import DRIVE_CHECKS, DRIVE_COLUMNS, MOTORS
from qsm.embodiment.stiffness.stiffness_columns import STIFFNESS_COLUMNS
from qsm.embodiment.strength.strength_columns import JOINT_COLUMNS, STRENGTH_COLUMNS
from qsm.mechanisms.scale import MECHANISM_COLUMNS
from qsm.physics.results import DYNAMICS_COLUMNS

__all__ = [
    "DATASET_COLUMNS",
    "DRIVE_CHECKS",
    "DRIVE_COLUMNS",
    "DYNAMICS_COLUMNS",
    "JOINT_COLUMNS",
    "MOTORS",
    "STIFFNESS_COLUMNS",
    "STRENGTH_COLUMNS",
]

DATASET_COLUMNS: dict[str, str] = {
    **MECHANISM_COLUMNS,
    **DYNAMICS_COLUMNS,
    **STRENGTH_COLUMNS,
    **DRIVE_COLUMNS,
    **STIFFNESS_COLUMNS,
}
