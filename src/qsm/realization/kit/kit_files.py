"""The kit's files from its layout (:mod:`qsm.realization.kit.kit_layout`, mm): a STEP file per part
and one of the assembled arm, a DXF outline of every plate with its holes and openings (ezdxf),
and the exploded assembly view (matplotlib).

Each part's STEP holds one closed solid, named after the part, in the part's own frame; the
assembly's holds one named solid per part, placed, the drives as plain cylinders of their bodies'
size (envelopes, not parts). The solids are made and written with OpenCASCADE through OCP, the
kernel binding that build123d ships and builds on (build123d itself takes 2 s to import, for its
STL reader's scikit-learn among others; the tests read the files back with build123d). Parametric
curves are left out of the files (OpenCASCADE's ``write.surfacecurve.mode`` 0: a third less
time; CAD systems rebuild them) and the header's time stamp is fixed, so a rerun writes the same
bytes.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import ezdxf
import matplotlib.pyplot as plt
import numpy as np
import shapely
from mpl_toolkits.mplot3d.art3d import Poly3DCollection
from OCP.APIHeaderSection import APIHeaderSection_MakeHeader
from OCP.BRepAlgoAPI import BRepAlgoAPI_Cut, BRepAlgoAPI_Fuse
from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace, BRepBuilderAPI_MakePolygon
from OCP.BRepPrimAPI import BRepPrimAPI_MakeBox, BRepPrimAPI_MakeCylinder, BRepPrimAPI_MakePrism
from OCP.gp import gp_Ax2, gp_Ax3, gp_Dir, gp_Pnt, gp_Trsf, gp_Vec
from OCP.IFSelect import IFSelect_ReturnStatus
from OCP.Interface import Interface_Static
from OCP.Message import Message, Message_Gravity
from OCP.STEPCAFControl import STEPCAFControl_Writer
from OCP.STEPControl import STEPControl_Controller, STEPControl_StepModelType
from OCP.TCollection import TCollection_ExtendedString, TCollection_HAsciiString
from OCP.TDataStd import TDataStd_Name
from OCP.TDocStd import TDocStd_Document
from OCP.TopLoc import TopLoc_Location
from OCP.TopoDS import TopoDS_Shape, TopoDS_Wire
from OCP.XCAFDoc import XCAFDoc_DocumentTool

#: The STEP header's time stamp: fixed, so that the same kit gives the same files.
TIMESTAMP = "2000-01-01T00:00:00"


def _wire(points: list[list[float]]) -> TopoDS_Wire:
    polygon = BRepBuilderAPI_MakePolygon()
    for x, y in points:
        polygon.Add(gp_Pnt(float(x), float(y), 0.0))
    polygon.Close()
    return polygon.Wire()


def _cylinder(point: tuple, direction: tuple, d: float, length: float) -> TopoDS_Shape:
    """A cylinder (mm) of diameter ``d`` from ``point`` along ``direction`` for ``length``."""
    axis = gp_Ax2(gp_Pnt(*map(float, point)), gp_Dir(*map(float, direction)))
    return BRepPrimAPI_MakeCylinder(axis, d / 2, length).Shape()


def _cut(shape: TopoDS_Shape, tools: list[TopoDS_Shape]) -> TopoDS_Shape:
    for tool in tools:
        shape = BRepAlgoAPI_Cut(shape, tool).Shape()
    return shape


def plate_solid(plate: dict[str, Any]) -> TopoDS_Shape:
    """A plate's solid (mm) in its own frame: the outline less the holes, extruded along +z,
    less its ``pocket`` (a cheek's, about its origin) where it has one and its ``edge_holes``
    (x, diameter, y from, y to: tapped holes along y at mid-thickness)."""
    ring = shapely.geometry.polygon.orient(shapely.Polygon(plate["outline"], plate["holes"]))
    face = BRepBuilderAPI_MakeFace(_wire(list(ring.exterior.coords)[:-1]), True)
    for hole in ring.interiors:  # clockwise: the face's inner wires
        face.Add(_wire(list(hole.coords)[:-1]))
    t = plate["thickness_mm"]
    solid = BRepPrimAPI_MakePrism(face.Face(), gp_Vec(0, 0, t)).Shape()
    pocket = plate.get("pocket") or {}
    cuts = [
        _cylinder((x, a, t / 2), (0, 1, 0), d, b - a) for x, d, a, b in plate.get("edge_holes", [])
    ]
    if pocket.get("depth_mm", 0.0) > 0:
        cuts.append(
            _cylinder((0, 0, pocket["z0_mm"]), (0, 0, 1), pocket["d_mm"], pocket["depth_mm"])
        )
    return _cut(solid, cuts)


def turned_solid(part: dict[str, Any]) -> TopoDS_Shape:
    """A turned part's solid (mm): its coaxial cylinders fused, along +z from its lowest, less
    the bore through them, its ``holes`` (x, y about its axis, diameter, z from, z to), its
    ``cross_holes`` (angle rad, z, diameter: from the axis out, across) and its ``keyways``
    (angle rad, width, depth from the axis, z from, z to)."""
    z0, shape = part["z0_mm"], None
    for d, a, b in part["steps"]:
        cylinder = _cylinder((0, 0, a - z0), (0, 0, 1), d, b - a)
        shape = cylinder if shape is None else BRepAlgoAPI_Fuse(shape, cylinder).Shape()
    bore = part["bore_mm"]
    cuts = [_cylinder((0, 0, 0), (0, 0, 1), bore, part["length_mm"])] if bore > 0 else []
    cuts += [
        _cylinder((x, y, a - z0), (0, 0, 1), d, b - a) for x, y, d, a, b in part.get("holes", [])
    ]
    r = part["d_mm"]
    for t, z, d in part.get("cross_holes", []):
        cuts.append(_cylinder((0, 0, z - z0), (math.cos(t), math.sin(t), 0), d, r))
    for t, w, depth, a, b in part.get("keyways", []):
        corner = gp_Pnt(w / 2 * math.sin(t), -w / 2 * math.cos(t), a - z0)  # the box's y: across
        frame = gp_Ax2(corner, gp_Dir(0, 0, 1), gp_Dir(math.cos(t), math.sin(t), 0))
        cuts.append(BRepPrimAPI_MakeBox(frame, depth, w, b - a).Shape())
    return _cut(shape, cuts)


def _placed(shape: TopoDS_Shape, origin: list, normal: list, x_dir: list) -> TopoDS_Shape:
    """``shape`` moved from the global frame to the frame (``origin``, ``normal``, ``x_dir``)."""
    frame = gp_Ax3(
        gp_Pnt(*map(float, origin)), gp_Dir(*map(float, normal)), gp_Dir(*map(float, x_dir))
    )
    move = gp_Trsf()
    move.SetDisplacement(gp_Ax3(), frame)
    return shape.Moved(TopLoc_Location(move))


def _write(shapes: dict[str, TopoDS_Shape], path: str) -> None:
    """A STEP file (AP214, mm) of the named ``shapes``."""
    doc = TDocStd_Document(TCollection_ExtendedString("XmlOcaf"))
    tool = XCAFDoc_DocumentTool.ShapeTool_s(doc.Main())
    for name, shape in shapes.items():
        TDataStd_Name.Set_s(tool.AddShape(shape, False), TCollection_ExtendedString(name))
    for printer in Message.DefaultMessenger_s().Printers():  # no transfer statistics on stdout
        printer.SetTraceLevel(Message_Gravity.Message_Fail)
    STEPControl_Controller.Init_s()
    Interface_Static.SetIVal_s("write.surfacecurve.mode", 0)
    writer = STEPCAFControl_Writer()
    writer.SetNameMode(True)
    header = APIHeaderSection_MakeHeader(writer.Writer().Model())
    if not header.IsDone():
        header = APIHeaderSection_MakeHeader(0)
        header.Apply(writer.Writer().Model())
    header.SetTimeStamp(TCollection_HAsciiString(TIMESTAMP))
    writer.Transfer(doc, STEPControl_StepModelType.STEPControl_AsIs)
    if writer.Write(path) != IFSelect_ReturnStatus.IFSelect_RetDone:
        raise RuntimeError(f"OpenCASCADE could not write {path}")


def _frame_of(part: dict[str, Any]) -> tuple[list, list, list]:
    """Where a turned part's own frame sits: its lowest point on its axis, the axis and its x
    direction; along z at ``at_mm``, or along its ``frame`` (origin, normal, x_dir)."""
    frame = part.get("frame")
    if frame is None:
        x, y = part["at_mm"]
        return [x, y, part["z0_mm"]], [0, 0, 1], [1, 0, 0]
    origin = np.add(frame["origin"], part["z0_mm"] * np.asarray(frame["normal"]))
    return origin.tolist(), frame["normal"], frame["x_dir"]


def write_step(layout: dict[str, Any], folder: str | Path) -> dict[str, str]:
    """``folder/<part>.step`` for every plate and turned part, and ``folder/assembly.step``
    with every part placed, the drives' envelopes and the hardware
    (:mod:`qsm.realization.kit.kit_hardware`); returns the paths by name."""
    out = Path(folder)
    out.mkdir(parents=True, exist_ok=True)
    paths, placed = {}, {}
    for name, plate in layout["plates"].items():
        solid = plate_solid(plate)
        paths[name] = str(out / f"{name}.step")
        _write({name: solid}, paths[name])
        placed[name] = _placed(solid, plate["origin"], plate["normal"], plate["x_dir"])
    for name, part in layout["turned"].items():
        solid = turned_solid(part)
        if not name.startswith("drive"):
            paths[name] = str(out / f"{name}.step")
            _write({name: solid}, paths[name])
        x, y = part["at_mm"]
        placed[name] = _placed(solid, [x, y, part["z0_mm"]], [0, 0, 1], [1, 0, 0])
    for name, part in layout.get("hardware", {}).items():
        placed[name] = _placed(turned_solid(part), *_frame_of(part))
    paths["assembly"] = str(out / "assembly.step")
    _write(placed, paths["assembly"])
    return paths


def write_dxf(layout: dict[str, Any], folder: str | Path) -> dict[str, str]:
    """``folder/<plate>.dxf`` (mm): the outline on layer OUTLINE, every hole and opening on
    layer HOLES, as closed polylines, and a cheek's pocket as a circle on a layer named with
    its depth (``POCKET_<depth>MM_DEEP``); returns the paths by name."""
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
        pocket = plate.get("pocket") or {}
        if pocket.get("depth_mm", 0.0) > 0:
            name_depth = f"POCKET_{pocket['depth_mm']:g}MM_DEEP".replace(".", "_")
            doc.layers.add(name_depth, color=3)
            msp.add_circle((0.0, 0.0), pocket["d_mm"] / 2, dxfattribs={"layer": name_depth})
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
