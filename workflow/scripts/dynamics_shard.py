"""Rule dynamics: Stage 2 (closed-chain dynamics, link strength, drives, tool sag) of one shard of
the mechanisms."""

from qsm.config.settings.dataset import dataset_of
from qsm.dataset.evaluation import evaluate_shard
from qsm.dataset.gathering import status_counts
from qsm.mechanisms.scale import MECHANISM_COLUMNS
from qsm.workflow.logs import logged
from qsm.workflow.sharding import shard_slice
from qsm.workflow.tables import read_table, write_table

with logged(snakemake.log[0]) as log:
    p = snakemake.params
    shard = int(snakemake.wildcards.shard)
    mechanisms = read_table(snakemake.input[0], MECHANISM_COLUMNS)
    rows = mechanisms.iloc[shard_slice(len(mechanisms), p.shards, shard)]
    result = evaluate_shard(rows, dataset_of(p.dataset))  # p.dataset: Stage 2's share of the config
    log.info(
        "shard %d of %d: %d mechanisms, status %s, %d hold their loads, %d have drives",
        shard,
        p.shards,
        len(result),
        status_counts(result),
        int(result["holds_loads"].sum()),
        int(result["has_drives"].sum()),
    )
    write_table(result, snakemake.output[0])
