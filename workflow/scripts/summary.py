"""Rule summary: results/summary.md with the headline numbers of every stage."""

import json

from qsm.report.headline import headline_markdown
from qsm.workflow.logs import logged
from qsm.workflow.tables import read_table

with logged(snakemake.log[0]) as log:
    inp = snakemake.input
    loaded = {}
    keys = ("filters", "status", "metrics", "comparison", "selected", "torques", "payload")
    for key in (*keys, "topology"):
        with open(inp[key]) as fh:
            loaded[key] = json.load(fh)
    with open(inp.bom) as fh:
        bom = fh.read()
    text = headline_markdown(findings=read_table(inp.findings), bom=bom, **loaded)
    with open(snakemake.output[0], "w") as fh:
        fh.write(text)
    log.info("wrote the summary")
