"""Choose a drive for a joint's duty: every compatible motor-gearbox pair checked at once.

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
catalogue lacks (nan) makes the utilisation infinite. A drive's violation is max(u) - 1; it
meets the duty when that is <= 0. The joint's violation (constraint g14) is the least violation
over the catalogue: <= 0 when some drive meets the duty, continuous in the duty otherwise.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from qsm.embodiment.drives.catalogue import Catalogue

CHECKS = ("motor_peak", "motor_rms", "motor_speed", "gear_peak", "gear_rms")
RULES = {"lightest": "mass", "smallest_inertia": "reflected_inertia"}
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


@dataclass(frozen=True)
class Selection:
    """Drive chosen for each of D duties (one joint of D designs), with what the duty requires.

    ``choice`` (D,) is the index into ``catalogue.drives`` of the chosen drive, -1 when none meets
    the duty; ``best`` (D,) is the drive of least violation (the choice when there is one);
    ``violation`` (D,) is g14's value (<= 0: a drive exists); ``utilisation`` (D, len(CHECKS)) is
    that of ``best``. Required (output side): peak_torque and rms_torque (N m), peak_speed
    (rad/s), peak_power (W, max |tau omega|). ``strongest`` is the drive of the largest peak
    output torque at standstill.
    """

    catalogue: Catalogue
    rule: str
    choice: np.ndarray
    best: np.ndarray
    violation: np.ndarray
    utilisation: np.ndarray
    peak_torque: np.ndarray
    rms_torque: np.ndarray
    peak_speed: np.ndarray
    peak_power: np.ndarray
    strongest: int

    def report(self, d: int = 0) -> dict:
        """JSON-ready account of duty ``d``: the drive, its margins (1 - utilisation) and, when
        no drive meets the duty, the failing limits of the best drive (excess = utilisation - 1)
        and what the strongest drive offers."""
        u = self.utilisation[d]
        out = {
            "has_drive": bool(self.choice[d] >= 0),
            "violation": float(self.violation[d]),
            "required": {
                "peak_torque_Nm": float(self.peak_torque[d]),
                "rms_torque_Nm": float(self.rms_torque[d]),
                "peak_speed_rad_s": float(self.peak_speed[d]),
                "peak_power_W": float(self.peak_power[d]),
            },
            "drive" if self.choice[d] >= 0 else "best_drive": self._describe(int(self.best[d])),
            "margins": {k: float(1 - v) for k, v in zip(CHECKS, u, strict=True)},
        }
        if self.choice[d] < 0:
            out["failing"] = {k: float(v - 1) for k, v in zip(CHECKS, u, strict=True) if v > 1}
            out["strongest_drive"] = (
                self._describe(self.strongest) | offer(self.catalogue)[self.strongest]
            )
        return out

    def _describe(self, i: int) -> dict:
        row = self.catalogue.drives.iloc[i]
        m = self.catalogue.motors.loc[row["motor"]]
        g = self.catalogue.gearboxes.loc[row["gearbox"]]
        return {
            "motor": f"{m['manufacturer']} {m['ID']}",
            "gearbox": f"{g['manufacturer']} {g['ID']}",
            "motor_key": row["motor"],
            "gearbox_key": row["gearbox"],
            "ratio": float(row["ratio"]),
            "mass_kg": float(row["mass"]),
            "reflected_inertia_kgm2": float(row["reflected_inertia"]),
        }


def offer(cat: Catalogue) -> list[dict]:
    """What each drive offers at the output: peak torque at standstill (N m), continuous torque
    (N m) and top speed (rad/s), in the driving direction."""
    arr = DriveArrays.of(cat)
    with np.errstate(invalid="ignore"):
        motor_peak = np.fmin(arr.stall_torque, arr.int_torque)
        peak = np.fmin(motor_peak * arr.ratio * arr.efficiency, arr.gear_int_torque)
        cont = np.fmin(arr.cont_torque * arr.ratio * arr.efficiency, arr.gear_cont_torque)
        top = np.fmin(arr.int_speed, arr.no_load_speed) / arr.ratio
    for i, (sp, tq) in arr.tables.items():
        peak[i] = min(tq[0] * arr.ratio[i] * arr.efficiency[i], arr.gear_int_torque[i])
        top[i] = sp[-1] / arr.ratio[i]
    return [
        {"peak_torque_Nm": float(p), "cont_torque_Nm": float(c), "top_speed_rad_s": float(s)}
        for p, c, s in zip(peak, cont, top, strict=True)
    ]


def select_drives(
    cat: Catalogue,
    tau: np.ndarray,
    omega: np.ndarray,
    weights: np.ndarray,
    rule: str = "lightest",
    accel: np.ndarray | None = None,
) -> Selection:
    """Choose, for each duty, the drive that meets every sample and is first by ``rule``.

    tau (N m), omega (rad/s): (N,) for one design or (D, N); weights (s): broadcast to them.
    rule 'lightest' orders by total mass (kg), 'smallest_inertia' by reflected inertia (kg m^2);
    ties go to the other key, then to catalogue order. A duty with a non-finite sample gets no
    drive and an infinite violation.

    ``accel`` (rad/s^2, the joint's acceleration, shaped as tau), when given, checks each drive c
    against its own output torque ``tau + J_c accel``, J_c its reflected inertia (the torque of
    the joint with that drive's rotor, MuJoCo's joint armature): exact, with no iteration between
    the choice and the torques. The required torques, speed and power are then those of ``best``.
    """
    if rule not in RULES:
        raise ValueError(f"unknown drive rule {rule!r}; expected one of {sorted(RULES)}")
    arr = DriveArrays.of(cat)
    tau, omega, w = _duty(tau, omega, weights)
    acc = (
        None
        if accel is None
        else np.broadcast_to(np.atleast_2d(np.asarray(accel, float)), tau.shape)
    )
    inertia = cat.drives["reflected_inertia"].to_numpy(float)
    keys = [cat.drives[RULES[rule]].to_numpy(float)]
    keys.append(cat.drives[next(v for v in RULES.values() if v != RULES[rule])].to_numpy(float))
    order = np.lexsort([np.nan_to_num(k, nan=np.inf) for k in reversed(keys)])
    rank = np.empty(order.size, int)
    rank[order] = np.arange(order.size)
    n_d, n_c = tau.shape[0], arr.ratio.size
    choice, best = np.full(n_d, -1), np.zeros(n_d, int)
    violation, util = np.full(n_d, np.inf), np.full((n_d, len(CHECKS)), np.inf)
    finite = np.isfinite(tau).all(axis=1) & np.isfinite(omega).all(axis=1)
    if acc is not None:
        finite &= np.isfinite(acc).all(axis=1)
    step = max(1, _CHUNK // max(1, n_c * tau.shape[1]))
    for lo in range(0, n_d, step):
        d = np.arange(lo, min(n_d, lo + step))
        d = d[finite[d]]
        if d.size == 0:
            continue
        if acc is None:
            u = utilisation(arr, tau[d], omega[d], w[d])
        else:
            u = _utilisation_with_inertia(arr, inertia, tau[d], acc[d], omega[d], w[d])
        v = u.max(axis=2) - 1
        best[d] = v.argmin(axis=1)
        violation[d] = v[np.arange(d.size), best[d]]
        ranked = np.where(v <= 0, rank, n_c).argmin(axis=1)
        ok = v[np.arange(d.size), ranked] <= 0
        choice[d[ok]] = ranked[ok]
        best[d[ok]] = ranked[ok]
        util[d] = u[np.arange(d.size), best[d]]
    if acc is not None:
        tau = tau + np.nan_to_num(inertia[best])[:, None] * acc
    a = np.abs(tau)
    wn = w / w.sum(axis=1, keepdims=True)
    return Selection(
        catalogue=cat,
        rule=rule,
        choice=choice,
        best=best,
        violation=violation,
        utilisation=util,
        peak_torque=a.max(axis=1),
        rms_torque=np.sqrt((wn * tau**2).sum(axis=1)),
        peak_speed=np.abs(omega).max(axis=1),
        peak_power=np.abs(tau * omega).max(axis=1),
        strongest=int(np.nanargmax([o["peak_torque_Nm"] for o in offer(cat)])),
    )


def _utilisation_with_inertia(
    arr: DriveArrays,
    inertia: np.ndarray,
    tau: np.ndarray,
    accel: np.ndarray,
    omega: np.ndarray,
    w: np.ndarray,
) -> np.ndarray:
    """:func:`utilisation` (D, C, checks) with drive c loaded by ``tau + inertia[c] accel``;
    drives of equal reflected inertia are checked together; an unknown (nan) inertia is never
    met.

    Screening, exact for the choice and for g14: on the samples without acceleration the torque
    does not depend on the drive, so their peak checks bound each drive's utilisation from below
    at the cost of one small :func:`utilisation` call. A drive whose bound exceeds 1 cannot meet
    the duty; it is evaluated (its entries are inf until then) only for the duties that no
    unscreened drive meets, where g14 needs the least violation over the whole catalogue.
    """
    n_d, n_c = tau.shape[0], inertia.size
    out = np.full((n_d, n_c, len(CHECKS)), np.inf)
    known = np.isfinite(inertia)
    still = np.all(accel == 0, axis=0)
    if still.any():
        u0 = utilisation(arr, tau[:, still], omega[:, still], np.ones(int(still.sum())))
        candidate = u0[..., [0, 3]].max(axis=-1) <= 1  # (D, C)
    else:
        candidate = np.ones((n_d, n_c), bool)
    done = np.zeros((n_d, n_c), bool)
    values, group = np.unique(inertia[known], return_inverse=True)
    groups = [np.flatnonzero(known)[group == k] for k in range(values.size)]

    def run(rows_of: np.ndarray) -> None:
        for j, idx in zip(values, groups, strict=True):
            rows = np.flatnonzero(rows_of[:, idx].any(axis=1) & ~done[:, idx].all(axis=1))
            if rows.size:
                u = utilisation(arr.take(idx), tau[rows] + j * accel[rows], omega[rows], w[rows])
                out[np.ix_(rows, idx)] = u
                done[np.ix_(rows, idx)] = True

    run(candidate)
    met = (out.max(axis=2) <= 1).any(axis=1)
    run(np.broadcast_to(~met[:, None], (n_d, n_c)))
    return out


@dataclass(frozen=True)
class OutputEnvelope:
    """The torque one drive can give at the joint (output side), by speed and direction, for a
    simulation that saturates the motor on it (the conventions of :func:`utilisation`: a driving
    sample gets eta N T_m, a back-driven one N T_m / eta, both at most the gearbox's intermittent
    torque; T_m is the motor's torque-speed line or table at N |omega|, at most its intermittent
    torque, and 0 beyond its speed limit)."""

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
