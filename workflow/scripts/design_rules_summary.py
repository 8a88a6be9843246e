"""Rule design_rules_summary: this run's findings beside the paper's Section 4."""

import json

from qsm.design_rules.findings import Evidence, findings, summary_markdown
from qsm.mechanisms.dataset import DATASET_COLUMNS, ok_rows
from qsm.workflow.logs import logged
from qsm.workflow.tables import read_meta, read_table, write_table

with logged(snakemake.log[0]) as log:  # noqa: F821
    p = snakemake.params  # noqa: F821
    inp = snakemake.input  # noqa: F821
    with open(inp.first_splits) as fh:
        trees = json.load(fh)
    evidence = Evidence(
        sobol=read_table(inp.sobol),
        n_sobol=read_meta(inp.sobol)["n_evaluations"],
        first_splits={k: v["variable"] for k, v in trees["first_splits"].items()},
        n_designs=trees["n_designs"],
        n_unique=trees["n_unique"],
        correlations=read_table(inp.correlations),
        gradients=read_table(inp.derivatives),
        pareto=read_table(inp.pareto),
        dataset=ok_rows(read_table(inp.dataset, DATASET_COLUMNS)),
    )
    table = findings(evidence, p.alpha)
    write_table(table, snakemake.output.table)  # noqa: F821
    with open(snakemake.output.summary, "w") as fh:  # noqa: F821
        fh.write(summary_markdown(table, evidence, p.primary))
    log.info("%d of %d findings agree", (table["agree"] == "agree").sum(), len(table))
