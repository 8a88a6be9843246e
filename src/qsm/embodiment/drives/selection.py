"""Choose a drive for a joint's duty: every compatible motor-gearbox pair checked at once.

Each drive gets the utilisations of :mod:`qsm.embodiment.drives.utilization` (<= 1 meets the
limit); a drive's violation is max(u) - 1 and it meets the duty when that is <= 0. The joint's
violation (constraint g14) is the least violation over the catalogue: <= 0 when some drive meets
the duty, continuous in the duty otherwise.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from qsm.embodiment.drives.catalogue import Catalogue
from qsm.embodiment.drives.compliance import gear_compliance
from qsm.embodiment.drives.report import (
    CatalogueDrive,
    DriveOffer,
    DriveRequirement,
    MotorReport,
)
from qsm.embodiment.drives.utilization import CHECKS, DriveArrays, duty_arrays, utilization

RULES = {"lightest": "mass", "smallest_inertia": "reflected_inertia"}


@dataclass(frozen=True)
class Selection:
    """Drive chosen for each of D duties (one joint of D designs), with what the duty requires.

    ``choice`` (D,) is the index into ``catalogue.drives`` of the chosen drive, -1 when none meets
    the duty; ``best`` (D,) is the drive of least violation (the choice when there is one);
    ``violation`` (D,) is g14's value (<= 0: a drive exists); ``utilisation`` (D, len(CHECKS)) is
    that of ``best``. Required (output side): peak_torque and rms_torque (N m), peak_speed
    (rad/s), peak_power (W, max |tau omega|). ``strongest`` is the drive of the largest peak
    output torque at standstill. ``task_excess`` (D,): ``best``'s violation of the second duty
    (the task's motion; None: none was given); ``stiff_enough``: whether any drive was allowed
    (the gearbox stiffness the tolerance asks).
    """

    catalogue: Catalogue
    rule: str
    choice: np.ndarray
    best: np.ndarray
    violation: np.ndarray
    utilization: np.ndarray
    peak_torque: np.ndarray
    rms_torque: np.ndarray
    peak_speed: np.ndarray
    peak_power: np.ndarray
    strongest: int
    task_excess: np.ndarray | None = None
    stiff_enough: bool = True

    def report(self, d: int = 0) -> MotorReport:
        """Duty ``d``'s account: the drive it is built with (the chosen, else the nearest), its
        margins (1 - utilisation) and, when no drive meets the duty, the failing limits of the
        nearest (excess = utilisation - 1) and what the strongest drive offers."""
        u = self.utilization[d]
        required = DriveRequirement(
            float(self.peak_torque[d]),
            float(self.rms_torque[d]),
            float(self.peak_speed[d]),
            float(self.peak_power[d]),
        )
        base = MotorReport(
            has_drive=bool(self.choice[d] >= 0),
            violation=float(self.violation[d]),
            required=required,
            drive=self._describe(int(self.best[d])),
            margins={k: float(1 - v) for k, v in zip(CHECKS, u, strict=True)},
        )
        if base.has_drive:
            return base
        failing = {k: float(v - 1) for k, v in zip(CHECKS, u, strict=True) if v > 1}
        if self.task_excess is not None and self.task_excess[d] > 0:
            failing["task_motion"] = float(self.task_excess[d])
        return replace(
            base,
            failing=failing,
            stiff_enough=self.stiff_enough,
            strongest=self._describe(self.strongest),
            strongest_offer=DriveOffer(**offer(self.catalogue)[self.strongest]),
        )

    def _describe(self, i: int) -> CatalogueDrive:
        row = self.catalogue.drives.iloc[i]
        m = self.catalogue.motors.loc[row["motor"]]
        g = self.catalogue.gearboxes.loc[row["gearbox"]]
        return CatalogueDrive(
            motor=f"{m['manufacturer']} {m['ID']}",
            gearbox=f"{g['manufacturer']} {g['ID']}",
            motor_key=row["motor"],
            gearbox_key=row["gearbox"],
            ratio=float(row["ratio"]),
            mass_kg=float(row["mass"]),
            reflected_inertia_kgm2=float(row["reflected_inertia"]),
            **gear_compliance(g),
        )


def offer(cat: Catalogue | DriveArrays) -> list[dict]:
    """What each drive offers at the output: peak torque at standstill (N m), continuous torque
    (N m) and top speed (rad/s; None where the catalogue states no limit), in the driving
    direction."""
    return [
        {
            "peak_torque_Nm": float(p),
            "cont_torque_Nm": float(c),
            "top_speed_rad_s": float(s) if np.isfinite(s) else None,
        }
        for p, c, s in zip(*_offer(cat), strict=True)
    ]


def _offer(cat: Catalogue | DriveArrays) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    arr = cat if isinstance(cat, DriveArrays) else DriveArrays.of(cat)
    with np.errstate(invalid="ignore"):
        motor_peak = np.fmin(arr.stall_torque, arr.int_torque)
        peak = np.fmin(motor_peak * arr.ratio * arr.efficiency, arr.gear_int_torque)
        cont = np.fmin(arr.cont_torque * arr.ratio * arr.efficiency, arr.gear_cont_torque)
        top = np.fmin(arr.int_speed, arr.no_load_speed) / arr.ratio
    for i, (sp, tq) in arr.tables.items():
        peak[i] = min(tq[0] * arr.ratio[i] * arr.efficiency[i], arr.gear_int_torque[i])
        top[i] = sp[-1] / arr.ratio[i]
    return peak, cont, top


def select_drives(
    cat: Catalogue,
    tau: np.ndarray,
    omega: np.ndarray,
    weights: np.ndarray,
    rule: str = "lightest",
    accel: np.ndarray | None = None,
    arrays: DriveArrays | None = None,
    allowed: np.ndarray | None = None,
    also: np.ndarray | None = None,
) -> Selection:
    """Choose, for each duty, the drive that meets every sample and is first by ``rule``.

    tau (N m), omega (rad/s): (N,) for one design or (D, N); weights (s): broadcast to them.
    rule 'lightest' orders by total mass (kg), 'smallest_inertia' by reflected inertia (kg m^2);
    ties go to the other key, then to catalogue order. A duty with a non-finite sample gets no
    drive and an infinite violation.

    ``accel`` (rad/s^2, the joint's acceleration, shaped as tau), when given, checks each drive c
    against its own output torque ``tau + J_c accel``, J_c its reflected inertia (the torque of
    the joint with that drive's rotor, MuJoCo's joint armature): exact, with no iteration between
    the choice and the torques; a drive of unknown J_c is never met. The required torques, speed
    and power are then those of ``best``. ``arrays``: ``DriveArrays.of(cat)`` when at hand.
    ``allowed`` (C,): the drives that may be chosen (None: all); the others never meet a duty.
    ``also`` (C,): each drive's violation of a second duty it must meet as well (the task's
    motion, :func:`drive_violations`); a drive's violation is then the larger of the two.
    """
    if rule not in RULES:
        raise ValueError(f"unknown drive rule {rule!r}; expected one of {sorted(RULES)}")
    arr = DriveArrays.of(cat) if arrays is None else arrays
    tau, omega, w = duty_arrays(tau, omega, weights)
    acc = None if accel is None else np.broadcast_to(np.asarray(accel, float), tau.shape)
    rank = _rank(arr, rule)
    u = _utilisations(arr, tau, omega, w, acc)
    v = u.max(axis=2) - 1
    if also is not None:
        v = np.maximum(v, also)
    if allowed is not None:
        v = np.where(allowed, v, np.inf)
    rows = np.arange(tau.shape[0])
    choice, best, violation = _choose(v, rank)
    if acc is not None:
        tau = tau + np.nan_to_num(arr.reflected_inertia[best])[:, None] * acc
    wn = w / w.sum(axis=1, keepdims=True)
    return Selection(
        catalogue=cat,
        rule=rule,
        choice=choice,
        best=best,
        violation=violation,
        utilization=u[rows, best],
        peak_torque=np.abs(tau).max(axis=1),
        rms_torque=np.sqrt((wn * tau**2).sum(axis=1)),
        peak_speed=np.abs(omega).max(axis=1),
        peak_power=np.abs(tau * omega).max(axis=1),
        strongest=int(np.nanargmax(_offer(arr)[0])),
        task_excess=None if also is None else np.broadcast_to(also, v.shape)[rows, best],
        stiff_enough=bool(allowed is None or np.any(allowed)),
    )


def _choose(v: np.ndarray, rank: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """From each drive's violation ``v`` (D, C) and place ``rank`` (C,): the first-ranked drive
    that meets each duty (-1: none), the drive used (that one, else the least violation) and
    the least violation (D,) each."""
    rows = np.arange(v.shape[0])
    best = v.argmin(axis=1)
    violation = v[rows, best]
    ranked = np.where(v <= 0, rank, v.shape[1]).argmin(axis=1)
    ok = v[rows, ranked] <= 0
    return np.where(ok, ranked, -1), np.where(ok, ranked, best), violation


def _rank(arr: DriveArrays, rule: str) -> np.ndarray:
    """Each drive's place (C,) in the order of ``rule``: by its key (unknown last), ties to the
    other key, then to catalogue order."""
    keys = {"mass": arr.mass, "reflected_inertia": arr.reflected_inertia}
    first = keys.pop(RULES[rule])
    order = np.lexsort([np.nan_to_num(k, nan=np.inf) for k in (*keys.values(), first)])
    rank = np.empty(order.size, int)
    rank[order] = np.arange(order.size)
    return rank


def _utilisations(
    arr: DriveArrays,
    tau: np.ndarray,
    omega: np.ndarray,
    w: np.ndarray,
    acc: np.ndarray | None,
) -> np.ndarray:
    """Each drive's utilisations (D, C, len(CHECKS)) on duties (D, N); infinite for a duty with a
    non-finite sample."""
    finite = np.isfinite(tau).all(axis=1) & np.isfinite(omega).all(axis=1)
    if acc is not None:
        finite &= np.isfinite(acc).all(axis=1)
    if finite.all():
        return utilization(arr, tau, omega, w, acc)
    u = np.full((tau.shape[0], arr.ratio.size, len(CHECKS)), np.inf)
    u[finite] = utilization(
        arr, tau[finite], omega[finite], w[finite], None if acc is None else acc[finite]
    )
    return u


def drive_violations(
    arr: DriveArrays,
    tau: np.ndarray,
    omega: np.ndarray,
    weights: np.ndarray,
    accel: np.ndarray | None = None,
) -> np.ndarray:
    """Each drive's violation (C,) of one duty (tau N m, omega rad/s, weights s: (N,) each;
    ``accel`` rad/s^2 as in :func:`select_drives`): its largest utilisation of
    :mod:`~qsm.embodiment.drives.utilization` less 1 (<= 0: it meets the duty)."""
    tau, omega, w = duty_arrays(tau, omega, weights)
    acc = None if accel is None else np.broadcast_to(np.asarray(accel, float), tau.shape)
    return _utilisations(arr, tau, omega, w, acc).max(axis=2)[0] - 1
