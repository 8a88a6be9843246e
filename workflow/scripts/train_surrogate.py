"""Rule train_surrogate: fit the MLP, write the model (JSON), metrics and parity plots."""

from qsm.config.settings import surrogate
from qsm.dataset.gathering import OK_ROWS, ok_rows
from qsm.report.figures import parity_figure
from qsm.surrogate.model import INPUTS, OUTPUTS, metrics_markdown, train
from qsm.workflow.json_files import write_json
from qsm.workflow.logs import logged
from qsm.workflow.tables import read_table

with logged(snakemake.log[0]) as log:
    out = snakemake.output
    surrogate_settings = surrogate.surrogate(snakemake.params.surrogate)
    needed = ["status", *INPUTS, *OUTPUTS]  # of the dataset's columns, the only ones read
    dataset = ok_rows(read_table(snakemake.input[0], needed, only=True, where=OK_ROWS))
    x = dataset[list(INPUTS)].to_numpy()
    y = dataset[list(OUTPUTS)].to_numpy()
    log.info("training on %d designs (status ok) with %s", len(x), surrogate_settings)
    result = train(x, y, surrogate_settings)
    result.model.save(out.model)
    write_json(out.metrics, result.metrics)
    with open(out.table, "w") as fh:
        fh.write(metrics_markdown(result.metrics))
    parity_figure(
        y[result.test_index],
        result.test_prediction,
        ["eta", "tau1 (N m)", "tau2 (N m)"],
        out.parity,
    )
    log.info(
        "test R^2 %s after %d epochs, %.1f s",
        result.metrics["test"]["r2"],
        result.metrics["epochs"],
        result.metrics["fit_seconds"],
    )
