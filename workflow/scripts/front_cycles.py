"""Rule front_cycles: the task's time-optimal cycle of every design of one verified front."""

import numpy as np

from qsm.config.settings import actuation, links, simulation
from qsm.physics.kinematics import DESIGN_COLUMNS
from qsm.physics.task_points import TaskCycle
from qsm.realization.motion.front_cycles import CYCLE_COLUMNS, front_cycles
from qsm.workflow.logs import logged
from qsm.workflow.tables import read_table, write_table

with logged(snakemake.log[0]) as log:
    p = snakemake.params
    case = links.load_case(p.load_case)
    (lo, hi), theta2_min = case.operating_range_deg
    op = {"theta1_deg": [lo, hi], "theta2_min_deg": theta2_min}
    test = simulation.payload_test(p.payload_test, case.payload_kg, op)
    check = links.strength_check(case, p.strength)
    catalogue = actuation.drive_check(p.drives, case).catalogue
    verified = read_table(snakemake.input.verification)
    cycles = front_cycles(verified, check, catalogue, TaskCycle(**p.cycle), test)
    table = verified[list(DESIGN_COLUMNS)].join(cycles)
    write_table(table, snakemake.output.cycles, {"columns": CYCLE_COLUMNS})
    planned = np.isfinite(cycles["time_optimal_cycle_s"])
    log.info(
        "%d of %d designs planned; fastest %.2f s",
        planned.sum(),
        len(cycles),
        cycles["time_optimal_cycle_s"].min() if planned.any() else float("nan"),
    )
