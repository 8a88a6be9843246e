"""Figures a person can read whole (tests/figure_checks.py): the links' drawing and the
accuracy budget's bars keep every text inside the canvas and every bar inside its axes."""

import matplotlib.pyplot as plt
import numpy as np
import shapely
from figure_checks import outside_canvas

from qsm.embodiment.parts import bearings
from qsm.embodiment.parts import link_parts as parts
from qsm.report.accuracy_report import budget_bars
from qsm.report.drawing import drawing_figure

DESIGN = np.array([0.457, 0.0625, 0.495, 0.122, 0.409, 0.0614])  # m


def test_the_drawing_keeps_its_titles_inside_with_many_openings():
    """Every link with 15 openings: its title's openings note is the longest it gets."""
    table = bearings.load_catalogue()
    idx = [int(np.flatnonzero(table.designation == n)[0]) for n in ("6003", "626", "626", "626")]
    built = parts.link_parts(DESIGN, idx)
    for name, part in built.items():
        holes = [shapely.box(0.02 * k, -0.002, 0.02 * k + 0.004, 0.002) for k in range(1, 16)]
        cut = part.polygon.difference(shapely.union_all(holes))
        built[name] = parts.LinkPart(name, cut, part.bores, part.section)
    fig = drawing_figure(DESIGN, built)
    assert outside_canvas(fig) == []
    plt.close(fig)


def test_the_budget_bars_stack_to_the_placing_error_inside_the_axes():
    """A point far past the tolerance, a base term, no tracking yet: each stack ends at its
    point's placing error and stays inside the axes, the tolerance line too."""
    per = {
        "sag_mm": [3.0, 6.0, 2.0], "dynamic_sag_mm": [4.0, None, 1.0], "creep_mm": [1.0, 2.0, 0.5],
        "lost_motion_mm": [0.2, 0.2, 0.2], "tracking_error_mm": None, "base_mm": [0.4, 0.4, 0.4],
    }  # fmt: skip
    per["error_budget_mm"] = [5.6, 8.6, 3.1]
    fig, ax = plt.subplots(figsize=(5.5, 4.5))
    budget_bars(ax, {"per_point": per, "tolerance_mm": 10.0, "meets_requirements": True})
    fig.tight_layout()
    assert outside_canvas(fig) == []
    tops = {}
    for bar in ax.patches:
        x = round(bar.get_x() + bar.get_width() / 2)
        tops[x] = max(tops.get(x, 0.0), bar.get_y() + bar.get_height())
    np.testing.assert_allclose([tops[k] for k in (1, 2, 3)], per["error_budget_mm"])
    assert ax.get_ylim()[1] > 10.0  # the tolerance inside
    plt.close(fig)
