"""The payload test's outputs (:func:`qsm.realization.motion.payload.payload_test`): its time series
as a table, its scalar summary for JSON and its figure."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from qsm.prose import per_motor
from qsm.realization.motion.payload import SERIES_KEYS

#: Columns of :func:`series_table`: the time series of a payload test, one row per sample.
SERIES_COLUMNS: dict[str, str] = {
    "t_s": "time (s)",
    **{
        f"theta{j}{kind}_deg": f"motor {j} angle, {what} (deg)"
        for kind, what in (("_ref", "reference"), ("", "simulated"))
        for j in (1, 2)
    },
    **{
        f"tau{j}_{kind}_Nm": f"motor {j} torque, {kind} (N m)"
        for kind in ("requested", "applied", "available")
        for j in (1, 2)
    },
}


def series_table(result: dict[str, Any]) -> pd.DataFrame:
    """The time series of a :func:`payload_test` result as a table (:data:`SERIES_COLUMNS`)."""
    pairs = {
        "theta{}_ref_deg": "theta_ref_deg",
        "theta{}_deg": "theta_deg",
        "tau{}_requested_Nm": "torque_requested_Nm",
        "tau{}_applied_Nm": "torque_applied_Nm",
        "tau{}_available_Nm": "torque_available_Nm",
    }
    data = {"t_s": np.asarray(result["t_s"], dtype=float)}
    for pattern, key in pairs.items():
        for j in (1, 2):
            data[pattern.format(j)] = np.asarray(result[key], dtype=float)[:, j - 1]
    return pd.DataFrame(data)[list(SERIES_COLUMNS)]


def summary(result: dict[str, Any]) -> dict[str, Any]:
    """The scalar part of a :func:`payload_test` result (JSON-friendly)."""
    return {k: v for k, v in result.items() if k not in SERIES_KEYS}


def drive_duty_note(motors: Mapping[str, Any], drives: Sequence[Any]) -> dict[str, Any]:
    """Whether each motor's drive (``selected.json``'s ``drives.motors``) meets its duty, and, when
    one does not, a ``drive_note`` that says the test simulated the nearest drive, by how much
    that drive misses its duty (the drive check's violation) and which limits it fails."""
    meets = [bool(m["has_drive"]) for m in motors.values()]
    out: dict[str, Any] = {"drive_meets_duty": meets}
    missing = [
        f"{name} ({m['drives']}) has no drive in the catalogue that meets its duty: simulated "
        f"with the nearest, {drive.name}, which exceeds its "
        f"{', '.join(k.replace('_', ' ') for k in m['failing'])} limit by "
        f"{100 * m['violation']:.0f} %"
        for (name, m), drive, ok in zip(motors.items(), drives, meets, strict=True)
        if not ok
    ]
    if missing:
        out["drive_note"] = "; ".join(missing) + " (so the test cannot tell whether it can follow)"
    return out


def plot_payload_test(result: dict[str, Any], path: str | Path) -> Path:
    """Figure: motor angles (reference and simulated), requested torques with the limits, and the
    tracking error over time."""
    import matplotlib.pyplot as plt

    t = result["t_s"]
    fig, axes = plt.subplots(3, 1, figsize=(8, 7.5), sharex=True)
    colours = ("tab:blue", "tab:orange")
    for j, c in enumerate(colours):
        axes[0].plot(
            t,
            result["theta_ref_deg"][:, j],
            color=c,
            ls="--",
            lw=1,
            label=f"theta{j + 1} reference",
        )
        axes[0].plot(t, result["theta_deg"][:, j], color=c, lw=1, label=f"theta{j + 1} simulated")
        axes[1].plot(
            t, result["torque_requested_Nm"][:, j], color=c, lw=1, label=f"tau{j + 1} requested"
        )
        lim = np.abs(result["torque_available_Nm"][:, j])
        axes[1].plot(t, lim, color=c, ls=":", lw=1)
        axes[1].plot(t, -lim, color=c, ls=":", lw=1)
        axes[2].plot(
            t,
            np.abs(result["theta_deg"][:, j] - result["theta_ref_deg"][:, j]),
            color=c,
            lw=1,
            label=f"motor {j + 1}",
        )
    axes[2].axhline(result["tracking_tolerance_deg"], color="k", ls=":", lw=1, label="tolerance")
    axes[0].set_ylabel("angle (deg)")
    axes[1].set_ylabel("torque (N m)")
    axes[2].set_ylabel("|error| (deg)")
    axes[2].set_xlabel("time (s)")
    for ax in axes:
        ax.legend(fontsize=7, loc="upper right")
    verdict = "PASSED" if result["passed"] else f"FAILED: {result['reason']}"
    axes[0].set_title(
        f"payload test, {result['payload_kg']:.1f} kg at E: {verdict}\n"
        f"peak torque {per_motor(result['peak_torque_Nm'], 1, 'N m')} "
        f"(limits {per_motor(result['limit_Nm'], 1, 'N m')}), "
        f"max error {result['max_tracking_error_deg']:.3f} deg",
        fontsize=9,
    )
    fig.tight_layout()
    out = Path(path)
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=130)
    plt.close(fig)
    return out
