"""Stage 1 figures: designs with workspace, task disk and linkage; scale and eta."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from matplotlib.axes import Axes
from matplotlib.tri import Triangulation

from qsm.kinematics import DESIGN_NAMES, pose
from qsm.task import Disk
from qsm.workspace import OperatingRange


def draw_design(
    ax: Axes, design: np.ndarray, op: OperatingRange, disk: Disk, title: str = "", n: int = 120
) -> None:
    """Draw the workspace (filled image of the joint domain), the task disk and a mid-range pose."""
    t1 = np.linspace(op.theta1_min, op.theta1_max, n)
    t2 = np.linspace(op.theta2_min, op.theta1_max, n)
    g1, g2 = np.meshgrid(t1, t2)
    g2 = np.minimum(g2, g1)  # fold the square onto the domain theta2 <= theta1
    e = pose(design, g1.ravel(), g2.ravel()).E
    tri = Triangulation(g1.ravel(), g2.ravel())
    ax.tripcolor(
        e[:, 0],
        e[:, 1],
        tri.triangles,
        np.zeros(len(tri.triangles)),
        cmap="Blues",
        vmin=-1,
        vmax=1.5,
        edgecolors="none",
        rasterized=True,
    )
    ax.add_patch(plt.Circle(disk.centre, disk.radius, fill=False, color="tab:red", lw=1.5))
    mid = pose(design, np.radians(120.0), np.radians(20.0))
    a = np.zeros(2)
    for p, q, style in [
        (a, mid.B, "k-"),
        (a, mid.C, "k-"),
        (mid.C, mid.D, "g-"),
        (mid.D, mid.B, "k-"),
        (mid.B, mid.E, "k-"),
    ]:
        ax.plot([p[0], q[0]], [p[1], q[1]], style, lw=2)
    joints = np.array([a, mid.B, mid.C, mid.D])
    ax.plot(joints[:, 0], joints[:, 1], "o", color="k", ms=4)
    ax.plot(*mid.E, "s", color="tab:orange", ms=5)
    ax.set_aspect("equal")
    ax.grid(alpha=0.3)
    ax.set_title(title, fontsize=8)
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")


def examples_figure(
    mechanisms: pd.DataFrame, op: OperatingRange, disk: Disk, path: str | Path, n: int
) -> None:
    """A grid of ``n`` mechanisms (evenly spread over the eta range) with workspace and task."""
    order = mechanisms.sort_values("eta")
    pick = order.iloc[np.linspace(0, len(order) - 1, min(n, len(order))).astype(int)]
    cols = min(3, len(pick))
    rows = int(np.ceil(len(pick) / cols))
    fig, axes = plt.subplots(rows, cols, figsize=(4.2 * cols, 4.0 * rows), squeeze=False)
    for ax, (_, row) in zip(axes.ravel(), pick.iterrows(), strict=False):
        design = row[[f"{name}_m" for name in DESIGN_NAMES]].to_numpy(dtype=float)
        title = f"id {int(row.mechanism_id)}: scale {row.scale_m:.3f} m, eta {row.eta:.3f}"
        draw_design(ax, design, op, disk, title)
    for ax in axes.ravel()[len(pick) :]:
        ax.axis("off")
    fig.suptitle("Workspaces (blue), task disk (red) and the pose theta1 = 120, theta2 = 20 deg")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def distributions_figure(mechanisms: pd.DataFrame, path: str | Path) -> None:
    """Histograms of the scale factor and eta, and eta against the scale."""
    fig, axes = plt.subplots(1, 3, figsize=(13, 3.8))
    axes[0].hist(mechanisms["scale_m"], bins=50, color="tab:blue")
    axes[0].set_xlabel("scale factor l1 (m)")
    axes[1].hist(mechanisms["eta"], bins=50, color="tab:green")
    axes[1].set_xlabel("eta = task area / workspace area (-)")
    for ax in axes[:2]:
        ax.set_ylabel("mechanisms")
    axes[2].scatter(mechanisms["scale_m"], mechanisms["eta"], s=2, alpha=0.4)
    axes[2].set_xlabel("scale factor l1 (m)")
    axes[2].set_ylabel("eta (-)")
    fig.suptitle(f"{len(mechanisms)} mechanisms")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def performance_figure(dataset: pd.DataFrame, path: str | Path) -> None:
    """eta, tau1 and tau2 of every mechanism against each other, coloured by the scale factor."""
    pairs = [("eta", "tau1_Nm"), ("eta", "tau2_Nm"), ("tau1_Nm", "tau2_Nm")]
    labels = {"eta": "eta (-)", "tau1_Nm": "tau1 (N m)", "tau2_Nm": "tau2 (N m)"}
    fig, axes = plt.subplots(1, 3, figsize=(14, 4.2))
    for ax, (x, y) in zip(axes, pairs, strict=True):
        sc = ax.scatter(dataset[x], dataset[y], c=dataset["scale_m"], s=3, cmap="viridis")
        ax.set_xlabel(labels[x])
        ax.set_ylabel(labels[y])
        ax.grid(alpha=0.3)
    fig.colorbar(sc, ax=axes, label="scale factor l1 (m)")
    fig.suptitle(
        f"Engineering performance of {len(dataset)} mechanisms (peak torques over the duty)"
    )
    fig.savefig(path, dpi=110, bbox_inches="tight")
    plt.close(fig)
