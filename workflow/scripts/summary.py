"""Rule summary: results/summary.md with the headline numbers of every stage, and
results/datasheet.md, the realised design's datasheet."""

import json

import pandas as pd

from qsm.physics.workspace import operating_reach
from qsm.realization.kit.kit_hardware import mass_kg, moving_mass_kg
from qsm.report.datasheet import datasheet_markdown
from qsm.report.envelope_figure import envelope_figure
from qsm.report.headline import headline_markdown
from qsm.report.kit_report import kit_markdown
from qsm.report.readiness import failures, verdict_lines, verdict_sentence
from qsm.workflow.logs import logged
from qsm.workflow.tables import read_table

with logged(snakemake.log[0]) as log:
    inp = snakemake.input
    out = snakemake.output
    loaded = {}
    keys = ("filters", "status", "metrics", "comparison", "selected", "torques", "payload")
    for key in (*keys, "topology"):
        with open(inp[key]) as fh:
            loaded[key] = json.load(fh)
    with open(inp.bom) as fh:
        bom = fh.read()
    text = headline_markdown(findings=read_table(inp.findings), bom=bom, **loaded)
    with open(inp.kit) as fh:
        kit = json.load(fh)
    text += "\n" + kit_markdown(kit)
    with open(out.summary, "w") as fh:
        fh.write(text)
    records = (loaded["selected"], loaded["topology"], loaded["payload"])
    verdict = (verdict_sentence(*records), verdict_lines(failures(*records)))
    params = snakemake.params
    reach = operating_reach(
        loaded["selected"]["design_m"], params.theta1_deg, params.theta2_min_deg
    )
    hardware_kg = (mass_kg(kit["layout"].get("hardware", {})), moving_mass_kg(kit["layout"]))
    sheet = datasheet_markdown(
        loaded["selected"], pd.read_csv(inp.bom_csv), params.density_kg_m3, verdict, reach,
        hardware_kg,
    )  # fmt: skip
    with open(out.datasheet, "w") as fh:
        fh.write(sheet)
    limits = (params.theta1_deg, params.theta2_min_deg)
    envelope_figure(loaded["selected"], reach, limits, out.envelope)
    log.info("wrote the summary and the datasheet")
