"""g11 (task containment, m) and g12 (printability, mm) against hand-computed cases and
independent references: point membership by inverse kinematics, Stage 1's containment test and
the box check of qsm.embodiment.parts.printing on the link outlines."""

import numpy as np
import pytest
from reference_workspace import reachable

from qsm.embodiment.parts.printing import (
    all_links_fit,
    link_boxes_mm,
    needed_volume_mm,
    outline_boxes_mm,
    printability_violation_mm,
)
from qsm.mechanisms.filters import kinematic_checks
from qsm.mechanisms.scale import FitSettings
from qsm.optimization.constraint_set import ExtraConstraints
from qsm.optimization.constraints import OPEN_LOOP_VIOLATION_M, containment_margin_m
from qsm.optimization.problems import LabelStats, PaperProblem, RatiosProblem, paper_constraints
from qsm.physics.cad import CadSettings
from qsm.physics.containment import containment_margin
from qsm.physics.task import Disk, min_enclosing_circle
from qsm.physics.workspace import OperatingRange, slice_workspace

OP = OperatingRange.from_degrees([45.0, 180.0], -37.5)
DISK = min_enclosing_circle([[-0.53, 0.17], [-0.70, 0.02], [-0.60, 0.02], [-0.70, 0.12]])
CAD = CadSettings()
PRINTER = (600.0, 350.0, 350.0)


def random_designs(n: int, seed: int, scale=(0.2, 0.6)) -> np.ndarray:
    """Designs whose loop closes, ratios in Table 1, random scales (m)."""
    rng = np.random.default_rng(seed)
    lo, hi = np.array([0.18, 0.8, 0.3, 1.0, 0.2]), np.array([0.6, 1.3, 0.6, 1.4, 0.7])
    r = lo + (hi - lo) * rng.random((8 * n, 5))
    r = r[np.logical_and.reduce(list(kinematic_checks(r, OP, 0.0).values()))][:n]
    s = rng.uniform(*scale, len(r))
    return np.column_stack([s, r * s[:, None]])


def test_g12_by_hand():
    # boxes (mm): lower arm 550 x 50, crank 250 x 50, coupler 650 x 50,
    # upper arm (200 + 500 + 50) x (300 + 50); every plate 20 thick
    design = np.array([0.5, 0.2, 0.6, 0.2, 0.5, 0.3])
    boxes = link_boxes_mm(design, None, CAD)[0]
    np.testing.assert_allclose(boxes[:, 0], [550, 250, 650, 750])
    np.testing.assert_allclose(boxes[:, 1], [50, 50, 50, 350])
    np.testing.assert_allclose(boxes[:, 2], 20)
    # sorted printer (350, 350, 600): the upper arm's 750 mm exceeds 600 mm by 150 mm
    assert printability_violation_mm(design, CAD, PRINTER)[0] == pytest.approx(150.0)
    assert printability_violation_mm(design, CAD, (800, 400, 400))[0] == pytest.approx(-50.0)
    np.testing.assert_allclose(needed_volume_mm(design, None, CAD)[0], [750, 350, 20])


def test_g12_section_too_large_for_a_link_is_a_violation():
    tiny_crank = np.array([0.3, 0.02, 0.3, 0.15, 0.36, 0.12])  # bosses need 30 mm of crank
    assert printability_violation_mm(tiny_crank, CAD, PRINTER)[0] == pytest.approx(10.0)
    assert not all_links_fit(tiny_crank, CAD, PRINTER)


def test_g12_agrees_with_the_outline_boxes_of_qsm_printing():
    designs = random_designs(200, 1, scale=(0.25, 0.5))
    ours = link_boxes_mm(designs, None, CAD)
    outlines = np.array([list(outline_boxes_mm(d, CAD).values()) for d in designs])
    np.testing.assert_allclose(ours, outlines, atol=0.05)  # the boss polygons' chord error
    g12 = printability_violation_mm(designs, CAD, PRINTER)
    fits = np.array([all_links_fit(d, CAD, PRINTER) for d in designs])
    clear = np.abs(g12) > 0.05
    assert 20 < fits.sum() < len(fits) - 20  # both cases are exercised
    np.testing.assert_array_equal((g12 <= 0)[clear], fits[clear])


def test_g11_agrees_with_stage_1_containment():
    designs = random_designs(300, 2)
    g = containment_margin_m(designs, OP, DISK)
    stage1 = np.array(
        [
            containment_margin(
                slice_workspace(d[1:] / d[0], OP, DISK.angle), d[0], DISK.distance, DISK.radius
            )[0]
            for d in designs
        ]
    )
    assert 20 < (stage1 >= 0).sum() < len(designs) - 20
    clear = np.abs(g) > 1e-3
    np.testing.assert_array_equal((g >= 0)[clear], (stage1 >= 0)[clear])


def disk_points(disk: Disk, n_rings: int = 6, n_around: int = 90) -> np.ndarray:
    """Points on concentric rings of the disk, its boundary included."""
    rings = [np.array([disk.centre])]
    for k in range(1, n_rings + 1):
        a = np.linspace(0.0, 2 * np.pi, n_around, endpoint=False)
        r = disk.radius * k / n_rings
        rings.append(np.column_stack([r * np.cos(a), r * np.sin(a)]) + disk.centre)
    return np.vstack(rings)


def test_g11_against_inverse_kinematics_point_membership():
    designs = random_designs(120, 3)
    g = containment_margin_m(designs, OP, DISK)
    points = disk_points(DISK)
    held, missed = 0, 0
    for design, margin in zip(designs, g, strict=True):
        inside = reachable(design, points, OP)
        if margin > 2e-3:
            assert inside.all(), (design, margin)
            held += 1
        elif margin < -2e-3:
            assert not inside.all(), (design, margin)
            missed += 1
    assert held >= 5 and missed >= 5


def test_g11_is_continuous_in_the_scale():
    """Refining the scale around the largest step of g11 shrinks the step: no jump (the margin
    rises steeply, like a square root, where the disk leaves a crescent's tip)."""
    for design in random_designs(40, 4)[:3]:
        unit = design / design[0]

        def steps(scales, unit=unit):
            g = containment_margin_m(unit[None, :] * scales[:, None], OP, DISK)
            return np.abs(np.diff(g))

        coarse = np.linspace(0.2, 0.8, 400)
        jumps = steps(coarse)
        i = int(np.argmax(jumps))
        fine = steps(np.linspace(coarse[i], coarse[i + 1], 1000))
        assert jumps[i] > 0.05 and fine.max() < 0.25 * jumps[i]


def test_g11_hand_cases():
    open_loop = np.array([[0.3, 0.2, 0.1, 0.1, 0.36, 0.12]])  # l3 + l4 far shorter than |BC|
    assert containment_margin_m(open_loop, OP, DISK)[0] == -OPEN_LOOP_VIOLATION_M
    round_the_base = Disk((0.0, 0.0), 0.5)
    designs = random_designs(5, 5)
    assert (containment_margin_m(designs, OP, round_the_base) == -OPEN_LOOP_VIOLATION_M).all()


@pytest.fixture
def extra():
    fit = FitSettings(op=OP, disk=DISK, scale_max=2.0)
    return lambda containment, printable: ExtraConstraints(
        containment, printable, fit, CAD, PRINTER, tolerance_m=0.001
    )


class Constant:
    """A stand-in surrogate predicting fixed values."""

    label_mean = np.array([0.1, 40.0, 15.0])
    label_std = np.array([0.05, 10.0, 5.0])

    def predict(self, x):
        return np.tile([0.1, 40.0, 15.0], (len(x), 1))


def test_switches_off_give_the_papers_g1_to_g10_exactly(extra):
    designs = random_designs(30, 6)
    stats = LabelStats(Constant.label_mean, Constant.label_std)
    lo, hi = designs.min(axis=0), designs.max(axis=0)
    off = PaperProblem(Constant(), lo, hi, stats, extra(False, False))
    assert off.n_ieq_constr == 10
    out = {}
    off._evaluate(designs, out)
    np.testing.assert_array_equal(out["G"], paper_constraints(designs, out["F"], stats))
    assert extra(False, False).label("paper") == "g1..g10 (the paper's)"
    on = PaperProblem(Constant(), lo, hi, stats, extra(True, True))
    assert on.n_ieq_constr == 12
    on._evaluate(designs, out)
    g11 = -containment_margin_m(designs, OP, Disk(DISK.centre, DISK.radius + 0.001))
    np.testing.assert_array_equal(out["G"][:, 10], g11)
    np.testing.assert_array_equal(out["G"][:, 11], printability_violation_mm(designs, CAD, PRINTER))
    assert "g11" in extra(True, True).label("paper") and "g12" in extra(True, True).label("paper")
    ratios = RatiosProblem(
        Constant(), lo[1:] / lo[0], hi[1:] / hi[0], stats, None, extra(True, True)
    )
    assert ratios.n_ieq_constr == 11  # the scale holds the task: no g11


def test_disk_touching_the_outer_edge_where_the_edge_does_not_cover_it():
    """The tip of a crescent: Stage 1 once held the outermost level's margin up to rho_max and
    called this disk contained; inverse kinematics finds points of it out of reach."""
    design = np.array([0.348487, 0.141759, 0.374202, 0.167974, 0.358574, 0.155955])
    disk = min_enclosing_circle(
        [[-0.53, 0.17], [-0.70, 0.02], [-0.60, 0.02], [-0.70, 0.12], [-0.60, 0.12]]
    )
    points = disk_points(disk, 12, 360)
    assert not reachable(design, points, OP).all()
    slices = slice_workspace(design[1:] / design[0], OP, disk.angle)
    assert containment_margin(slices, design[0], disk.distance, disk.radius)[0] < 0
    assert containment_margin_m(design, OP, disk)[0] < 0


def test_g11_holds_exactly_when_the_euclidean_clearance_reaches_the_tolerance():
    """g11 <= 0 (the task disk grown by the tolerance is held) against the clearance of
    qsm.physics.clearance (the distance from the disk to the workspace's edge)."""
    from qsm.physics.clearance import disk_clearance_m

    tolerance = 0.02
    fit = FitSettings(op=OP, disk=DISK, scale_max=2.0)
    extra = ExtraConstraints(True, False, fit, CAD, PRINTER, tolerance_m=tolerance)
    designs = random_designs(40, 11)
    g11 = extra.columns("paper", designs)[0]
    checked = 0
    for design, g in zip(designs, g11, strict=True):
        if abs(g) < 2e-3 or g >= OPEN_LOOP_VIOLATION_M:
            continue  # too near the edge for the slicing's resolution, or no closed loop
        clearance = disk_clearance_m(design, OP, DISK)
        assert (g <= 0) == (clearance >= tolerance), (g, clearance)
        checked += 1
    assert checked >= 10


def test_g13_g14_evaluated_only_where_the_cheaper_constraints_hold():
    """g13 / g14 of the designs that meet g1..g12 equal the checks' own values (with the loop's
    allowance); the others read NOT_EVALUATED, and never reach the checks."""
    from qsm.embodiment.drives.drive_checks import DriveCheck
    from qsm.embodiment.strength.link_checks import StrengthCheck
    from qsm.optimization.constraint_set import LOOP_ALLOWANCE, NOT_EVALUATED
    from qsm.physics.duty import DutySettings, duty_cycle

    duty = duty_cycle(DutySettings(samples_per_segment=6))
    strength, drives = StrengthCheck(duty=duty), DriveCheck(duty=duty)
    fit = FitSettings(op=OP, disk=DISK, scale_max=2.0)
    extra = ExtraConstraints(False, True, fit, CAD, PRINTER, strength=strength, drives=drives)
    designs = random_designs(12, 5)
    g = np.zeros((len(designs), 10))
    g[::3, 4] = 0.5  # every third design fails a surrogate bound
    g12, g13, g14 = extra.columns("paper", designs, g)
    todo = (g <= 0).all(1) & (g12 <= 0)
    assert 0 < todo.sum() < len(designs)
    assert np.all(g13[~todo] == NOT_EVALUATED) and np.all(g14[~todo] == NOT_EVALUATED)
    # the links' utilisation with the allowance, the bearings' without (from the full table)
    table = strength.evaluate(designs[todo])
    allow = strength.allowable_stress_pa / 1e6
    links = np.max(
        [
            np.maximum(
                table[f"stress_peak_{k}_MPa"] / allow,
                strength.strength.buckling_safety_factor / table[f"buckling_factor_{k}"],
            )
            for k in ("lower_arm", "crank", "coupler", "upper_arm")
        ],
        axis=0,
    )
    expected13 = np.maximum(links * (1 + LOOP_ALLOWANCE), table["bearing_utilisation"]) - 1
    assert g13[todo] == pytest.approx(expected13, rel=1e-12)
    assert g14[todo] == pytest.approx(drives.violation(designs[todo]) + LOOP_ALLOWANCE, rel=1e-12)
