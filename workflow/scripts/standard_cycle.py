"""Rule standard_cycle: the selected design on the standard pick-and-place cycle (25 mm up,
305 mm across, 25 mm down and back) at the rated payload and at 1 kg, checked as the task's."""

from qsm.app.cycle_inputs import cycle_inputs
from qsm.physics.task import min_enclosing_circle
from qsm.realization.final.standard_cycle import standard_cycles, standard_record, standard_route
from qsm.workflow.json_files import write_json
from qsm.workflow.logs import logged

with logged(snakemake.log[0]) as log:
    c = cycle_inputs(dict(snakemake.input.items()), dict(snakemake.params.items()))
    centre = min_enclosing_circle(c.settings.task_points_m).centre
    route = standard_route(c.done.design, centre, *c.test.operating_range.degrees)
    cycles = (
        []
        if route is None
        else standard_cycles(c.done, c.props, c.settings, c.test, route, c.raster_speed_deg_s,
                             c.limit_N, c.jerk.jerk_time_s)
    )  # fmt: skip
    record = standard_record(route, cycles, c.mirrored) | {"jerk": c.jerk.record()}
    write_json(snakemake.output.cycle, record)
    for x in record["payloads"]:
        log.info(
            "standard cycle at %g kg: %s", x["payload_kg"], x.get("cycle_time_s", x.get("reason"))
        )
