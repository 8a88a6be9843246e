"""Rule payload_test: forward simulation of the optimised design carrying the task payload."""

import json

import numpy as np

from qsm.config.settings import actuation, physics, simulation
from qsm.embodiment.drives.envelope import OutputEnvelope
from qsm.embodiment.drives.report import drive_of
from qsm.embodiment.drives.torque_limits import limited
from qsm.physics.task_points import design_task
from qsm.realization.kit.moving_parts import as_built
from qsm.realization.motion.payload import payload_test
from qsm.report.payload_report import (
    SERIES_COLUMNS,
    drive_duty_note,
    plot_payload_test,
    series_table,
    summary,
)
from qsm.workflow.json_files import write_json
from qsm.workflow.logs import logged
from qsm.workflow.tables import write_table

with logged(snakemake.log[0]) as log:
    p = snakemake.params
    inp = snakemake.input
    out = snakemake.output
    with open(inp.selected) as fh:
        selected = json.load(fh)
    design = np.asarray(selected["design_m"])
    with open(inp.links) as fh, open(inp.kit) as kit:
        props = as_built(json.load(fh), json.load(kit))  # with the kit's moving parts
    r = p.realization  # the realisation's share of the config
    payload_kg = r["task"]["payload_kg"]
    tool_kg = selected["tool_flange_kg"]  # the realised tool flange, at E beside the payload
    carried = payload_kg + tool_kg
    op = physics.operating_range(r["operating_range"])
    test_settings = simulation.payload_test(p.payload_test, carried, op)
    catalogue = actuation.catalogue(r["drives"])
    drives = []
    limits = selected["torque_limits_Nm"]  # each drive's, which its controller keeps
    for (j, m), limit in zip(selected["drives"]["motors"].items(), limits, strict=True):
        d = drive_of(m)  # the chosen drive, or the nearest
        drives.append(
            limited(OutputEnvelope.of(catalogue, d["motor_key"], d["gearbox_key"]), limit)
        )
        log.info("%s: %s%s", j, drives[-1].name, "" if d["chosen"] else " (NOT meeting its duty)")
    points = design_task(r["task"]["points"])[1]
    cad = physics.cad(r["cad"], r["material"])
    result = payload_test(design, points, cad, props, test_settings, drives)
    scalars = summary(result) | {"payload_kg": payload_kg, "tool_flange_kg": tool_kg}
    scalars.update(drive_duty_note(selected["drives"]["motors"], drives))
    write_json(out.result, scalars)
    write_table(series_table(result), out.series, {"columns": SERIES_COLUMNS})
    plot_payload_test(result, out.figure)
    log.info(
        "payload test: passed %s, max tracking error %.4f deg, peak torque %s N m",
        scalars["passed"],
        scalars["max_tracking_error_deg"],
        scalars["peak_torque_Nm"],
    )
