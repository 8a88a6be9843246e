"""Rule front_cycles: the task's time-optimal cycle of every design of one verified front."""

import numpy as np

from qsm.config.settings.simulation import cycles_of
from qsm.physics.kinematics import DESIGN_COLUMNS
from qsm.physics.task_points import TaskCycle
from qsm.realization.motion.front_cycles import CYCLE_COLUMNS, front_cycles
from qsm.workflow.logs import logged
from qsm.workflow.tables import read_table, write_table

with logged(snakemake.log[0]) as log:
    p = snakemake.params
    s = cycles_of(p.cycles)
    verified = read_table(snakemake.input.verification)
    cycles = front_cycles(verified, s.strength, s.catalogue, TaskCycle(**p.cycle), s.test)
    table = verified[list(DESIGN_COLUMNS)].join(cycles)
    write_table(table, snakemake.output.cycles, {"columns": CYCLE_COLUMNS})
    planned = np.isfinite(cycles["time_optimal_cycle_s"])
    log.info(
        "%d of %d designs planned; fastest %.2f s",
        planned.sum(),
        len(cycles),
        cycles["time_optimal_cycle_s"].min() if planned.any() else float("nan"),
    )
