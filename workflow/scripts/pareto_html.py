"""Rule pareto_html: one verified front as a self-contained interactive HTML page."""

from qsm.report.interactive import write_front_html
from qsm.workflow.logs import logged
from qsm.workflow.tables import read_meta, read_table

with logged(snakemake.log[0]) as log:  # noqa: F821
    p = snakemake.params  # noqa: F821
    path = snakemake.input.verification  # noqa: F821
    table = read_table(path)
    constraints = read_meta(path).get("constraints") or ""
    out = write_front_html(table, p.formulation, snakemake.output.html, constraints)  # noqa: F821
    log.info("%s front: %d designs, %.1f MB", p.formulation, len(table), out.stat().st_size / 1e6)
