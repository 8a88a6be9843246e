"""Rule cycle_time: the selected design's time-optimal cycle on the task, checked in MuJoCo."""

from qsm.app.cycle_inputs import cycle_inputs
from qsm.physics.task_points import TaskCycle
from qsm.realization.final.cycle_run import run_cycle, trajectory_table
from qsm.realization.final.settling import elastic_error
from qsm.report.cycle_report import cycle_figure
from qsm.workflow.json_files import write_json
from qsm.workflow.logs import logged

with logged(snakemake.log[0]) as log:
    out = snakemake.output
    c = cycle_inputs(dict(snakemake.input.items()), dict(snakemake.params.items()))
    log.info("the payload's peak force that keeps the tool within the tolerance: %s N", c.limit_N)
    task = TaskCycle(**snakemake.params.cycle)
    log.info("jerk times weighed: %s s", c.jerk.candidates())
    record, checked, arm = run_cycle(
        c.done, c.props, c.settings, c.test, task, c.raster_speed_deg_s, c.limit_N,
        c.jerk.candidates(), c.settling,
    )  # fmt: skip
    record["jerk"] = (
        c.jerk.record()
        if checked is None
        else c.jerk.record(checked.cycle.jerk_time_s, checked.jerk_chosen)
    )
    write_json(out.cycle, record)
    cycle = None if checked is None else checked.cycle
    trajectory_table(cycle, arm).to_csv(out.trajectory, index=False, float_format="%.8g")
    elastic = None
    if cycle is not None and c.settling is not None:  # the tool's ringing over the cycle
        elastic = (*elastic_error(cycle, c.settling), 1e3 * c.settling.allowed_m)
    cycle_figure(cycle, arm, out.figure, record.get("reason", ""), elastic)
    if checked is None:
        log.warning("no cycle could be planned: %s", record["reason"])
    else:
        log.info(
            "cycle: %.2f s, %.0f per hour (time-optimal %.2f s, slowed %gx), MuJoCo %s",
            record["cycle_time_s"],
            record["cycles_per_hour"],
            record["time_optimal_s"],
            record["slowed_by"],
            record["simulation"]["reason"],
        )
