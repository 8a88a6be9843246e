"""Workspace area and task containment against an independent inverse-kinematics reference."""

import numpy as np
import pytest
from reference_workspace import pixel_area, reachable

from qsm.physics.containment import (
    _interp_rows,
    containment_margin,
    minimal_scale,
    minimal_scales,
    radial_misfit,
)
from qsm.physics.kinematics import design_from_ratios, end_effector, loop_closes_everywhere
from qsm.physics.task import Disk
from qsm.physics.workspace import (
    OperatingRange,
    Resolution,
    SliceStack,
    operating_reach,
    slice_workspace,
    union_and_margin,
    unit_areas,
)

pytestmark = pytest.mark.filterwarnings("ignore:invalid value encountered:RuntimeWarning")

OP = OperatingRange.from_degrees([45.0, 180.0], -37.5)
DISK = Disk((-0.72, 0.11), 0.1345)


def feasible_ratios(seed, n):
    rng = np.random.default_rng(seed)
    out = []
    while len(out) < n:
        r = np.array(
            [
                rng.uniform(0.18, 0.6),
                rng.uniform(0.8, 1.3),
                rng.uniform(0.3, 0.6),
                rng.uniform(1.0, 1.4),
                rng.uniform(0.2, 0.7),
            ]
        )
        if r[1] + r[0] < 1 + r[2] and loop_closes_everywhere(r, OP.delta_max):
            out.append(r)
    return out


@pytest.mark.parametrize("ratios", feasible_ratios(11, 4))
def test_area_matches_pixel_count_of_reachable_points(ratios):
    reference = pixel_area(design_from_ratios(ratios), OP, n=700)
    area = slice_workspace(ratios, OP).area
    assert area == pytest.approx(reference, rel=5e-3)  # the bound; seen: 2e-4


def test_area_converges_with_resolution():
    ratios = feasible_ratios(12, 1)[0]
    fine = slice_workspace(ratios, OP, resolution=Resolution(2881, 2400)).area
    coarse = slice_workspace(ratios, OP, resolution=Resolution(181, 150)).area
    default = slice_workspace(ratios, OP).area
    assert abs(default - fine) < abs(coarse - fine) + 1e-12
    assert default == pytest.approx(fine, rel=1e-3)


def test_area_handles_folds_a_wrapped_operating_range():
    """A wide theta1 range makes arcs overlap themselves: the union, not the sum, counts."""
    ratios = feasible_ratios(13, 1)[0]
    wide = OperatingRange.from_degrees([-170.0, 185.0], -37.5)
    if not loop_closes_everywhere(ratios, wide.delta_max):
        pytest.skip("loop does not close on the wide range")
    area = slice_workspace(ratios, wide).area
    reference = pixel_area(design_from_ratios(ratios), wide, n=700)
    assert area == pytest.approx(reference, rel=5e-3)


def disk_points(disk: Disk, n_rings: int = 12, n_around: int = 72) -> np.ndarray:
    rings = np.linspace(0.0, disk.radius, n_rings)
    ang = np.linspace(0.0, 2 * np.pi, n_around, endpoint=False)
    pts = [
        np.asarray(disk.centre)[None] + r * np.column_stack([np.cos(ang), np.sin(ang)])
        for r in rings
    ]
    return np.concatenate(pts)


@pytest.mark.parametrize("ratios", feasible_ratios(21, 6))
def test_minimal_scale_contains_the_task_and_nothing_smaller_does(ratios):
    slices = slice_workspace(ratios, OP, DISK.angle)
    fit = minimal_scale(slices, DISK.distance, DISK.radius, scale_max=2.0)
    if not fit.feasible:
        # no scale: the reference must find the disk uncovered on a scan of scales as well
        for s in np.linspace(0.2, 2.0, 40):
            assert not reachable(design_from_ratios(ratios, s), disk_points(DISK), OP).all()
        return
    pts = disk_points(DISK)
    inside = reachable(design_from_ratios(ratios, fit.scale * (1 + 2e-3)), pts, OP)
    assert inside.mean() > 0.999  # contained, up to the discretisation at the boundary
    for shrink in (1e-2, 3e-2, 1e-1, 0.3):
        below = reachable(design_from_ratios(ratios, fit.scale * (1 - shrink)), pts, OP)
        assert not below.all()


def test_minimal_scale_is_the_first_contained_scale_of_a_fine_scan():
    for ratios in feasible_ratios(22, 5):
        slices = slice_workspace(ratios, OP, DISK.angle)
        fit = minimal_scale(slices, DISK.distance, DISK.radius, scale_max=2.0)
        scan = np.linspace(0.05, 2.0, 5000)
        ok = containment_margin(slices, scan, DISK.distance, DISK.radius) >= 0
        if not fit.feasible:
            assert not ok.any()
            continue
        assert scan[ok][0] >= fit.scale - 1e-9
        assert containment_margin(slices, fit.scale, DISK.distance, DISK.radius)[0] >= 0


def test_interp_rows_is_np_interp():
    """Against ``np.interp``, a second path (C, which a compiler may fuse into a multiply-add):
    to a few ulps of the values interpolated (``fp`` crosses zero, so the tolerance is absolute:
    8 ulps of the largest |fp|)."""
    rng = np.random.default_rng(5)
    xp = np.sort(rng.uniform(0.2, 3.0, (40, 50)), axis=1)
    xp[:10] = np.linspace(0.3, 2.0, 50) * rng.uniform(0.5, 2.0, (10, 1))  # evenly spaced
    fp = rng.normal(size=xp.shape)
    x = rng.uniform(0.0, 3.5, (40, 30))
    x[:, :3] = xp[:, [0, 17, -1]]  # on the nodes and the ends
    got = _interp_rows(x, xp, fp, -1.0)
    ref = np.stack([np.interp(x[i], xp[i], fp[i], left=-1.0, right=-1.0) for i in range(40)])
    np.testing.assert_allclose(got, ref, rtol=0, atol=8 * np.finfo(float).eps * np.abs(fp).max())


def test_batched_scale_search_matches_one_design_at_a_time():
    designs = feasible_ratios(23, 6)
    slices = [slice_workspace(r, OP, DISK.angle) for r in designs]
    together = minimal_scales(SliceStack.of(slices), DISK.distance, DISK.radius, 2.0)
    for sl, fit in zip(slices, together, strict=True):
        assert fit == minimal_scale(sl, DISK.distance, DISK.radius, 2.0)
        if fit.feasible:  # the smallest scale that holds the disk, to the bisection's tolerance
            assert containment_margin(sl, fit.scale, DISK.distance, DISK.radius)[0] >= 0
            below = fit.scale * (1 - 2e-9)
            assert containment_margin(sl, below, DISK.distance, DISK.radius)[0] < 0


def test_containment_is_not_monotone_in_scale():
    """Growing the scale can push the disk out through the crescent's inner edge."""
    ratios = feasible_ratios(23, 1)[0]
    slices = slice_workspace(ratios, OP, DISK.angle)
    fit = minimal_scale(slices, DISK.distance, DISK.radius, scale_max=5.0)
    assert fit.feasible
    big = containment_margin(slices, 3.0 * fit.scale, DISK.distance, DISK.radius)[0]
    assert big < 0


def test_infeasible_reasons():
    ratios = feasible_ratios(24, 1)[0]
    slices = slice_workspace(ratios, OP, DISK.angle)
    assert minimal_scale(slices, 0.1, 0.2, 2.0).reason == "task disk covers the base"
    low = minimal_scale(slices, DISK.distance, DISK.radius, scale_max=0.01)
    assert not low.feasible and low.reason.startswith("scale.max_m below")
    with pytest.raises(ValueError, match="does not close"):
        slice_workspace([0.6, 0.3, 0.3, 1.2, 0.4], OP)


def test_union_and_margin_of_hand_made_arcs():
    """Arcs from different branches can overlap: the union and the centred margin chain them."""
    from qsm.physics.workspace import margin_about_zero

    # per level (column): intervals (rows) [start, end]
    starts = np.array([[-0.3, -0.3, 0.2, -1.0], [0.05, 0.5, 0.3, -0.5], [0.35, 0.6, 0.4, 0.9]])
    ends = np.array([[0.1, 0.1, 0.25, -0.6], [0.4, 0.7, 0.5, 0.7], [0.9, 0.8, 0.45, 1.2]])
    np.testing.assert_allclose(union_and_margin(starts, ends)[0], [1.2, 0.7, 0.25, 1.9])
    # level 0: [-0.3, 0.1] + [0.05, 0.4] + [0.35, 0.9] chain to [-0.3, 0.9] -> margin 0.3
    # level 1: [-0.3, 0.1] then a gap -> margin 0.1; level 2: 0 not covered -> -1
    # level 3: [-0.5, 0.7] holds 0 -> margin 0.5
    np.testing.assert_allclose(margin_about_zero(starts, ends), [0.3, 0.1, -1.0, 0.5])


def _chained_union_and_margin(starts, ends):
    """Reference: per level, merge the closed intervals one by one in a Python loop."""
    covered, margin = [], []
    for s, e in zip(starts.T, ends.T, strict=True):
        merged = []
        for a, b in sorted(zip(s, e, strict=True)):
            if merged and a <= merged[-1][1]:
                merged[-1][1] = max(merged[-1][1], b)
            else:
                merged.append([a, b])
        covered.append(sum(b - a for a, b in merged))
        around = [min(b, -a) for a, b in merged if a <= 0.0 <= b]
        margin.append(around[0] if around else -1.0)
    return np.array(covered), np.array(margin)


def test_union_and_margin_match_a_merge_loop():
    """Random arcs with shared ends, nesting and touching pieces, as the slicing produces."""
    rng = np.random.default_rng(4)
    grid = np.linspace(-3.0, 3.0, 25)  # coarse grid: many exactly touching ends
    for n in (1, 2, 5, 9):
        a = rng.choice(grid, size=(n, 400))
        b = a + rng.choice(grid[12:], size=(n, 400))
        covered, margin = union_and_margin(a, b)
        ref_covered, ref_margin = _chained_union_and_margin(a, b)
        np.testing.assert_allclose(covered, ref_covered, rtol=0, atol=1e-12)
        np.testing.assert_array_equal(margin, ref_margin)
        assert (margin == -1.0).any() and (margin > 0.0).any()


def test_unit_area_is_the_slices_area_and_radial_misfit_agrees_with_the_scan():
    """The area without margins is the same number (to rounding: the two sum the union's pieces
    in different orders); a design the radii alone rule out is one that the full scan also
    rejects, for the same reason."""
    rejected = 0
    for ratios in feasible_ratios(11, 30):
        slices = slice_workspace(ratios, OP, DISK.angle)
        assert unit_areas(ratios, OP)[0] == pytest.approx(slices.area, rel=1e-13)
        for radius in (0.05, DISK.radius, 0.3):
            why = radial_misfit(slices.rho_min, slices.rho_max, DISK.distance, radius, 2.0)
            fit = minimal_scale(slices, DISK.distance, radius, 2.0)
            if why:
                rejected += 1
                assert not fit.feasible and fit.reason == why
    assert rejected > 0


def test_the_operating_reach_is_the_farthest_tool_point_over_the_motors_angle_grid():
    """The reach over the operating range (a scan of delta alone, since |AE| depends on nothing
    else) against a 2-D grid of both motors' angles within their limits (theta2 <= theta1): the
    same within the grid's resolution, and never past the arm in line, l1 + |BE|."""
    design = np.array([0.5, 0.15, 0.55, 0.22, 0.6, 0.2])
    reach = operating_reach(design, (45.0, 180.0), -37.5)
    t1, t2 = np.meshgrid(
        np.radians(np.linspace(45, 180, 601)), np.radians(np.linspace(-37.5, 180, 601))
    )
    inside = t2 <= t1
    grid = np.nanmax(np.hypot(*end_effector(design, t1[inside], t2[inside]).T))
    assert reach.reach_m == pytest.approx(grid, abs=2e-4)
    assert reach.reach_m >= grid - 1e-9
    assert reach.in_line_m == pytest.approx(0.5 + np.hypot(0.6, 0.2))
    assert reach.reach_m <= reach.in_line_m + 1e-12
    narrow = operating_reach(design, (45.0, 90.0), 60.0)  # delta at most 30 degrees
    assert narrow.delta_rad <= np.radians(30.0) + 1e-12 and narrow.reach_m <= reach.reach_m
