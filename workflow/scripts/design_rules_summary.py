"""Rule design_rules_summary: this run's findings beside the paper's Section 4 and Table 3."""

import json

from qsm.dataset.gathering import OK_ROWS, ok_rows
from qsm.design_rules.claims import Evidence, Study
from qsm.design_rules.correlations import FEATURES_MM, OBJECTIVES, correlations
from qsm.design_rules.findings import findings, summary_markdown
from qsm.design_rules.study import RULE_COLUMNS, distinct_rows, elasticities
from qsm.workflow.logs import logged
from qsm.workflow.tables import read_meta, read_table, write_table

with logged(snakemake.log[0]) as log:
    p = snakemake.params
    inp = snakemake.input
    with open(inp.first_splits) as fh:
        trees = json.load(fh)
    dataset = ok_rows(read_table(inp.dataset, RULE_COLUMNS, only=True, where=OK_ROWS))
    gradients = read_table(inp.derivatives)
    study = None
    if "lengths" in inp.keys():
        with open(inp.lengths) as fh:
            lengths = json.load(fh)
        with open(inp.torques) as fh:
            change = json.load(fh)["change"]
        distinct = distinct_rows(read_table(inp.designs), list(FEATURES_MM))
        table3 = read_table(inp.table3)
        study = Study(
            lengths=lengths,
            elasticity=elasticities(gradients, dataset),
            distinct=correlations(distinct, FEATURES_MM, list(OBJECTIVES)),
            n_distinct=len(distinct),
            table3=table3,
            table3_run={k: -change[f"{k}_change_pct"] for k in ("tau1", "tau2")},
            payload_to_link_mass=p.payload_kg / float(table3["link_mass_kg"].iloc[0]),
        )
    evidence = Evidence(
        sobol=read_table(inp.sobol),
        n_sobol=read_meta(inp.sobol)["n_evaluations"],
        first_splits={k: v["variable"] for k, v in trees["first_splits"].items()},
        n_designs=trees["n_designs"],
        n_unique=trees["n_unique"],
        correlations=read_table(inp.correlations),
        gradients=gradients,
        pareto=read_table(inp.pareto),
        dataset=dataset,
        study=study,
    )
    table = findings(evidence, p.alpha)
    write_table(table, snakemake.output.table)
    with open(snakemake.output.summary, "w") as fh:
        fh.write(summary_markdown(table, evidence, p.primary))
    for row in table.itertuples():
        log.info("%s: %s; %s", row.finding, row.agree, row.verdict)
