"""Stage 2's closed-chain dynamics of every row of a table of mechanisms.

One shard's rows of the dataset (and the study's designs at a drawn scale) go through
:func:`qsm.physics.dynamics.evaluate_mechanism` one design at a time, with progress in the log; a
failing design gives a row with its status, not an exception.
"""

from __future__ import annotations

import logging
import time

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike

from qsm.physics.cad import DEFAULT_CAD, CadSettings
from qsm.physics.duty import Duty, duty_cycle
from qsm.physics.dynamics import evaluate_mechanism
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
    for i, (design, scale) in enumerate(zip(designs, factors, strict=True), start=1):
        rows.append(evaluate_mechanism(design, duty, settings, payload_kg, scale))
        if i % log_every == 0 or i == len(designs):
            elapsed = time.perf_counter() - start
            log.info("dynamics: %d/%d mechanisms, %.1f mechanisms/s", i, len(designs), i / elapsed)
    out = pd.DataFrame(rows, index=df.index, columns=list(DYNAMICS_COLUMNS))
    if "mechanism_id" in df.columns:
        out.insert(0, "mechanism_id", df["mechanism_id"].to_numpy())
    return out
