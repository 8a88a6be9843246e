"""Array kernels of the workspace slicing (:mod:`qsm.physics.workspace`), batched over designs.

The arcs of one ``delta`` sample are cut by the circles (levels) about the base: on each monotone
piece of ``rho(delta)`` every level the piece reaches gets one interval of polar angles,
interpolated linearly in ``rho`` between the two samples that bracket it, with the arithmetic of
``np.interp`` (so that a design's numbers do not depend on the designs sliced with it). The union
of the intervals on a level and the largest arc of it centred on the task's angle follow by
sorting. Designs lie along a leading axis; intervals along axis 0 of the union functions.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

TWO_PI = 2.0 * np.pi


def levels_between(
    rho_min: NDArray[np.float64], rho_max: NDArray[np.float64], n_levels: int
) -> NDArray[np.float64]:
    """Midpoints (G, n_levels) of ``n_levels`` equal bins from ``rho_min`` to ``rho_max`` (G,)."""
    width = (rho_max - rho_min)[:, None]
    return rho_min[:, None] + (np.arange(n_levels) + 0.5) * width / n_levels


def intervals_on_levels(
    rho: NDArray[np.float64],
    lo: NDArray[np.float64],
    hi: NDArray[np.float64],
    levels: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.intp]]:
    """Arc ``[start, end]`` (rad) of every monotone piece of ``rho(delta)`` on every level.

    ``rho``, ``lo``, ``hi`` are closed :func:`qsm.physics.workspace.arcs` (G, n_delta), ``levels``
    (G, L) increasing along axis 1. Returns starts and ends (P, G, L), P the largest number of
    pieces, NaN on levels a piece does not reach and on the pieces a design lacks, and the number
    of pieces of each design (G,). The pieces share their end samples; a piece that falls is read
    backwards, and the level ``x`` takes the segment ``[x0, x1)`` of the piece's samples that holds
    it (``x1`` included on the piece's top segment), as ``np.interp`` does.
    """
    g, n = rho.shape
    step = np.sign(np.diff(rho, axis=1))
    turn = np.zeros((g, n), dtype=bool)
    turn[:, 1:-1] = step[:, 1:] * step[:, :-1] < 0
    bound = turn.copy()
    bound[:, [0, -1]] = True
    sample = np.arange(n)
    piece = np.cumsum(turn, axis=1)[:, :-1]  # piece of segment [k, k + 1]
    first = np.maximum.accumulate(np.where(bound, sample, 0), axis=1)[:, :-1]
    last = np.minimum.accumulate(np.where(bound, sample, n - 1)[:, ::-1], axis=1)[:, ::-1][:, 1:]
    row = np.arange(g)[:, None]
    falls = rho[row, last] < rho[row, first]
    k = sample[:-1]
    i0, i1 = np.where(falls, k + 1, k), np.where(falls, k, k + 1)  # lower and upper sample
    top = np.where(falls, k == first, k + 1 == last)
    x0, x1 = rho[row, i0], rho[row, i1]
    c0 = _count_below(levels, x0, np.zeros_like(top))
    count = np.maximum(_count_below(levels, x1, top) - c0, 0)
    # one entry per (segment, level it holds)
    seg = np.repeat(np.arange(count.size), count.ravel())
    offset = np.cumsum(count.ravel()) - count.ravel()
    level = c0.ravel()[seg] + np.arange(seg.size) - offset[seg]
    design = seg // (n - 1)
    x = levels[design, level]
    a, b, on_top = x0.ravel()[seg], x1.ravel()[seg], top.ravel()[seg]
    n_pieces = piece[:, -1] + 1
    shape = (int(n_pieces.max(initial=0)), g, levels.shape[1])
    out = []
    for values in (lo, hi):
        y0, y1 = values[row, i0].ravel()[seg], values[row, i1].ravel()[seg]
        with np.errstate(invalid="ignore", divide="ignore"):
            y = (y1 - y0) / (b - a) * (x - a) + y0
        y = np.where(x == a, y0, y)
        arc = np.full(shape, np.nan)
        arc[piece.ravel()[seg], design, level] = np.where(on_top & (x == b), y1, y)
        out.append(arc)
    return out[0], out[1], n_pieces


def _count_below(
    xp: NDArray[np.float64], x: NDArray[np.float64], inclusive: NDArray[np.bool_]
) -> NDArray[np.intp]:
    """How many of row ``i``'s ``xp[i]`` (increasing, about evenly spaced) lie below each of
    ``x[i]`` (or at it, where ``inclusive``): a guess from the spacing, walked to the count."""
    n = xp.shape[1]
    first, last = xp[:, :1], xp[:, -1:]
    with np.errstate(invalid="ignore", divide="ignore"):
        guess = np.ceil((x - first) / (last - first) * (n - 1))
    c = np.clip(np.nan_to_num(guess), 0, n).astype(np.intp)
    row = np.arange(len(xp))[:, None]

    def below(v: NDArray[np.float64]) -> NDArray[np.bool_]:
        return (v < x) | (inclusive & (v == x))

    while True:
        back = (c > 0) & ~below(xp[row, np.maximum(c - 1, 0)])
        ahead = (c < n) & below(xp[row, np.minimum(c, n - 1)])
        if not (back.any() or ahead.any()):
            return c
        c = c - back + ahead


def wrap_about(
    starts: NDArray[np.float64], ends: NDArray[np.float64], centre: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Express arcs relative to ``centre`` on [-pi, pi], splitting an arc that crosses pi.

    Every arc is shorter than 2 pi (theta1's range), so one split suffices. Empty arcs become
    zero-length arcs at pi.
    """
    s = starts - centre
    shift = np.floor((s + np.pi) / TWO_PI) * TWO_PI
    s = s - shift
    e = ends - centre - shift
    over = e > np.pi
    s2 = np.where(over, -np.pi, np.pi)
    e2 = np.where(over, e - TWO_PI, np.pi)
    e = np.minimum(e, np.pi)
    empty = ~np.isfinite(s)
    s, e = np.where(empty, np.pi, s), np.where(empty, np.pi, e)
    return np.concatenate([s, s2]), np.concatenate([e, e2])


def _sorted_apart(
    starts: NDArray[np.float64], ends: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.bool_], NDArray[np.float64]]:
    """Starts and ends each sorted along axis 0, whether the union has a gap after the k-th end
    (axis 0 one shorter), and the union's length.

    There is a gap between the k-th end and the (k+1)-th start exactly when the first lies below
    the second (the k-th start never exceeds the k-th end), so the union is the hull less those
    gaps: no sort of the ends by their starts.
    """
    s, e = np.sort(starts, axis=0), np.sort(ends, axis=0)
    gap = s[1:] > e[:-1]
    return s, e, gap, e[-1] - s[0] - np.where(gap, s[1:] - e[:-1], 0.0).sum(axis=0)


def margin_about_zero(
    starts: NDArray[np.float64], ends: NDArray[np.float64]
) -> NDArray[np.float64]:
    """Half-width of the largest arc centred on 0 inside the union; -1 where 0 is not covered."""
    return union_and_margin(starts, ends)[1]


def union_and_margin(
    starts: NDArray[np.float64], ends: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Length of the union of closed intervals and the half-width of its largest arc centred on 0
    (-1 where 0 is not covered); intervals along axis 0, levels (and designs) along the others.

    The union's connected pieces (:func:`_sorted_apart`) start at the first start and after each
    gap, and end before each gap and at the last end; 0 is covered when the last piece to start
    at or below 0 is not one that ends below 0.
    """
    s, e, gap, covered = _sorted_apart(starts, ends)
    piece_start = np.concatenate([s[:1], np.where(gap, s[1:], np.inf)])
    piece_end = np.concatenate([np.where(gap, e[:-1], -np.inf), e[-1:]])
    left = np.max(np.where(piece_start <= 0.0, piece_start, -np.inf), axis=0)
    right = np.min(np.where(piece_end >= 0.0, piece_end, np.inf), axis=0)
    ended = np.max(np.where(piece_end < 0.0, piece_end, -np.inf), axis=0)
    holds = (left > ended) & np.isfinite(left) & np.isfinite(right)
    return covered, np.where(holds, np.minimum(right, -left), -1.0)
