"""Rule correlations: Spearman and Pearson coefficients on the 400 designs."""

from qsm.design_rules.correlations import FEATURES_MM, OBJECTIVES, correlations
from qsm.design_rules.plots import correlation_figure
from qsm.workflow.logs import logged
from qsm.workflow.tables import read_table, write_table

with logged(snakemake.log[0]) as log:
    alpha = snakemake.params.alpha
    designs = read_table(snakemake.input.designs, [*FEATURES_MM, *OBJECTIVES])
    table = correlations(designs, FEATURES_MM, list(OBJECTIVES))
    write_table(table, snakemake.output.table, {"n_designs": len(designs)})
    correlation_figure(table, FEATURES_MM, list(OBJECTIVES), alpha, snakemake.output.figure)
    tau = table[(table["a"] == "tau1_pred_Nm") & (table["b"] == "tau2_pred_Nm")].iloc[0]
    log.info("Pearson(tau1, tau2) = %.3f on %d designs", tau["pearson"], len(designs))
