"""Cross-sections of the beam-against-FE comparison (tests/reference_fe.py): where
the arms are cut, the beam's cuts there, and the FE's peak at the upper arm's inside corner."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from qsm.embodiment.strength.beam import Cuts, Section
from qsm.physics.cad import CadSettings


class Section2D(NamedTuple):
    """A cross-section of a bar: label, link-frame point (m) on the spine, unit tangent into the
    piece beyond the cut (towards the loaded end)."""

    label: str
    at: tuple[float, float]
    tangent: tuple[float, float]


class SectionResult(NamedTuple):
    """Beam stress and the largest FE von Mises stress of the cells across one section (Pa)."""

    label: str
    at: tuple[float, float]
    beam_pa: float
    fe_pa: float


def bar_sections(
    design: NDArray[np.float64], link: str, sec: Section, h: float, fillet: float
) -> list[Section2D]:
    """Sections clear of the bosses (the first cell column whose cells all lie outside the boss,
    with a cell of margin), at mid-span of the lower arm, half a width before and below the
    upper arm's corner E' (its legs' edges meet at x = E_x - w/2, y = -w/2) and where its corner
    fillet of radius ``fillet`` (m) meets the legs; ``h`` the cell size."""
    l1, _, _, l4, ex, ey = (float(v) for v in design)
    clear = float(np.hypot(sec.boss_radius_m + h, sec.width_m / 2))  # every cell outside
    half = sec.width_m / 2
    if link == "lower_arm":
        return [
            Section2D("bar clear of boss A", (clear, 0.0), (1.0, 0.0)),
            Section2D("bar at mid-span", (l1 / 2, 0.0), (1.0, 0.0)),
            Section2D("bar clear of boss B", (l1 - clear, 0.0), (1.0, 0.0)),
        ]
    return [
        Section2D("leg B-D clear of boss B", (-clear, 0.0), (-1.0, 0.0)),
        Section2D("leg B-D clear of boss D", (-l4 + clear, 0.0), (-1.0, 0.0)),
        Section2D("leg B-E' clear of boss B", (clear, 0.0), (1.0, 0.0)),
        Section2D("leg B-E' before the corner", (ex - 2 * half, 0.0), (1.0, 0.0)),
        Section2D("leg E'-E below the corner", (ex, -2 * half), (0.0, -1.0)),
        Section2D("leg B-E' at the fillet", (ex - half - fillet, 0.0), (1.0, 0.0)),
        Section2D("leg E'-E at the fillet", (ex, -half - fillet), (0.0, -1.0)),
        Section2D("leg E'-E clear of boss E", (ex, -ey + clear), (0.0, -1.0)),
    ]


def snap(grid_origin: float, h: float, x: float) -> float:
    """The cell-centre coordinate nearest ``x``."""
    return grid_origin + (np.round((x - grid_origin) / h - 0.5) + 0.5) * h


def section_cuts(design: NDArray[np.float64], link: str, sections: list[Section2D]) -> Cuts:
    """Cuts of :mod:`qsm.embodiment.strength.stresses` at ``sections`` (bar stress, no bore)."""
    l1, _, _, l4, ex, ey = (float(v) for v in design)
    at, tangent, piece, load, slot = [], [], [], [], []
    for s in sections:
        p = np.array(s.at)
        if link == "lower_arm":
            end = np.array([l1, 0.0])
            pts, ld, k = [p, end, end], end, 0
        elif s.tangent[0] < 0:  # towards D
            end = np.array([-l4, 0.0])
            pts, ld, k = [p, end, end], end, 0
        else:  # towards E, round the corner E' when on the horizontal leg
            corner, end = np.array([ex, 0.0]), np.array([ex, -ey])
            pts = [p, corner, end] if s.tangent[0] > 0 else [p, end, end]
            ld, k = end, 1
        at.append(p)
        tangent.append(s.tangent)
        piece.append(np.stack(pts))
        load.append(ld)
        slot.append(k)
    n = len(sections)
    return Cuts(
        np.stack(at),
        np.array(tangent, dtype=float),
        np.stack(piece),
        np.stack(load),
        np.array(slot),
        np.zeros(n, dtype=bool),
        np.zeros(n, dtype=bool),
        tuple(s.label for s in sections),
    )


def inside_corner(
    design: NDArray[np.float64],
    cad: CadSettings,
    centres: NDArray[np.float64],
    vm: NDArray[np.float64],
    beam: NDArray[np.float64],
    labels: list[str],
) -> SectionResult:
    """The upper arm's inside corner E': the largest FE von Mises stress ``vm`` (Pa) of the
    cells (centres ``centres`` (ny, nx, 2) m) within r_f + w/2 of the fillet's centre (the sharp
    corner when r_f = 0) and at most a cell before its quadrant (the cells touching a sharp
    corner), against the larger beam stress ``beam`` of the cuts "bar at the corner" and "bar
    below the corner" (those the corner factor multiplies); at the fillet's centre."""
    h, rf = cad.width_m / 2, cad.corner_fillet_m
    at = np.array([float(design[4]) - h - rf, -h - rf])
    r = centres - at
    cell = float(centres[0, 1, 0] - centres[0, 0, 0])
    near = (r >= -cell).all(-1) & (np.hypot(r[..., 0], r[..., 1]) <= rf + h)
    cut = max(beam[labels.index(k)] for k in ("bar at the corner", "bar below the corner"))
    return SectionResult(
        "inside corner E'", (float(at[0]), float(at[1])), float(cut), float(vm[near].max())
    )
