"""Rule filter_kinematics: crank-rocker, loop closure and transmission-angle filters, on the
samples a million rows at a time, the candidates written as they are found."""

from qsm.config.settings import physics
from qsm.mechanisms.filters import added, filter_batches
from qsm.physics.kinematics import RATIO_NAMES
from qsm.workflow.json_files import write_json
from qsm.workflow.logs import logged
from qsm.workflow.tables import read_batches, write_batches

with logged(snakemake.log[0]) as log:
    p = snakemake.params
    samples = read_batches(snakemake.input[0], ["sample_id", *RATIO_NAMES])
    op = physics.operating_range(p.operating_range)
    angle = p.filters["min_transmission_angle_deg"]
    counts: dict[str, int] = {}

    def candidates():
        """Each batch's candidates, its counts added to ``counts`` as it is written."""
        for kept, batch_counts in filter_batches(samples, op, angle):
            counts.update(added(counts, batch_counts))
            yield kept

    write_batches(candidates(), snakemake.output.candidates)
    for step, n in counts.items():
        log.info("%-20s %7d", step, n)
    write_json(snakemake.output.counts, counts)
