"""Rule eta_derivatives: gather the shards; box plot of the derivatives (paper Fig. 9)."""

import pandas as pd

from qsm.design_rules.plots import derivatives_figure
from qsm.workflow.logs import logged
from qsm.workflow.tables import read_table, write_table

with logged(snakemake.log[0]) as log:
    grads = pd.concat([read_table(f) for f in snakemake.input], ignore_index=True)
    write_table(grads, snakemake.output.table)
    derivatives_figure(grads, snakemake.output.figure)
    log.info("median |d eta / d x| (1/m): %s", grads.filter(like="deta_d").abs().median().to_dict())
