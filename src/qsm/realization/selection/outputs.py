"""Stage 6 orchestration: the selection, link mass properties as JSON, STL export and checks."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import trimesh

from qsm.embodiment.parts.printing import box_fits
from qsm.physics.cad import MassProperties
from qsm.physics.kinematics import DESIGN_COLUMNS


def selection_record(row: pd.Series) -> dict[str, Any]:
    """The chosen design as JSON-friendly values (lengths in m, torques in N m)."""
    out: dict[str, Any] = {}
    for key, value in row.items():
        if isinstance(value, np.generic):
            value = value.item()
        elif isinstance(value, np.ndarray | tuple):
            value = [float(v) for v in value]
        out[str(key)] = value
    out["design_m"] = [float(row[c]) for c in DESIGN_COLUMNS]
    return out


def props_to_json(props: Mapping[str, MassProperties]) -> dict[str, Any]:
    """Link mass properties (kg, m, kg m^2 about the centre of mass, link frames) as JSON."""
    return {
        name: {
            "mass_kg": p.mass_kg,
            "com_m": np.asarray(p.com_m).tolist(),
            "inertia_kg_m2": np.asarray(p.inertia_kg_m2).tolist(),
        }
        for name, p in props.items()
    }


def props_from_json(data: Mapping[str, Any]) -> dict[str, MassProperties]:
    """Inverse of :func:`props_to_json`."""
    return {
        name: MassProperties(
            float(p["mass_kg"]), np.asarray(p["com_m"]), np.asarray(p["inertia_kg_m2"])
        )
        for name, p in data.items()
    }


def export_stls(
    meshes: Mapping[str, trimesh.Trimesh], directory: str | Path, volume_mm: tuple[float, ...]
) -> dict[str, dict[str, Any]]:
    """Write each mesh (metres) as ``<name>.stl`` in millimetres and check it.

    Returns per link: path, watertight (a mesh that is not is mended first, :func:`watertight`,
    and ``repaired`` says so), the sorted box (mm) and whether it fits ``volume_mm`` in some
    axis-aligned orientation (:func:`qsm.embodiment.parts.printing.box_fits`).
    """
    out = Path(directory)
    out.mkdir(parents=True, exist_ok=True)
    checks = {}
    for name, mesh in meshes.items():
        mm = mesh.copy()
        mm.apply_scale(1000.0)
        repaired = not mm.is_watertight and watertight(mm)
        path = out / f"{name}.stl"
        mm.export(path)
        box = sorted(float(v) for v in mm.extents)
        checks[name] = {
            "path": str(path),
            "watertight": bool(mm.is_watertight),
            "repaired": repaired,
            "box_mm": box,
            "fits_build_volume": box_fits(box, volume_mm),
        }
    return checks


def watertight(mesh: trimesh.Trimesh) -> bool:
    """Mend ``mesh`` in place with trimesh's repairs (vertices merged, degenerate and
    duplicate faces dropped, holes filled, normals fixed); whether it is watertight after."""
    mesh.merge_vertices()
    mesh.update_faces(mesh.nondegenerate_faces())
    mesh.update_faces(mesh.unique_faces())
    trimesh.repair.fill_holes(mesh)
    trimesh.repair.fix_normals(mesh)
    return bool(mesh.is_watertight)


def torques_markdown(torques: Mapping[str, Mapping[str, float]]) -> str:
    """Before/after torques like the paper's Table 3."""
    lines = [
        "| motor | before (N m) | after (N m) | reduction | paper before / after / reduction |",
        "| --- | --- | --- | --- | --- |",
    ]
    paper = {"tau1_Nm": "132.60 / 98.58 / 25.65 %", "tau2_Nm": "37.63 / 31.42 / 16.50 %"}
    for key in ("tau1_Nm", "tau2_Nm"):
        b, a = torques["before"][key], torques["after"][key]
        lines.append(
            f"| {key.removesuffix('_Nm')} | {b:.2f} | {a:.2f} | {100 * (b - a) / b:.2f} % "
            f"| {paper[key]} |"
        )
    return "\n".join(lines) + "\n"
