"""Figures of the design-rule stage: Sobol bars, trees, correlation heatmaps, eta derivatives."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd

if TYPE_CHECKING:
    from qsm.design_rules.trees import TreeRules


def sobol_figure(indices: pd.DataFrame, outputs: Sequence[str], path: str | Path) -> None:
    """First-order and total indices with 95 % confidence intervals, one panel per output."""
    fig, axes = plt.subplots(1, len(outputs), figsize=(5 * len(outputs), 4), squeeze=False)
    for ax, out in zip(axes[0], outputs, strict=True):
        sel = indices[indices["output"] == out]
        names = sel.loc[sel["index"] == "S1", "variable"].tolist()
        pos = np.arange(len(names))
        for shift, kind, colour in ((-0.2, "S1", "tab:blue"), (0.2, "ST", "tab:orange")):
            part = sel[sel["index"] == kind].set_index("variable").loc[names]
            ax.bar(pos + shift, part["value"], 0.4, yerr=part["conf"], label=kind, color=colour)
        ax.set_xticks(pos, names)
        ax.set_title(f"Sobol indices of {out}")
        ax.grid(axis="y", alpha=0.3)
        ax.legend()
    _save(fig, path)


def trees_figure(trees: Sequence[TreeRules], path: str | Path) -> None:
    """The regression trees, one panel each, lengths in millimetres."""
    from sklearn.tree import plot_tree  # scikit-learn: only this figure needs it

    fig, axes = plt.subplots(len(trees), 1, figsize=(16, 5.5 * len(trees)), squeeze=False)
    for ax, rules in zip(axes[:, 0], trees, strict=True):
        names = [f"{n} (mm)" for n in ("l1", "l2", "l3", "l4", "ee_x", "ee_y")]
        plot_tree(rules.tree, feature_names=names, filled=True, ax=ax, fontsize=7, precision=3)
        ax.set_title(f"Decision tree of {rules.objective}")
    _save(fig, path, dpi=90)


def correlation_figure(
    table: pd.DataFrame,
    variables: Sequence[str],
    objectives: Sequence[str],
    alpha: float,
    path: str | Path,
) -> None:
    """Spearman and Pearson heatmaps of variables x objectives; cells with p >= alpha are blank."""
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5))
    for ax, kind in zip(axes, ("spearman", "pearson"), strict=True):
        grid = np.full((len(variables), len(objectives)), np.nan)
        for i, v in enumerate(variables):
            for j, o in enumerate(objectives):
                row = table[(table["a"] == v) & (table["b"] == o)].iloc[0]
                if row[f"{kind}_p"] < alpha:
                    grid[i, j] = row[kind]
        im = ax.imshow(grid, cmap="coolwarm", vmin=-1, vmax=1)
        for (i, j), value in np.ndenumerate(grid):
            if np.isfinite(value):
                ax.text(j, i, f"{value:.2f}", ha="center", va="center", fontsize=9)
        ax.set_xticks(range(len(objectives)), objectives)
        ax.set_yticks(range(len(variables)), variables)
        ax.set_title(f"{kind.capitalize()} (only p < {alpha})")
    fig.colorbar(im, ax=axes, shrink=0.8)
    fig.savefig(path, dpi=110, bbox_inches="tight")
    plt.close(fig)


def derivatives_figure(gradients: pd.DataFrame, path: str | Path) -> None:
    """Box plot of d eta / d x over all mechanisms, one box per design variable."""
    cols = [c for c in gradients.columns if c.startswith("deta_d")]
    fig, ax = plt.subplots(figsize=(8, 4.5))
    ax.boxplot([gradients[c].dropna() for c in cols], showfliers=False)
    ax.set_xticks(
        range(1, len(cols) + 1), [c.removeprefix("deta_d").removesuffix("_per_m") for c in cols]
    )
    ax.axhline(0.0, color="k", lw=0.8)
    ax.set_ylabel("d eta / d x (1/m)")
    ax.set_title(f"Derivatives of the true eta over {len(gradients)} mechanisms")
    ax.grid(axis="y", alpha=0.3)
    _save(fig, path)


def study_lengths_figure(
    sample: pd.DataFrame, dataset: pd.DataFrame, outcome: dict, path: str | Path
) -> None:
    """The scale-apart-from-ratios experiment: tau1 against EE_x at the minimal scale (the dataset)
    and at the drawn scales, and the first-order Sobol indices of each output."""
    fig, axes = plt.subplots(1, 2, figsize=(11, 4))
    ax = axes[0]
    ax.scatter(dataset["ee_x_m"], dataset["tau1_Nm"], s=4, alpha=0.3, label="minimal scale")
    ax.scatter(sample["ee_x_m"], sample["tau1_Nm"], s=4, alpha=0.5, label="scale drawn apart")
    ax.set_xlabel("EE_x (m)")
    ax.set_ylabel("peak |tau1| (N m)")
    ax.legend()
    ax.grid(alpha=0.3)
    ax = axes[1]
    outputs = list(outcome["sobol_s1"])
    names = list(outcome["sobol_s1"][outputs[0]])
    pos = np.arange(len(names))
    width = 0.8 / len(outputs)
    for k, out in enumerate(outputs):
        values = [outcome["sobol_s1"][out][n] for n in names]
        ax.bar(pos + (k - (len(outputs) - 1) / 2) * width, values, width, label=out)
    ax.set_xticks(pos, names)
    ax.set_title(f"first-order indices, scale apart from ratios ({outcome['n_designs']} designs)")
    ax.grid(axis="y", alpha=0.3)
    ax.legend()
    _save(fig, path)


def table3_figure(
    sweep: pd.DataFrame, paper_pct: dict[str, float], run_ratio: float, path: str | Path
) -> None:
    """Torque reduction by topology optimisation against payload / link mass, with the paper's
    Table 3 values and this run's ratio marked."""
    fig, ax = plt.subplots(figsize=(6.5, 4))
    x = sweep["payload_to_link_mass"]
    for (key, value), colour in zip(paper_pct.items(), ("tab:blue", "tab:orange"), strict=True):
        ax.plot(x, sweep[f"{key}_reduction_pct"], "o-", color=colour, label=f"{key} (this design)")
        ax.axhline(value, color=colour, ls="--", lw=1, label=f"{key} paper {value:.2f} %")
    ax.axvline(run_ratio, color="grey", lw=1, label=f"this run's payload ({run_ratio:.2f})")
    ax.set_xlabel("payload / CAD-link mass (-)")
    ax.set_ylabel("peak-torque reduction (%)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    _save(fig, path)


def _save(fig: plt.Figure, path: str | Path, dpi: int = 110) -> None:
    """Lay out, write and close ``fig``."""
    fig.tight_layout()
    fig.savefig(path, dpi=dpi)
    plt.close(fig)
