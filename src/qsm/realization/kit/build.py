"""The parts to build of a realised design: the printed plates topology-optimised where they
still hold, bored for the bearings, their bill of materials, STL files, masses and the torques
with them (the rule ``topology_optimize``)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

from qsm.embodiment.parts.link_parts import LinkPart, part_meshes
from qsm.physics.cad import MassProperties
from qsm.physics.duty import Duty
from qsm.realization.kit.builders_kit import Kit, KitSettings, builders_kit
from qsm.realization.motion.torques import torques_before_after
from qsm.realization.selection.assembly import final_parts, write_parts
from qsm.realization.selection.outputs import export_stls
from qsm.realization.selection.pipeline import Realization
from qsm.realization.topology.fe import TopologySettings
from qsm.realization.topology.geometry import extrude
from qsm.realization.topology.topology import TopologyResult, optimize_links


@dataclass(frozen=True)
class BuiltLinks:
    """What :func:`build_links` made: the topology result, the link mass properties (kg, m,
    kg m^2) of the parts to build, the torques before and after (N m), the STL checks
    (``before`` and ``after``), the ``topology.json`` record, the builder's kit and the final
    parts (bored, optimised plates with their openings)."""

    topology: TopologyResult
    props: dict[str, MassProperties]
    torques: dict[str, Any]
    stl_checks: dict[str, Any]
    record: dict[str, Any]
    kit: Kit
    parts: dict[str, LinkPart]


def build_links(
    done: Realization,
    carried_kg: float,
    duty: Duty,
    topology: TopologySettings,
    material_name: str,
    folder: str | Path,
    volume_mm: tuple[float, ...],
    drawing: dict[str, str],
    kit: KitSettings,
) -> BuiltLinks:
    """Optimise the plates of ``done`` (:func:`qsm.realization.selection.pipeline.realize`) for
    its loads (``carried_kg`` at E, the payload and the tool flange, over ``duty``), keep an
    optimised plate only where it holds and keeps its stiffness, bore every part, and write the
    BOM into ``folder`` and the STLs (mm) of the solid and the final parts into
    ``folder/stl/before`` and ``folder/stl/after``, checked against ``volume_mm``.
    ``drawing`` names the dimensioned drawing's files (``svg``, ``png``) for the record; the
    builder's kit (:func:`qsm.realization.kit.builders_kit.builders_kit`, with ``kit``) joins the
    BOM."""
    cad = done.part_settings.cad
    result = optimize_links(done.design, cad, carried_kg, duty, topology, scale=done.scale)
    held = {
        name: link.polygon
        for name, link in result.links.items()
        if link.carries_loads and not link.kept_solid
    }
    parts = final_parts(done.design, done.bearing_rows, done.part_settings, held)
    made = builders_kit(done, parts, kit)
    parts = made.parts  # with the hubs' screw holes
    written = write_parts(
        parts,
        done.bearing_rows,
        done.part_settings,
        material_name,
        {name: name in held for name in parts},
        folder,
        done.drives,
        made.bom,
    )
    written["drawing"] = dict(drawing)
    written["kit"] = {k: made.record[k] for k in ("holds", "checks", "problems")}
    written["section_mm"] = {  # each part's section as drawn and built
        name: [1e3 * link.section.width_m, 1e3 * link.section.thickness_m]
        for name, link in parts.items()
    }
    props = written.pop("masses")
    written["masses_kg"] = {name: m.mass_kg for name, m in props.items()}
    torques = torques_before_after(done.design, cad, carried_kg, duty, props, done.scale)
    checks = _write_stls(done.parts, parts, held, Path(folder), volume_mm)
    written["printer"] = {  # the parts to print against the printer, as drawn
        name: {"box_mm": c["box_mm"], "fits": c["fits_build_volume"], "watertight": c["watertight"]}
        for name, c in checks["after"].items()
    }
    summary = {name: link.summary() for name, link in result.links.items()}
    record = {"carries_loads": result.carries_loads, "links": summary, "parts": written}
    return BuiltLinks(result, props, torques, checks, record, made, parts)


def _write_stls(
    solid: dict[str, LinkPart],
    final: dict[str, LinkPart],
    held: dict[str, Any],
    folder: Path,
    volume_mm: tuple[float, ...],
) -> dict[str, Any]:
    """Write the solid parts' and the final parts' STLs (mm; an optimised plate of ``held`` as
    its outline extruded) into ``folder/stl/before`` and ``after``, with their checks."""
    after = part_meshes(final)
    after.update(
        {name: extrude(final[name].polygon, final[name].section.thickness_m) for name in held}
    )
    return {
        "before": export_stls(part_meshes(solid), f"{folder}/stl/before", volume_mm),
        "after": export_stls(after, f"{folder}/stl/after", volume_mm),
    }
