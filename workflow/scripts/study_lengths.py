"""Rule study_lengths: the dataset's designs with the scale drawn apart from their ratios."""

from qsm.config.settings import physics
from qsm.dataset.gathering import OK_ROWS, ok_rows
from qsm.design_rules.experiments import INDEPENDENT_COLUMNS, independent_lengths
from qsm.design_rules.plots import study_lengths_figure
from qsm.design_rules.study import RULE_COLUMNS, lengths_outcome
from qsm.physics.duty import duty_cycle
from qsm.workflow.json_files import write_json
from qsm.workflow.logs import logged
from qsm.workflow.tables import read_table, write_table

with logged(snakemake.log[0]) as log:
    p = snakemake.params
    out = snakemake.output
    dataset = ok_rows(read_table(snakemake.input.dataset, RULE_COLUMNS, only=True, where=OK_ROWS))
    duty = duty_cycle(physics.duty(p.duty, p.operating_range))
    sample = independent_lengths(
        dataset,
        p.study["n_designs"],
        p.study["seed"],
        duty,
        physics.cad(p.cad, p.material),
        p.payload_kg,
    )
    log.info("%d designs re-evaluated at independently drawn scales", len(sample))
    outcome = lengths_outcome(sample, p.study["seed"], p.tree_depth)
    write_table(sample, out.table, {"columns": INDEPENDENT_COLUMNS})
    write_json(out.outcome, outcome)
    study_lengths_figure(sample, dataset, outcome, out.figure)
    for name, ranking in outcome["ranking"].items():
        log.info("%s: first-order Sobol ranking %s", name, ", ".join(ranking))
