"""The kit's files from its layout (:mod:`qsm.realization.kit_layout`, mm): a STEP file per part
and one of the assembled arm (build123d on the OpenCASCADE kernel), a DXF outline of every plate
with its holes and openings (ezdxf), and the exploded assembly view (matplotlib).

Each part's STEP holds one closed solid in the part's own frame; the assembly's holds one solid
per part, placed, the drives as plain cylinders of their bodies' size (envelopes, not parts).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import ezdxf
import matplotlib.pyplot as plt
import numpy as np
from build123d import (
    Align,
    Compound,
    Cylinder,
    Face,
    Location,
    Plane,
    Solid,
    Vector,
    Wire,
    export_step,
    extrude,
)
from mpl_toolkits.mplot3d.art3d import Poly3DCollection


def _wire(points: list[list[float]]) -> Wire:
    return Wire.make_polygon([Vector(x, y, 0.0) for x, y in points], close=True)


def plate_solid(plate: dict[str, Any]) -> Solid:
    """A plate's solid (mm) in its own frame: the outline less the holes, extruded along +z."""
    face = Face(_wire(plate["outline"]), [_wire(h) for h in plate["holes"]])
    return extrude(face, amount=plate["thickness_mm"])


def turned_solid(part: dict[str, Any]) -> Solid:
    """A turned part's solid (mm) along +z from 0, with its bore."""
    align = (Align.CENTER, Align.CENTER, Align.MIN)
    solid = Cylinder(part["d_mm"] / 2, part["length_mm"], align=align)
    if part["bore_mm"] > 0:
        solid = solid - Cylinder(part["bore_mm"] / 2, part["length_mm"], align=align)
    return solid


def _placed_plate(solid: Solid, plate: dict[str, Any]) -> Solid:
    plane = Plane(origin=plate["origin"], x_dir=plate["x_dir"], z_dir=plate["normal"])
    return solid.moved(Location(plane))


def _placed_turned(solid: Solid, part: dict[str, Any]) -> Solid:
    x, y = part["at_mm"]
    return solid.moved(Location((x, y, part["z0_mm"])))


def write_step(layout: dict[str, Any], folder: str | Path) -> dict[str, str]:
    """``folder/<part>.step`` for every plate and turned part, and ``folder/assembly.step``
    with every part placed and the drives' envelopes; returns the paths by name."""
    out = Path(folder)
    out.mkdir(parents=True, exist_ok=True)
    paths, placed = {}, []
    for name, plate in layout["plates"].items():
        solid = plate_solid(plate)
        solid.label = name
        paths[name] = str(out / f"{name}.step")
        export_step(solid, paths[name])
        placed.append(_placed_plate(solid, plate))
    for name, part in layout["turned"].items():
        solid = turned_solid(part)
        solid.label = name
        if not name.startswith("drive"):
            paths[name] = str(out / f"{name}.step")
            export_step(solid, paths[name])
        placed.append(_placed_turned(solid, part))
    paths["assembly"] = str(out / "assembly.step")
    export_step(Compound(children=placed, label="arm"), paths["assembly"])
    return paths


def write_dxf(layout: dict[str, Any], folder: str | Path) -> dict[str, str]:
    """``folder/<plate>.dxf`` (mm): the outline on layer OUTLINE, every hole and opening on
    layer HOLES, as closed polylines; returns the paths by name."""
    out = Path(folder)
    out.mkdir(parents=True, exist_ok=True)
    paths = {}
    for name, plate in layout["plates"].items():
        doc = ezdxf.new("R2010", units=ezdxf.units.MM)
        doc.layers.add("OUTLINE", color=7)
        doc.layers.add("HOLES", color=1)
        msp = doc.modelspace()
        msp.add_lwpolyline(plate["outline"], close=True, dxfattribs={"layer": "OUTLINE"})
        for hole in plate["holes"]:
            msp.add_lwpolyline(hole, close=True, dxfattribs={"layer": "HOLES"})
        paths[name] = str(out / f"{name}.dxf")
        doc.saveas(paths[name])
    return paths


def _plate_points(plate: dict[str, Any], ring: list[list[float]], z: float) -> np.ndarray:
    """A ring of a plate's local outline (mm) in the global frame at local height ``z``."""
    x_dir, normal = np.asarray(plate["x_dir"]), np.asarray(plate["normal"])
    y_dir = np.cross(normal, x_dir)
    local = np.asarray(ring)
    return plate["origin"] + local[:, :1] * x_dir + local[:, 1:2] * y_dir + z * normal


def exploded_view(
    layout: dict[str, Any], numbers: dict[str, int], path: str | Path, spread_mm: float = 60.0
) -> None:
    """The assembly drawn exploded along the joint axis (each plate ``spread_mm`` further per
    place in the stack, each turned part with the plate nearest it), each part labelled with
    its assembly step's number."""
    fig = plt.figure(figsize=(10, 7))
    ax = fig.add_subplot(projection="3d")
    order = sorted(layout["plates"], key=lambda n: layout["plates"][n]["origin"][2])
    shift = {name: k * spread_mm for k, name in enumerate(order)}
    for name, plate in layout["plates"].items():
        top = _plate_points(plate, plate["outline"], plate["thickness_mm"])
        top[:, 2] += shift[name]
        colour = "tab:orange" if plate["kind"] == "printed" else "tab:gray"
        ax.add_collection3d(Poly3DCollection([top], alpha=0.5, facecolor=colour, edgecolor="k"))
        centre = top.mean(axis=0)
        ax.text(*centre, str(numbers.get(name, "")), fontsize=11, weight="bold")
    for name, part in layout["turned"].items():
        a = np.linspace(0, 2 * np.pi, 48)
        x, y = part["at_mm"]
        near = min(order, key=lambda n: abs(layout["plates"][n]["origin"][2] - part["z0_mm"]))
        z = part["z0_mm"] + part["length_mm"] + shift[near]
        ring = np.column_stack(
            [x + part["d_mm"] / 2 * np.cos(a), y + part["d_mm"] / 2 * np.sin(a), np.full_like(a, z)]
        )
        style = ":" if name.startswith("drive") else "-"
        ax.plot(*ring.T, style, color="tab:blue")
        ax.text(x, y, z, str(numbers.get(name, name.replace("_", " "))), fontsize=9)
    _fit(ax, layout)
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    ax.set_zlabel("z, exploded (mm)")
    ax.set_title("Exploded assembly: numbers are the assembly steps in summary.md")
    fig.savefig(path, dpi=110, bbox_inches="tight")
    plt.close(fig)


def _fit(ax: Any, layout: dict[str, Any]) -> None:
    """Equal-ish axes around every plate's outline."""
    pts = np.vstack([_plate_points(p, p["outline"], 0.0) for p in layout["plates"].values()])
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_zlim(lo[2] - 100, hi[2] + 60 * (len(layout["plates"]) + 1))
