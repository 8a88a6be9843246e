"""Rule pareto_html: one verified front as a self-contained interactive HTML page."""

import json

from qsm.physics.kinematics import DESIGN_COLUMNS
from qsm.report.interactive import selected_row, write_front_html
from qsm.workflow.logs import logged
from qsm.workflow.tables import read_meta, read_table

with logged(snakemake.log[0]) as log:
    p = snakemake.params
    path = snakemake.input.verification
    table = read_table(path)
    if snakemake.input.cycles:  # the primary front's time-optimal cycles
        table = table.join(read_table(snakemake.input.cycles).drop(columns=list(DESIGN_COLUMNS)))
    constraints = read_meta(path).get("constraints") or ""
    with open(snakemake.input.selected) as fh:
        selected = json.load(fh)
    row = selected_row(table, selected["design_m"]) if selected["source"] == p.formulation else None
    out = write_front_html(table, p.formulation, snakemake.output.html, constraints, row)
    log.info("%s front: %d designs, %.1f MB", p.formulation, len(table), out.stat().st_size / 1e6)
