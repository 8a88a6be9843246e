"""Rule optimize: NSGA-II on the surrogate in one formulation; tables and figures."""

from qsm.config.settings import optimization, physics
from qsm.dataset.columns import DATASET_COLUMNS
from qsm.dataset.gathering import ok_rows
from qsm.optimization.nsga import optimize
from qsm.report.figures import pareto_figures, representatives_figure
from qsm.surrogate.model import load
from qsm.workflow.logs import logged
from qsm.workflow.tables import read_table, write_table

with logged(snakemake.log[0]) as log:
    p = snakemake.params
    out = snakemake.output
    model = load(snakemake.input.model)
    dataset = ok_rows(read_table(snakemake.input.dataset, DATASET_COLUMNS))
    fit = physics.fit(p.operating_range, p.task_points, p.scale, p.workspace, p.filters)
    every = max(1, p.optimization["generations"] // 10)

    def progress(generation: int, hypervolume: float) -> None:
        if generation % every == 0:
            log.info("generation %d: hypervolume %.4f", generation, hypervolume)

    extra = optimization.constraints(p.constraints, fit)
    log.info("%s formulation, constraints: %s", p.formulation, extra.label(p.formulation))
    tables = optimize(
        p.formulation, model, dataset, p.optimization, fit, p.ratio_bounds, extra, progress
    )
    meta = {
        "formulation": p.formulation,
        "constraints": tables.constraints,
        "settings": dict(p.optimization),
    }
    write_table(tables.pareto, out.pareto, meta)
    write_table(tables.last_generations, out.generations, meta)
    write_table(tables.hypervolume, out.hypervolume, meta)
    pareto_figures(tables.pareto, tables.hypervolume, out.front_3d, out.front_pairs)
    representatives_figure(
        tables.pareto, fit.op, fit.disk, p.optimization["n_representatives"], out.designs
    )
    log.info("%s formulation: %d Pareto designs", p.formulation, len(tables.pareto))
    log.info("constraints met: %s", tables.constraints)
