"""What a rendered figure shows a person: every text inside the canvas, every bar inside its
axes."""

from __future__ import annotations

import matplotlib.pyplot as plt
from matplotlib.patches import Rectangle


def outside_canvas(fig: plt.Figure) -> list[str]:
    """The texts of ``fig`` (titles, labels, ticks, legends, annotations) whose rendered box
    leaves the canvas (as saved: no tight bounding box), and the bars whose top passes their
    axes' upper limit."""
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    canvas = fig.bbox
    found = []
    for text in _drawn_texts(fig):
        box = text.get_window_extent(renderer)
        if (
            box.x0 < canvas.x0 - 0.5
            or box.x1 > canvas.x1 + 0.5
            or box.y0 < canvas.y0 - 0.5
            or (box.y1 > canvas.y1 + 0.5)
        ):
            found.append(f"text {text.get_text()!r}")
    for ax in fig.axes:
        top = ax.get_ylim()[1]
        for bar in (p for p in ax.patches if isinstance(p, Rectangle)):
            if bar.get_y() + bar.get_height() > top:
                found.append(f"bar at x {bar.get_x():g} to {bar.get_y() + bar.get_height():g}")
    return found


def _drawn_texts(fig: plt.Figure) -> list:
    """The texts ``fig`` draws: its own, its axes' titles, labels, annotations and legends, and
    the tick labels of the ticks within view."""
    texts = list(fig.texts)
    for ax in fig.axes:
        texts += [ax.title, ax._left_title, ax._right_title, ax.xaxis.label, ax.yaxis.label]
        texts += list(ax.texts)
        if ax.get_legend() is not None:
            texts += list(ax.get_legend().get_texts())
        for axis in (ax.xaxis, ax.yaxis):
            lo, hi = sorted(axis.get_view_interval())
            texts += [t.label1 for t in axis.get_major_ticks() if lo <= t.get_loc() <= hi]
    return [t for t in texts if t.get_visible() and t.get_text().strip()]
