"""The export's ``design.png``: a design with its workspace, task disk and points, and its link
outlines with their boxes (mm) against the printer."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

import matplotlib.pyplot as plt
import numpy as np
from numpy.typing import ArrayLike

from qsm.physics.cad import CadSettings, link_outlines
from qsm.physics.kinematics import as_design
from qsm.physics.task import min_enclosing_circle
from qsm.physics.workspace import OperatingRange
from qsm.report.figures import draw_design


def design_sheet(
    design: ArrayLike,
    op: OperatingRange,
    cad: CadSettings,
    task_points: ArrayLike,
    volume_mm: tuple[float, float, float],
    boxes: Mapping[str, Mapping[str, Any]],
    title: str,
    path: str | Path,
    scale: ArrayLike | None = None,
) -> Path:
    """PNG: the design with its workspace in ``op``, task disk and points (n, 2) m as designed,
    and its link outlines (each of ``cad``'s section scaled by its entry of ``scale`` (4,), None:
    the section itself) with their boxes (mm) against the printer ``volume_mm``."""
    d = as_design(design)
    points = np.asarray(task_points, dtype=float).reshape(-1, 2)
    fig, (ax, ax_links) = plt.subplots(1, 2, figsize=(12, 5.2), width_ratios=(1, 1.1))
    draw_design(ax, d, op, min_enclosing_circle(points), title)
    ax.plot(points[:, 0], points[:, 1], "x", color="tab:red", ms=6, mew=1.5)
    y = 0.0
    volume = " x ".join(f"{v:g}" for v in volume_mm)
    for name, outline in link_outlines(d, cad, scale).items():
        xy = outline * 1e3
        y -= xy[:, 1].max()
        ax_links.fill(xy[:, 0], xy[:, 1] + y, color="0.75", ec="k", lw=0.8)
        box = boxes[name]
        ax_links.text(
            xy[:, 0].min(),
            y + xy[:, 1].max() + 8,
            f"{name}: {' x '.join(f'{v:.0f}' for v in box['box_mm'])} mm, "
            f"{'fits' if box['fits'] else 'does NOT fit'}",
            fontsize=8,
        )
        y += xy[:, 1].min() - 45
    ax_links.set_aspect("equal")
    ax_links.set_xlabel("mm (link frames)")
    ax_links.set_yticks([])
    ax_links.set_title(f"links as printed, printer {volume} mm", fontsize=9)
    fig.tight_layout()
    out = Path(path)
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return out
