"""Rule filter_kinematics: crank-rocker, loop closure and transmission-angle filters."""

from qsm.config.settings import physics
from qsm.mechanisms.filters import kinematic_filters
from qsm.physics.kinematics import RATIO_NAMES
from qsm.workflow.json_files import write_json
from qsm.workflow.logs import logged
from qsm.workflow.tables import read_table, write_table

with logged(snakemake.log[0]) as log:
    p = snakemake.params
    samples = read_table(snakemake.input[0], ["sample_id", *RATIO_NAMES])
    op = physics.operating_range(p.operating_range)
    candidates, counts = kinematic_filters(samples, op, p.filters["min_transmission_angle_deg"])
    for step, n in counts.items():
        log.info("%-20s %7d", step, n)
    write_table(candidates, snakemake.output.candidates)
    write_json(snakemake.output.counts, counts)
