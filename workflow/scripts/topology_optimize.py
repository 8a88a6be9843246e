"""Rule topology_optimize: SIMP on the arm plates, printed meshes, STL files, torques again."""

import json

import numpy as np

from qsm import settings
from qsm.physics.cad import link_meshes
from qsm.physics.duty import duty_cycle
from qsm.realisation.export import export_stls, props_to_json, torques_markdown
from qsm.realisation.topology import optimise_links, plot_links
from qsm.realisation.torques import torques_before_after
from qsm.workflow.logs import logged

with logged(snakemake.log[0]) as log:  # noqa: F821
    p = snakemake.params  # noqa: F821
    out = snakemake.output  # noqa: F821
    with open(snakemake.input.selected) as fh:  # noqa: F821
        design = np.asarray(json.load(fh)["design_m"])
    cad = settings.cad(p.cad, p.material)
    duty = duty_cycle(settings.duty(p.duty, p.operating_range))
    topo = settings.topology(p.topology, p.material, p.strength)
    result = optimise_links(design, cad, p.payload_kg, duty, topo)
    torques = torques_before_after(design, cad, p.payload_kg, duty, result.props)
    with open(out.torques, "w") as fh:
        json.dump(torques, fh, indent=2)
    with open(out.table, "w") as fh:
        fh.write(torques_markdown(torques))
    summary = {name: link.summary() for name, link in result.links.items()}
    with open(out.topology, "w") as fh:
        json.dump({"carries_loads": result.carries_loads, "links": summary}, fh, indent=2)
    with open(out.links, "w") as fh:
        json.dump(props_to_json(result.props), fh, indent=2)
    before = link_meshes(design, cad)
    after = {**before, **{name: link.mesh for name, link in result.links.items()}}
    volume = tuple(p.build_volume_mm)
    stl_dir = out.stl_before[0].rsplit("/", 2)[0]
    checks = {
        "before": export_stls(before, f"{stl_dir}/before", volume),
        "after": export_stls(after, f"{stl_dir}/after", volume),
    }
    with open(out.stl_check, "w") as fh:
        json.dump(checks, fh, indent=2)
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
