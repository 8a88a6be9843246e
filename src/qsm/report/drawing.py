"""Dimensioned drawing of every bored link of a design (SVG for a workshop, PNG for a glance).

One view per link in its link frame (millimetres): the outline with its bores, the hole centres
with their coordinates, the distances between hole centres (l1, l2, l3; on the upper arm l4, EE_x
and EE_y), the overall length, each bore's diameter and kind, and the link's own section (bar
width, plate thickness). Texts stay text in the SVG (``svg.fonttype = none``), so the numbers can be
searched and checked.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.patches import PathPatch
from matplotlib.path import Path as MplPath
from matplotlib.text import Text
from numpy.typing import ArrayLike

from qsm.embodiment.parts.link_parts import Bore, LinkPart
from qsm.physics.kinematics import LINK_NAMES, as_design

KIND_LABEL = {"seat": "bearing seat", "pin": "pin", "shaft": "hub spigot", "tool": "tool mount"}


def mm(value_m: float) -> str:
    """A length in m as the drawing writes it: millimetres with one decimal."""
    return f"{1e3 * value_m:.1f}"


def _patch(part: LinkPart) -> PathPatch:
    verts, codes = [], []
    for ring in [part.polygon.exterior, *part.polygon.interiors]:
        xy = np.asarray(ring.coords) * 1e3
        verts.extend(xy)
        codes.extend([MplPath.MOVETO] + [MplPath.LINETO] * (len(xy) - 2) + [MplPath.CLOSEPOLY])
    return PathPatch(MplPath(verts, codes), facecolor="0.88", edgecolor="k", lw=0.8)


def _dimension(ax, p0, p1, offset, text, color="tab:blue") -> Text:
    """A dimension line between points p0 and p1 (mm), shifted by ``offset`` (mm) normal to it;
    returns its label."""
    p0, p1 = np.asarray(p0, float), np.asarray(p1, float)
    u = p1 - p0
    n = np.array([-u[1], u[0]]) / max(np.hypot(*u), 1e-12)
    a, b = p0 + offset * n, p1 + offset * n
    for p, q in ((p0, a), (p1, b)):
        ax.plot(*np.column_stack([p, q + 0.1 * offset * n]), color=color, lw=0.5)
    ax.annotate(
        "",
        a,
        b,
        arrowprops={"arrowstyle": "<->", "color": color, "lw": 0.7, "shrinkA": 0, "shrinkB": 0},
    )
    angle = np.degrees(np.arctan2(u[1], u[0]))
    if angle > 90 or angle < -90:
        angle -= 180 * np.sign(angle)
    mid = 0.5 * (a + b) + 0.04 * abs(offset) * n * np.sign(offset)
    return ax.text(
        *mid,
        text,
        color=color,
        fontsize=7,
        ha="center",
        va="center",
        rotation=angle,
        bbox={"fc": "white", "ec": "none", "pad": 0.5},
    )


def _centre_dims(name: str, design: np.ndarray) -> list[tuple[tuple, tuple, str]]:
    """Hole-centre distances (mm points, label) of a link."""
    l1, l2, l3, l4, ex, ey = design * 1e3
    if name == "upper_arm":
        return [
            ((-l4, 0.0), (0.0, 0.0), f"D-B {l4:.1f}"),
            ((0.0, 0.0), (ex, 0.0), f"B-E' {ex:.1f}"),
            ((ex, 0.0), (ex, -ey), f"E'-E {ey:.1f}"),
        ]
    length = {"lower_arm": l1, "crank": l2, "coupler": l3}[name]
    a, b = {"lower_arm": "AB", "crank": "AC", "coupler": "CD"}[name]
    return [((0.0, 0.0), (length, 0.0), f"{a}-{b} {length:.1f}")]


def draw_links(
    design: ArrayLike,
    parts: Mapping[str, LinkPart],
    path_stem: str | Path,
    title: str = "",
) -> tuple[Path, Path]:
    """Draw every link with its dimensions (:func:`drawing_figure`); write ``<path_stem>.svg``
    and ``<path_stem>.png``. Returns both paths."""
    stem = Path(path_stem)
    stem.parent.mkdir(parents=True, exist_ok=True)
    with plt.rc_context({"svg.fonttype": "none", "font.family": "DejaVu Sans"}):
        fig = drawing_figure(design, parts, title)
        svg, png = stem.with_suffix(".svg"), stem.with_suffix(".png")
        fig.savefig(svg)
        fig.savefig(png, dpi=150)
        plt.close(fig)
    return svg, png


#: The drawing's size (in): 864 x 612 pt, shown at about 1150 x 820 px.
DRAWING_SIZE_IN = (12.0, 8.5)


def drawing_figure(design: ArrayLike, parts: Mapping[str, LinkPart], title: str = "") -> plt.Figure:
    """The drawing: each link (link frame, mm) as built, its openings included, with the
    centre distances above it, the overall length below it and, in the lower left corner, a
    note per joint (position, bore, boss); ``parts`` from
    :func:`qsm.embodiment.parts.link_parts.link_parts` or the final, optimised parts."""
    d = as_design(design).astype(float)
    # 2 x 2 links in 12 x 8.5 in: the report's viewer shows the SVG at its natural size,
    # centred, so it must fit a laptop's window (about 1200 x 900 px) to be seen whole
    fig, axes = plt.subplots(2, 2, figsize=DRAWING_SIZE_IN)
    below = [_draw_link(ax, n, parts[n], d) for ax, n in zip(axes.flat, LINK_NAMES, strict=True)]
    fig.suptitle(
        title or "Links of the design as built, dimensions in mm (link frames)", fontsize=10
    )
    fig.tight_layout()
    _clear_notes(fig, below)
    return fig


def _clear_notes(fig: plt.Figure, pairs: list[tuple[Text, Text]], gap_px: float = 3.0) -> None:
    """Lower each view's bottom edge until its joint notes (the first of each pair, at the
    bottom left) sit ``gap_px`` below the overall length's label (the second), measured on the
    rendered figure: the notes' height is in points, the view's scale depends on its size."""
    for _ in range(10):  # an equal-aspect view may shrink as it grows: settle in a few passes
        fig.canvas.draw()
        renderer = fig.canvas.get_renderer()
        moved = False
        for notes, label in pairs:
            ax = notes.axes
            overlap = notes.get_window_extent(renderer).y1 + gap_px
            overlap -= label.get_window_extent(renderer).y0
            if overlap > 0:
                bottom, top = ax.get_ylim()
                per_px = (top - bottom) / ax.get_window_extent(renderer).height
                ax.set_ylim(bottom - 1.2 * overlap * per_px, top)
                moved = True
        if not moved:
            return


def _draw_link(ax: plt.Axes, name: str, part: LinkPart, d: np.ndarray) -> tuple[Text, Text]:
    """One link's outline, dimensions and joint notes on ``ax``: returns the notes and the
    overall length's label."""
    ax.add_patch(_patch(part))
    x0, y0, x1, y1 = (1e3 * v for v in part.polygon.bounds)
    span = max(x1 - x0, y1 - y0)
    below = -0.06 * span - 15
    overall = _dimension(ax, (x0, y0), (x1, y0), below, f"overall {x1 - x0:.1f}", color="tab:red")
    for k, (p, q, text) in enumerate(_centre_dims(name, d)):
        _dimension(ax, p, q, 0.06 * span + 15 + 14 * k, text)
    for bore in part.bores:
        cx, cy = (1e3 * v for v in bore.centre_m)
        ax.plot([cx - 4, cx + 4], [cy, cy], color="k", lw=0.4)
        ax.plot([cx, cx], [cy - 4, cy + 4], color="k", lw=0.4)
        ax.annotate(bore.joint, (cx, cy), (3, 3), textcoords="offset points", fontsize=7)
    notes = "\n".join(_joint_note(b) for b in sorted(part.bores, key=lambda b: b.centre_m[0]))
    note = ax.text(0.01, 0.02, notes, transform=ax.transAxes, fontsize=6.5, va="bottom")
    holes = len(part.polygon.interiors) - sum(b.diameter_m > 0 for b in part.bores)
    plural = "s" if holes > 1 else ""
    openings = (
        f"\n{holes} hole{plural} besides the joint bores (openings, hub screws)" if holes else ""
    )
    ax.set_title(
        f"{name}: section width {mm(part.section.width_m)} x thickness "
        f"{mm(part.section.thickness_m)} mm{openings}",
        fontsize=9,
        loc="left",
    )
    ax.set_aspect("equal")
    pad = 0.12 * span + 40
    ax.set_xlim(x0 - pad, x1 + pad)
    ax.set_ylim(y0 + below - 25 - 14 * len(part.bores), y1 + pad + 14 * len(_centre_dims(name, d)))
    ax.tick_params(labelsize=6)
    ax.grid(True, lw=0.2)
    return note, overall


def _joint_note(bore: Bore) -> str:
    """A joint's note: position (mm, link frame), bore and what goes in it, boss radius."""
    cx, cy = (1e3 * v for v in bore.centre_m)
    hole = (
        f"Ø{1e3 * bore.diameter_m:.1f} {KIND_LABEL[bore.kind]}"
        if bore.diameter_m > 0
        else "no hole"
    )
    seat = f" {bore.bearing}" if bore.bearing and bore.kind == "seat" else ""
    return f"{bore.joint} ({cx:.1f}, {cy:.1f}): {hole}{seat}, boss R{1e3 * bore.boss_radius_m:.1f}"


def text_overlaps(fig: plt.Figure) -> list[tuple[str, str]]:
    """Pairs of texts of ``fig`` (titles, dimensions, notes) whose boxes overlap on the
    rendered figure."""
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    found = []
    for ax in fig.axes:
        texts = [t for t in ax.texts if t.get_text().strip()] + [ax.title]
        boxes = [Text.get_window_extent(t, renderer) for t in texts]  # the text, not its arrow
        for i in range(len(texts)):
            for j in range(i + 1, len(texts)):
                if boxes[i].overlaps(boxes[j]):
                    found.append((texts[i].get_text(), texts[j].get_text()))
    return found
