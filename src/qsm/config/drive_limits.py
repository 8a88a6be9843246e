"""Checks of the configured drives and payload: the drive catalogue reads, and the link section and
the motors (their torque limits, N m) can hold the payload (kg) at every task point.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from qsm.config.errors import ConfigError

G = 9.81  # m/s^2
#: A payload from this mass (kg) up is reported as grams when it is too heavy.
GRAMS_FROM_KG = 100.0


def catalogue_folder(config: dict[str, Any]) -> str:
    """The drive catalogue's folder: ``drives.catalogue``, or the one shipped with qsm."""
    from qsm.embodiment.drives.catalogue import catalogue_folder as folder_of

    return str(folder_of(config["drives"]["catalogue"]))


def check_drives(config: dict[str, Any]) -> None:
    """The drive catalogue reads: every file, row and column valid, ``interfaces.csv`` too (the
    error names them)."""
    from qsm.embodiment.drives.catalogue import load_catalogue
    from qsm.embodiment.kit.interfaces import interface_rows

    folder = catalogue_folder(config)
    try:
        gearboxes = load_catalogue(folder).gearboxes.index
        rows = interface_rows(folder)  # every file, row and column; a key given twice
        unknown = [
            (path, line, key) for key, (path, line, _) in rows.items() if key not in gearboxes
        ]
    except (ValueError, FileNotFoundError) as exc:
        raise ConfigError(f"config key 'drives.catalogue': {exc}") from None
    if unknown:
        path, line, key = unknown[0]
        raise ConfigError(
            f"config key 'drives.catalogue': {path}, line {line}: key {key!r} is no gearbox "
            "of the catalogue's gearboxes (a row for it would never be used)"
        )


def motor_limits_Nm(config: dict[str, Any]) -> tuple[list[float], str]:
    """The largest torque each motor can give at the output, and where it comes from: the
    override ``payload_test.torque_limits_Nm``, or the strongest drive of the catalogue."""
    limits = config["payload_test"]["torque_limits_Nm"]
    if limits is not None:
        return [float(v) for v in limits], "payload_test.torque_limits_Nm"
    from qsm.embodiment.drives.catalogue import load_catalogue
    from qsm.embodiment.drives.selection import offer

    peak = max(o["peak_torque_Nm"] for o in offer(load_catalogue(catalogue_folder(config))))
    return [peak, peak], "the strongest drive of drives.catalogue, for each motor"


def check_payload(config: dict[str, Any]) -> None:
    """A payload the link section and the motors can hold at every task point (payload alone)."""
    mass = config["task"]["payload_kg"]
    cad = config["cad"]
    allowable = config["material"]["yield_strength_pa"] / config["strength"]["safety_factor"]
    section_kg = cad["width_m"] * cad["thickness_m"] * allowable / G
    limits, source = motor_limits_Nm(config)
    points = np.asarray(config["task"]["points"], dtype=float)
    arm = float(np.abs(points[:, 0]).max())
    motors_kg = sum(limits) / (G * arm) if arm > 0 else math.inf
    if mass <= min(section_kg, motors_kg):
        return
    if section_kg <= motors_kg:
        bound, basis = (
            section_kg,
            (
                f"its weight would stress a link section of cad.width_m x cad.thickness_m beyond "
                f"material.yield_strength_pa / strength.safety_factor = {allowable:.3g} Pa even in "
                f"pure tension"
            ),
        )
    else:
        bound, basis = (
            motors_kg,
            (
                f"holding it {arm:.3g} m out from the base (the task point farthest out in x) "
                f"takes motor torques summing to m g |x| = {mass * G * arm:.0f} N m (turning both "
                f"motors together turns the whole arm about the base; the links' own weight "
                f"aside), beyond {limits[0]:g} + {limits[1]:g} N m ({source})"
            ),
        )
    cause = (
        f"; looks like grams: task.payload_kg is in kilograms ({mass:g} g = {mass / 1e3:g} kg)"
        if mass >= GRAMS_FROM_KG and mass / 1e3 <= bound
        else ""
    )
    raise ConfigError(
        f"config key 'task.payload_kg': {mass:g} kg is more than the arm can hold: {basis}; at "
        f"most {bound:.3g} kg is possible{cause}"
    )
