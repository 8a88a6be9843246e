"""Rule accuracy_budget: selected.json, the chosen design with its final accuracy budget."""

import json
from pathlib import Path

from qsm.config.settings import realization
from qsm.realization.final.final_budget import final_record
from qsm.realization.kit.moving_parts import as_built
from qsm.realization.selection.machine import realization_from_record
from qsm.realization.selection.pipeline import carrying
from qsm.report.accuracy_report import accuracy_figure, final_verdict
from qsm.workflow.json_files import write_json
from qsm.workflow.logs import logged

with logged(snakemake.log[0]) as log:
    p = snakemake.params
    inp = snakemake.input
    out = snakemake.output
    paths = (inp.choice, inp.links, inp.topology, inp.payload, inp.cycle)
    choice, optimized, topology, payload, cycle = (json.loads(Path(f).read_text()) for f in paths)
    kit = json.loads(Path(inp.kit).read_text())
    props = as_built(optimized, kit)  # the printed links with the kit's moving parts
    settings = realization.realization_of(p.realization)
    points = [list(xy) for xy in settings.task_points_m]
    done = realization_from_record(json.loads(Path(inp.machine).read_text()), settings)
    settings = carrying(settings, done.tool_kg)  # the tool flange at E, as realised
    base = kit["base"]["tool_error_mm"]  # the kit's cheeks
    parts = (topology, props)
    iso = realization.iso(p.iso)
    record = final_record(choice, done, parts, payload, settings, points, cycle, base, iso)
    record["standard_cycle"] = json.loads(Path(inp.standard).read_text())
    record["verdict"] = final_verdict(record)
    write_json(out.selected, record)
    accuracy_figure(record, done, topology, props, settings, points, out.figure)
    budget = record["stiffness"]
    log.info("accuracy: %s", budget["verdict"])
    for line in budget["would_meet"]:
        log.warning("would meet the tolerance: %s", line)
