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
    """d eta / d x for the 6 lengths (1/m) by central differences with step ``rel_step * x``.

    A design on the edge of loop closure, where one step opens the loop, gets the one-sided
    difference of the other step; NaN where neither side closes.
    """
    h = rel_step * design
    steps = np.diag(h)
    e_up, e_down = np.split(
        true_etas(np.vstack([design + steps, design - steps]), op, disk, res), 2
    )
    grad = (e_up - e_down) / (2 * h)
    one_sided = ~(np.isfinite(e_up) & np.isfinite(e_down))
    if one_sided.any():
        centre = true_etas(design, op, disk, res)[0]
        grad = np.where(np.isfinite(e_up), (e_up - centre) / h, (centre - e_down) / h)
        grad = np.where(one_sided, grad, (e_up - e_down) / (2 * h))
    return grad


def eta_gradients(
    designs: pd.DataFrame,
    op: OperatingRange,
    disk: Disk,
    res: Resolution,
    rel_step: float = 1e-3,
    log_every: int = 1000,
) -> pd.DataFrame:
    """``eta_gradient`` of every row (columns l1_m ... ee_y_m, plus ``mechanism_id``); progress
    is logged every ``log_every`` rows."""
    lengths = designs[[f"{n}_m" for n in DESIGN_NAMES]].to_numpy()
    grads = np.empty((len(lengths), 6))
    start = time.perf_counter()
    for i, d in enumerate(lengths):
        grads[i] = eta_gradient(d, op, disk, res, rel_step)
        if (i + 1) % log_every == 0 or i + 1 == len(lengths):
            rate = (i + 1) / max(time.perf_counter() - start, 1e-9)
            log.info(
                "derivatives of %d/%d mechanisms (%.0f mechanisms/s)", i + 1, len(lengths), rate
            )
    out = pd.DataFrame(grads, columns=[f"deta_d{n}_per_m" for n in DESIGN_NAMES])
    out.insert(0, "mechanism_id", designs["mechanism_id"].to_numpy())
    return out
