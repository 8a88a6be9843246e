"""The batched slicing and scale search give each design the numbers of a per-design reference
(tests/reference_slicing.py), degenerate designs included.

The reference is a second code path (Python loops and ``np.interp`` where the batch uses its own
vectorised interpolation), so floats are compared to a relative tolerance: RTOL (1e-12) is about
4,500 ulps, room for the few roundings on the way that a compiler or a NumPy build may order
differently (a fused multiply-add in ``np.interp``), and 1e9 times below a slice's resolution.
Decisions (covered levels, feasible, the reason) stay exact; one design alone is the batch's
own path, so it is compared bit for bit."""

import numpy as np
import pytest
import reference_slicing as ref

from qsm.mechanisms.scale import FitSettings, _fit_arcs
from qsm.physics.task import Disk
from qsm.physics.workspace import (
    OperatingRange,
    Resolution,
    arcs,
    slice_stack,
    slices_of_arcs,
    unit_areas,
)

pytestmark = pytest.mark.filterwarnings("ignore:invalid value encountered:RuntimeWarning")

OP = OperatingRange.from_degrees([45.0, 180.0], -37.5)
WIDE = OperatingRange.from_degrees([-170.0, 185.0], -37.5)  # folded, overlapping arcs
RES = Resolution(241, 150)
RTOL = 1e-12
#: The scale search bisects to a relative 1e-9: a comparison that one rounding flips moves the
#: scale within that band, and an area with the scale squared (eta with it) within twice it.
SCALE_RTOL = 1e-8
LOW = np.array([0.18, 0.8, 0.3, 1.0, 0.2])
HIGH = np.array([0.6, 1.3, 0.6, 1.4, 0.7])


def random_ratios(seed: int, n: int) -> np.ndarray:
    """Ratios about the sampling bounds, some outside (loops that do not close)."""
    rng = np.random.default_rng(seed)
    return rng.uniform(LOW - 0.2 * (HIGH - LOW), HIGH + 0.2 * (HIGH - LOW), (n, 5))


def closed_arcs(op: OperatingRange, seed: int, n: int):
    rho, lo, hi = arcs(random_ratios(seed, 4 * n), op, RES.n_delta)
    keep = np.flatnonzero(np.isfinite(rho).all(axis=1))[:n]
    return rho[keep], lo[keep], hi[keep]


@pytest.mark.parametrize(("op", "angle"), [(OP, 2.98), (WIDE, -0.4), (OP, np.pi)])
def test_stack_is_the_per_design_slicing(op, angle):
    rho, lo, hi = closed_arcs(op, 1, 40)
    stack = slice_stack(rho, lo, hi, angle, RES.n_levels)
    pieces = set()
    for k in range(len(rho)):
        want = ref.slices(rho[k], lo[k], hi[k], angle, RES.n_levels)
        got = stack.row(k)
        alone = slices_of_arcs(rho[k], lo[k], hi[k], angle, RES.n_levels)
        for name, value in zip(
            ["rho_min", "rho_max", "rho", "covered", "margin_rho", "margin"], want, strict=True
        ):
            if name == "covered":
                assert np.array_equal(getattr(got, name), value), name
            else:
                np.testing.assert_allclose(getattr(got, name), value, RTOL, 1e-15, err_msg=name)
            assert np.array_equal(getattr(alone, name), getattr(got, name)), name
        area = float(np.sum(want[2] * want[3]) * (want[1] - want[0]) / RES.n_levels)
        assert got.area == pytest.approx(area, rel=RTOL)
        step = np.sign(np.diff(rho[k]))
        pieces.add(int((step[1:] * step[:-1] < 0).sum()) + 1)
    assert len(pieces) > 1  # designs with different numbers of monotone pieces in one stack


TASKS = [  # (centre, radius, scale_max, safety margin), m
    ((-0.615, 0.095), 0.113, 2.0, 0.0),  # the default task
    ((-1.5, 0.45), 0.12, 2.0, 0.0),  # far out
    ((-1.5, 0.45), 0.12, 0.5, 0.0),  # far out, beyond scale.max_m
    ((-0.6, -0.3), 0.1, 2.0, 0.02),  # below the base
    ((-0.6, -0.3), 0.1, 0.4, 0.0),  # below the base, scale.max_m cuts in
    ((-0.1, 0.05), 0.2, 2.0, 0.0),  # disk covers the base
]


def test_fits_are_the_per_design_fits():
    rho, lo, hi = arcs(random_ratios(2, 150), OP, RES.n_delta)
    reasons = set()
    for centre, radius, scale_max, margin in TASKS:
        settings = FitSettings(OP, Disk(centre, radius), scale_max, margin, RES)
        for k, fit in enumerate(_fit_arcs(rho, lo, hi, settings)):
            want = ref.fit(rho[k], lo[k], hi[k], settings)
            assert fit["feasible"] == want["feasible"] and fit["reason"] == want["reason"]
            for name in ("scale_m", "workspace_area_m2", "eta"):
                np.testing.assert_allclose(fit[name], want[name], SCALE_RTOL, err_msg=name)
            np.testing.assert_allclose(fit["workspace_area_unit"], want["unit"], RTOL)
            reasons.add(fit["reason"])
    assert {  # every way to fail occurs, so every path was compared
        "",
        "loop does not close",
        "task disk covers the base",
        "workspace too thin for the task disk",
        "no scale holds the task",
        "no scale up to scale.max_m holds the task",
        "scale.max_m below the smallest scale that could hold the task",
    } <= reasons


def test_unit_areas_are_the_per_design_areas():
    ratios = random_ratios(3, 60)
    got = unit_areas(ratios, OP, RES)
    rho, lo, hi = arcs(ratios, OP, RES.n_delta)
    for k in range(len(ratios)):
        if not np.isfinite(rho[k]).all():
            assert np.isnan(got[k])
            continue
        r_min, r_max, levels, covered, *_ = ref.slices(rho[k], lo[k], hi[k], 0.0, RES.n_levels)
        area = float(np.sum(levels * covered) * (r_max - r_min) / RES.n_levels)
        assert got[k] == pytest.approx(area, rel=RTOL)
    assert np.isnan(got).any() and np.isfinite(got).any()
