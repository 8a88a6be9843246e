"""Rule topology_optimize: SIMP on the arm plates, the bored parts to build (STL files, drawing,
bill of materials), torques again."""

import json
from pathlib import Path

from qsm.config.settings import links, plates, realization
from qsm.realization.kit.build import build_links
from qsm.realization.selection.machine import realization_from_record
from qsm.realization.selection.outputs import props_to_json, torques_markdown
from qsm.report.drawing import draw_links
from qsm.report.topology_figure import plot_links
from qsm.workflow.json_files import write_json
from qsm.workflow.logs import logged

with logged(snakemake.log[0]) as log:
    p = snakemake.params
    inp = snakemake.input
    out = snakemake.output
    r = p.realization  # the realisation's share of the config
    case = links.load_case_of(r)
    settings = realization.realization_of(r)
    done = realization_from_record(json.loads(Path(inp.machine).read_text()), settings)
    folder = out.bom_csv.rsplit("/", 1)[0]
    topo = plates.topology(p.topology, r["material"], r["strength"])
    volume = tuple(r["printing"]["build_volume_mm"])
    drawing = {"svg": out.drawing, "png": out.drawing_png}
    material = case.material.name
    kit = realization.kit(case.operating_range, r["drives"], settings.accuracy)
    carried = case.payload_kg + done.tool_kg  # the payload and the tool flange at E
    built = build_links(done, carried, case.cycle(), topo, material, folder, volume, drawing, kit)
    draw_links(done.design, built.parts, f"{folder}/drawing")  # as built, openings included
    write_json(out.kit, built.kit.record)
    log.info("builder's kit: checks %s", built.kit.record["checks"])
    write_json(out.torques, built.torques)
    with open(out.table, "w") as fh:
        fh.write(torques_markdown(built.torques))
    write_json(out.stl_check, built.stl_checks)
    write_json(out.topology, built.record)
    write_json(out.links, props_to_json(built.props))
    plot_links(built.topology, out.figure)
    for name, s in built.record["links"].items():
        log.info(
            "%s: mass %.3f -> %.3f kg, peak von Mises %.1f MPa (allowable %.1f), carries loads %s, "
            "%s; attempts %s",
            *(name, s["mass_before_kg"], s["mass_after_kg"], s["max_von_mises_after_MPa"]),
            *(s["allowable_stress_MPa"], s["carries_loads"]),
            "solid plate kept" if s["kept_solid"] else "optimised plate kept",
            s["attempts"],
        )
    log.info("torques %s", built.torques)
