"""Find one design of a run: a front's design by rank, a dataset mechanism by id, or a unit
design scaled to the task; and check that a config is the run's own (the settings stored in the
run's ``dataset.parquet``; a difference is an error naming the keys)."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from qsm.app.evaluate import checked_ratios, evaluate_ratios
from qsm.dataset.columns import DATASET_COLUMNS
from qsm.optimization.ranking import front_ranks
from qsm.physics.kinematics import DESIGN_COLUMNS, RATIO_NAMES
from qsm.physics.task_points import design_task
from qsm.workflow.tables import read_meta, read_table

#: Values of a front's row the JSON carries beside the fresh evaluation.
FRONT_VALUES: tuple[str, ...] = (
    "eta_pred",
    "tau1_pred_Nm",
    "tau2_pred_Nm",
    "eta_true",
    "tau1_true_Nm",
    "tau2_true_Nm",
    "task_contained",
    "printable",
)
#: What :func:`qsm.optimization.verify.verify_design` evaluates for one design.
TRUE_KEYS: tuple[str, ...] = (
    "crank_rocker",
    "loop_closes",
    "transmission_ok",
    "containment_margin_m",
    "task_contained",
    "feasible",
    "eta_true",
    "tau1_true_Nm",
    "tau2_true_Nm",
    "dynamics_status",
)
#: Where each key of the run's stored settings (dataset.parquet) lives in the config.
SETTING_PATHS: dict[str, tuple[str, ...]] = {
    "task_points": ("task", "points"),
    "payload_kg": ("task", "payload_kg"),
    "duty": ("dynamics", "duty"),
}


def plain(value: Any) -> Any:
    """JSON-friendly: numpy scalars and arrays as Python values, non-finite floats as None."""
    if isinstance(value, Mapping):
        return {str(k): plain(v) for k, v in value.items()}
    if isinstance(value, list | tuple | np.ndarray):
        return [plain(v) for v in value]
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


#: Settings a run derives and stores beside the config's (the drive catalogue's hash).
DERIVED_KEYS = frozenset({"catalogue_sha256"})


def _same(stored: Any, current: Any) -> bool:
    """Whether ``current`` holds every value of ``stored`` (numbers compared as floats), the
    derived :data:`DERIVED_KEYS` aside."""
    if isinstance(stored, Mapping):
        return isinstance(current, Mapping) and all(
            _same(v, current.get(k)) for k, v in stored.items() if k not in DERIVED_KEYS
        )
    if isinstance(stored, list | tuple):
        return (
            isinstance(current, list | tuple)
            and len(stored) == len(current)
            and all(_same(a, b) for a, b in zip(stored, current, strict=True))
        )
    if isinstance(stored, int | float) and not isinstance(stored, bool):
        return isinstance(current, int | float) and float(stored) == float(current)
    return stored == current


def check_run_config(dataset_path: str | Path, config: Mapping[str, Any]) -> None:
    """``ValueError`` naming the settings in which ``config`` differs from the run that wrote
    ``dataset_path`` (its metadata holds the settings of Stages 1 and 2; all but ``sampling``
    decide how one design evaluates)."""
    stored = read_meta(dataset_path).get("settings", {})
    differ = []
    for key, value in stored.items():
        if key == "sampling":  # which designs the run drew, not how one design is evaluated
            continue
        current: Any = config
        for part in SETTING_PATHS.get(key, (key,)):
            current = current.get(part) if isinstance(current, Mapping) else None
        if key == "task_points" and current is not None:  # the run stores the designed task
            current = design_task(current)[1]
        if not _same(value, current):
            differ.append(key)
    if differ:
        raise ValueError(
            f"the config differs from the run that wrote '{dataset_path}' in: "
            f"{', '.join(differ)}; pass the run's config with --config"
        )


def front_table(results: str | Path, front: str) -> pd.DataFrame:
    """A verified front of a run with its ``rank`` column first (:mod:`qsm.optimization.ranking`);
    ``ValueError`` naming the fronts there when ``front`` is not one of them."""
    folder = Path(results) / "optimization"
    path = folder / front / "verification.parquet"
    if not path.is_file():
        fronts = sorted(p.parent.name for p in folder.glob("*/verification.parquet"))
        have = ", ".join(fronts) if fronts else "none (run the workflow first)"
        raise ValueError(f"unknown front '{front}' (--front): {folder} holds the fronts: {have}")
    table = read_table(path)
    rank = pd.Series(front_ranks(table), index=table.index, name="rank")
    return pd.concat([rank, table], axis=1)  # Arrow's split blocks: no insert into them


def front_design(results: str | Path, front: str, rank: int) -> tuple[np.ndarray, dict[str, Any]]:
    """The design of ``front`` at ``rank`` and its source record (with the run's values)."""
    table = front_table(results, front)
    n = len(table)
    if not 1 <= rank <= n:
        raise ValueError(f"--rank {rank} is out of range: the {front} front has ranks 1 to {n}")
    row = table.loc[table["rank"] == rank].iloc[0]
    source = {
        "kind": "front",
        "front": front,
        "rank": rank,
        "n_designs": n,
        "table": str(Path(results) / "optimization" / front / "verification.parquet"),
        "run_values": {k: row[k] for k in FRONT_VALUES},
    }
    return row[list(DESIGN_COLUMNS)].to_numpy(float), source


def dataset_design(results: str | Path, mechanism_id: int) -> tuple[np.ndarray, dict[str, Any]]:
    """The dataset mechanism ``mechanism_id`` and its source record (with the run's values)."""
    path = Path(results) / "dataset.parquet"
    table = read_table(path, DATASET_COLUMNS)
    row = table.loc[table["mechanism_id"] == mechanism_id]
    if row.empty:
        raise ValueError(
            f"--id {mechanism_id} is not a mechanism_id in '{path}' ({len(table)} mechanisms, "
            f"ids {table['mechanism_id'].min()} to {table['mechanism_id'].max()})"
        )
    first = row.iloc[0]
    source = {
        "kind": "dataset",
        "mechanism_id": int(mechanism_id),
        "table": str(path),
        "run_values": {k: first[k] for k in ("eta", "tau1_Nm", "tau2_Nm", "status")},
    }
    return first[list(DESIGN_COLUMNS)].to_numpy(float), source


def ratios_design(ratios: Sequence[float], config: Mapping[str, Any]) -> tuple[np.ndarray, dict]:
    """The unit design ``ratios`` scaled to the config's task as Stage 1 does."""
    try:
        r = checked_ratios(ratios)
    except ValueError as exc:
        raise ValueError(f"--ratios: {exc}") from exc
    result = evaluate_ratios(r, config)
    if not result["feasible"]:
        raise ValueError(f"--ratios: this design cannot hold the task: {result['reason']}")
    design = np.array(list(result["design_m"].values()))
    return design, {"kind": "ratios", "ratios": dict(zip(RATIO_NAMES, r.tolist(), strict=True))}
