"""Per-design reference of Stage 1's slicing and scale search, for the tests of the batched path.

One design at a time, in plain loops: the monotone pieces of rho(delta) each interpolated with
np.interp, the union of a level's arcs by merging them in sorted order, the scale scan and the
bisection with np.interp. It shares the arithmetic of every number with the batched code of
qsm.physics (so the two agree to the bit) but none of its indexing.
"""

from __future__ import annotations

import itertools

import numpy as np

from qsm.physics.containment import radial_misfit


def slices(rho, lo, hi, reference_angle, n_levels):
    """(rho_min, rho_max, levels, covered, margin_rho, margin) of one design's closed arcs."""
    rho_min, rho_max = float(rho.min()), float(rho.max())
    levels = rho_min + (np.arange(n_levels) + 0.5) * (rho_max - rho_min) / n_levels
    margin_rho = np.concatenate([[rho_min], levels, [rho_max]])
    step = np.sign(np.diff(rho))
    turns = np.flatnonzero(step[1:] * step[:-1] < 0) + 1
    bounds = np.concatenate([[0], turns, [rho.size - 1]])
    starts, ends = [], []
    for a, b in itertools.pairwise(bounds):
        r, s, e = rho[a : b + 1], lo[a : b + 1], hi[a : b + 1]
        if r[-1] < r[0]:
            r, s, e = r[::-1], s[::-1], e[::-1]
        inside = (margin_rho >= r[0]) & (margin_rho <= r[-1])
        starts.append(np.where(inside, np.interp(margin_rho, r, s), np.nan))
        ends.append(np.where(inside, np.interp(margin_rho, r, e), np.nan))
    s, e = _wrap_about(np.array(starts), np.array(ends), reference_angle)
    covered, margin = _union_and_margin(s, e)
    return rho_min, rho_max, levels, covered[1:-1], margin_rho, margin


def _wrap_about(starts, ends, centre):
    s = starts - centre
    shift = np.floor((s + np.pi) / (2.0 * np.pi)) * (2.0 * np.pi)
    s = s - shift
    e = ends - centre - shift
    over = e > np.pi
    s2 = np.where(over, -np.pi, np.pi)
    e2 = np.where(over, e - 2.0 * np.pi, np.pi)
    e = np.minimum(e, np.pi)
    empty = ~np.isfinite(s)
    s, e = np.where(empty, np.pi, s), np.where(empty, np.pi, e)
    return np.concatenate([s, s2]), np.concatenate([e, e2])


def _union_and_margin(starts, ends):
    """Per level: the union's length as the hull less the gaps between the sorted starts and
    ends (summed in order), and the margin about 0 from the merged pieces."""
    covered, margin = [], []
    for s, e in zip(starts.T, ends.T, strict=True):
        s_sorted, e_sorted = np.sort(s), np.sort(e)
        gaps = 0.0
        for k in range(len(s) - 1):
            gaps += s_sorted[k + 1] - e_sorted[k] if s_sorted[k + 1] > e_sorted[k] else 0.0
        covered.append(e_sorted[-1] - s_sorted[0] - gaps)
        merged = []
        for a, b in sorted(zip(s, e, strict=True)):
            if merged and a <= merged[-1][1]:
                merged[-1][1] = max(merged[-1][1], b)
            else:
                merged.append([a, b])
        around = [min(b, -a) for a, b in merged if a <= 0.0 <= b]
        margin.append(around[0] if around else -1.0)
    return np.array(covered), np.array(margin)


def minimal_scale(margin_rho, margin, rho_min, rho_max, c, r, scale_max, n_scan=128, tol=1e-9):
    """(scale, feasible, reason): the scan of every scale in order, then the bisection."""
    radial = radial_misfit(rho_min, rho_max, c, r, scale_max)
    if radial:
        return np.nan, False, radial
    radii = c - r * np.cos(np.linspace(0.0, np.pi, 64))
    need = np.arccos(np.clip((radii**2 + c**2 - r**2) / (2.0 * radii * c), -1.0, 1.0))

    def holds(scale):
        have = np.interp(radii / scale, margin_rho, margin, left=-1.0, right=-1.0)
        return np.min(have - need) >= 0.0

    lo = (c + r) / rho_max
    hi_geometry = (c - r) / rho_min
    scan = np.linspace(lo, min(scale_max, hi_geometry), n_scan)
    ok = [holds(s) for s in scan]
    if not any(ok):
        where = "up to scale.max_m " if hi_geometry > scale_max else ""
        return np.nan, False, f"no scale {where}holds the task"
    first = ok.index(True)
    if first == 0:
        return float(lo), True, ""
    a, b = float(scan[first - 1]), float(scan[first])
    while b - a > tol * b:
        mid = 0.5 * (a + b)
        a, b = (a, mid) if holds(mid) else (mid, b)
    return b, True, ""


def fit(rho, lo, hi, settings):
    """The fit dict of one design's arcs, as qsm.mechanisms.scale.fit_design gives it."""
    disk = settings.disk
    radius = disk.radius + settings.safety_margin
    nan = {"scale_m": np.nan, "workspace_area_m2": np.nan, "eta": np.nan}
    if not np.all(np.isfinite(rho)):
        return {"feasible": False, "reason": "loop does not close", **nan, "unit": np.nan}
    radial = radial_misfit(rho.min(), rho.max(), disk.distance, radius, settings.scale_max)
    if radial:
        return {"feasible": False, "reason": radial, **nan, "unit": np.nan}
    rho_min, rho_max, levels, covered, margin_rho, margin = slices(
        rho, lo, hi, disk.angle, settings.resolution.n_levels
    )
    unit = float(np.sum(levels * covered) * (rho_max - rho_min) / levels.size)
    scale, ok, reason = minimal_scale(
        margin_rho, margin, rho_min, rho_max, disk.distance, radius, settings.scale_max,
        settings.n_scan,
    )  # fmt: skip
    if not ok:
        return {"feasible": False, "reason": reason, **nan, "unit": unit}
    area = unit * scale**2
    return {
        "feasible": True,
        "reason": "",
        "scale_m": scale,
        "workspace_area_m2": area,
        "eta": disk.area / area,
        "unit": unit,
    }
