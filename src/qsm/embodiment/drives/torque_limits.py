"""The torque limit each drive's controller keeps: the kit is sized for it, and every planned
motion and simulation of the realised arm stays within it.

A drive can put far more torque on its joint than any checked motion asks (a gearbox's
standstill torque is several times the duty's peak), and the parts between drive and link
(hub, its screws and inserts, the cheek) would have to carry it. Instead the realisation sets
each motor's limit at ``margin`` times the largest torque its checks found (over the duty and
the task motion, its drive's reflected inertia included), at most what its drive gives at
standstill. The controller keeps to it; the
time-optimal cycle is planned within it and the payload test's drive saturates at it, so a
motion that needs more fails its check.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from numpy.typing import ArrayLike, NDArray

from qsm.embodiment.drives.drive_checks import DriveCheck
from qsm.embodiment.drives.envelope import OutputEnvelope
from qsm.embodiment.drives.report import DriveReport


def checked_peaks_Nm(
    check: DriveCheck, design: ArrayLike, scales: ArrayLike | None, reflected_kgm2: ArrayLike
) -> NDArray[np.float64]:
    """The largest torque (2,) N m at each joint over ``check``'s duty and its task motion
    (``task_duty``, where set): the links' and payload's, and each drive's reflected inertia
    ``reflected_kgm2`` (2,) kg m^2 times the joint's acceleration where ``check`` counts it."""
    peaks = np.zeros(2)
    for duty in (check.duty, check.task_duty):
        if duty is None:
            continue
        tau, good = replace(check, duty=duty, task_duty=None).torques(design, scales)
        if not good[0]:
            continue
        rotor = np.asarray(reflected_kgm2, dtype=float) * duty.ddtheta
        total = tau[0] + (rotor if check.reflected_inertia else 0.0)
        peaks = np.maximum(peaks, np.abs(total).max(axis=0))
    return peaks


def torque_limits_Nm(
    report: DriveReport,
    check: DriveCheck,
    design: ArrayLike,
    scales: ArrayLike | None,
    margin: float,
) -> tuple[float, float]:
    """Each motor's torque limit (N m at the joint): ``margin`` times its :func:`checked_peaks_Nm`
    with the drive of the drive ``report`` (the chosen, else the nearest), at most that drive's
    torque at standstill; 0 for a motor with no drive in the report."""
    motors = [report.motors.get(f"motor{k}") for k in (1, 2)]
    if not all(motors):
        return 0.0, 0.0
    envelopes = [
        OutputEnvelope.of(check.catalogue, m.drive.motor_key, m.drive.gearbox_key) for m in motors
    ]
    peaks = checked_peaks_Nm(check, design, scales, [e.reflected_inertia for e in envelopes])
    limits = [
        min(margin * float(p), float(e.limit(1.0, 0.0)))
        for p, e in zip(peaks, envelopes, strict=True)
    ]
    return limits[0], limits[1]


def limited(envelope: OutputEnvelope, limit_Nm: float) -> OutputEnvelope:
    """``envelope`` with its torque at the joint capped at ``limit_Nm`` (the controller's)."""
    return replace(envelope, gear_int_torque=min(envelope.gear_int_torque, limit_Nm))
