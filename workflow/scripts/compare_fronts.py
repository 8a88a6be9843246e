"""Rule compare_fronts: the paper and ratios fronts compared on their true values."""

import json

from qsm.dataset import DATASET_COLUMNS, ok_rows
from qsm.logs import logged
from qsm.tables import read_table
from qsm.verify import compare, comparison_markdown

with logged(snakemake.log[0]) as log:  # noqa: F821
    inp = snakemake.input  # noqa: F821
    out = snakemake.output  # noqa: F821
    dataset = ok_rows(read_table(inp.dataset, DATASET_COLUMNS))
    fronts = {"paper": read_table(inp.paper), "ratios": read_table(inp.ratios)}
    result = compare(fronts, dataset, snakemake.params.primary)  # noqa: F821
    with open(out.data, "w") as fh:
        json.dump(result, fh, indent=2)
    with open(out.summary, "w") as fh:
        fh.write(comparison_markdown(result))
    log.info("comparison: %s", result)
