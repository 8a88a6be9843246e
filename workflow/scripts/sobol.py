"""Rule sobol: Sobol indices of the surrogate's eta, tau1, tau2 over the optimisation bounds."""

from qsm.dataset.gathering import OK_ROWS, ok_rows
from qsm.design_rules.plots import sobol_figure
from qsm.design_rules.sensitivity import sobol_indices
from qsm.optimization.nsga import bounds_from
from qsm.optimization.ranking import OPTIMISATION_COLUMNS
from qsm.physics.kinematics import DESIGN_NAMES
from qsm.surrogate.model import INPUTS, load
from qsm.workflow.logs import logged
from qsm.workflow.tables import read_table, write_table

OUTPUTS = ["eta", "tau1", "tau2"]

with logged(snakemake.log[0]) as log:
    p = snakemake.params
    out = snakemake.output
    model = load(snakemake.input.model)
    dataset = ok_rows(
        read_table(snakemake.input.dataset, OPTIMISATION_COLUMNS, only=True, where=OK_ROWS)
    )
    lo, hi = bounds_from(dataset, INPUTS, p.bounds)
    result = sobol_indices(
        model.predict,
        list(DESIGN_NAMES),
        list(zip(lo, hi, strict=True)),
        OUTPUTS,
        p.sobol_n,
        p.seed,
    )
    write_table(result.indices, out.indices, {"n_evaluations": result.n_evaluations})
    sobol_figure(result.indices, OUTPUTS, out.figure)
    log.info("Sobol indices from %d surrogate evaluations", result.n_evaluations)
