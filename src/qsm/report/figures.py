"""Figures: designs with workspace, task and linkage; distributions; parity; Pareto fronts."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from matplotlib.axes import Axes
from matplotlib.tri import Triangulation
from numpy.typing import NDArray

from qsm.optimization.ranking import drawn_objectives
from qsm.physics.kinematics import DESIGN_NAMES, LoopPose, pose
from qsm.physics.task import Disk
from qsm.physics.workspace import OperatingRange


def draw_workspace(ax: Axes, design: np.ndarray, op: OperatingRange, n: int = 120) -> None:
    """Fill the workspace: the image of the joint domain theta2 <= theta1 on an n x n grid."""
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


def linkage_segments(p: LoopPose) -> list[tuple[np.ndarray, np.ndarray, str]]:
    """The bars of one pose as (start, end, matplotlib style): AB, AC, the coupler CD (green),
    DB and BE of the upper arm."""
    a = np.zeros(2)
    return [(a, p.B, "k-"), (a, p.C, "k-"), (p.C, p.D, "g-"), (p.D, p.B, "k-"), (p.B, p.E, "k-")]


def draw_design(
    ax: Axes, design: np.ndarray, op: OperatingRange, disk: Disk, title: str = "", n: int = 120
) -> None:
    """Draw the workspace (filled image of the joint domain), the task disk and a mid-range pose."""
    draw_workspace(ax, design, op, n)
    ax.add_patch(plt.Circle(disk.centre, disk.radius, fill=False, color="tab:red", lw=1.5))
    mid = pose(design, np.radians(120.0), np.radians(20.0))
    a = np.zeros(2)
    for p, q, style in linkage_segments(mid):
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


def parity_figure(
    truth: NDArray[np.float64],
    prediction: NDArray[np.float64],
    names: Sequence[str],
    path: str | Path,
) -> None:
    """Predicted against true values of each output, with the identity line and R^2."""
    fig, axes = plt.subplots(1, len(names), figsize=(4.3 * len(names), 4.2))
    for ax, name, t, p in zip(axes, names, truth.T, prediction.T, strict=True):
        ax.scatter(t, p, s=3, alpha=0.5)
        lo, hi = min(t.min(), p.min()), max(t.max(), p.max())
        ax.plot([lo, hi], [lo, hi], "k--", lw=1)
        r2 = 1 - np.sum((t - p) ** 2) / np.sum((t - t.mean()) ** 2)
        ax.set_title(f"{name}: test R^2 = {r2:.4f}")
        ax.set_xlabel(f"true {name}")
        ax.set_ylabel(f"predicted {name}")
        ax.set_aspect("equal")
        ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def pareto_figures(
    pareto: pd.DataFrame, hypervolume: pd.DataFrame, path_3d: str | Path, path_pairs: str | Path
) -> None:
    """The Pareto front in 3D and pairwise (its objectives, then tau1 and tau2 to make three:
    :func:`qsm.optimization.ranking.drawn_objectives`), coloured by the scale factor; the HV
    history."""
    drawn = drawn_objectives(pareto)
    cols = [o.predicted for o in drawn]
    labels = [o.label.replace(" (", "' (", 1) for o in drawn]
    fig = plt.figure(figsize=(6.5, 5.5))
    ax = fig.add_subplot(projection="3d")
    sc = ax.scatter(*(pareto[c] for c in cols), c=pareto["scale_m"], cmap="viridis", s=14)
    ax.set_xlabel(labels[0])
    ax.set_ylabel(labels[1])
    ax.set_zlabel(labels[2])
    fig.colorbar(sc, ax=ax, shrink=0.7, label="scale factor l1 (m)")
    ax.set_title(f"{len(pareto)} Pareto designs (NSGA-II's values)")
    fig.savefig(path_3d, dpi=110, bbox_inches="tight")
    plt.close(fig)
    fig, axes = plt.subplots(1, 4, figsize=(18, 4.2))
    for ax, (i, j) in zip(axes[:3], [(0, 1), (0, 2), (1, 2)], strict=True):
        sc = ax.scatter(pareto[cols[i]], pareto[cols[j]], c=pareto["scale_m"], cmap="viridis", s=12)
        ax.set_xlabel(labels[i])
        ax.set_ylabel(labels[j])
        ax.grid(alpha=0.3)
    fig.colorbar(sc, ax=axes[:3], label="scale factor l1 (m)")
    axes[3].plot(hypervolume["generation"], hypervolume["hypervolume"])
    axes[3].set_xlabel("generation")
    axes[3].set_ylabel("hypervolume (normalised objectives)")
    axes[3].grid(alpha=0.3)
    fig.savefig(path_pairs, dpi=110, bbox_inches="tight")
    plt.close(fig)


def representatives(pareto: pd.DataFrame, n: int) -> pd.DataFrame:
    """``n`` Pareto designs evenly spread over the range of the scale factor."""
    order = pareto.sort_values("scale_m")
    return order.iloc[np.unique(np.linspace(0, len(order) - 1, min(n, len(order))).astype(int))]


def representatives_figure(
    pareto: pd.DataFrame, op: OperatingRange, disk: Disk, n: int, path: str | Path
) -> None:
    """Representative Pareto designs with linkage, workspace and task (paper Fig. 6)."""
    pick = representatives(pareto, n)
    fig, axes = plt.subplots(1, len(pick), figsize=(4.0 * len(pick), 4.0), squeeze=False)
    for ax, (_, row) in zip(axes[0], pick.iterrows(), strict=True):
        design = row[[f"{name}_m" for name in DESIGN_NAMES]].to_numpy(dtype=float)
        title = (
            f"l1 {row.scale_m:.3f} m: eta' {row.eta_pred:.3f}\n"
            f"tau1' {row.tau1_pred_Nm:.1f}, tau2' {row.tau2_pred_Nm:.1f} N m"
        )
        draw_design(ax, design, op, disk, title)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def infill_figure(
    rounds: Sequence[dict], goals: tuple[float, float], formulation: str, path: str | Path
) -> None:
    """The adaptive infill's rounds: each objective's median and 90th-percentile relative error
    of the predictions on the front (log scale, with the ``goals``: median and 90th percentile)
    and the front's true hypervolume, against the round; a note when no round ran."""
    fig, (err, hv) = plt.subplots(1, 2, figsize=(10, 4))
    if not rounds:
        for ax in (err, hv):
            ax.text(0.5, 0.5, "no infill rounds (surrogate.infill.rounds: 0)", ha="center")
            ax.set_axis_off()
    else:
        r = [x["round"] for x in rounds]
        for name in rounds[0]["median_rel_error"]:
            for kind, style in (("median_rel_error", "-o"), ("p90_rel_error", "--s")):
                values = [x[kind][name] for x in rounds]
                err.plot(r, [np.nan if v is None else 100 * v for v in values], style,
                         label=f"{name} {kind.split('_')[0]}")  # fmt: skip
        err.axhline(100 * goals[0], color="grey", lw=1, label="median goal")
        err.axhline(100 * goals[1], color="grey", lw=1, ls="--", label="p90 goal")
        err.set_yscale("log")
        err.set_xlabel("round")
        err.set_ylabel("relative error on the front (%)")
        err.legend(fontsize=7)
        hv.plot(r, [x["hypervolume"] for x in rounds], "-o")
        hv.set_xlabel("round")
        hv.set_ylabel("true hypervolume of the front (-)")
        for ax in (err, hv):
            ax.set_xticks(r)
            ax.grid(alpha=0.3)
    fig.suptitle(f"{formulation} formulation: adaptive infill")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
