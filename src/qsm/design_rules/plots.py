"""Figures of the design-rule stage: Sobol bars, trees, correlation heatmaps, eta derivatives."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from sklearn.tree import plot_tree

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
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def trees_figure(trees: Sequence[TreeRules], path: str | Path) -> None:
    """The regression trees, one panel each, lengths in millimetres."""
    fig, axes = plt.subplots(len(trees), 1, figsize=(16, 5.5 * len(trees)), squeeze=False)
    for ax, rules in zip(axes[:, 0], trees, strict=True):
        names = [f"{n} (mm)" for n in ("l1", "l2", "l3", "l4", "ee_x", "ee_y")]
        plot_tree(rules.tree, feature_names=names, filled=True, ax=ax, fontsize=7, precision=3)
        ax.set_title(f"Decision tree of {rules.objective}")
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


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
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
