"""The torque limit each drive's controller keeps: the kit is sized for it, and every planned
motion and simulation of the realised arm stays within it.

A drive can put far more torque on its joint than any checked motion asks (a gearbox's
standstill torque is several times the duty's peak), and the parts between drive and link
(hub, its screws and inserts, the cheek) would have to carry it. Instead the realisation sets
each motor's limit at ``margin`` times the largest torque its checks found (the duty's peak and
the task motion's), at most what its drive gives at standstill. The controller keeps to it; the
time-optimal cycle is planned within it and the payload test's drive saturates at it, so a
motion that needs more fails its check.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import replace
from typing import Any

from qsm.embodiment.drives.catalogue import Catalogue
from qsm.embodiment.drives.envelope import OutputEnvelope
from qsm.embodiment.drives.selection import drive_of


def checked_peak_Nm(report: Mapping[str, Any], motor: int) -> float:
    """The largest torque (N m at the joint) the checks of a drive report found on ``motor``
    (1 or 2): the duty's peak and, where defined, the task motion's."""
    entry = report.get("motors", {}).get(f"motor{motor}", {})
    peak = float(entry.get("required", {}).get("peak_torque_Nm", 0.0))
    motion = report.get("task_motion", {})
    if motion.get("defined"):
        peak = max(peak, float(motion["peak_torque_Nm"][motor - 1]))
    return peak


def torque_limits_Nm(
    report: Mapping[str, Any], catalogue: Catalogue, margin: float
) -> tuple[float, float]:
    """Each motor's torque limit (N m at the joint): ``margin`` times :func:`checked_peak_Nm`,
    at most its drive's (the chosen, else the nearest) torque at standstill; 0 for a motor with
    no drive in the report."""
    out = []
    for k in (1, 2):
        drive = drive_of(report.get("motors", {}).get(f"motor{k}", {}))
        if not drive:
            out.append(0.0)
            continue
        env = OutputEnvelope.of(catalogue, drive["motor_key"], drive["gearbox_key"])
        out.append(min(margin * checked_peak_Nm(report, k), float(env.limit(1.0, 0.0))))
    return out[0], out[1]


def limited(envelope: OutputEnvelope, limit_Nm: float) -> OutputEnvelope:
    """``envelope`` with its torque at the joint capped at ``limit_Nm`` (the controller's)."""
    return replace(envelope, gear_int_torque=min(envelope.gear_int_torque, limit_Nm))
