"""Rule dynamics: closed-chain inverse dynamics, link strength and drives of one shard of the
mechanisms."""

import numpy as np

from qsm.config.settings import actuation, links
from qsm.embodiment.drives.drive_checks import with_embodiment
from qsm.mechanisms.dataset import status_counts
from qsm.mechanisms.evaluation import evaluate_table
from qsm.mechanisms.scale import MECHANISM_COLUMNS
from qsm.physics.kinematics import DESIGN_COLUMNS
from qsm.workflow.logs import logged
from qsm.workflow.sharding import shard_slice
from qsm.workflow.tables import read_table, write_table

with logged(snakemake.log[0]) as log:
    p = snakemake.params
    shard = int(snakemake.wildcards.shard)
    mechanisms = read_table(snakemake.input[0], MECHANISM_COLUMNS)
    case = links.load_case(p.load_case)
    rows = mechanisms.iloc[shard_slice(len(mechanisms), p.shards, shard)]
    designs = rows[list(DESIGN_COLUMNS)].to_numpy(float)
    check = links.strength_check(case, p.strength)
    sized = check.section_scales(designs)  # None: the fixed section
    scales = None if sized is None else sized.scale
    result = evaluate_table(rows, check.duty, case.cad, case.payload_kg, scales=scales)
    result = result.reset_index(drop=True)
    drives = actuation.drive_check(p.drives, case)
    result = with_embodiment(result, designs, check, drives, sized)
    sag = links.sag_check(case, p.task_points)
    ok = result["status"].eq("ok").to_numpy()
    result["tool_sag_mm"] = np.where(ok, sag.sag_mm(designs), np.nan)  # the configured section
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
