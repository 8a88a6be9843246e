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
from numpy.typing import ArrayLike

from qsm.embodiment.parts.link_parts import LinkPart
from qsm.physics.kinematics import LINK_NAMES, as_design

KIND_LABEL = {"seat": "bearing seat", "pin": "pin", "shaft": "motor shaft", "tool": "tool mount"}


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


def _dimension(ax, p0, p1, offset, text, color="tab:blue") -> None:
    """A dimension line between points p0 and p1 (mm), shifted by ``offset`` (mm) normal to it."""
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
    ax.text(
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
    """Draw every link with its dimensions; write ``<path_stem>.svg`` and ``<path_stem>.png``.

    ``design`` the 6 scaled lengths (m); ``parts`` from
    :func:`qsm.embodiment.parts.link_parts.link_parts`. Returns the SVG and PNG paths.
    """
    d = as_design(design).astype(float)
    stem = Path(path_stem)
    stem.parent.mkdir(parents=True, exist_ok=True)
    heights = []
    for name in LINK_NAMES:
        _, y0, _, y1 = parts[name].polygon.bounds
        heights.append(max(1e3 * (y1 - y0), 60.0) + 80.0)
    with plt.rc_context({"svg.fonttype": "none", "font.family": "DejaVu Sans"}):
        fig, axes = plt.subplots(
            len(LINK_NAMES),
            1,
            figsize=(11, 3.2 * len(LINK_NAMES)),
            gridspec_kw={"height_ratios": heights},
        )
        for ax, name in zip(axes, LINK_NAMES, strict=True):
            part = parts[name]
            ax.add_patch(_patch(part))
            x0, y0, x1, y1 = (1e3 * v for v in part.polygon.bounds)
            span = max(x1 - x0, y1 - y0)
            # overall length, below the part
            _dimension(
                ax, (x0, y0), (x1, y0), -0.06 * span - 15, f"overall {x1 - x0:.1f}", color="tab:red"
            )
            for k, (p, q, text) in enumerate(_centre_dims(name, d)):
                _dimension(ax, p, q, 0.06 * span + 15 + 12 * k * (name == "upper_arm"), text)
            for bore in part.bores:
                cx, cy = (1e3 * v for v in bore.centre_m)
                ax.plot([cx - 4, cx + 4], [cy, cy], color="k", lw=0.4)
                ax.plot([cx, cx], [cy - 4, cy + 4], color="k", lw=0.4)
                label = (
                    f"{bore.joint} ({cx:.1f}, {cy:.1f})\n"
                    + (
                        f"Ø{1e3 * bore.diameter_m:.1f} {KIND_LABEL[bore.kind]}"
                        if bore.diameter_m > 0
                        else "no hole"
                    )
                    + (f" {bore.bearing}" if bore.bearing and bore.kind == "seat" else "")
                    + f"\nboss R{1e3 * bore.boss_radius_m:.1f}"
                )
                ax.annotate(
                    label,
                    (cx, cy),
                    (cx + 0.02 * span, cy - 1e3 * bore.boss_radius_m - 8),
                    fontsize=6.5,
                    ha="left",
                    va="top",
                    arrowprops={"arrowstyle": "-", "lw": 0.4, "color": "0.3"},
                )
            ax.set_title(
                f"{name}: section width {mm(part.section.width_m)} x thickness "
                f"{mm(part.section.thickness_m)} mm",
                fontsize=9,
                loc="left",
            )
            ax.set_aspect("equal")
            pad = 0.12 * span + 40
            ax.set_xlim(x0 - pad, x1 + pad)
            ax.set_ylim(y0 - pad, y1 + pad)
            ax.tick_params(labelsize=6)
            ax.grid(True, lw=0.2)
        fig.suptitle(title or "Links of the design, dimensions in mm (link frames)", fontsize=10)
        fig.tight_layout()
        svg, png = stem.with_suffix(".svg"), stem.with_suffix(".png")
        fig.savefig(svg)
        fig.savefig(png, dpi=150)
        plt.close(fig)
    return svg, png
