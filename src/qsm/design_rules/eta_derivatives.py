"""Derivatives of the true eta with respect to the 6 design variables (paper Fig. 9).

eta(X) = task-disk area / workspace area of the design X = (l1, l2, l3, l4, ee_x, ee_y) in metres,
with the workspace from Stage 1's slicing (no surrogate). Central differences with a relative
step; the slicing is smooth in X, so the step's truncation and noise errors are small (tested
against a step-halved estimate).
"""

from __future__ import annotations

import logging
import time

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from qsm.physics.kinematics import DESIGN_NAMES
from qsm.physics.task import Disk
from qsm.physics.workspace import OperatingRange, Resolution, unit_areas

log = logging.getLogger(__name__)

#: Designs whose slicings run in one call: each design's numbers do not depend on it.
BATCH = 256


def true_etas(
    designs: NDArray[np.float64], op: OperatingRange, disk: Disk, res: Resolution
) -> NDArray[np.float64]:
    """Task-disk area over the workspace area of designs (M, 6 lengths, m); NaN where the loop
    does not close over the whole operating range."""
    d = np.atleast_2d(designs)
    return disk.area / (unit_areas(d[:, 1:] / d[:, :1], op, res) * d[:, 0] ** 2)


def eta_gradient(
    design: NDArray[np.float64],
    op: OperatingRange,
    disk: Disk,
    res: Resolution,
    rel_step: float = 1e-3,
) -> NDArray[np.float64]:
    """d eta / d x for the 6 lengths (1/m) of one design (6,) m (:func:`batch_gradients`)."""
    return batch_gradients(np.atleast_2d(design), op, disk, res, rel_step)[0]


def batch_gradients(
    designs: NDArray[np.float64],
    op: OperatingRange,
    disk: Disk,
    res: Resolution,
    rel_step: float = 1e-3,
) -> NDArray[np.float64]:
    """d eta / d x (M, 6) 1/m of designs (M, 6) m by central differences with step
    ``rel_step * x``, the 13 slicings of each design in one call.

    A design on the edge of loop closure, where one step opens the loop, gets the one-sided
    difference of the other step; NaN where neither side closes.
    """
    h = rel_step * designs
    steps = h[:, None, :] * np.eye(6)
    centre = designs[:, None, :]
    probes = np.concatenate([centre + steps, centre - steps, centre], axis=1)  # (M, 13, 6)
    etas = true_etas(probes.reshape(-1, 6), op, disk, res).reshape(len(designs), 13)
    e_up, e_down, e_centre = etas[:, :6], etas[:, 6:12], etas[:, 12:]
    one_sided = ~(np.isfinite(e_up) & np.isfinite(e_down))
    side = np.where(np.isfinite(e_up), (e_up - e_centre) / h, (e_centre - e_down) / h)
    return np.where(one_sided, side, (e_up - e_down) / (2 * h))


def eta_gradients(
    designs: pd.DataFrame,
    op: OperatingRange,
    disk: Disk,
    res: Resolution,
    rel_step: float = 1e-3,
    log_every: int = 1024,
) -> pd.DataFrame:
    """:func:`batch_gradients` of every row (columns l1_m ... ee_y_m, plus ``mechanism_id``),
    :data:`BATCH` rows at a time; progress is logged every ``log_every`` rows."""
    lengths = designs[[f"{n}_m" for n in DESIGN_NAMES]].to_numpy()
    grads = np.empty((len(lengths), 6))
    start = time.perf_counter()
    for first in range(0, len(lengths), BATCH):
        done = min(first + BATCH, len(lengths))
        grads[first:done] = batch_gradients(lengths[first:done], op, disk, res, rel_step)
        if done % log_every == 0 or done == len(lengths):
            rate = done / max(time.perf_counter() - start, 1e-9)
            log.info(
                "derivatives of %d/%d mechanisms (%.0f mechanisms/s)", done, len(lengths), rate
            )
    out = pd.DataFrame(grads, columns=[f"deta_d{n}_per_m" for n in DESIGN_NAMES])
    out.insert(0, "mechanism_id", designs["mechanism_id"].to_numpy())
    return out


def sampled_rows(n_rows: int, most: int, seed: int) -> NDArray[np.intp]:
    """The rows (sorted) whose derivatives are computed: all ``n_rows`` up to ``most``, else
    ``most`` drawn without replacement with ``seed``, so that the stage's work stops growing
    with the dataset (its medians and box plots are those of a sample of that size)."""
    if n_rows <= most:
        return np.arange(n_rows)
    return np.sort(np.random.default_rng(seed).choice(n_rows, size=most, replace=False))
