"""Rule select_mechanisms: gather the shards (fitting on where they fell short), keep the first n
feasible designs, count filters."""

import json

import pandas as pd

from qsm.config.settings import physics
from qsm.mechanisms.scale import (
    FIT_COLUMNS,
    MECHANISM_COLUMNS,
    fit_counts,
    gathered_fits,
    select_mechanisms,
)
from qsm.physics.kinematics import RATIO_NAMES
from qsm.workflow.json_files import write_json
from qsm.workflow.logs import logged
from qsm.workflow.tables import read_table, settings_hash, write_table

with logged(snakemake.log[0]) as log:
    p = snakemake.params
    fits = pd.concat(
        [read_table(f, FIT_COLUMNS, only=True) for f in snakemake.input.fits], ignore_index=True
    )
    path = snakemake.input.candidates
    ids = read_table(path, ["sample_id"], only=True)["sample_id"].to_numpy()

    def candidates_after(last: int) -> pd.DataFrame:
        """The candidates (sample id, ratios) of sample id above ``last``."""
        return read_table(path, ["sample_id", *RATIO_NAMES], True, [("sample_id", ">", last)])

    fit = physics.scale_up(p.mechanisms)  # p.mechanisms: Stage 1's share of the config
    fits = gathered_fits(fits, ids, candidates_after, p.n_mechanisms, fit)
    with open(snakemake.input.counts) as fh:
        counts = json.load(fh)
    counts.update(fit_counts(fits))
    if counts["task_fits"] == 0:
        sides = {x > 0 for x, _ in p.mechanisms["task_points"]}
        raise ValueError(
            "no design holds the task: check config key 'task.points' (the workspace of this "
            "family lies on one side of the base, x < 0, and a task at x > 0 is designed as its "
            "mirror image"
            + (
                "; these points lie on both sides, and no design's workspace holds their whole "
                "enclosing disk: keep the task on one side"
                if len(sides) == 2
                else ""
            )
            + ") and 'scale.max_m'"
        )
    table = select_mechanisms(fits, p.n_mechanisms)
    counts["selected"] = len(table)
    counts["requested"] = p.n_mechanisms
    counts["shortfall"] = p.n_mechanisms - len(table)
    if counts["shortfall"] > 0:
        log.warning(
            "only %d feasible designs for the %d requested: no filter was loosened",
            len(table),
            p.n_mechanisms,
        )
    for step, n in counts.items():
        log.info("%-20s %s", step, n)
    meta = {
        "settings_hash": settings_hash(p.mechanisms),
        "settings": p.mechanisms,
        "columns": MECHANISM_COLUMNS,
    }
    write_table(table, snakemake.output.mechanisms, meta)
    write_json(snakemake.output.report, counts)
