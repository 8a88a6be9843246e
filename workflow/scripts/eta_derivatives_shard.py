"""Rule eta_derivatives_shard: d eta / d x of the true eta for one shard of the mechanisms."""

from qsm.config.settings import physics
from qsm.design_rules.eta_derivatives import eta_gradients, sampled_rows
from qsm.mechanisms.scale import MECHANISM_COLUMNS
from qsm.physics.task import min_enclosing_circle
from qsm.physics.workspace import Resolution
from qsm.workflow.logs import logged
from qsm.workflow.sharding import shard_slice
from qsm.workflow.tables import read_table, write_table

with logged(snakemake.log[0]) as log:
    p = snakemake.params
    shard = int(snakemake.wildcards.shard)
    table = read_table(snakemake.input[0], MECHANISM_COLUMNS)
    table = table.iloc[sampled_rows(len(table), p.most_designs, p.seed)]
    rows = table.iloc[shard_slice(len(table), p.shards, shard)]
    op = physics.operating_range(p.operating_range)
    res = Resolution(p.resolution["n_delta"], p.resolution["n_levels"])
    grads = eta_gradients(rows, op, min_enclosing_circle(p.task_points), res, p.step)
    write_table(grads, snakemake.output[0])
    log.info(
        "shard %d of %d: derivatives of %d of the %d mechanisms sampled",
        shard, p.shards, len(grads), len(table),
    )  # fmt: skip
