"""Rule compare_fronts: the formulations' fronts compared on their true values."""

from qsm.dataset.gathering import OK_ROWS, ok_rows
from qsm.optimization.comparison import compare, comparison_markdown
from qsm.optimization.ranking import OPTIMISATION_COLUMNS
from qsm.workflow.json_files import write_json
from qsm.workflow.logs import logged
from qsm.workflow.tables import read_meta, read_table

with logged(snakemake.log[0]) as log:
    inp = snakemake.input
    p = snakemake.params
    out = snakemake.output
    dataset = ok_rows(read_table(inp.dataset, OPTIMISATION_COLUMNS, only=True, where=OK_ROWS))
    paths = dict(zip(p.formulations, inp.fronts, strict=True))
    fronts = {name: read_table(path) for name, path in paths.items()}
    labels = {name: read_meta(path).get("constraints", "") for name, path in paths.items()}
    result = compare(fronts, dataset, p.primary, labels)
    write_json(out.data, result)
    with open(out.summary, "w") as fh:
        fh.write(comparison_markdown(result))
    log.info("comparison: %s", result)
