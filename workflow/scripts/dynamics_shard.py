"""Rule dynamics: closed-chain inverse dynamics of one shard of the mechanisms."""

from qsm import settings
from qsm.mechanisms.dataset import status_counts
from qsm.mechanisms.scale import MECHANISM_COLUMNS
from qsm.physics.dynamics import evaluate_shard
from qsm.workflow.logs import logged
from qsm.workflow.tables import read_table, write_table

with logged(snakemake.log[0]) as log:  # noqa: F821
    p = snakemake.params  # noqa: F821
    shard = int(snakemake.wildcards.shard)  # noqa: F821
    mechanisms = read_table(snakemake.input[0], MECHANISM_COLUMNS)  # noqa: F821
    result = evaluate_shard(
        mechanisms,
        p.shards,
        shard,
        settings.cad(p.cad),
        settings.duty(p.duty, p.operating_range),
        p.payload_kg,
    )
    log.info(
        "shard %d of %d: %d mechanisms, status %s",
        shard,
        p.shards,
        len(result),
        status_counts(result),
    )
    write_table(result, snakemake.output[0])  # noqa: F821
