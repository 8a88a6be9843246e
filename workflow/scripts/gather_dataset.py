"""Rule gather_dataset: join the mechanisms with the dynamics of every shard, shard by shard;
check coverage."""

from qsm.dataset.columns import (
    DATASET_COLUMNS,
    DRIVE_COLUMNS,
    DYNAMICS_COLUMNS,
    STRENGTH_COLUMNS,
)
from qsm.dataset.gathering import (
    COUNTED_COLUMNS,
    check_coverage,
    drive_counts,
    gather,
    gathered_batches,
    status_counts,
    strength_counts,
)
from qsm.mechanisms.scale import MECHANISM_COLUMNS
from qsm.workflow.json_files import write_json
from qsm.workflow.logs import logged
from qsm.workflow.tables import (
    read_table,
    settings_hash,
    table_schema,
    write_batches,
    write_table,
)

with logged(snakemake.log[0]) as log:
    p = snakemake.params
    inp = snakemake.input
    out = snakemake.output
    mechanisms = read_table(inp.mechanisms, MECHANISM_COLUMNS)
    columns = ["mechanism_id", *DYNAMICS_COLUMNS, *STRENGTH_COLUMNS, *DRIVE_COLUMNS]
    ids = [read_table(path, ["mechanism_id"], only=True)["mechanism_id"] for path in inp.shards]
    in_order = check_coverage(mechanisms["mechanism_id"], ids)
    meta = {
        "settings_hash": settings_hash(p.settings),
        "settings": p.settings,
        "columns": DATASET_COLUMNS,
    }
    if in_order:  # shard by shard: the job holds one shard's rows, not the dataset
        shards = (read_table(path, columns) for path in inp.shards)
        schema = table_schema([inp.mechanisms, *inp.shards], DATASET_COLUMNS)
        write_batches(gathered_batches(mechanisms, shards), out.dataset, meta, schema)
    else:
        shards = [read_table(path, columns) for path in inp.shards]
        write_table(gather(mechanisms, shards), out.dataset, meta)
    dataset = read_table(out.dataset, COUNTED_COLUMNS, only=True)
    counts = status_counts(dataset)
    failed = dataset.loc[dataset["status"] != "ok"]
    for status, group in failed.groupby("status"):
        log.warning(
            "%d mechanisms %s, e.g. id %d: %s",
            len(group),
            status,
            group["mechanism_id"].iloc[0],
            group["status_reason"].iloc[0],
        )
    strength = strength_counts(dataset)
    drives = drive_counts(dataset)
    log.info(
        "dataset: %d mechanisms, status %s, strength %s, drives %s",
        len(dataset),
        counts,
        strength,
        drives,
    )
    summary = {"mechanisms": len(dataset), "status": counts, "strength": strength}
    summary["drives"] = drives
    summary["failures"] = {
        str(row.mechanism_id): f"{row.status}: {row.status_reason}" for row in failed.itertuples()
    }
    write_json(snakemake.output.status, summary)
