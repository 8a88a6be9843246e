"""Plain sentences about a design's drives for ``summary.md`` and ``selected.json``, from a
:meth:`qsm.embodiment.drives.drive_checks.DriveCheck.report` (torques in N m, speeds in rad/s,
power in W, masses in kg)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any


def _drive_name(d: dict[str, Any]) -> str:
    return f"{d['motor']} + {d['gearbox']} ({d['ratio']:.4g}:1, {d['mass_kg']:.3f} kg)"


def _required(m: dict[str, Any]) -> str:
    r = m["required"]
    return (
        f"{r['peak_torque_Nm']:.1f} N m peak, {r['rms_torque_Nm']:.1f} N m RMS, "
        f"{r['peak_speed_rad_s']:.2f} rad/s, {r['peak_power_W']:.0f} W"
    )


def drive_sentences(report: dict[str, Any]) -> list[str]:
    """One plain sentence per motor of a :meth:`DriveCheck.report`: its drive with the smallest
    margin and what it must give, or, without a drive, by how much the nearest drive fails and
    what the strongest drive of the catalogue offers. Every number from ``report``."""
    if not report.get("defined", True):
        return ["no drives: the loop does not close (or is singular) over the duty"]
    out = []
    for key, m in report["motors"].items():
        head = f"motor {key.removeprefix('motor')} ({m['drives']})"
        if m["has_drive"]:
            check, margin = min(m["margins"].items(), key=lambda kv: kv[1])
            out.append(
                f"{head}: {_drive_name(m['drive'])}, smallest margin {100 * margin:.0f} % "
                f"({check.replace('_', ' ')}); it must give {_required(m)}"
            )
            continue
        s = m["strongest_drive"]
        out.append(
            f"{head}: NO DRIVE in the catalogue meets its duty ({_required(m)}); the nearest, "
            f"{_drive_name(m['best_drive'])}, {shortfall(m)}; the strongest drive, "
            f"{_drive_name(s)}, offers {s['peak_torque_Nm']:.0f} N m peak, "
            f"{s['cont_torque_Nm']:.0f} N m continuous and {_speed(s['top_speed_rad_s'])}"
        )
    return out


def shortfall(motor: dict[str, Any]) -> str:
    """Why a motor's nearest drive does not do (a motor entry of the report without a drive):
    no gearbox as stiff as the tolerance asks, or the limits it exceeds, worst first."""
    if not motor.get("stiff_enough", True):
        return "is not considered: no gearbox of the catalogue is as stiff as the tolerance asks"
    failing = sorted(motor.get("failing", {}).items(), key=lambda kv: -kv[1])
    if not failing:
        return "has no defined figures for this duty"
    return "exceeds its " + ", ".join(
        f"{k.replace('_', ' ')} limit by {100 * v:.0f} %" for k, v in failing
    )


def _speed(rad_s: float | None) -> str:
    """A top speed in rad/s, or "an unknown top speed" when the catalogue states none."""
    return "an unknown top speed" if rad_s is None else f"{rad_s:.2f} rad/s"


def use_text(use: Sequence[float | None]) -> str:
    """Peak torque uses as percentages; "past its top speed" for a motor that ran past its
    drive's top speed (None: :func:`qsm.realization.motion.payload.torque_use`)."""
    return ", ".join("past its top speed" if u is None else f"{u:.0%}" for u in use)
