"""Dimensioned drawing: files written, and the SVG carries the dimensions of the design."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
import shapely
from matplotlib.text import Annotation

from qsm.embodiment.parts import bearings
from qsm.embodiment.parts import link_parts as parts
from qsm.report.drawing import draw_links, drawing_figure, text_overlaps

DESIGN = np.array([0.5, 0.15, 0.55, 0.22, 0.6, 0.2])


def test_drawing_files_and_dimension_texts(tmp_path) -> None:
    table = bearings.load_catalogue()
    idx = [int(np.flatnonzero(table.designation == n)[0]) for n in ("6000", "608", "6204", "6206")]
    built = parts.link_parts(DESIGN, idx)
    svg, png = draw_links(DESIGN, built, tmp_path / "links")
    assert svg.stat().st_size > 10_000 and png.stat().st_size > 10_000
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    text = svg.read_text(encoding="utf-8")
    expected = [
        # hole-centre distances: l1, l2, l3, l4, EE_x, EE_y (mm)
        "A-B 500.0",
        "A-C 150.0",
        "C-D 550.0",
        "D-B 220.0",
        "B-E' 600.0",
        "E'-E 200.0",
        # overall lengths: lower arm 500 + 25 + 25 (6000 and 608 keep the 25 mm boss);
        # coupler 550 + (47/2 + 4) + (62/2 + 4); upper arm 220 + 35 + 600 + 25
        "overall 550.0",
        "overall 612.5",
        "overall 880.0",
        # bores: 6000 shaft at A (d 10), 608 seat at B (D 22), 6204 pin at C (d 20),
        # 6206 seat at D (D 62), tool hole 9
        "Ø10.0 hub spigot",
        "Ø22.0 bearing seat 608",
        "Ø20.0 pin",
        "Ø62.0 bearing seat 6206",
        "Ø9.0 tool mount",
        "boss R35.0",
        "boss R27.5",
        # hole centres and the section
        "E (600.0, -200.0)",
        "D (-220.0, 0.0)",
        "width 40.0 x thickness 20.0",
    ]
    missing = [t for t in expected if t.replace("'", "&#39;") not in text and t not in text]
    assert not missing, missing


def test_no_label_overlaps_another_and_the_openings_are_drawn() -> None:
    """A short crank (the default design's is 62 mm between its bores) and an optimised plate
    with openings: no two texts of the drawing overlap, and the openings are drawn and
    counted."""
    short = np.array([0.457, 0.0625, 0.495, 0.122, 0.409, 0.0614])
    table = bearings.load_catalogue()
    idx = [int(np.flatnonzero(table.designation == n)[0]) for n in ("6003", "626", "626", "626")]
    built = parts.link_parts(short, idx)
    lower = built["lower_arm"]
    opening = shapely.box(0.1, -0.005, 0.2, 0.005)
    built["lower_arm"] = parts.LinkPart(
        "lower_arm", lower.polygon.difference(opening), lower.bores, lower.section
    )
    fig = drawing_figure(short, built)
    assert text_overlaps(fig) == []
    assert "1 hole besides the joint bores" in fig.axes[0].get_title(loc="left")
    patch = fig.axes[0].patches[0]
    assert len(patch.get_path().to_polygons()) == 1 + 2 + 1  # outline, bores A and B, opening
    plt.close(fig)


def test_the_joint_notes_stay_clear_of_the_overall_length() -> None:
    """A long arm with its sections doubled (a heavy task's: the upper arm 930 mm over all,
    bosses of 50 mm): each view's joint notes, at its bottom left, sit below the overall
    length's dimension line and label, measured on the rendered figure."""
    heavy = np.array([0.5024, 0.2007, 0.6099, 0.3238, 0.5058, 0.1782])
    table = bearings.load_catalogue()
    idx = [int(np.flatnonzero(table.designation == n)[0]) for n in ("6005", "6000", "608", "608")]
    built = parts.link_parts(heavy, idx, parts.PartSettings(scale=(2.0, 2.0, 2.0, 2.0)))
    fig = drawing_figure(heavy, built)
    renderer = fig.canvas.get_renderer()
    for ax in fig.axes:
        notes = [t for t in ax.texts if t.get_transform() == ax.transAxes]
        label = next(t for t in ax.texts if t.get_text().startswith("overall"))
        arrows = [t.xy for t in ax.texts if isinstance(t, Annotation) and t.arrow_patch]
        line = ax.transData.transform(min(arrows, key=lambda xy: xy[1]))[1]  # the lowest
        top = max(n.get_window_extent(renderer).y1 for n in notes)
        assert top < label.get_window_extent(renderer).y0, ax.get_title(loc="left")
        assert top < line, ax.get_title(loc="left")
    plt.close(fig)
