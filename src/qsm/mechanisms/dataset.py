"""Stage 2's table: its columns with units, the gathered dataset and its healthy rows.

Light on purpose (no MuJoCo, no trimesh): most later rules read the dataset through it. One shard's
dynamics is :func:`qsm.physics.dynamics.evaluate_shard`."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pandas as pd

from qsm.mechanisms.scale import MECHANISM_COLUMNS

#: Columns that Stage 2 adds to the mechanism table, with units.
DYNAMICS_COLUMNS: dict[str, str] = {
    "tau1_Nm": "peak |torque| of motor 1 (lower arm) over the duty (N m)",
    "tau2_Nm": "peak |torque| of motor 2 (crank) over the duty (N m)",
    "theta1_at_tau1_peak_deg": "theta1 where |tau1| peaks (deg)",
    "theta2_at_tau1_peak_deg": "theta2 where |tau1| peaks (deg)",
    "theta1_at_tau2_peak_deg": "theta1 where |tau2| peaks (deg)",
    "theta2_at_tau2_peak_deg": "theta2 where |tau2| peaks (deg)",
    "tau1_rms_Nm": "time-weighted RMS torque of motor 1 over the moving duty (N m)",
    "tau2_rms_Nm": "time-weighted RMS torque of motor 2 over the moving duty (N m)",
    "coupler_force_peak_N": "peak coupler force at D, the D bearing load (N)",
    "transmission_angle_min_deg": "smallest transmission angle at D, folded into [0, 90] (deg)",
    "mass_lower_arm_kg": "lower arm mass (kg)",
    "mass_crank_kg": "crank mass (kg)",
    "mass_coupler_kg": "coupler mass (kg)",
    "mass_upper_arm_kg": "upper arm mass without payload (kg)",
    "status": "ok, or the failure: cad_invalid, loop_open, singular, nonfinite, error",
    "status_reason": "why a mechanism failed (empty when ok)",
}
DATASET_COLUMNS: dict[str, str] = {**MECHANISM_COLUMNS, **DYNAMICS_COLUMNS}


class DatasetError(ValueError):
    """The dynamics shards do not cover the mechanisms exactly once."""


def gather(mechanisms: pd.DataFrame, shards: Sequence[pd.DataFrame]) -> pd.DataFrame:
    """Join the mechanism table with the dynamics of all shards, in the mechanism table's order.

    Raises :class:`DatasetError` unless every mechanism id appears exactly once in the shards.
    """
    dyn = pd.concat(shards, ignore_index=True)
    counts = dyn["mechanism_id"].value_counts()
    expected = pd.Index(mechanisms["mechanism_id"])
    missing = expected.difference(counts.index)
    extra = counts.index.difference(expected)
    repeated = counts[counts > 1].index
    if len(missing) or len(extra) or len(repeated):
        raise DatasetError(
            "dynamics shards do not cover the mechanisms exactly once: "
            f"missing {_ids(missing)}, unknown {_ids(extra)}, repeated {_ids(repeated)}"
        )
    table = mechanisms.merge(dyn, on="mechanism_id", how="left", validate="one_to_one")
    return table[list(DATASET_COLUMNS)]


def _ids(ids: pd.Index) -> str:
    """A count and the first few ids, for error messages."""
    head = ", ".join(map(str, sorted(ids)[:5]))
    return f"{len(ids)} ({head}{', ...' if len(ids) > 5 else ''})"


def status_counts(dataset: pd.DataFrame) -> dict[str, int]:
    """How many mechanisms ended in each status."""
    return {str(k): int(v) for k, v in dataset["status"].value_counts().sort_index().items()}


def ok_rows(dataset: pd.DataFrame) -> pd.DataFrame:
    """Mechanisms whose dynamics succeeded and whose labels are finite."""
    ok = dataset["status"].eq("ok") & np.isfinite(dataset[["tau1_Nm", "tau2_Nm", "eta"]]).all(1)
    return dataset.loc[ok].reset_index(drop=True)
