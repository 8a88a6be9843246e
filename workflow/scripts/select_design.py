"""Rule select_design: the design to realise, printable if any is, truly feasible always."""

import matplotlib.pyplot as plt
import numpy as np

from qsm.embodiment.advice import advice_sentences as strength_sentences
from qsm.embodiment.advice import strength_advice
from qsm.embodiment.printing import advice_sentence, smallest_build_volume
from qsm.embodiment.verdict import strength_record, strength_verdict
from qsm.mechanisms.dataset import DATASET_COLUMNS, ok_rows
from qsm.physics.clearance import disk_clearance_m
from qsm.physics.mirror import task_record
from qsm.physics.task import min_enclosing_circle
from qsm.realization.export import selection_record
from qsm.realization.selection import (
    advice_sentences,
    candidate_pool,
    choose_design,
    printing_advice,
)
from qsm.report.drive_text import drive_sentences
from qsm.report.figures import draw_design
from qsm.settings import actuation, links, physics
from qsm.workflow.json_files import write_json
from qsm.workflow.logs import logged
from qsm.workflow.tables import read_table

with logged(snakemake.log[0]) as log:
    p = snakemake.params
    inp = snakemake.input
    out = snakemake.output
    fronts = {name: read_table(path) for name, path in zip(p.formulations, inp.fronts, strict=True)}
    dataset = ok_rows(read_table(inp.dataset, DATASET_COLUMNS))
    rule = p.printing["selection_rule"]
    cad = physics.cad(p.cad, p.material)
    volume = tuple(p.printing["build_volume_mm"])
    disk = min_enclosing_circle(p.task_points)
    row, how = choose_design(fronts, p.primary, dataset, rule, cad, volume)
    record = selection_record(row)
    record.update(how)
    record["task"] = task_record(p.user_points)
    mirrored = record["task"]["mirrored"]
    if mirrored:
        log.info("mirrored: %s", record["task"]["note"])
    for line in how["fallback"]:
        log.warning("skipped: %s", line)
    op = physics.operating_range(p.operating_range)
    record["clearance_m"] = disk_clearance_m(record["design_m"], op, disk)
    check = links.strength_check(
        p.cad, p.material, p.strength, p.payload_kg, physics.duty(p.duty, p.operating_range)
    )
    record["strength"] = strength_record(record["design_m"], check)
    drives = actuation.drive_check(
        p.drives, p.cad, p.material, p.payload_kg, physics.duty(p.duty, p.operating_range)
    )
    sized = check.section_scales(record["design_m"])
    record["drives"] = drives.report(record["design_m"], None if sized is None else sized.scale)
    verdicts = []
    if not how["holds_loads"]:
        advice = strength_advice(record["design_m"], check)
        record["strength_advice"] = advice
        verdicts.append(
            strength_verdict(record["strength"])
            + ", and no design of the fronts or the dataset holds its loads. What would change "
            + "that: "
            + "; ".join(strength_sentences(advice, check))
        )
    if not record["drives"]["has_drives"]:
        verdicts.append(
            "NO DRIVE for each motor in the catalogue"
            + ("" if how["has_drives"] else ", for any design of the fronts or the dataset")
            + ": "
            + "; ".join(drive_sentences(record["drives"]))
        )
    if not how["printable"]:
        advice = printing_advice(record["design_m"], cad, volume, disk)
        pool = candidate_pool(fronts, dataset)
        strong = pool["holds_loads"].astype(bool)
        advice["smallest_over_designs"] = smallest_build_volume(
            pool, strong if how["holds_loads"] else np.ones(len(pool), bool), cad
        )
        record["printing_advice"] = advice
        verdicts.append(
            "NOT PRINTABLE on the configured printer: no design of the fronts or the dataset "
            + ("that holds its loads " if how["holds_loads"] else "")
            + "fits it. What would change that: "
            + "; ".join(
                [
                    advice_sentence(advice["smallest_over_designs"], volume),
                    *advice_sentences(advice, cad)[1:],
                ]
            )
        )
    if verdicts:
        record["verdict"] = ". ".join(verdicts) + "."
        log.warning(record["verdict"])
    else:
        record["verdict"] = (
            f"printable on {' x '.join(f'{v:g}' for v in volume)} mm, every link holds its loads "
            f"({strength_verdict(record['strength'])}), each motor has a drive "
            f"({'; '.join(drive_sentences(record['drives']))}), chosen from the "
            f"{how['source']} {'designs' if how['source'] == 'dataset' else 'front'}"
        )
    write_json(out.selected, record)
    fig, ax = plt.subplots(figsize=(6, 6))
    title = (
        f"selected ({rule}, {record['formulation']}"
        f"{'' if how['printable'] else ', NOT PRINTABLE'}"
        f"{'' if how['holds_loads'] else ', NOT STRONG ENOUGH'}"
        f"{'' if record['drives']['has_drives'] else ', NO DRIVES'}"
        f"{', designed MIRRORED (x -> -x)' if mirrored else ''}): "
        f"l1 {record['scale_m']:.3f} m\n"
        f"eta {record['eta_true']:.3f}, tau1 {record['tau1_true_Nm']:.1f} N m, "
        f"tau2 {record['tau2_true_Nm']:.1f} N m"
    )
    draw_design(ax, record["design_m"], op, disk, title)
    fig.savefig(out.figure, dpi=110, bbox_inches="tight")
    plt.close(fig)
    log.info("selected %s: %s", record["design_m"], record["verdict"])
