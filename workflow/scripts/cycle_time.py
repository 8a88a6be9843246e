"""Rule cycle_time: the selected design's time-optimal cycle on the task, checked in MuJoCo."""

import json
from pathlib import Path

from qsm.config.settings import links, realization, simulation
from qsm.physics.task_points import TaskCycle
from qsm.realization.accuracy.accuracy_budget import largest_load_N
from qsm.realization.final.cycle_run import run_cycle, trajectory_table
from qsm.realization.final.final_budget import measured_budget
from qsm.realization.selection.machine import realization_from_record
from qsm.realization.selection.outputs import props_from_json
from qsm.realization.selection.pipeline import carrying
from qsm.report.cycle_report import cycle_figure
from qsm.workflow.json_files import write_json
from qsm.workflow.logs import logged

with logged(snakemake.log[0]) as log:
    p = snakemake.params
    inp = snakemake.input
    out = snakemake.output
    paths = (inp.choice, inp.links, inp.topology, inp.payload)
    choice, optimized, topology, payload = (json.loads(Path(f).read_text()) for f in paths)
    props = props_from_json(optimized)
    case = links.load_case(p.load_case)
    settings = realization.realization(
        case, p.strength, p.drives, p.task, p.motion, p.task_points, p.build_volume_mm
    )
    done = realization_from_record(json.loads(Path(inp.machine).read_text()), settings)
    settings = carrying(settings, done.tool_kg)  # the tool flange at E, as realised
    (lo, hi), theta2_min = case.operating_range_deg
    op = {"theta1_deg": [lo, hi], "theta2_min_deg": theta2_min}
    test = simulation.payload_test(p.payload_test, settings.motion.payload_kg, op)
    task = TaskCycle(**p.cycle)
    base = json.loads(Path(inp.kit).read_text())["base"]["tool_error_mm"]
    budget = measured_budget(done, (topology, props), payload, settings, p.task_points, None, base)
    limit = largest_load_N(budget)  # the payload's peak force that keeps the tolerance
    log.info("the payload's peak force that keeps the tool within the tolerance: %s N", limit)
    speed = case.duty.peak_speed_deg_s
    record, checked, arm = run_cycle(done, props, settings, test, task, speed, limit)
    write_json(out.cycle, record)
    cycle = None if checked is None else checked.cycle
    trajectory_table(cycle, arm).to_csv(out.trajectory, index=False)
    cycle_figure(cycle, arm, out.figure, record.get("reason", ""))
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
