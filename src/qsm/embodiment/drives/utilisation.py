"""The utilisation of every motor-gearbox pair of the catalogue over a joint's duty, all at once.

The duty of one joint is a set of samples: output torque tau (N m), output speed omega (rad/s)
and the time each sample stands for, w (s). Conventions (magnitudes; the gearbox ``direction``
does not matter):

- motor speed w_m = ratio |omega| (rad/s);
- driving samples (tau omega >= 0: power flows from the motor to the load, standstill included):
  motor torque tau_m = |tau| / (ratio eta); back-driven samples (tau omega < 0: the load drives
  the motor through the gear): tau_m = |tau| eta / ratio;
- DC motor (type DC or BLDC, no torque-speed table): stall torque T_s = k_t V / R; a driving
  sample uses u = tau_m / T_s + w_m / omega_nl, the datasheet's straight torque-speed line at V
  (u = 1 on it); a back-driven (braking) sample uses u = tau_m / T_s (the supply then allows at
  least the stall current);
- a motor with a torque-speed table (a stepper's pull-out curve): u = tau_m / T(w_m), T
  interpolated linearly; its speed limit is the table's last speed;
- friction and no-load current are not modelled (the omega_nl line already contains them).

Each drive gets five utilisations (required over allowed, <= 1 meets the limit), in CHECKS order:
motor_peak = max over samples of max(u, tau_m / max_int_torque); motor_rms = rms(tau_m) /
(k_t I_nom), the thermal (continuous) rating, rms weighted by w; motor_speed = max(max w_m /
max_int_speed, rms(w_m) / max_cont_speed); gear_peak = max |tau| / max_int_torque of the
gearbox; gear_rms = rms(tau) / max_cont_torque of the gearbox. A value a check needs that the
catalogue lacks (nan) makes the utilisation infinite.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from qsm.embodiment.drives.catalogue import Catalogue

CHECKS = ("motor_peak", "motor_rms", "motor_speed", "gear_peak", "gear_rms")
_CHUNK = 2_000_000  # elements of a (designs, drives, samples) block held at once


@dataclass(frozen=True)
class DriveArrays:
    """Per-drive limits (C,) in SI units, motor side unless named gear_."""

    ratio: np.ndarray
    efficiency: np.ndarray
    stall_torque: np.ndarray  # k_t V / R, N m
    no_load_speed: np.ndarray  # rad/s
    int_torque: np.ndarray  # N m
    cont_torque: np.ndarray  # k_t I_nom, N m
    int_speed: np.ndarray  # rad/s
    cont_speed: np.ndarray  # rad/s
    gear_int_torque: np.ndarray  # N m at the output
    gear_cont_torque: np.ndarray  # N m at the output
    tables: dict[int, tuple[np.ndarray, np.ndarray]]  # drive index -> (speed, torque)

    @classmethod
    def of(cls, cat: Catalogue) -> DriveArrays:
        m = cat.motors.loc[cat.drives["motor"]]
        g = cat.gearboxes.loc[cat.drives["gearbox"]]
        col = lambda frame, name: frame[name].to_numpy(dtype=float)  # noqa: E731
        tables = {
            i: cat.torque_speed[k]
            for i, k in enumerate(cat.drives["motor"])
            if k in cat.torque_speed
        }
        int_speed = col(m, "max_int_speed").copy()
        for i, (speed, _) in tables.items():
            int_speed[i] = min(int_speed[i], speed[-1])
        with np.errstate(divide="ignore", invalid="ignore"):
            stall = col(m, "k_t") * col(m, "V") / col(m, "R")
        return cls(
            ratio=cat.drives["ratio"].to_numpy(dtype=float),
            efficiency=cat.drives["efficiency"].to_numpy(dtype=float),
            stall_torque=stall,
            no_load_speed=col(m, "omega_nl"),
            int_torque=col(m, "max_int_torque"),
            cont_torque=col(m, "k_t") * col(m, "I_nom"),
            int_speed=int_speed,
            cont_speed=col(m, "max_cont_speed"),
            gear_int_torque=col(g, "max_int_torque"),
            gear_cont_torque=col(g, "max_cont_torque"),
            tables=tables,
        )

    def take(self, idx: np.ndarray) -> DriveArrays:
        """The limits of drives ``idx`` (indices into the catalogue's drives), in that order."""
        idx = np.asarray(idx, dtype=int)
        where = {int(i): k for k, i in enumerate(idx)}
        fields = {
            name: getattr(self, name)[idx] for name in self.__dataclass_fields__ if name != "tables"
        }
        tables = {where[i]: t for i, t in self.tables.items() if i in where}
        return DriveArrays(**fields, tables=tables)


def utilisation(
    cat: Catalogue | DriveArrays, tau: np.ndarray, omega: np.ndarray, weights: np.ndarray
) -> np.ndarray:
    """Utilisation (D, C, len(CHECKS)) of every drive for duties (D, N) (or (N,): D = 1).

    tau in N m, omega in rad/s at the joint, weights in s (positive sum per design).
    """
    arr = cat if isinstance(cat, DriveArrays) else DriveArrays.of(cat)
    tau, omega, w = _duty(tau, omega, weights)
    n_ratio, eta = arr.ratio, arr.efficiency
    a = np.abs(tau)
    speed = np.abs(omega)
    driving = tau * omega >= 0
    ad, ab = np.where(driving, a, 0.0), np.where(driving, 0.0, a)
    wn = w / w.sum(axis=1, keepdims=True)
    with np.errstate(divide="ignore", invalid="ignore"):
        motor_max = np.maximum(ad.max(axis=1)[:, None] / eta, ab.max(axis=1)[:, None] * eta) / (
            n_ratio
        )
        ms = (wn * ad**2).sum(axis=1)[:, None] / eta**2 + (wn * ab**2).sum(axis=1)[:, None] * eta**2
        motor_rms = np.sqrt(ms) / n_ratio
        u = np.stack(
            [
                np.maximum(_envelope_peak(arr, ad, ab, speed, driving), motor_max / arr.int_torque),
                motor_rms / arr.cont_torque,
                np.maximum(
                    speed.max(axis=1)[:, None] * n_ratio / arr.int_speed,
                    np.sqrt((wn * speed**2).sum(axis=1))[:, None] * n_ratio / arr.cont_speed,
                ),
                a.max(axis=1)[:, None] / arr.gear_int_torque,
                np.sqrt((wn * a**2).sum(axis=1))[:, None] / arr.gear_cont_torque,
            ],
            axis=-1,
        )
    return np.where(np.isnan(u), np.inf, u)


def _duty(tau, omega, weights) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    tau, omega = np.atleast_2d(np.asarray(tau, float)), np.atleast_2d(np.asarray(omega, float))
    w = np.broadcast_to(np.atleast_2d(np.asarray(weights, float)), tau.shape)
    if tau.shape != omega.shape:
        raise ValueError(f"tau {tau.shape} and omega {omega.shape} differ in shape")
    if np.any(w < 0) or np.any(w.sum(axis=1) <= 0):
        raise ValueError("time weights must be >= 0 with a positive sum per design")
    return tau, omega, w


def _envelope_peak(arr: DriveArrays, ad, ab, speed, driving) -> np.ndarray:
    """max over samples of the torque-speed envelope utilisation u, (D, C), in drive chunks.

    For a DC motor u is linear in (|tau| driving, |tau| back-driven, |omega| driving), so one
    matrix product gives every drive at once.
    """
    n_d, n_s = ad.shape
    n_c = arr.ratio.size
    ratio, eta, stall = arr.ratio, arr.efficiency, arr.stall_torque
    coef = np.stack([1 / (eta * ratio * stall), eta / (ratio * stall), ratio / arr.no_load_speed])
    x = np.stack([ad, ab, np.where(driving, speed, 0.0)], axis=-1)
    out = np.empty((n_d, n_c))
    step = max(1, _CHUNK // max(1, n_d * n_s))
    for lo in range(0, n_c, step):
        c = slice(lo, min(n_c, lo + step))
        out[:, c] = (x @ coef[:, c]).max(axis=1)
    for i, (sp, tq) in arr.tables.items():
        tau_m = (ad / eta[i] + ab * eta[i]) / ratio[i]
        pull_out = np.interp(speed * ratio[i], sp, tq)  # the last torque beyond the table
        out[:, i] = np.where(tau_m > 0, tau_m / pull_out, 0.0).max(axis=1)
    return out
