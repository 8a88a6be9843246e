"""The datasheet's envelope figure: where the tool reaches within the operating range, in the
user's frame (m, the base joint A at the origin, gravity along -y), with the reach, the task
points, the ISO 9283 test plane and the standard cycle's route."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from qsm.physics.kinematics import end_effector
from qsm.physics.workspace import Reach

#: Motor angle samples per axis of the envelope's scatter.
ENVELOPE_SAMPLES = 241


def envelope_points(
    design: Sequence[float], theta1_deg: Sequence[float], theta2_min_deg: float
) -> np.ndarray:
    """Tool positions (k, 2) m over a grid of the operating range (theta2 up to theta1), where
    the loop closes."""
    lo, hi = np.radians(theta1_deg)
    t1, t2 = np.meshgrid(
        np.linspace(lo, hi, ENVELOPE_SAMPLES),
        np.linspace(np.radians(theta2_min_deg), hi, ENVELOPE_SAMPLES),
    )
    inside = t2 <= t1
    tool = end_effector(np.asarray(design, dtype=float), t1[inside], t2[inside])
    return tool[np.isfinite(tool).all(axis=1)]


def envelope_figure(
    selected: Mapping[str, Any], reach: Reach, operating_range: tuple[Sequence[float], float],
    path: str | Path,
) -> Path:  # fmt: skip
    """The figure at ``path``: the envelope of ``selected``'s design over the
    ``operating_range`` ((theta1 lo, hi) deg, theta2 min deg), mirrored back to the user's frame
    when the task was designed mirrored, the ``reach`` circle, the task points, the ISO 9283
    plane and the standard cycle (where ``selected`` holds them)."""
    import matplotlib.pyplot as plt

    sign = np.array([-1.0 if selected["task"]["mirrored"] else 1.0, 1.0])
    tool = envelope_points(selected["design_m"], *operating_range) * sign
    fig, ax = plt.subplots(figsize=(7, 6))
    ax.plot(*tool.T, ",", color="0.75", label="tool within the operating range")
    phi = np.linspace(0, 2 * np.pi, 361)
    ax.plot(reach.reach_m * np.cos(phi), reach.reach_m * np.sin(phi), "k--", lw=0.7,
            label=f"reach {reach.reach_m:.3f} m")  # fmt: skip
    ax.plot(0, 0, "k^", ms=9, label="base joint A")
    pts = np.asarray(selected["task"]["points_m"], dtype=float)
    ax.plot(*pts.T, "o", color="tab:blue", label="task points")
    if (iso := selected.get("iso9283") or {}).get("simulated"):
        c, h = np.asarray(iso["plane_centre_m"]), iso["plane_side_m"] / 2
        square = c + h * np.array([[-1, -1], [1, -1], [1, 1], [-1, 1], [-1, -1]])
        ax.plot(*square.T, "-", color="tab:green", lw=1, label="ISO 9283 test plane")
        ax.plot(*np.asarray(iso["points_m"]).T, "x", color="tab:green", label="P1-P5")
    std = selected.get("standard_cycle") or {}
    if std.get("planned"):
        ax.plot(*np.asarray(std["corners_m"]).T, "-", color="tab:red", lw=1.5,
                label=f"standard cycle (25 / {std['stroke_mm']:.0f} / 25 mm)")  # fmt: skip
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title("Envelope of the realised arm")
    ax.legend(loc="best", fontsize=7, markerscale=1.5)
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return Path(path)
