"""Choose a drive for a joint's duty: every compatible motor-gearbox pair checked at once.

Each drive gets the utilisations of :mod:`qsm.embodiment.drives.utilisation` (<= 1 meets the
limit); a drive's violation is max(u) - 1 and it meets the duty when that is <= 0. The joint's
violation (constraint g14) is the least violation over the catalogue: <= 0 when some drive meets
the duty, continuous in the duty otherwise.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from qsm.embodiment.drives.catalogue import Catalogue
from qsm.embodiment.drives.utilisation import _CHUNK, CHECKS, DriveArrays, _duty, utilisation

RULES = {"lightest": "mass", "smallest_inertia": "reflected_inertia"}


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
