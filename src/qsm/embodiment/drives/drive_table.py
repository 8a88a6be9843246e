"""Stage 2's drive columns of a chunk of designs (:data:`qsm.dataset.columns.DRIVE_COLUMNS`): each
motor's requirements, its drive (chosen, or the nearest) and its margins, and g14."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from qsm.embodiment.drives.drive_columns import DRIVE_COLUMNS, MOTORS
from qsm.embodiment.drives.selection import Selection
from qsm.embodiment.drives.utilization import CHECKS


def drive_columns(
    selections: list[Selection], good: NDArray[np.bool_], columns: dict[str, NDArray]
) -> dict[str, NDArray]:
    """The drive columns of designs from each motor's :class:`Selection`, where their torques are
    defined (``good``), and the catalogue's drive columns (``motor``, ``ratio``, ...; (C,) each)."""
    out: dict[str, NDArray] = {}
    for j, sel in zip(MOTORS, selections, strict=True):
        b = sel.best
        out[f"drive{j}_peak_torque_Nm"] = sel.peak_torque
        out[f"drive{j}_rms_torque_Nm"] = sel.rms_torque
        out[f"drive{j}_peak_speed_rad_s"] = sel.peak_speed
        out[f"drive{j}_peak_power_W"] = sel.peak_power
        for key, values in columns.items():
            out[f"drive{j}_{key}"] = values[b]
        for k, check in enumerate(CHECKS):
            out[f"drive{j}_margin_{check}"] = 1.0 - sel.utilization[:, k]
        out[f"drive{j}_violation"] = sel.violation
    for j in MOTORS:
        for key in (f"drive{j}_motor", f"drive{j}_gearbox"):
            out[key] = np.where(good, out[key], "")
        for key in DRIVE_COLUMNS:
            if key.startswith(f"drive{j}_") and out[key].dtype.kind == "f":
                out[key] = np.where(good, out[key], np.nan)
    out["drive_mass_kg"] = out["drive1_mass_kg"] + out["drive2_mass_kg"]
    viol = np.maximum(out["drive1_violation"], out["drive2_violation"])
    out["drive_violation"] = np.where(good, viol, np.nan)
    out["has_drives"] = good & (viol <= 0)
    return out
