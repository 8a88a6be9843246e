"""Rule gather_dataset: join the mechanisms with the dynamics of every shard; check coverage."""

from qsm.dataset.columns import DATASET_COLUMNS, DRIVE_COLUMNS, DYNAMICS_COLUMNS, STRENGTH_COLUMNS
from qsm.dataset.gathering import drive_counts, gather, status_counts, strength_counts
from qsm.mechanisms.scale import MECHANISM_COLUMNS
from qsm.workflow.json_files import write_json
from qsm.workflow.logs import logged
from qsm.workflow.tables import read_table, settings_hash, write_table

with logged(snakemake.log[0]) as log:
    p = snakemake.params
    inp = snakemake.input
    mechanisms = read_table(inp.mechanisms, MECHANISM_COLUMNS)
    columns = ["mechanism_id", *DYNAMICS_COLUMNS, *STRENGTH_COLUMNS, *DRIVE_COLUMNS]
    shards = [read_table(path, columns) for path in inp.shards]
    dataset = gather(mechanisms, shards)
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
    meta = {
        "settings_hash": settings_hash(p.settings),
        "settings": p.settings,
        "columns": DATASET_COLUMNS,
    }
    write_table(dataset, snakemake.output.dataset, meta)
    summary = {"mechanisms": len(dataset), "status": counts, "strength": strength}
    summary["drives"] = drives
    summary["failures"] = {
        str(row.mechanism_id): f"{row.status}: {row.status_reason}" for row in failed.itertuples()
    }
    write_json(snakemake.output.status, summary)
