"""The choice of the design to realise on any task: fallbacks, the not-printable verdict and the
advice's numbers, checked by hand and against the box check."""

import numpy as np
import pandas as pd
import pytest

from qsm.dataset.columns import DRIVE_COLUMNS, STRENGTH_COLUMNS
from qsm.embodiment.parts.printing import advice_sentence, box_excess_mm, smallest_build_volume
from qsm.optimization.ranking import rule_scores
from qsm.physics.cad import CadSettings
from qsm.physics.kinematics import DESIGN_COLUMNS
from qsm.physics.task import Disk
from qsm.realization.selection.choice import (
    HowChosen,
    NoFeasibleDesign,
    advice_sentences,
    choose_design,
    printer_fix,
    printing_advice,
)
from qsm.report.selection_record import _printing_failure

CAD = CadSettings()
PRINTER = (600.0, 350.0, 350.0)
SMALL = [0.30, 0.10, 0.30, 0.15, 0.36, 0.12]  # upper arm 560 mm long: fits
LARGE = [0.40, 0.12, 0.40, 0.20, 0.48, 0.16]  # upper arm 730 mm long: does not fit


def strong(table, utilization, drives=True):
    """Strength and drive columns: every one NaN but the utilisation and whether it is at most
    1, and whether each motor has a drive."""
    for column in [*STRENGTH_COLUMNS, *DRIVE_COLUMNS]:
        table[column] = np.nan
    table["strength_utilisation"] = utilization
    table["holds_loads"] = table["strength_utilisation"] <= 1.0
    table["has_drives"] = drives
    return table


def front(designs, feasible, tau1, utilization=0.5, drives=True):
    table = pd.DataFrame(designs, columns=list(DESIGN_COLUMNS))
    table["scale_m"] = table["l1_m"]
    table["eta_true"] = 0.1
    table["tau1_true_Nm"] = tau1
    table["tau2_true_Nm"] = 10.0
    table["feasible"] = feasible
    table["dynamics_status"] = "ok"
    return strong(table, utilization, drives)


def dataset(designs, tau1, utilization=0.5):
    table = pd.DataFrame(designs, columns=list(DESIGN_COLUMNS))
    table["mechanism_id"] = np.arange(len(table))
    table["scale_m"] = table["l1_m"]
    table["eta"], table["tau1_Nm"], table["tau2_Nm"], table["status"] = 0.1, tau1, 10.0, "ok"
    return strong(table, utilization)


def test_primary_front_first():
    fronts = {"ratios": front([SMALL, LARGE], True, [50.0, 40.0]), "paper": front([SMALL], True, 1)}
    row, how = choose_design(fronts, "ratios", dataset([SMALL], 1.0), "min_tau1", CAD, PRINTER)
    assert how == HowChosen("ratios", True, True, True, ())
    assert row["tau1_true_Nm"] == 50.0  # the larger design has less torque but does not fit


def test_a_front_whose_infeasible_designs_were_never_checked_is_read():
    """An infeasible design's strength was never checked (holds_loads missing, pandas' NA): the
    choice reads holds_loads on the feasible designs alone, as it filtered them before."""
    table = front([LARGE, SMALL], [False, True], [40.0, 50.0])
    table["holds_loads"] = pd.array([pd.NA, True], dtype="boolean")
    row, how = choose_design({"ratios": table}, "ratios", dataset([SMALL], 70.0), "min_tau1", CAD,
                             PRINTER)  # fmt: skip
    assert how.source == "ratios" and row["tau1_true_Nm"] == 50.0


def test_falls_back_to_the_other_front_then_the_dataset():
    fronts = {"ratios": front([SMALL], False, 5.0), "paper": front([LARGE], True, 5.0)}
    row, how = choose_design(fronts, "ratios", dataset([SMALL], 70.0), "knee", CAD, PRINTER)
    assert how.source == "dataset" and how.printable
    assert how.fallback[0].startswith("ratios front: 1 designs, 0 truly feasible")
    assert how.fallback[1].startswith(
        "paper front: 1 designs, 1 truly feasible, 1 of them hold their loads, 1 of those have "
        "drives, 0 of those printable"
    )
    assert row["tau1_true_Nm"] == 70.0


def test_a_front_without_drives_counts_its_printable_designs_truly():
    """No design has drives: the fallback line counts the printable ones among those that hold
    their loads (one of the two fits), not "0 of those printable"."""
    fronts = {"ratios": front([SMALL, LARGE], True, 5.0, drives=False)}
    data = strong(dataset([SMALL], 5.0), 0.5, drives=False)
    row, how = choose_design(fronts, "ratios", data, "knee", CAD, PRINTER)
    assert how.source == "ratios" and how.printable and not how.has_drives
    assert list(row[list(DESIGN_COLUMNS)]) == SMALL
    assert how.fallback[0] == (
        "ratios front: 2 designs, 2 truly feasible, 2 of them hold their loads, 0 of those have "
        "drives (1 of the 2 that hold their loads printable on 600 x 350 x 350 mm)"
    )


def test_nothing_printable_gives_the_best_feasible_design_marked():
    fronts = {"ratios": front([LARGE, LARGE], True, [30.0, 20.0])}
    row, how = choose_design(fronts, "ratios", dataset([LARGE], 1.0), "min_tau1", CAD, PRINTER)
    assert how.source == "ratios" and not how.printable and len(how.fallback) == 2
    assert row["tau1_true_Nm"] == 20.0


def test_strength_comes_before_printability():
    """A printable design that breaks loses to a strong one that needs a larger printer."""
    fronts = {"ratios": front([SMALL, LARGE], True, [5.0, 50.0], utilization=[1.2, 0.9])}
    row, how = choose_design(fronts, "ratios", dataset([SMALL], 1.0, 1.5), "knee", CAD, PRINTER)
    assert how.holds_loads and not how.printable
    assert row["tau1_true_Nm"] == 50.0


def test_drives_come_after_strength_and_before_printability():
    """A printable strong design without drives loses to a strong one with drives that needs a
    larger printer; a design that breaks loses to both."""
    fronts = {
        "ratios": front(
            [SMALL, LARGE, SMALL], True, [5.0, 50.0, 7.0], [0.5, 0.5, 1.2], [False, True, True]
        )
    }
    row, how = choose_design(fronts, "ratios", dataset([SMALL], 1.0, 1.5), "knee", CAD, PRINTER)
    assert how.holds_loads and how.has_drives and not how.printable
    assert row["tau1_true_Nm"] == 50.0
    # no strong design has drives: the strong printable one, marked without drives
    fronts["ratios"]["has_drives"] = [False, False, True]
    row, how = choose_design(fronts, "ratios", dataset([SMALL], 1.0, 1.5), "knee", CAD, PRINTER)
    assert how.holds_loads and not how.has_drives and how.printable
    assert row["tau1_true_Nm"] == 5.0
    assert any("has a drive in the catalogue for each motor" in line for line in how.fallback)


def test_nothing_strong_gives_the_least_utilized_design_marked():
    fronts = {"ratios": front([SMALL, SMALL], True, [5.0, 50.0], utilization=[1.3, 1.1])}
    row, how = choose_design(fronts, "ratios", dataset([SMALL], 1.0, 2.0), "knee", CAD, PRINTER)
    assert how == HowChosen("ratios", True, False, True, how.fallback)
    assert row["strength_utilisation"] == 1.1
    assert (
        how.fallback[-1] == "no truly feasible design of the fronts or the dataset holds its loads"
    )


def test_nothing_feasible_anywhere_raises():
    fronts = {"ratios": front([SMALL], False, 5.0)}
    with pytest.raises(NoFeasibleDesign, match="ratios front: 1 designs, 0 truly feasible"):
        choose_design(fronts, "ratios", dataset([], 1.0).iloc[:0], "knee", CAD, PRINTER)


def test_advice_by_hand():
    # the upper arm is the longest part: l4 + ee_x + 2 r = 200 + 480 + 50 = 730 mm
    disk = Disk((-0.9, 0.1), 0.2)
    advice = printing_advice(np.array(LARGE), CAD, PRINTER, disk)
    np.testing.assert_allclose(advice["needed_volume_mm"], [730, 210, 20])
    k = (600 - 50) / (730 - 50)  # the bosses do not scale
    assert advice["scale_factor"] == pytest.approx(k, rel=1e-9)
    assert advice["scaled_task_distance_m"] == pytest.approx(k * disk.distance)
    assert box_excess_mm(np.array(LARGE) * k * 1.001, CAD, PRINTER)[0] > 0
    assert advice["max_boss_radius_mm"] is None  # 730 - 50 = 680 mm of bare link > 600 mm
    text = " ".join(advice_sentences(advice, CAD))
    assert "at least 730 x 210 x 20 mm" in text and f"scaled by {k:.3f}" in text


def test_advice_finds_the_boss_radius_that_fits():
    # SMALL's upper arm is 150 + 360 = 510 mm between its outer joints: on a 555 mm printer
    # bosses of radius up to (555 - 510) / 2 = 22.5 mm let it fit (it has 25 mm)
    advice = printing_advice(np.array(SMALL), CAD, (555.0, 350.0, 350.0), Disk((-0.6, 0), 0.1))
    assert advice["max_boss_radius_mm"] == pytest.approx(22.5, abs=0.03)


def test_advice_at_the_realised_sections_by_hand():
    """The advice holds each link's section as realised: the upper arm's scaled by 1.2 has
    bosses of 30 mm and a 24 mm plate."""
    scale = [1.0, 1.0, 1.0, 1.2]
    disk = Disk((-0.9, 0.1), 0.2)
    advice = printing_advice(np.array(LARGE), CAD, PRINTER, disk, scale)
    # l4 + EE_x + 2 x 30 = 740 mm by (30 + 160 + 30) mm, 24 mm thick
    np.testing.assert_allclose(advice["needed_volume_mm"], [740, 220, 24])
    # the lengths scale, the 60 mm of bosses do not: 680 k + 60 = 600
    assert advice["scale_factor"] == pytest.approx(540 / 680, rel=1e-9)
    # on a 735 mm printer: 680 + 2 x 1.2 r = 735 at r = 22.92 mm (25 mm at scale 1 would fit)
    wide = printing_advice(np.array(LARGE), CAD, (735.0, 350.0, 350.0), disk, scale)
    assert wide["max_boss_radius_mm"] == pytest.approx(55 / 2.4, abs=1e-6)
    assert printing_advice(np.array(LARGE), CAD, (735.0, 350.0, 350.0), disk)[
        "max_boss_radius_mm"
    ] == pytest.approx(25.0)


def test_the_scaled_design_still_holds_its_bosses():
    """SMALL's upper arm is 150 + 360 + 2 x 25 mm long: on a 260 mm printer it fits at
    k = 210 / 510. On a 230 mm one the box alone would fit at 180 / 510 = 0.353, but its leg
    EE_y (120 k mm) must exceed a boss overlap, half a width and the fillet, 15 + 20 + 10 mm:
    k > 0.375, so no scale fits."""
    disk = Disk((-0.6, 0.0), 0.1)
    fits = printing_advice(np.array(SMALL), CAD, (260.0, 260.0, 260.0), disk)
    assert fits["scale_factor"] == pytest.approx(210 / 510, rel=1e-9)
    short = printing_advice(np.array(SMALL), CAD, (230.0,) * 3, disk)
    assert short["scale_factor"] is None
    assert short["smallest_scale"] == pytest.approx(45 / 120, rel=1e-8)
    assert "hold their bosses only with its lengths scaled by 0.375 or more" in " ".join(
        advice_sentences(short, CAD)
    )


@pytest.mark.parametrize(
    ("own_holds", "other_holds", "other_volume", "expected"),
    [
        (True, True, [650.0, 200.0, 20.0], "for design 3"),  # another, smaller printer
        (True, True, [800.0, 220.0, 24.0], "at least 740 x 220 x 24 mm (conf"),  # its own
        (True, False, [650.0, 200.0, 20.0], "at least 740 x 220 x 24 mm (conf"),  # other weak
        (True, True, [650.0, 230.0, 20.0], "x 350 mm); or a printer of at least 650 x 230"),
        (False, True, [650.0, 200.0, 20.0], "a printer of at least 650 x 200 x 20 mm"),
        (False, False, [650.0, 200.0, 20.0], None),  # a printer for a weak design: none
        (True, True, [550.0, 200.0, 20.0], "fits the configured printer (550 x 200 x 20 mm"),
        (False, True, [550.0, 200.0, 20.0], "export --lengths 0.3 0.1 0.3 0.15 0.36 0.12 --config"),
    ],
)
def test_the_printer_fix_is_one_that_holds_its_loads(
    own_holds, other_holds, other_volume, expected
):
    """The fix: this design's own printer as realised, unless another design that holds its
    loads as realised needs no side larger (both where neither does); a weak design only gets
    the other's, and none where that one is weak as realised too. Another design that, realised,
    fits the configured printer is named as one to export, not as a printer to buy."""
    advice = printing_advice(np.array(LARGE), CAD, PRINTER, Disk((-0.9, 0.1), 0.2), [1, 1, 1, 1.2])
    advice["smallest_over_designs"] = {
        "needed_volume_mm": [int(np.ceil(v)) for v in other_volume],
        "exact_volume_mm": other_volume,
        "row": 3,
        "mechanism_id": 3,
        "designs_holding": 9,
        "holds_loads": other_holds,
        "strength_utilisation": 0.8 if other_holds else 1.3,
        "design_m": SMALL,
    }
    fix = printer_fix(advice, own_holds, PRINTER)
    assert fix is None if expected is None else expected in fix


@pytest.mark.parametrize(
    ("has_drives", "meets", "expected"),
    [
        (True, True, "build it with `qsm export --lengths 0.3 0.1 0.3 0.15 0.36 0.12 --config`"),
        (False, True, "but a motor has no drive of the catalogue that meets its duty: no printer"),
        (True, False, "but its structure misses the tolerance (4.10 mm, 3.50 mm allowed): no"),
    ],
)
def test_a_design_that_fits_as_realised_is_to_build_only_where_it_passes(
    has_drives, meets, expected
):
    """Another design that, realised, fits the configured printer is named to export only
    where it also has drives and meets the tolerance as realised; else the advice says what
    fails, with its numbers."""
    advice = {
        "needed_volume_mm": [550, 200, 20],
        "exact_volume_mm": [550.0, 200.0, 20.0],
        "row": 3,
        "designs_holding": 9,
        "holds_loads": True,
        "strength_utilisation": 0.8,
        "has_drives": has_drives,
        "meets_tolerance": meets,
        "structure_mm": 2.0 if meets else 4.1,
        "target_mm": 3.5,
        "design_m": SMALL,
    }
    assert expected in advice_sentence(advice, PRINTER)


def test_a_printable_design_within_the_tolerance_comes_first():
    """The front's designs within task.tolerance_mm (verification's within_tolerance) are
    chosen from when any is: min_tau1 takes the one within, not the lower-torque one outside."""
    table = front([SMALL, SMALL], True, [40.0, 50.0])
    table["within_tolerance"] = [False, True]
    row, _ = choose_design(
        {"ratios": table}, "ratios", dataset([SMALL], 1.0), "min_tau1", CAD, PRINTER
    )
    assert row["tau1_true_Nm"] == 50.0
    table["within_tolerance"] = [False, False]  # none within: the rule picks among all
    row, _ = choose_design(
        {"ratios": table}, "ratios", dataset([SMALL], 1.0), "min_tau1", CAD, PRINTER
    )
    assert row["tau1_true_Nm"] == 40.0


def test_fastest_takes_the_shortest_cycle_and_the_knee_without_cycles():
    """printing.selection_rule: fastest ranks by the time-optimal cycle (NaN: never); a table
    without cycles (the dataset's designs) is ranked by the knee."""
    table = pd.DataFrame(
        {
            "eta_true": [0.2, 0.1, 0.3],
            "tau1_true_Nm": [40.0, 60.0, 30.0],
            "tau2_true_Nm": [10.0, 12.0, 9.0],
            "time_optimal_cycle_s": [3.0, np.nan, 2.5],
        }
    )
    np.testing.assert_array_equal(rule_scores(table, "fastest"), [3.0, np.inf, 2.5])
    bare = table.drop(columns="time_optimal_cycle_s")
    np.testing.assert_array_equal(rule_scores(bare, "fastest"), rule_scores(bare, "knee"))


@pytest.mark.parametrize("strong_exists", [True, False])
def test_a_design_too_weak_gets_no_printer_of_its_own(strong_exists):
    """Not printable and not strong: no printer size for this design (it would stay too weak),
    only the smallest printer of a design that holds its loads, where one does; a design that
    holds them gets its own scale and section too."""
    advice = printing_advice(np.array(LARGE), CAD, PRINTER, Disk((-0.9, 0.1), 0.2))
    pool = dataset([SMALL, LARGE], 1.0, utilization=[0.5 if strong_exists else 1.5, 1.5])
    advice["smallest_over_designs"] = smallest_build_volume(pool, pool["holds_loads"], CAD)
    weak = _printing_failure({"printing_advice": advice, "holds_loads": False}, CAD, PRINTER)
    assert "at least 730 x" not in weak and "scaled by" not in weak
    if strong_exists:
        assert "would leave this design NOT STRONG ENOUGH" in weak
        assert "a printer of at least 560 x" in weak  # SMALL's upper arm: 510 + 2 x 25 mm
    else:
        assert "no larger printer would help: none holds its loads" in weak
        assert "a printer of at least" not in weak
    held = _printing_failure({"printing_advice": advice, "holds_loads": True}, CAD, PRINTER)
    assert "scaled by" in held and "bosses" in held
