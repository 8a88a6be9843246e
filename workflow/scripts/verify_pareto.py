"""Rule verify_pareto: one formulation's Pareto designs under the true physics."""

import json
from pathlib import Path

from qsm.config.settings.optimization import front_of
from qsm.optimization.comparison import summary
from qsm.optimization.infill import final_front
from qsm.optimization.nsga import PREDICTION_COLUMNS
from qsm.optimization.verify import TRUE_COLUMNS
from qsm.surrogate.model import INPUTS
from qsm.workflow.json_files import write_json
from qsm.workflow.logs import logged
from qsm.workflow.tables import read_meta, read_table, write_table

with logged(snakemake.log[0]) as log:
    p = snakemake.params
    out = snakemake.output
    path = snakemake.input.pareto
    pareto = read_table(path, [*INPUTS, *PREDICTION_COLUMNS])
    meta = read_meta(path)
    table = final_front(read_table(snakemake.input.infill), pareto)  # the infill's last check
    if table is None:
        table = front_of(p.front, p.formulation).verify(pareto)
    else:
        log.info("the front as the infill's last round verified it")
    result = {"formulation": meta.get("formulation"), "constraints": meta.get("constraints")}
    result.update(summary(table))
    rounds = json.loads(Path(snakemake.input.rounds).read_text())["rounds"]
    result["infill"] = {
        "rounds": rounds,
        "true_evaluations": rounds[-1]["true_evaluations"] if rounds else 0,
    }
    write_table(table, out.table, {"columns": TRUE_COLUMNS, **result})
    write_json(out.summary, result)
    log.info(
        "%d designs: %.0f %% truly hold the task, %.0f %% printable, %.0f %% hold their loads, "
        "%.0f %% have drives, %.0f %% keep the tool's sag within the tolerance",
        result["n"],
        100 * result["holds_task_share"],
        100 * result["printable_share"],
        100 * result["holds_loads_share"],
        100 * result["has_drives_share"],
        100 * result["within_tolerance_share"],
    )
