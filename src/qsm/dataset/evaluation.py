"""Stage 2 for one shard of mechanisms: closed-chain dynamics, then strength, drives and tool sag.

:func:`evaluate_shard` is what the rule ``dynamics`` runs. Its first step, :func:`evaluate_table`
(also the study's, for designs at a drawn scale), takes the rows through
:func:`qsm.physics.dynamics.evaluate_mechanism` one design at a time, with progress in the log; a
failing design gives a row with its status, not an exception. :func:`with_embodiment` then adds the
strength and drive columns of the healthy rows, vectorised.
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray

from qsm.embodiment.drives.drive_checks import DriveCheck, same_loads
from qsm.embodiment.load_case import LoadCase
from qsm.embodiment.stiffness.sag_check import SagCheck
from qsm.embodiment.strength.link_checks import StrengthCheck
from qsm.embodiment.strength.sizing import SizedSections
from qsm.physics.cad import DEFAULT_CAD, CadSettings
from qsm.physics.duty import Duty, duty_cycle
from qsm.physics.dynamics import evaluate_mechanism, loop_states
from qsm.physics.kinematics import DESIGN_COLUMNS
from qsm.physics.results import DYNAMICS_COLUMNS

log = logging.getLogger(__name__)


def evaluate_table(
    df: pd.DataFrame,
    duty: Duty | None = None,
    settings: CadSettings = DEFAULT_CAD,
    payload_kg: float = 5.0,
    log_every: int = 1000,
    scales: ArrayLike | None = None,
) -> pd.DataFrame:
    """:func:`qsm.physics.dynamics.evaluate_mechanism` for every row of ``df`` (columns
    l1_m ... ee_y_m, m), with each row's section scales (rows, 4) when ``scales`` is given.

    Returns one row per input row, in the same order and with the same index, holding
    ``mechanism_id`` (when ``df`` has it) and the :data:`qsm.physics.results.DYNAMICS_COLUMNS`
    columns. ``duty`` defaults to :func:`qsm.physics.duty.duty_cycle` with default settings.
    Progress is logged every ``log_every`` rows.
    """
    duty = duty_cycle() if duty is None else duty
    designs = df.loc[:, list(DESIGN_COLUMNS)].to_numpy(dtype=float)
    rows = []
    start = time.perf_counter()
    factors = [None] * len(designs) if scales is None else np.asarray(scales, dtype=float)
    each = zip(designs, factors, loop_states(designs, duty), strict=True)
    for i, (design, scale, state) in enumerate(each, start=1):
        rows.append(evaluate_mechanism(design, duty, settings, payload_kg, scale, state))
        if i % log_every == 0 or i == len(designs):
            elapsed = time.perf_counter() - start
            log.info("dynamics: %d/%d mechanisms, %.1f mechanisms/s", i, len(designs), i / elapsed)
    out = pd.DataFrame(rows, index=df.index, columns=list(DYNAMICS_COLUMNS))
    if "mechanism_id" in df.columns:
        out.insert(0, "mechanism_id", df["mechanism_id"].to_numpy())
    return out


#: Mechanisms evaluated together (rows): bounds a dynamics job's memory whatever its shard's size
#: (the vectorised checks hold about 50 kB per row); each row's numbers do not depend on it.
CHUNK_ROWS = 2048


@dataclass(frozen=True)
class DatasetSettings:
    """Stage 2's settings (:func:`qsm.config.settings.dataset.dataset_of`): the load ``case``,
    the link check, the drive check and the tool's sag check at the task points."""

    case: LoadCase
    strength: StrengthCheck
    drives: DriveCheck
    sag: SagCheck


def evaluate_shard(
    rows: pd.DataFrame, settings: DatasetSettings, chunk_rows: int = CHUNK_ROWS
) -> pd.DataFrame:
    """Stage 2's columns (:data:`qsm.dataset.columns.DATASET_COLUMNS` but the mechanism's own) of
    the mechanisms ``rows``, ``chunk_rows`` at a time (:func:`evaluate_chunk`)."""
    parts = [
        evaluate_chunk(rows.iloc[start : start + chunk_rows], settings)
        for start in range(0, max(len(rows), 1), chunk_rows)
    ]
    return pd.concat(parts, ignore_index=True)


def evaluate_chunk(rows: pd.DataFrame, settings: DatasetSettings) -> pd.DataFrame:
    """Stage 2's columns of the mechanisms ``rows``: the dynamics at each row's section (sized by
    the link check when it sizes them), then strength and drives, and ``tool_sag_mm`` at the
    configured section."""
    case, strength = settings.case, settings.strength
    designs = rows[list(DESIGN_COLUMNS)].to_numpy(float)
    sized = strength.section_scales(designs)  # None: the fixed section
    scales = None if sized is None else sized.scale
    result = evaluate_table(rows, strength.duty, case.cad, case.payload_kg, scales=scales)
    result = with_embodiment(
        result.reset_index(drop=True), designs, strength, settings.drives, sized
    )
    ok = result["status"].eq("ok").to_numpy()
    result["tool_sag_mm"] = np.where(ok, settings.sag.sag_mm(designs), np.nan)
    return result


def with_embodiment(
    table: pd.DataFrame,
    designs: ArrayLike,
    strength: StrengthCheck,
    drives: DriveCheck,
    sized: SizedSections | None = None,
) -> pd.DataFrame:
    """``table`` (dynamics results, one row per design of ``designs`` (N, 6) m) with
    :data:`STRENGTH_COLUMNS` and :data:`DRIVE_COLUMNS` appended for its rows whose ``status`` is
    'ok' (NaN elsewhere); the joint loads are computed once for both checks when they share
    section, payload and duty. ``sized``: the sized sections
    (:meth:`StrengthCheck.section_scales`) when computed already."""
    ok = table["status"].eq("ok").to_numpy()
    d = np.asarray(designs, dtype=float)[ok]
    links, tau, good = strength.evaluate_with_torques(d, None if sized is None else sized.rows(ok))
    motors = drives.evaluate(d, (tau, good) if same_loads(strength, drives) else None)
    out = append_columns(table, ok, links, "holds_loads")
    return append_columns(out, ok, motors, "has_drives")


def append_columns(
    table: pd.DataFrame, ok: NDArray[np.bool_], values: pd.DataFrame, flag: str
) -> pd.DataFrame:
    """``table`` with the columns of ``values`` (one row per True of ``ok``) appended, NaN on the
    other rows, whose boolean ``flag`` column is False there."""
    out = pd.DataFrame(index=table.index, columns=list(values.columns), dtype=float)
    for key in values.columns:
        column: Any = values[key].to_numpy()
        if column.dtype.kind in "OUb":
            out[key] = out[key].astype(object)
        out.loc[ok, key] = column
    out[flag] = out[flag].eq(True)
    return pd.concat([table, out], axis=1)
