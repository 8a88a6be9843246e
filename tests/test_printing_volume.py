"""Printing advice over every design: the smallest printer a verified design fits, rounded up."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from qsm.embodiment.parts import link_parts as parts
from qsm.embodiment.parts import printing
from qsm.physics.cad import CadSettings
from qsm.physics.kinematics import DESIGN_COLUMNS

CAD = CadSettings()


def _table(designs, holds, ids) -> pd.DataFrame:
    t = pd.DataFrame(np.asarray(designs, float), columns=list(DESIGN_COLUMNS))
    t["holds"] = holds
    t["mechanism_id"] = ids
    t["source"] = ["dataset", "paper", "ratios"][: len(t)]
    return t


def test_smallest_volume_over_the_designs_that_hold_the_task_rounded_up() -> None:
    # bosses of 25 mm: a bar of length L is (L + 50) x 50 x 20 mm; the upper arm
    # (l4 + EE_x + 50) x (EE_y + 50) x 20 mm.
    small_but_fails = [0.30, 0.10, 0.30, 0.15, 0.40, 0.20]  # needs 600 mm, does not hold
    long_lower = [1.35922, 0.20, 1.20, 0.30, 0.60, 0.30]  # lower arm 1409.22 mm long
    long_upper = [1.00, 0.20, 1.10, 0.50, 0.90, 0.30]  # upper arm 1450 mm
    t = _table([small_but_fails, long_lower, long_upper], [False, True, True], [7, 11, 12])
    advice = printing.smallest_build_volume(t, "holds", CAD)
    assert advice["mechanism_id"] == 11 and advice["source"] == "paper"
    # lower arm 1409.22 x 50 x 20, upper arm 950 x 350 x 20: 1409.22 rounds up, never down
    assert advice["needed_volume_mm"] == [1410, 350, 20]
    assert advice["exact_volume_mm"][0] == pytest.approx(1409.22)
    assert advice["designs_holding"] == 2
    text = printing.advice_sentence(advice, (600, 350, 350))
    assert "1410 x 350 x 20 mm" in text and "design 11 (paper)" in text
    # nothing holds: no advice rather than a wrong printer
    assert printing.smallest_build_volume(t, [False] * 3, CAD) is None


def test_boxes_follow_the_bored_bosses() -> None:
    design = np.array([0.5, 0.15, 0.55, 0.22, 0.6, 0.2])
    radii = np.array([0.025, 0.03, 0.035, 0.0275, 0.025])  # A, B, C, D, E
    boxes = printing.link_boxes_mm(design, radii, CAD)[0]
    # by hand: lower arm 500 + 25 + 30 by 60; crank 150 + 25 + 35 by 70; coupler
    # 550 + 35 + 27.5 by 70; upper arm x from -(220 + 27.5) to 600 + 25, y from -(200 + 25) to 30
    hand = [[555, 60, 20], [210, 70, 20], [612.5, 70, 20], [872.5, 255, 20]]
    np.testing.assert_allclose(boxes, hand)
    # equal radii: the boxes of the outlines of qsm.physics.cad (their 64-gons' arcs aside)
    outline = printing.outline_boxes_mm(design, CAD)
    np.testing.assert_allclose(
        printing.link_boxes_mm(design, None, CAD)[0],
        [outline[name] for name in ("lower_arm", "crank", "coupler", "upper_arm")],
        atol=0.05,
    )


def test_boxes_bound_the_bored_outlines() -> None:
    design = np.array([0.5, 0.15, 0.55, 0.22, 0.6, 0.2])
    idx = [3, 10, 12, 16]
    built = parts.link_parts(design, idx)
    boxes = printing.link_boxes_mm(design, parts.joint_radii(idx), CAD)[0]
    for k, name in enumerate(("lower_arm", "crank", "coupler", "upper_arm")):
        x0, y0, x1, y1 = built[name].polygon.bounds
        got = np.array([x1 - x0, y1 - y0]) * 1e3
        assert (got <= boxes[k, :2] + 1e-9).all()
        np.testing.assert_allclose(got, boxes[k, :2], atol=0.05)  # the 64-gon's arcs
