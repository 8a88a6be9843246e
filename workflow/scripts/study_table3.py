"""Rule study_table3: Table 3's torque reduction against the payload / link-mass ratio."""

import json

import numpy as np

from qsm.config.settings import physics
from qsm.design_rules.experiments import table3_sweep
from qsm.design_rules.plots import table3_figure
from qsm.design_rules.study import PAPER_TABLE3_PCT
from qsm.physics.duty import duty_cycle
from qsm.realization.selection.outputs import props_from_json
from qsm.workflow.logs import logged
from qsm.workflow.tables import write_table

with logged(snakemake.log[0]) as log:
    p = snakemake.params
    out = snakemake.output
    with open(snakemake.input.selected) as fh:
        design = np.asarray(json.load(fh)["design_m"])
    with open(snakemake.input.links) as fh:
        optimized = props_from_json(json.load(fh))
    duty = duty_cycle(physics.duty(p.duty, p.operating_range))
    sweep = table3_sweep(design, physics.cad(p.cad, p.material), duty, optimized, p.payloads_kg)
    write_table(sweep, out.table)
    run_ratio = p.payload_kg / sweep["link_mass_kg"].iloc[0]
    table3_figure(sweep, PAPER_TABLE3_PCT, run_ratio, out.figure)
    for row in sweep.itertuples():
        log.info(
            "payload %.2f kg (payload / links %.2f): reduction tau1 %.2f %%, tau2 %.2f %%",
            row.payload_kg,
            row.payload_to_link_mass,
            row.tau1_reduction_pct,
            row.tau2_reduction_pct,
        )
