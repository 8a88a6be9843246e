"""Rule fit_task: workspace, minimal scale factor and eta for one shard of the candidates: every
``shards``-th from the shard's number, until its share of the selection is found."""

from qsm.config.settings import physics
from qsm.mechanisms.scale import fit_designs, shard_quota
from qsm.physics.kinematics import RATIO_NAMES
from qsm.workflow.logs import logged
from qsm.workflow.tables import read_table, write_table

with logged(snakemake.log[0]) as log:
    p = snakemake.params
    shard = int(snakemake.wildcards.shard)
    candidates = read_table(snakemake.input[0], ["sample_id", *RATIO_NAMES])
    rows = candidates.iloc[shard :: p.shards]
    log.info("shard %d of %d: %d designs", shard, p.shards, len(rows))
    fit = physics.scale_up(p.mechanisms)  # p.mechanisms: Stage 1's share of the config
    fits = fit_designs(rows, fit, stop_after=shard_quota(p.n_mechanisms, p.shards))
    write_table(fits, snakemake.output[0])
