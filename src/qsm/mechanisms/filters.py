"""Stage 1 kinematic filters of the sampled unit mechanisms, each step counted."""

from __future__ import annotations

from collections.abc import Iterable, Iterator

import numpy as np
import pandas as pd

from qsm.physics.kinematics import RATIO_NAMES, loop_closes_everywhere, transmission_angle_range
from qsm.physics.workspace import OperatingRange


def crank_rocker(ratios: np.ndarray) -> np.ndarray:
    """The paper's crank-rocker condition l3 + l2 < l1 + l4 (Eq. 1), with l1 = 1."""
    return ratios[:, 1] + ratios[:, 0] < 1.0 + ratios[:, 2]


def transmission_ok(ratios: np.ndarray, op: OperatingRange, min_angle_deg: float) -> np.ndarray:
    """Transmission angle within [m, 180 - m] deg at every pose of ``op`` (all True for m = 0)."""
    if min_angle_deg <= 0:
        return np.ones(len(ratios), dtype=bool)
    mu_a, mu_b = transmission_angle_range(ratios, op.delta_max)
    m = np.radians(min_angle_deg)
    lo, hi = np.minimum(mu_a, mu_b), np.maximum(mu_a, mu_b)
    return (lo >= m) & (hi <= np.pi - m)


def kinematic_checks(
    ratios: np.ndarray, op: OperatingRange, min_transmission_angle_deg: float
) -> dict[str, np.ndarray]:
    """Each kinematic condition of Stage 1 for ratios (N, 5), in filter order.

    ``crank_rocker``: the paper's l3 + l2 < l1 + l4; ``loop_closes``: the loop closes at every
    pose of ``op``; ``transmission_ok``: the optional transmission-angle limit.
    """
    r = np.atleast_2d(ratios)
    return {
        "crank_rocker": crank_rocker(r),
        "loop_closes": loop_closes_everywhere(r, op.delta_max),
        "transmission_ok": transmission_ok(r, op, min_transmission_angle_deg),
    }


def kinematic_filters(
    samples: pd.DataFrame, op: OperatingRange, min_transmission_angle_deg: float
) -> tuple[pd.DataFrame, dict[str, int]]:
    """Rows of ``samples`` that pass every kinematic filter, and how many pass each step.

    Steps, in order: the crank-rocker condition; the loop closes at every pose of the operating
    range (|l3 - l4| <= |BC| <= l3 + l4); the optional transmission-angle limit.
    """
    ratios = samples[list(RATIO_NAMES)].to_numpy()
    checks = kinematic_checks(ratios, op, min_transmission_angle_deg)
    keep = np.ones(len(samples), dtype=bool)
    counts = {"samples": len(samples)}
    steps = ("crank_rocker", "loop_closes", "transmission_angle")  # filter_report.json keys
    for step, ok in zip(steps, checks.values(), strict=True):
        keep &= ok
        counts[step] = int(keep.sum())
    return samples.loc[keep].reset_index(drop=True), counts


def filter_batches(
    batches: Iterable[pd.DataFrame], op: OperatingRange, min_transmission_angle_deg: float
) -> Iterator[tuple[pd.DataFrame, dict[str, int]]]:
    """:func:`kinematic_filters` of a table read in ``batches``, one batch at a time: the rows of
    each that pass, in order, and its counts (:func:`added` sums them to the whole table's)."""
    for batch in batches:
        yield kinematic_filters(batch, op, min_transmission_angle_deg)


def added(total: dict[str, int], counts: dict[str, int]) -> dict[str, int]:
    """Filter counts ``total`` with a batch's ``counts`` added, step by step."""
    return {k: total.get(k, 0) + n for k, n in counts.items()}
