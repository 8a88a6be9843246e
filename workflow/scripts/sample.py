"""Rule sample: Latin-hypercube samples of the unit-mechanism ratios, written a million rows at
a time."""

from qsm.mechanisms.sampling import lhs_batches
from qsm.workflow.logs import logged
from qsm.workflow.tables import settings_hash, write_batches

with logged(snakemake.log[0]) as log:
    sampling = snakemake.params.sampling
    batches = lhs_batches(sampling["n_samples"], sampling["bounds"], sampling["seed"])
    meta = {"settings_hash": settings_hash(sampling)}
    rows = write_batches(batches, snakemake.output[0], meta)
    log.info("wrote %d LHS samples (seed %d)", rows, sampling["seed"])
