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
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Arc ``[start, end]`` (rad) of every monotone piece of ``rho(delta)`` on every level.

    ``rho``, ``lo``, ``hi`` are closed :func:`qsm.physics.workspace.arcs` (G, n_delta), ``levels``
    (G, L) increasing along axis 1. Returns starts and ends (P, G, L), P the largest number of
    pieces (:func:`piece_counts`), NaN on levels a piece does not reach and on the pieces a design
    lacks. The pieces share their end samples; a piece that falls is read
    backwards, and the level ``x`` takes the segment ``[x0, x1)`` of the piece's samples that holds
    it (``x1`` included on the piece's top segment), as ``np.interp`` does.
    """
    g, n = rho.shape
    n_levels = levels.shape[1]
    turn = _turns(rho)
    bound = turn.copy()
    bound[:, [0, -1]] = True
    sample = np.arange(n)
    piece = np.cumsum(turn, axis=1)[:, :-1]  # piece of segment [k, k + 1]
    first = np.maximum.accumulate(np.where(bound, sample, 0), axis=1)[:, :-1]
    last = np.minimum.accumulate(np.where(bound, sample, n - 1)[:, ::-1], axis=1)[:, ::-1][:, 1:]
    # flat indices into the (G, n_delta) arrays: lower sample of each segment, and upper - lower
    base = (np.arange(g) * n)[:, None]
    flat = rho.ravel()
    falls = flat[base + last] < flat[base + first]
    k = sample[:-1]
    lower = base + np.where(falls, k + 1, k)
    up = np.where(falls, -1, 1)
    top = np.where(falls, k == first, k + 1 == last)
    below = count_below(levels, rho, inclusive=False).ravel()
    at_or_below = count_below(levels, rho, inclusive=True, start=below).ravel()
    c0 = below[lower]
    c1 = np.where(top, at_or_below[lower + up], below[lower + up])
    count = np.maximum(c1 - c0, 0).ravel()
    # one entry per (segment, level it holds)
    seg = np.repeat(np.arange(count.size), count)
    level = c0.ravel()[seg] + np.arange(seg.size) - (np.cumsum(count) - count)[seg]
    design = seg // (n - 1)
    x = levels.ravel()[design * n_levels + level]
    i0 = lower.ravel()[seg]
    i1 = i0 + up.ravel()[seg]
    a, b, on_top = flat[i0], flat[i1], top.ravel()[seg]
    target = (piece.ravel()[seg] * g + design) * n_levels + level
    out = []
    for values in (lo.ravel(), hi.ravel()):
        y0, y1 = values[i0], values[i1]
        with np.errstate(invalid="ignore", divide="ignore"):
            y = (y1 - y0) / (b - a) * (x - a) + y0
        y = np.where(x == a, y0, y)
        arc = np.full((int(piece[:, -1].max(initial=-1)) + 1, g, n_levels), np.nan)
        arc.reshape(-1)[target] = np.where(on_top & (x == b), y1, y)
        out.append(arc)
    return out[0], out[1]


def piece_counts(rho: NDArray[np.float64]) -> NDArray[np.intp]:
    """Number of monotone pieces of each row of ``rho`` (G, n_delta)."""
    return _turns(rho).sum(axis=1) + 1


def _turns(rho: NDArray[np.float64]) -> NDArray[np.bool_]:
    """Where ``rho`` (G, n_delta) turns: a sample between a rise and a fall (flat steps aside)."""
    step = np.sign(np.diff(rho, axis=1))
    turn = np.zeros(rho.shape, dtype=bool)
    turn[:, 1:-1] = step[:, 1:] * step[:, :-1] < 0
    return turn


def count_guess(xp: NDArray[np.float64], x: NDArray[np.float64]) -> NDArray[np.intp]:
    """How many of row ``i``'s ``xp[i]`` lie below each of ``x[i]``, exact or one off if
    ``xp[i]`` is evenly spaced but for its first and last value (as
    :attr:`qsm.physics.workspace.Slices.margin_rho` is), a guess else."""
    n = xp.shape[1]
    second, before_last = xp[:, 1:2], xp[:, -2:-1]
    with np.errstate(invalid="ignore", divide="ignore"):
        guess = 1.0 + np.ceil((x - second) / (before_last - second) * (n - 3))
    return np.clip(np.nan_to_num(guess), 0, n).astype(np.intp)


def count_below(
    xp: NDArray[np.float64],
    x: NDArray[np.float64],
    inclusive: bool,
    start: NDArray[np.intp] | None = None,
) -> NDArray[np.intp]:
    """How many of row ``i``'s ``xp[i]`` (increasing) lie below each of ``x[i]`` (or at it, if
    ``inclusive``): from ``start`` or :func:`count_guess`, walked to the count."""
    n = xp.shape[1]
    c = count_guess(xp, x) if start is None else start.reshape(x.shape)
    base = (np.arange(len(xp)) * n)[:, None]
    flat = xp.ravel()

    def below(j: NDArray[np.intp]) -> NDArray[np.bool_]:
        v = flat[base + j]
        return v <= x if inclusive else v < x

    while True:
        back = (c > 0) & ~below(np.maximum(c - 1, 0))
        ahead = (c < n) & below(np.minimum(c, n - 1))
        if not (back.any() or ahead.any()):
            return c
        c = c - back + ahead


def wrap_about(
    starts: NDArray[np.float64], ends: NDArray[np.float64], centre: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Express arcs relative to ``centre`` on [-pi, pi], splitting an arc that crosses pi.

    Every arc is shorter than 2 pi (theta1's range), so one split suffices: the first halves come
    first, then the second halves, (pi, pi) for an arc that does not cross. Empty arcs become
    zero-length arcs at pi.
    """
    s, e, over, e_over = _wrapped(starts, ends, centre)
    return (
        np.concatenate([s, np.where(over, -np.pi, np.pi)]),
        np.concatenate([e, np.where(over, e_over, np.pi)]),
    )


def wrap_compact(
    starts: NDArray[np.float64], ends: NDArray[np.float64], centre: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """:func:`wrap_about` with only the second halves of the arcs (rows) that cross pi somewhere,
    or one row of (pi, pi) if none does: the same :func:`union_and_margin`, number for number.

    The sorted starts and ends of :func:`wrap_about` end in the (pi, pi) intervals dropped here;
    each contributes a zero gap after the last one's sum, as every level keeps an end at pi (a
    crossing arc's first half, or a (pi, pi) interval).
    """
    s, e, over, e_over = _wrapped(starts, ends, centre)
    crosses = over.reshape(len(over), -1).any(axis=1)
    if not crosses.any():
        tail = np.full((1, *s.shape[1:]), np.pi)
        return np.concatenate([s, tail]), np.concatenate([e, tail])
    over = over[crosses]
    return (
        np.concatenate([s, np.where(over, -np.pi, np.pi)]),
        np.concatenate([e, np.where(over, e_over[crosses], np.pi)]),
    )


def _wrapped(
    starts: NDArray[np.float64], ends: NDArray[np.float64], centre: float
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.bool_], NDArray[np.float64]]:
    """First halves ``[s, e]`` of the arcs relative to ``centre`` (empty ones at pi), whether
    each crosses pi and the end of its second half, ``[-pi, e_over]``."""
    s = starts - centre
    shift = np.floor((s + np.pi) / TWO_PI) * TWO_PI
    s = s - shift
    e = ends - centre - shift
    over = e > np.pi
    e_over = e - TWO_PI
    e = np.minimum(e, np.pi)
    empty = ~np.isfinite(s)
    return np.where(empty, np.pi, s), np.where(empty, np.pi, e), over, e_over


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


def union_length(starts: NDArray[np.float64], ends: NDArray[np.float64]) -> NDArray[np.float64]:
    """Length of the union of closed intervals (axis 0), the first of :func:`union_and_margin`."""
    return _sorted_apart(starts, ends)[3]


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
