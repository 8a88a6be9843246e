"""Decision trees on the designs near the Pareto front (paper Section 4.2)."""

from __future__ import annotations

from dataclasses import dataclass

import pandas as pd
from sklearn.tree import DecisionTreeRegressor, export_text

from qsm.design_rules.correlations import FEATURES_MM, OBJECTIVES
from qsm.physics.kinematics import DESIGN_NAMES


def mining_designs(pareto: pd.DataFrame, last_generations: pd.DataFrame) -> pd.DataFrame:
    """The paper's 400 designs: the Pareto set followed by the last three generations' designs.

    Lengths are converted to millimetres, as the paper writes its rules. A design that is both on
    the front and in the last generation appears twice, as in the paper's count.
    """
    parts = [pareto.assign(source="pareto"), last_generations.assign(source="last_generations")]
    table = pd.concat(parts, ignore_index=True)
    for name in DESIGN_NAMES:
        table[f"{name}_mm"] = table[f"{name}_m"] * 1000.0
    return table[["source", *FEATURES_MM, "scale_m", *OBJECTIVES]]


@dataclass(frozen=True)
class TreeRules:
    """A fitted regression tree of one objective and its rules."""

    objective: str
    tree: DecisionTreeRegressor
    text: str
    first_split: str
    threshold_mm: float
    left_mean: float  # mean objective where feature <= threshold
    right_mean: float


def fit_tree(designs: pd.DataFrame, objective: str, depth: int, seed: int) -> TreeRules:
    """Regression tree of ``objective`` on the 6 lengths (mm), its rules and first split."""
    x = designs[list(FEATURES_MM)].to_numpy()
    y = designs[objective].to_numpy()
    tree = DecisionTreeRegressor(max_depth=depth, random_state=seed).fit(x, y)
    names = [n.removesuffix("_mm") for n in FEATURES_MM]
    t = tree.tree_
    root_feature = names[t.feature[0]] if t.node_count > 1 else ""
    left, right = (t.children_left[0], t.children_right[0]) if t.node_count > 1 else (0, 0)
    return TreeRules(
        objective=objective,
        tree=tree,
        text=export_text(tree, feature_names=[f"{n} (mm)" for n in names], decimals=1),
        first_split=root_feature,
        threshold_mm=float(t.threshold[0]) if t.node_count > 1 else float("nan"),
        left_mean=float(t.value[left].ravel()[0]),
        right_mean=float(t.value[right].ravel()[0]),
    )


def rule_sentence(rules: TreeRules) -> str:
    """The first split as a design rule, e.g. 'ee_x <= 662.1 mm -> lower tau1 (61.2 vs 70.3)'."""
    name = OBJECTIVES[rules.objective]
    if not rules.first_split:
        return f"{name}: no split"
    word = "lower" if rules.left_mean < rules.right_mean else "higher"
    return (
        f"{rules.first_split} <= {rules.threshold_mm:.1f} mm -> {word} {name} "
        f"({rules.left_mean:.4g} vs {rules.right_mean:.4g})"
    )
