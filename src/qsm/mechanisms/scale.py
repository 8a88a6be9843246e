"""Stage 1 scale-up: workspace, minimal scale factor and eta of each design; the final selection."""

from __future__ import annotations

import logging
import time
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray

from qsm.physics.containment import minimal_scales, radial_misfit
from qsm.physics.kinematics import DESIGN_NAMES, RATIO_NAMES
from qsm.physics.task import Disk
from qsm.physics.workspace import ARCS_CHUNK, OperatingRange, Resolution, arcs, slice_stack

log = logging.getLogger(__name__)

#: Columns of results/mechanisms/mechanisms.parquet and their units.
MECHANISM_COLUMNS: dict[str, str] = {
    "mechanism_id": "stable id: the row of the design in the LHS sample (-)",
    **{name: "ratio to l1 (-)" for name in RATIO_NAMES},
    "scale_m": "scale factor = l1 (m)",
    **{f"{name}_m": "scaled length (m)" for name in DESIGN_NAMES},
    "workspace_area_m2": "workspace area at the scale (m^2)",
    "eta": "task-disk area / workspace area (-)",
}

#: The columns of a shard's fits (rule ``fit_task``) that the selection and its counts read.
FIT_COLUMNS = (
    "sample_id",
    *RATIO_NAMES,
    "feasible",
    "reason",
    "scale_m",
    "workspace_area_m2",
    "eta",
)


@dataclass(frozen=True)
class FitSettings:
    """What the scale-up needs: motor ranges, task disk, scale limits and discretisation."""

    op: OperatingRange
    disk: Disk
    scale_max: float
    safety_margin: float = 0.0
    resolution: Resolution = field(default_factory=Resolution)
    n_scan: int = 128
    min_transmission_angle_deg: float = 0.0


def fit_design(ratios: Sequence[float], settings: FitSettings) -> dict[str, Any]:
    """Scale-up of one unit design ``(l2, l3, l4, ee_x, ee_y)``.

    Returns ``feasible``, ``reason`` (why not), ``scale_m``, ``workspace_area_unit`` (l1^2),
    ``workspace_area_m2`` and ``eta`` (NaN when infeasible). A design whose workspace radii alone
    rule the task out is not sliced: its ``workspace_area_unit`` is NaN too.
    """
    return _fit_arcs(
        *arcs(np.atleast_2d(ratios), settings.op, settings.resolution.n_delta), settings
    )[0]


def _fit_arcs(
    rho: NDArray[np.float64],
    lo: NDArray[np.float64],
    hi: NDArray[np.float64],
    settings: FitSettings,
) -> list[dict[str, Any]]:
    """:func:`fit_design` of designs from their :func:`qsm.physics.workspace.arcs` (M, n_delta):
    the slicing and the scale searches of all at once."""
    disk = settings.disk
    radius = disk.radius + settings.safety_margin
    fits = [_infeasible("loop does not close", np.nan) for _ in range(len(rho))]
    sliced = []
    for k in np.flatnonzero(np.isfinite(rho).all(axis=1)):
        radial = radial_misfit(
            rho[k].min(), rho[k].max(), disk.distance, radius, settings.scale_max
        )
        if radial:
            fits[k] = _infeasible(radial, np.nan)
        else:
            sliced.append(k)
    stack = slice_stack(
        rho[sliced], lo[sliced], hi[sliced], disk.angle, settings.resolution.n_levels
    )
    found = minimal_scales(stack, disk.distance, radius, settings.scale_max, settings.n_scan)
    for k, unit_area, fit in zip(sliced, stack.area.tolist(), found, strict=True):
        if not fit.feasible:
            fits[k] = _infeasible(fit.reason, unit_area)
            continue
        area = unit_area * fit.scale**2
        fits[k] = {
            "feasible": True,
            "reason": "",
            "scale_m": fit.scale,
            "workspace_area_unit": unit_area,
            "workspace_area_m2": area,
            "eta": disk.area / area,
        }
    return fits


def _infeasible(reason: str, unit_area: float) -> dict[str, Any]:
    return {
        "feasible": False,
        "reason": reason,
        "scale_m": np.nan,
        "workspace_area_unit": unit_area,
        "workspace_area_m2": np.nan,
        "eta": np.nan,
    }


def fit_rows(ratios: NDArray[np.float64], settings: FitSettings) -> Iterator[dict[str, Any]]:
    """:func:`fit_design` of each row of ``ratios`` (N, 5), lazily, in order; the workspace arcs and
    the scale searches of :data:`ARCS_CHUNK` rows at a time come from vectorised calls."""
    for start in range(0, len(ratios), ARCS_CHUNK):
        rho, lo, hi = arcs(
            ratios[start : start + ARCS_CHUNK], settings.op, settings.resolution.n_delta
        )
        yield from _fit_arcs(rho, lo, hi, settings)


def fit_designs(
    designs: pd.DataFrame,
    settings: FitSettings,
    stop_after: int | None = None,
    log_every: int = 5000,
) -> pd.DataFrame:
    """``fit_design`` for the rows (columns ``sample_id`` and the ratios), in row order.

    With ``stop_after``, the rows after the ``stop_after``-th feasible one are not examined and
    not returned: a shard needs to give no more than the whole selection (see
    :func:`examined_fits`).
    """
    ratios = designs[list(RATIO_NAMES)].to_numpy()
    columns: dict[str, list[Any]] = {key: [] for key in _infeasible("", 0.0)}  # lighter than rows
    found = i = 0
    start = time.perf_counter()
    for i, row in enumerate(fit_rows(ratios, settings), 1):
        for key, value in row.items():
            columns[key].append(value)
        found += row["feasible"]
        done = stop_after is not None and found >= stop_after
        if i % log_every == 0 or i == len(ratios) or done:
            rate = i / max(time.perf_counter() - start, 1e-9)
            log.info("scaled %d/%d designs (%.0f designs/s)", i, len(ratios), rate)
        if done:
            log.info("%d feasible designs found: the remaining rows are not needed", found)
            break
    fits = pd.DataFrame(columns)
    examined = designs[["sample_id", *RATIO_NAMES]].iloc[:i].reset_index(drop=True)
    return pd.concat([examined, fits], axis=1)


def shard_quota(n_mechanisms: int, shards: int) -> int:
    """The feasible designs each of ``shards`` interleaved shards of the candidates looks for:
    its share of the selection and 10 % more, so that together they have most likely examined
    every candidate up to the ``n_mechanisms``-th feasible one (:func:`covered_fits`)."""
    return -(-11 * n_mechanisms // (10 * shards))


def covered_fits(fits: pd.DataFrame, candidate_ids: ArrayLike) -> tuple[pd.DataFrame, int, int]:
    """The ``fits`` of the longest run of ``candidate_ids`` from the first (in sample order)
    that were all examined, that run's length and its last sample id (-1 when empty)."""
    ids = np.sort(np.asarray(candidate_ids))
    examined = np.isin(ids, fits["sample_id"].to_numpy())
    prefix = len(ids) if examined.all() else int(np.argmin(examined))
    last = int(ids[prefix - 1]) if prefix else -1
    return fits.loc[fits["sample_id"].to_numpy() <= last], prefix, last


def gathered_fits(
    fits: pd.DataFrame,
    candidate_ids: ArrayLike,
    candidates_after: Callable[[int], pd.DataFrame],
    n_mechanisms: int,
    settings: FitSettings,
) -> pd.DataFrame:
    """The shards' ``fits`` of the candidates (``candidate_ids``) up to the ``n_mechanisms``-th
    feasible one in sample order (:func:`examined_fits`). Where the shards' quotas
    (:func:`shard_quota`) fell short, the candidates after those the shards covered are fitted
    here: ``candidates_after(last)`` gives them (sample id and ratios), those of sample id above
    ``last``, so that they are read only when needed."""
    fits, covered, last = covered_fits(fits, candidate_ids)
    short = n_mechanisms - int(fits["feasible"].sum())
    if short > 0 and covered < len(candidate_ids):
        log.info("the shards cover %d candidates, %d fits short: fitting on", covered, short)
        rest = candidates_after(last).sort_values("sample_id", ignore_index=True)
        more = fit_designs(rest, settings, stop_after=short)
        fits = pd.concat([fits, more], ignore_index=True)
    return examined_fits(fits, n_mechanisms)


def examined_fits(fits: pd.DataFrame, n_mechanisms: int) -> pd.DataFrame:
    """The fits of every candidate up to the ``n_mechanisms``-th feasible one in sample order
    (all of them if fewer are feasible).

    How far each shard got depends on the sharding; this prefix of fits that cover every
    candidate up to their last (:func:`covered_fits`) does not.
    """
    fits = fits.sort_values("sample_id")
    feasible = fits["feasible"].to_numpy(dtype=bool)
    if feasible.sum() < n_mechanisms:
        return fits
    last = int(np.flatnonzero(feasible)[n_mechanisms - 1])
    return fits.iloc[: last + 1]


def select_mechanisms(fits: pd.DataFrame, n_mechanisms: int) -> pd.DataFrame:
    """The first ``n_mechanisms`` feasible designs in sample order, as the mechanism table."""
    ok = fits.loc[fits["feasible"]].sort_values("sample_id").head(n_mechanisms)
    table = pd.DataFrame({"mechanism_id": ok["sample_id"].to_numpy(dtype=np.int64)})
    for name in RATIO_NAMES:
        table[name] = ok[name].to_numpy()
    scale = ok["scale_m"].to_numpy()
    table["scale_m"] = scale
    table["l1_m"] = scale
    for name in RATIO_NAMES:
        table[f"{name}_m"] = ok[name].to_numpy() * scale
    table["workspace_area_m2"] = ok["workspace_area_m2"].to_numpy()
    table["eta"] = ok["eta"].to_numpy()
    return table


def fit_counts(fits: pd.DataFrame) -> dict[str, Any]:
    """How many of the examined designs fit the task, and how many failed for each reason."""
    reasons = fits.loc[~fits["feasible"], "reason"].value_counts().sort_index()
    return {
        "task_fit_examined": len(fits),
        "task_fits": int(fits["feasible"].sum()),
        "task_fit_failures": {str(k): int(v) for k, v in reasons.items()},
    }
