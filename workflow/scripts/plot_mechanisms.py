"""Rule plot_mechanisms: example designs with workspace and task, scale and eta distributions."""

from qsm.config.settings import physics
from qsm.mechanisms.scale import MECHANISM_COLUMNS
from qsm.physics.task import min_enclosing_circle
from qsm.report.figures import distributions_figure, examples_figure
from qsm.workflow.logs import logged
from qsm.workflow.tables import read_table

with logged(snakemake.log[0]) as log:
    p = snakemake.params
    out = snakemake.output
    table = read_table(snakemake.input[0], MECHANISM_COLUMNS)
    op = physics.operating_range(p.operating_range)
    disk = min_enclosing_circle(p.task_points)
    examples_figure(table, op, disk, out.examples, p.figures["n_examples"])
    distributions_figure(table, out.distributions)
    log.info("drew %d mechanisms", len(table))
