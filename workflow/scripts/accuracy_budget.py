"""Rule accuracy_budget: selected.json, the chosen design with its final accuracy budget."""

import json

from qsm.config.settings import realization
from qsm.realization.outputs import props_from_json
from qsm.report.accuracy_report import accuracy_figure, final_record
from qsm.workflow.json_files import write_json
from qsm.workflow.logs import logged

with logged(snakemake.log[0]) as log:
    p = snakemake.params
    inp = snakemake.input
    out = snakemake.output
    choice, links, topology, payload = (
        json.load(open(path)) for path in (inp.choice, inp.links, inp.topology, inp.payload)
    )
    props = props_from_json(links)
    settings = realization.realization(
        p.cad, p.material, p.strength, p.drives, p.payload_kg, p.duty, p.operating_range,
        p.task, p.payload_test,
    )  # fmt: skip
    record = final_record(choice, topology, props, payload, settings, p.task_points)
    write_json(out.selected, record)
    accuracy_figure(record, topology, props, settings, p.task_points, out.figure)
    budget = record["stiffness"]
    log.info("accuracy: %s", budget["verdict"])
    for line in budget["would_meet"]:
        log.warning("would meet the tolerance: %s", line)
