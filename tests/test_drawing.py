"""Dimensioned drawing: files written, and the SVG carries the dimensions of the design."""

from __future__ import annotations

import numpy as np

from qsm.embodiment.parts import bearings
from qsm.embodiment.parts import link_parts as parts
from qsm.report.drawing import draw_links

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
        "Ø10.0 motor shaft",
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
