"""Rule select_design: the printable, truly feasible Pareto design chosen by the config's rule."""

import json

import matplotlib.pyplot as plt

from qsm.dataset import cad_settings
from qsm.logs import logged
from qsm.plots import draw_design
from qsm.realization import select_printable, selection_record
from qsm.tables import read_table
from qsm.task import min_enclosing_circle
from qsm.workspace import OperatingRange

with logged(snakemake.log[0]) as log:  # noqa: F821
    p = snakemake.params  # noqa: F821
    inp = snakemake.input  # noqa: F821
    out = snakemake.output  # noqa: F821
    fronts = {"paper": read_table(inp.paper), "ratios": read_table(inp.ratios)}
    rule = p.printing["selection_rule"]
    row, fallback = select_printable(
        fronts, p.primary, rule, cad_settings(p.cad), tuple(p.printing["build_volume_mm"])
    )
    record = selection_record(row)
    record["fallback"] = fallback
    if fallback:
        log.warning("chose from the %s front because %s", record["formulation"], fallback)
    with open(out.selected, "w") as fh:
        json.dump(record, fh, indent=2)
    op = OperatingRange.from_degrees(
        p.operating_range["theta1_deg"], p.operating_range["theta2_min_deg"]
    )
    fig, ax = plt.subplots(figsize=(6, 6))
    title = (
        f"selected ({rule}, {record['formulation']} front): l1 {record['scale_m']:.3f} m\n"
        f"eta {record['eta_true']:.3f}, tau1 {record['tau1_true_Nm']:.1f} N m, "
        f"tau2 {record['tau2_true_Nm']:.1f} N m"
    )
    draw_design(ax, record["design_m"], op, min_enclosing_circle(p.task_points), title)
    fig.savefig(out.figure, dpi=110, bbox_inches="tight")
    plt.close(fig)
    log.info("selected %s among %d candidates", record["design_m"], record["n_candidates"])
