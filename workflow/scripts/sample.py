"""Rule sample: Latin-hypercube samples of the unit-mechanism ratios."""

from qsm.mechanisms.sampling import latin_hypercube
from qsm.workflow.logs import logged
from qsm.workflow.tables import settings_hash, write_table

with logged(snakemake.log[0]) as log:
    sampling = snakemake.params.sampling
    table = latin_hypercube(sampling["n_samples"], sampling["bounds"], sampling["seed"])
    write_table(table, snakemake.output[0], {"settings_hash": settings_hash(sampling)})
    log.info("wrote %d LHS samples (seed %d)", len(table), sampling["seed"])
