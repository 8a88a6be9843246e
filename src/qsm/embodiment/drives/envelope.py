"""The torque one drive can give at its joint, by speed and direction (N m), for a simulation that
saturates the motor on it; the conventions of :mod:`qsm.embodiment.drives.utilization`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from qsm.embodiment.drives.catalogue import Catalogue
from qsm.embodiment.drives.utilization import DriveArrays


@dataclass(frozen=True)
class OutputEnvelope:
    """The torque one drive can give at the joint (output side), by speed and direction, for a
    simulation that saturates the motor on it (the conventions of
    :func:`qsm.embodiment.drives.utilization.utilisation`: a driving sample gets eta N T_m, a
    back-driven one N T_m / eta, both at most the gearbox's intermittent torque; T_m is the motor's
    torque-speed line or table at N |omega|, at most its intermittent torque, and 0 beyond its
    speed limit)."""

    name: str
    ratio: float
    efficiency: float
    stall_torque: float
    no_load_speed: float
    int_torque: float
    int_speed: float
    gear_int_torque: float
    reflected_inertia: float
    table: tuple[np.ndarray, np.ndarray] | None = None

    @classmethod
    def of(cls, cat: Catalogue, motor_key: str, gearbox_key: str) -> OutputEnvelope:
        """The envelope of the catalogue's drive (motor_key, gearbox_key)."""
        rows = np.flatnonzero(
            (cat.drives["motor"] == motor_key).to_numpy()
            & (cat.drives["gearbox"] == gearbox_key).to_numpy()
        )
        if not rows.size:
            raise KeyError(f"no drive ({motor_key}, {gearbox_key}) in the catalogue")
        i = int(rows[0])
        arr = DriveArrays.of(cat).take(np.array([i]))
        m, g = cat.motors.loc[motor_key], cat.gearboxes.loc[gearbox_key]
        return cls(
            name=f"{m['manufacturer']} {m['ID']} + {g['manufacturer']} {g['ID']}",
            ratio=float(arr.ratio[0]),
            efficiency=float(arr.efficiency[0]),
            stall_torque=float(arr.stall_torque[0]),
            no_load_speed=float(arr.no_load_speed[0]),
            int_torque=float(arr.int_torque[0]),
            int_speed=float(arr.int_speed[0]),
            gear_int_torque=float(arr.gear_int_torque[0]),
            reflected_inertia=float(cat.drives["reflected_inertia"].iloc[i]),
            table=arr.tables.get(0),
        )

    def limit(self, tau: ArrayLike, omega: ArrayLike) -> np.ndarray:
        """Largest |torque| (N m) the drive gives at the joint in the direction of ``tau`` at
        joint speed ``omega`` (rad/s)."""
        tau, omega = np.asarray(tau, float), np.asarray(omega, float)
        w_m = self.ratio * np.abs(omega)
        driving = tau * omega >= 0
        if self.table is not None:
            t_m = np.interp(w_m, *self.table)
        else:
            line = self.stall_torque * np.clip(1.0 - w_m / self.no_load_speed, 0.0, None)
            t_m = np.where(driving, line, self.stall_torque)
        t_m = np.where(w_m > self.int_speed, 0.0, np.fmin(t_m, self.int_torque))
        eta = self.efficiency
        out = np.where(driving, eta * self.ratio * t_m, self.ratio * t_m / eta)
        return np.fmin(out, self.gear_int_torque)

    def limit_at(self, tau: float, omega: float) -> float:
        """:meth:`limit` at one torque (N m) and joint speed (rad/s), in plain floats: a
        simulation asks it at every step."""
        w_m = self.ratio * abs(omega)
        driving = tau * omega >= 0
        if self.table is not None:
            t_m = float(np.interp(w_m, *self.table))
        elif driving:
            t_m = self.stall_torque * max(1.0 - w_m / self.no_load_speed, 0.0)
        else:
            t_m = self.stall_torque
        t_m = 0.0 if w_m > self.int_speed else min(t_m, self.int_torque)
        eta = self.efficiency
        out = eta * self.ratio * t_m if driving else self.ratio * t_m / eta
        return min(out, self.gear_int_torque)
