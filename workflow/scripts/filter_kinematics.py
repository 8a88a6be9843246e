"""Rule filter_kinematics: crank-rocker, loop closure and transmission-angle filters, on the
samples a million rows at a time."""

from qsm.config.settings import physics
from qsm.mechanisms.filters import filter_batches
from qsm.physics.kinematics import RATIO_NAMES
from qsm.workflow.json_files import write_json
from qsm.workflow.logs import logged
from qsm.workflow.tables import read_batches, write_table

with logged(snakemake.log[0]) as log:
    p = snakemake.params
    samples = read_batches(snakemake.input[0], ["sample_id", *RATIO_NAMES])
    op = physics.operating_range(p.operating_range)
    angle = p.filters["min_transmission_angle_deg"]
    candidates, counts = filter_batches(samples, op, angle)
    for step, n in counts.items():
        log.info("%-20s %7d", step, n)
    write_table(candidates, snakemake.output.candidates)
    write_json(snakemake.output.counts, counts)
