"""Latin-hypercube sampling of the unit-mechanism ratios (paper Section 2.1, Table 1)."""

from __future__ import annotations

from collections.abc import Iterator, Mapping, Sequence

import numpy as np
import pandas as pd

from qsm.physics.kinematics import RATIO_NAMES


def latin_hypercube(
    n_samples: int, bounds: Mapping[str, Sequence[float]], seed: int
) -> pd.DataFrame:
    """``n_samples`` LHS rows of the ratios l2, l3, l4, ee_x, ee_y (l1 = 1) within ``bounds``.

    Columns: ``sample_id`` (row index, the stable id of a design) and one column per ratio.
    """
    return pd.concat(list(lhs_batches(n_samples, bounds, seed)), ignore_index=True)


def lhs_batches(
    n_samples: int, bounds: Mapping[str, Sequence[float]], seed: int, rows: int = 1_000_000
) -> Iterator[pd.DataFrame]:
    """:func:`latin_hypercube`'s table ``rows`` at a time: scipy's ``qmc.LatinHypercube(d=5,
    seed=seed).random(n_samples)``, scaled as ``qmc.scale`` scales, the same numbers, holding
    only the strata's permutations (4 bytes per sample and ratio) and one batch."""
    lo = np.array([bounds[name][0] for name in RATIO_NAMES], dtype=float)
    hi = np.array([bounds[name][1] for name in RATIO_NAMES], dtype=float)
    d = len(RATIO_NAMES)
    rng = np.random.default_rng(seed)
    jitter_state = rng.bit_generator.state
    rng.bit_generator.advance(n_samples * d)  # scipy draws the jitter first: (n, d) doubles
    perms = np.empty((d, n_samples), dtype=np.int32 if n_samples < 2**31 else np.int64)
    for i in range(d):
        perms[i] = np.arange(1, n_samples + 1)
        rng.shuffle(perms[i])
    rng.bit_generator.state = jitter_state
    for start in range(0, n_samples, rows):
        jitter = rng.uniform(size=(min(rows, n_samples - start), d))
        unit = (perms[:, start : start + len(jitter)].T - jitter) / n_samples
        table = pd.DataFrame(unit * (hi - lo) + lo, columns=list(RATIO_NAMES))
        table.insert(0, "sample_id", np.arange(start, start + len(jitter), dtype=np.int64))
        yield table
