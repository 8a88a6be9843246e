"""Rule decision_trees: one regression tree per objective on the paper's 400 designs."""

from qsm.design_rules.correlations import FEATURES_MM, OBJECTIVES
from qsm.design_rules.plots import trees_figure
from qsm.design_rules.trees import fit_tree, mining_designs, rule_sentence
from qsm.optimization.nsga import PREDICTION_COLUMNS
from qsm.workflow.json_files import write_json
from qsm.workflow.logs import logged
from qsm.workflow.tables import read_table, write_table

with logged(snakemake.log[0]) as log:
    p = snakemake.params
    inp = snakemake.input
    out = snakemake.output
    designs = mining_designs(
        read_table(inp.pareto, PREDICTION_COLUMNS), read_table(inp.generations, PREDICTION_COLUMNS)
    )
    write_table(designs, out.designs)
    trees = [fit_tree(designs, obj, p.tree_depth, p.seed) for obj in OBJECTIVES]
    splits = {}
    with open(out.rules, "w") as fh:
        for rules in trees:
            name = OBJECTIVES[rules.objective]
            sentence = rule_sentence(rules)
            fh.write(f"# {name}: {sentence}\n{rules.text}\n")
            splits[name] = {
                "variable": rules.first_split,
                "threshold_mm": rules.threshold_mm,
                "mean_at_or_below": rules.left_mean,
                "mean_above": rules.right_mean,
                "rule": sentence,
            }
            log.info("%s", sentence)
    n_unique = len(designs.drop_duplicates(subset=list(FEATURES_MM)))
    write_json(
        out.first_splits, {"n_designs": len(designs), "n_unique": n_unique, "first_splits": splits}
    )
    trees_figure(trees, out.figure)
