"""Rule plot_dynamics: eta against the motor torques, coloured by scale (paper Fig. 11)."""

from qsm.dataset.gathering import ok_rows
from qsm.report.figures import performance_figure
from qsm.workflow.logs import logged
from qsm.workflow.tables import read_table

with logged(snakemake.log[0]) as log:
    needed = ["status", "eta", "tau1_Nm", "tau2_Nm", "scale_m"]  # the only columns read
    dataset = read_table(snakemake.input[0], needed, only=True)
    ok = ok_rows(dataset)
    performance_figure(ok, snakemake.output[0])
    log.info("drew %d of %d mechanisms (status ok)", len(ok), len(dataset))
