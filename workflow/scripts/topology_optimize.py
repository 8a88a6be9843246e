"""Rule topology_optimize: SIMP on the arm plates, the bored parts to build (STL files, drawing,
bill of materials), torques again."""

import json
from dataclasses import replace

import numpy as np

from qsm.embodiment.parts import link_parts, part_meshes
from qsm.physics.duty import duty_cycle
from qsm.realization.assembly import bearing_rows, final_parts, write_parts
from qsm.realization.export import export_stls, props_to_json, section_scale, torques_markdown
from qsm.realization.geometry import extrude
from qsm.realization.topology import optimise_links
from qsm.realization.topology_figure import plot_links
from qsm.realization.torques import torques_before_after
from qsm.report.drawing import draw_links
from qsm.settings import links, physics, topology
from qsm.workflow.json_files import write_json
from qsm.workflow.logs import logged

with logged(snakemake.log[0]) as log:
    p = snakemake.params
    out = snakemake.output
    with open(snakemake.input.selected) as fh:
        selected = json.load(fh)
    design = np.asarray(selected["design_m"])
    cad = physics.cad(p.cad, p.material)
    duty = duty_cycle(physics.duty(p.duty, p.operating_range))
    topo = topology.topology(p.topology, p.material, p.strength)
    scale = section_scale(selected["strength"], cad)  # each link's checked section
    result = optimise_links(design, cad, p.payload_kg, duty, topo, scale=scale)
    part_settings = replace(links.parts(p.cad, p.material, p.strength), scale=scale)
    names = {j: b["designation"] for j, b in selected["strength"]["bearings"].items()}
    rows = bearing_rows(names, part_settings.table)
    solid = link_parts(design, rows, part_settings)
    held = {
        name: link.polygon
        for name, link in result.links.items()
        if link.carries_loads and not link.kept_solid
    }
    parts = final_parts(design, rows, part_settings, held)
    written = write_parts(
        parts,
        rows,
        part_settings,
        p.material["name"],
        {name: name in held for name in parts},
        out.bom_csv.rsplit("/", 1)[0],
        selected.get("drives"),
    )
    svg, png = draw_links(design, solid, f"{out.bom_csv.rsplit('/', 1)[0]}/drawing")
    written["drawing"] = {"svg": str(svg), "png": str(png)}
    written["section_mm"] = {  # each part's section as drawn and built
        name: [1e3 * link.section.width_m, 1e3 * link.section.thickness_m]
        for name, link in parts.items()
    }
    props = written.pop("masses")
    written["masses_kg"] = {name: m.mass_kg for name, m in props.items()}
    torques = torques_before_after(design, cad, p.payload_kg, duty, props, scale)
    write_json(out.torques, torques)
    with open(out.table, "w") as fh:
        fh.write(torques_markdown(torques))
    before, after = part_meshes(solid), part_meshes(parts)
    after.update(
        {name: extrude(parts[name].polygon, parts[name].section.thickness_m) for name in held}
    )
    volume = tuple(p.build_volume_mm)
    stl_dir = out.stl_before[0].rsplit("/", 2)[0]
    checks = {
        "before": export_stls(before, f"{stl_dir}/before", volume),
        "after": export_stls(after, f"{stl_dir}/after", volume),
    }
    write_json(out.stl_check, checks)
    written["printer"] = {  # the parts to print against the printer, as drawn
        name: {"box_mm": c["box_mm"], "fits": c["fits_build_volume"]}
        for name, c in checks["after"].items()
    }
    summary = {name: link.summary() for name, link in result.links.items()}
    record = {"carries_loads": result.carries_loads, "links": summary, "parts": written}
    write_json(out.topology, record)
    write_json(out.links, props_to_json(props))
    plot_links(result, out.figure)
    for name, s in summary.items():
        log.info(
            "%s: mass %.3f -> %.3f kg, peak von Mises %.1f MPa (allowable %.1f), carries loads %s, "
            "%s; attempts %s",
            name,
            s["mass_before_kg"],
            s["mass_after_kg"],
            s["max_von_mises_after_MPa"],
            s["allowable_stress_MPa"],
            s["carries_loads"],
            "solid plate kept" if s["kept_solid"] else "optimised plate kept",
            s["attempts"],
        )
    log.info("torques %s", torques)
