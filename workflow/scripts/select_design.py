"""Rule select_design: the design to realise (choice.json), printable if any is, truly feasible
always."""

from qsm.config.settings import physics, realization
from qsm.dataset.gathering import OK_ROWS, ok_rows
from qsm.physics.kinematics import DESIGN_COLUMNS
from qsm.realization.selection.choice import CANDIDATE_COLUMNS
from qsm.realization.selection.chosen_machine import chosen_machine
from qsm.realization.selection.machine import machine_record
from qsm.report.selection_record import selected_figure, selection_verdict
from qsm.workflow.json_files import write_json
from qsm.workflow.logs import logged
from qsm.workflow.tables import read_table

with logged(snakemake.log[0]) as log:
    p = snakemake.params
    inp = snakemake.input
    out = snakemake.output
    fronts = {name: read_table(path) for name, path in zip(p.formulations, inp.fronts, strict=True)}
    if inp.cycles:  # selection_rule: fastest, on the primary front's cycles
        cycles = read_table(inp.cycles).drop(columns=list(DESIGN_COLUMNS))
        fronts[p.primary] = fronts[p.primary].join(cycles)
    dataset = ok_rows(read_table(inp.dataset, CANDIDATE_COLUMNS, only=True, where=OK_ROWS))
    rule = p.selection_rule
    r = p.realization  # the realisation's share of the config
    op = physics.operating_range(r["operating_range"])
    volume = tuple(r["printing"]["build_volume_mm"])
    settings = realization.realization_of(r)
    points = [list(xy) for xy in settings.task_points_m]
    record, done = chosen_machine(
        fronts, p.primary, dataset, rule, volume, points, r["task"]["points"], op, settings
    )
    record["verdict"] = selection_verdict(record, settings.strength, settings.parts.cad, volume)
    if record["task"]["mirrored"]:
        log.info("mirrored: %s", record["task"]["note"])
    for line in record["fallback"]:
        log.warning("skipped: %s", line)
    if not (record["printable"] and record["holds_loads"] and record["drives"]["has_drives"]):
        log.warning(record["verdict"])
    write_json(out.choice, record)
    write_json(out.machine, machine_record(done))  # every later rule reads it: realised once
    selected_figure(record, rule, op, points, out.figure)
    log.info("selected %s: %s", record["design_m"], record["verdict"])
