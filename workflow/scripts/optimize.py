"""Rule optimize: NSGA-II on the surrogate in one formulation, with adaptive infill; tables and
figures."""

import numpy as np

from qsm.config.settings.optimization import front_of
from qsm.dataset.gathering import OK_ROWS, ok_rows
from qsm.optimization.comparison import true_hypervolume
from qsm.optimization.infill import Steps, infill, refit_rows
from qsm.optimization.nsga import optimize
from qsm.optimization.ranking import OBJECTIVE_SETS, OPTIMISATION_COLUMNS
from qsm.report.figures import infill_figure, pareto_figures, representatives_figure
from qsm.surrogate.model import INPUTS, OUTPUTS, Training, load, refit, training_rows
from qsm.workflow.json_files import write_json
from qsm.workflow.logs import logged
from qsm.workflow.tables import read_table, write_table

with logged(snakemake.log[0]) as log:
    p = snakemake.params
    out = snakemake.output
    model = load(snakemake.input.model)
    dataset = ok_rows(
        read_table(snakemake.input.dataset, OPTIMISATION_COLUMNS, only=True, where=OK_ROWS)
    )
    front = front_of(p.front, p.formulation)
    every = max(1, front.nsga["generations"] // 10)

    def progress(generation: int, hypervolume: float) -> None:
        if generation % every == 0:
            log.info("generation %d: hypervolume %.4f", generation, hypervolume)

    extra, fit, training, settings = front.extra, front.fit, front.training, front.infill
    log.info("%s formulation, constraints: %s", p.formulation, extra.label(p.formulation))
    rows = training_rows(len(dataset), training)[0]  # the surrogate's own training rows
    x0, y0 = dataset[list(INPUTS)].to_numpy()[rows], dataset[list(OUTPUTS)].to_numpy()[rows]
    fits: list[Training] = []

    def refitted(x: np.ndarray, y: np.ndarray) -> object:
        """The surrogate on its training rows (at most ``refit_rows``, the true designs'
        neighbourhood first) and every true design so far, normalised over all its training
        rows and true designs, warm-started from the last refit where its normalisation holds
        them."""
        keep = refit_rows(x0, x, settings.refit_rows, training.seed)
        xs, ys = np.vstack([x0[keep], x]), np.vstack([y0[keep], y])
        span = (np.vstack([x0, x]), np.vstack([y0, y]))
        fits.append(refit(xs, ys, training, (fits or [None])[-1], span))
        log.info("refit on %d designs: %s", len(xs), fits[-1].metrics)
        return fits[-1].model

    objectives = OBJECTIVE_SETS[front.nsga.get("objectives", "torques")]
    steps = Steps(
        optimize=lambda m, start: optimize(
            p.formulation, m, dataset, front.nsga, fit, front.ratio_bounds, extra, progress, start
        ),
        truth=front.verify,
        refit=refitted,
    )
    result = infill(
        model,
        steps,
        settings,
        lambda table: true_hypervolume(table, dataset, objectives),
        log.info,
    )
    tables = result.tables
    meta = {
        "formulation": p.formulation,
        "constraints": tables.constraints,
        "settings": dict(front.nsga),
        "infill_rounds": len(result.rounds),
    }
    write_table(tables.pareto, out.pareto, meta)
    write_table(tables.last_generations, out.generations, meta)
    write_table(tables.hypervolume, out.hypervolume, meta)
    write_table(result.evaluations, out.infill, meta)
    write_json(out.rounds, {"formulation": p.formulation, "rounds": result.rounds})
    goals = (settings.median_goal, settings.p90_goal)
    infill_figure(result.rounds, goals, p.formulation, out.infill_figure)
    pareto_figures(tables.pareto, tables.hypervolume, out.front_3d, out.front_pairs)
    representatives_figure(
        tables.pareto, fit.op, fit.disk, front.nsga["n_representatives"], out.designs
    )
    log.info("%s formulation: %d Pareto designs", p.formulation, len(tables.pareto))
    log.info("constraints met: %s", tables.constraints)
