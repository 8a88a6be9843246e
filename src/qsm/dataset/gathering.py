"""Stage 2's gathered dataset: the shards joined with the mechanisms, counts for the log, and
the healthy rows the later stages read (light: no MuJoCo, no trimesh)."""

from __future__ import annotations

from collections.abc import Iterable, Iterator, Sequence
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike

from qsm.dataset.columns import DATASET_COLUMNS, MOTORS


class DatasetError(ValueError):
    """The dynamics shards do not cover the mechanisms exactly once."""


def gather(mechanisms: pd.DataFrame, shards: Sequence[pd.DataFrame]) -> pd.DataFrame:
    """Join the mechanism table with the dynamics of all shards, in the mechanism table's order.

    Raises :class:`DatasetError` unless every mechanism id appears exactly once in the shards.
    """
    dyn = pd.concat(shards, ignore_index=True)
    check_coverage(mechanisms["mechanism_id"], [dyn["mechanism_id"]])
    table = mechanisms.merge(dyn, on="mechanism_id", how="left", validate="one_to_one")
    return table[list(DATASET_COLUMNS)]


def check_coverage(mechanism_ids: ArrayLike, shard_ids: Sequence[ArrayLike]) -> bool:
    """Raise :class:`DatasetError` unless every mechanism id appears exactly once in the shards'
    ids; whether the shards, one after another, hold them in the mechanisms' order."""
    ids = np.concatenate([np.asarray(x) for x in shard_ids]) if shard_ids else np.zeros(0, int)
    counts = pd.Series(ids).value_counts()
    expected = pd.Index(mechanism_ids)
    missing = expected.difference(counts.index)
    extra = counts.index.difference(expected)
    repeated = counts[counts > 1].index
    if len(missing) or len(extra) or len(repeated):
        raise DatasetError(
            "dynamics shards do not cover the mechanisms exactly once: "
            f"missing {_ids(missing)}, unknown {_ids(extra)}, repeated {_ids(repeated)}"
        )
    return bool(np.array_equal(ids, np.asarray(mechanism_ids)))


def gathered_batches(
    mechanisms: pd.DataFrame, shards: Iterable[pd.DataFrame]
) -> Iterator[pd.DataFrame]:
    """:func:`gather`'s table shard by shard, for shards that hold the mechanisms in their order
    (:func:`check_coverage`): each joined with its run of the mechanism table."""
    start = 0
    for dyn in shards:
        rows = mechanisms.iloc[start : start + len(dyn)]
        start += len(dyn)
        yield gather(rows, [dyn])


def _ids(ids: pd.Index) -> str:
    """A count and the first few ids, for error messages."""
    head = ", ".join(map(str, sorted(ids)[:5]))
    return f"{len(ids)} ({head}{', ...' if len(ids) > 5 else ''})"


#: The dataset's columns the counts below read (:func:`status_counts`, :func:`strength_counts`,
#: :func:`drive_counts`) and the failures' ids and reasons.
COUNTED_COLUMNS: tuple[str, ...] = (
    "mechanism_id", "status", "status_reason", "holds_loads", "weakest_link", "has_drives",
    *(f"drive{j}_{key}" for j in MOTORS for key in ("violation", "motor", "gearbox")),
)  # fmt: skip


def status_counts(dataset: pd.DataFrame) -> dict[str, int]:
    """How many mechanisms ended in each status."""
    return {str(k): int(v) for k, v in dataset["status"].value_counts().sort_index().items()}


def strength_counts(dataset: pd.DataFrame) -> dict[str, Any]:
    """How many mechanisms with dynamics hold their loads, and which link is weakest how often."""
    ok = dataset.loc[dataset["status"].eq("ok")]
    return {
        "with_dynamics": len(ok),
        "hold_loads": int(ok["holds_loads"].astype(bool).sum()),
        "weakest_link": {
            str(k): int(v) for k, v in ok["weakest_link"].value_counts().sort_index().items()
        },
    }


def drive_counts(dataset: pd.DataFrame) -> dict[str, Any]:
    """How many mechanisms with dynamics have a drive for each motor, and which drives."""
    ok = dataset.loc[dataset["status"].eq("ok")]
    out: dict[str, Any] = {
        "with_dynamics": len(ok),
        "have_drives": int(ok["has_drives"].astype(bool).sum()),
    }
    for j in MOTORS:
        has = ok[f"drive{j}_violation"].astype(float) <= 0
        out[f"motor{j}_has_drive"] = int(has.sum())
        pairs = ok.loc[has, f"drive{j}_motor"] + " + " + ok.loc[has, f"drive{j}_gearbox"]
        out[f"motor{j}_drives"] = {str(k): int(v) for k, v in pairs.value_counts().items()}
    return out


#: The rows :func:`ok_rows` keeps, as a filter of the dataset's file (``read_table(where=)``):
#: reading only them spares a job the failed rows and the copy that drops them.
OK_ROWS = [("status", "==", "ok")]


def ok_rows(dataset: pd.DataFrame) -> pd.DataFrame:
    """Mechanisms whose dynamics succeeded and whose labels are finite (the table itself, not a
    copy, where every row is)."""
    labels = dataset[["tau1_Nm", "tau2_Nm", "eta"]]
    ok = dataset["status"].eq("ok") & np.isfinite(labels).all(axis=1)
    if ok.all():
        return dataset.reset_index(drop=True)
    return dataset.loc[ok].reset_index(drop=True)
