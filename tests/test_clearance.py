"""True clearance of the task disk, against an independent polygon distance (issue 22's task)."""

from __future__ import annotations

import numpy as np
import pytest
import shapely

from qsm.optimization.constraints import containment_margin_m
from qsm.physics.clearance import disk_clearance_m, disk_clearances_m
from qsm.physics.kinematics import design_from_ratios, pose
from qsm.physics.task import Disk, min_enclosing_circle
from qsm.physics.workspace import OperatingRange

OP = OperatingRange.from_degrees([45.0, 180.0], -37.5)
#: Issue 22: two points 5 mm apart near (-0.45, 0.05) m.
TASK = min_enclosing_circle([[-0.4525, 0.05], [-0.4475, 0.05]])
#: Ratios (l2, l3, l4, EE_x, EE_y) within Table 1's bounds, crank-rocker, and the smallest scale
#: (m) at which Stage 1's slicing holds the task (found by a seeded search over the bounds).
DESIGNS = [
    ([0.394, 1.0554, 0.5259, 1.0592, 0.6098], 0.20533),
    ([0.2143, 1.2276, 0.5584, 1.3506, 0.436], 0.21763),
    ([0.2951, 0.8035, 0.4937, 1.288, 0.6178], 0.18747),
]


def independent_clearance_m(design, op, disk, n1=700, n2=1200, radius=0.02) -> float:
    """Disk clearance from the union of the images of a fine (theta1, theta2) triangulation,
    kept where it comes within ``radius`` of the disk's centre (shares only the forward
    kinematics with qsm.physics.clearance): shapely distance from the centre to that polygon's
    boundary, minus the disk radius (negative outside)."""
    t1 = np.linspace(op.theta1_min, op.theta1_max, n1)
    u = np.linspace(0.0, 1.0, n2)  # theta2 from theta2_min up to theta1
    g1, gu = np.meshgrid(t1, u, indexing="ij")
    e = pose(design, g1, op.theta2_min + gu * (g1 - op.theta2_min)).E
    c = np.asarray(disk.centre)
    near = np.hypot(*(e - c).transpose(2, 0, 1)) < radius
    cell = near[:-1, :-1] | near[1:, :-1] | near[:-1, 1:] | near[1:, 1:]
    i, j = np.nonzero(cell)
    quad = np.stack([e[i, j], e[i + 1, j], e[i + 1, j + 1], e[i, j + 1]], axis=1)
    tri = shapely.polygons(np.concatenate([quad[:, [0, 1, 2]], quad[:, [0, 2, 3]]]))
    region = shapely.union_all(tri[shapely.area(tri) > 0])
    p = shapely.Point(c)
    if region.covers(p):
        dist = region.boundary.distance(p)
        assert dist < 0.9 * radius  # else the kept cells would not decide it
        return dist - disk.radius
    return -region.distance(p) - disk.radius


@pytest.mark.parametrize("ratios, scale", DESIGNS)
def test_clearance_matches_an_independent_polygon_distance(ratios, scale) -> None:
    for k in (0.999, 1.0, 1.004):  # not contained, just contained, 1.5 mm of room
        design = design_from_ratios(ratios, scale * k)
        ours = disk_clearance_m(design, OP, TASK)
        ref = independent_clearance_m(design, OP, TASK)
        assert ours == pytest.approx(ref, abs=1e-4), (k, ours, ref)
        assert abs(ours) < 0.003  # within millimetres of the edge: a real test of the distance


def test_clearance_to_the_outer_circle_by_hand() -> None:
    """A disk 10 mm inside the outermost arc of the workspace: the nearest edge is that circle."""
    ratios = np.array(DESIGNS[0][0])
    design = design_from_ratios(ratios, 0.5)
    # outermost radius and the arc it spans: forward kinematics on a fine grid of delta
    delta = np.linspace(0.0, OP.delta_max, 200001)
    e = pose(design, OP.theta1_max, OP.theta1_max - delta).E
    k = int(np.argmax(np.hypot(*e.T)))
    rho_max = float(np.hypot(*e[k]))
    hi = np.arctan2(e[k, 1], e[k, 0])  # the arc of delta_k ends at theta1_max...
    lo_e = pose(design, OP.theta1_lower(delta[k]), OP.theta1_lower(delta[k]) - delta[k]).E
    lo = np.arctan2(lo_e[1], lo_e[0])  # ... and starts at theta1's lower limit
    a = np.angle(np.exp(1j * lo) + np.exp(1j * hi))  # the arc's middle
    r = 0.003
    centre = (rho_max - 0.010 - r) * np.array([np.cos(a), np.sin(a)])
    disk = Disk((float(centre[0]), float(centre[1])), r)
    assert disk_clearance_m(design, OP, disk) == pytest.approx(0.010, abs=1e-6)


def test_arc_length_margin_is_an_upper_bound_not_a_lower_one() -> None:
    designs = np.array(
        [design_from_ratios(r, s * k) for r, s in DESIGNS for k in (1.0, 1.002, 1.01)]
    )
    clear = disk_clearances_m(designs, OP, TASK)
    arc = containment_margin_m(designs, OP, TASK)
    assert (clear > 0).all() and (arc > 0).all()  # the same verdict: contained
    assert (arc >= clear - 1e-6).all()
    assert (arc - clear).max() > 2e-3  # and the arc overstates the room by millimetres


def test_open_loop_gives_nan() -> None:
    bad = design_from_ratios([0.6, 0.8, 0.3, 1.2, 0.5], 0.3)  # |l3 - l4| > |BC| somewhere
    assert np.isnan(disk_clearances_m(bad[None], OP, TASK)[0])


def test_a_workspace_whose_plane_image_folds_is_measured() -> None:
    """A Pareto design of a near task (0.3-0.38 m out, mirrored): mapping its polar patches to
    the plane folded a boundary onto itself, and the union raised a GEOS TopologyException that
    stopped the run's verification. The repaired union gives the independent distance."""
    design = np.array(
        [0.21116364141951685, 0.06988274639547845, 0.19874110995210706,
         0.08672125113334025, 0.19099306085604623, 0.06942155190278095]
    )  # fmt: skip
    disk = Disk((-0.34, 0.05), 0.04)
    ours = disk_clearance_m(design, OP, disk)
    ref = independent_clearance_m(design, OP, disk, radius=0.1)
    assert ours == pytest.approx(ref, abs=1e-4)
    assert ours > 0.02  # some 31 mm of room, within the reference's 0.1 m window
