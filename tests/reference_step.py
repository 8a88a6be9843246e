"""An independent reference check of the kit's ``assembly.step``, for the tests and for a finished
run: the file read back with build123d, each solid moved with its link (``moves_with`` in
``kit.json``), the volume two solids share (OpenCASCADE's boolean common), and each screw reached
by the ISO 2936 key of its size along the axis of its widest cylinder, past the solids that the
sequence's earlier steps put in. It uses none of the kit's own geometry code.

Run as ``python tests/reference_step.py <run folder>`` on a finished run: it prints the pairs of
solids that share more than 1 mm^3 at the kit's pose and each screw its key cannot reach.
"""

from __future__ import annotations

import itertools
import json
import math
import re
import sys
from pathlib import Path

import numpy as np

from qsm.embodiment.kit import fasteners as fs


def read_assembly(path: str | Path) -> dict:
    """``assembly.step``'s solids by their names (build123d's labels turned back)."""
    from build123d import import_step

    read = import_step(str(path)).children
    return {c.label: c.wrapped for c in read}


def named(read: dict, names) -> dict:
    """``read`` (build123d's labels: spaces and dots as underscores) by the kit's ``names``."""
    labels = {re.sub(r"[ .]", "_", n): n for n in names}
    return {labels[k]: v for k, v in read.items()}


def moved(shape, link: str, frames: tuple):
    """``shape`` moved with ``link`` from the frames ``frames[0]`` to ``frames[1]`` (each link's
    origin, m, and angle, rad; ``base`` stands still)."""
    from OCP.gp import gp_Ax1, gp_Dir, gp_Pnt, gp_Trsf, gp_Vec
    from OCP.TopLoc import TopLoc_Location

    if link == "base":
        return shape
    (x0, y0), a = frames[0][link]
    (x1, y1), b = frames[1][link]
    there, turn, back = gp_Trsf(), gp_Trsf(), gp_Trsf()
    back.SetTranslation(gp_Vec(-1e3 * x0, -1e3 * y0, 0.0))
    turn.SetRotation(gp_Ax1(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1)), b - a)
    there.SetTranslation(gp_Vec(1e3 * x1, 1e3 * y1, 0.0))
    return shape.Moved(TopLoc_Location(there.Multiplied(turn.Multiplied(back))))


def box(shape):
    from OCP.Bnd import Bnd_Box
    from OCP.BRepBndLib import BRepBndLib

    box = Bnd_Box()
    BRepBndLib.Add_s(shape, box)
    return box


def shared_mm3(a, b, boxes: tuple | None = None) -> float:
    """The volume (mm^3) two shapes share (0 where their ``boxes`` are apart)."""
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Common
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps

    boxes = boxes or (box(a), box(b))
    if boxes[0].IsOut(boxes[1]):
        return 0.0
    props = GProp_GProps()
    BRepGProp.VolumeProperties_s(BRepAlgoAPI_Common(a, b).Shape(), props)
    return props.Mass()


def overlaps(solids: dict, moves: dict, frames: tuple, pairs: set | None = None) -> dict:
    """The pairs of ``solids`` (OpenCASCADE shapes read back from the STEP) that share more
    than 1 mm^3 once each is moved with its link (``moves``) from the frames ``frames[0]`` to
    ``frames[1]``; only ``pairs`` where given."""
    pairs = pairs or set(itertools.combinations(solids, 2))
    placed = {n: moved(solids[n], moves[n], frames) for pair in pairs for n in pair}
    boxes = {n: box(shape) for n, shape in placed.items()}
    out = {}
    for a, b in sorted(pairs):
        shared = shared_mm3(placed[a], placed[b], (boxes[a], boxes[b]))
        if shared > 1.0:
            out[(a, b)] = shared
    return out


#: ISO 2936 key sizes (mm across flats) by standard and size: ISO 4762 cap screws (ISO 4762's s),
#: ISO 7379 shoulder screws by shoulder diameter, ISO 4029 set screws.
KEY_MM = {
    "ISO 4762": {"M3": 2.5, "M4": 3.0, "M5": 4.0, "M6": 5.0, "M8": 6.0, "M10": 8.0, "M12": 10.0},
    "ISO 7379": {"6": 3.0, "8": 4.0, "10": 5.0, "12": 6.0, "16": 8.0},
    "ISO 4029": {"M3": 1.5, "M4": 2.0, "M5": 2.5, "M6": 3.0, "M8": 4.0},
}


def _points_along(shape, origin, direction) -> tuple[float, float]:
    """The least and greatest distance along ``direction`` from ``origin`` of ``shape``'s
    vertices."""
    from OCP.BRep import BRep_Tool
    from OCP.TopAbs import TopAbs_VERTEX
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS

    out, explorer = [], TopExp_Explorer(shape, TopAbs_VERTEX)
    while explorer.More():
        p = BRep_Tool.Pnt_s(TopoDS.Vertex(explorer.Current())).Coord()
        out.append(float(np.dot(np.subtract(p, origin), direction)))
        explorer.Next()
    return min(out), max(out)


def socket_of(shape) -> tuple[np.ndarray, np.ndarray]:
    """Where a key enters a screw read back from the STEP, and the way out of its socket: on
    the axis of its widest cylinder (the head), at the head's end away from the shank; for a
    set screw (one cylinder), at its end farther from the joint axis z."""
    from OCP.BRepAdaptor import BRepAdaptor_Surface
    from OCP.GeomAbs import GeomAbs_SurfaceType
    from OCP.TopAbs import TopAbs_FACE
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS

    best, explorer = None, TopExp_Explorer(shape, TopAbs_FACE)
    while explorer.More():
        face = TopoDS.Face(explorer.Current())
        surface = BRepAdaptor_Surface(face)
        if surface.GetType() == GeomAbs_SurfaceType.GeomAbs_Cylinder:
            cylinder = surface.Cylinder()
            if best is None or cylinder.Radius() > best[0]:
                best = (cylinder.Radius(), cylinder.Axis(), face)
        explorer.Next()
    _, axis, face = best
    origin, d = np.array(axis.Location().Coord()), np.array(axis.Direction().Coord())
    (lo, hi), (head_lo, head_hi) = _points_along(shape, origin, d), _points_along(face, origin, d)
    if hi - head_hi > head_lo - lo + 1e-6:  # the shank beyond the head's high end
        return origin + head_lo * d, -d
    if head_lo - lo > hi - head_hi + 1e-6:
        return origin + head_hi * d, d
    ends = [origin + t * d for t in (lo, hi)]
    outer = int(np.hypot(*ends[1][:2]) > np.hypot(*ends[0][:2]))
    return ends[outer], d if outer else -d


def keys(name: str, socket: np.ndarray, out: np.ndarray, arms: dict) -> list:
    """The ways an ISO 2936 key turns the screw ``name``: its long arm straight out of the
    socket; for a shoulder screw also its short arm in the socket and the long arm as a handle
    across, four ways. Each a list of solids, the key's across-corners and 1 mm wide."""
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeBox, BRepPrimAPI_MakeCylinder
    from OCP.gp import gp_Ax2, gp_Dir, gp_Pnt

    s = KEY_MM[" ".join(name.split()[:2])][name.split()[2]]
    long, short = arms[s]
    d = s / math.cos(math.pi / 6) + 1.0
    start = socket + 0.05 * out

    def arm(length: float):
        return BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(*start), gp_Dir(*out)), d / 2, length).Shape()

    ways = [[arm(long)]]
    if name.startswith("ISO 7379"):
        end = start + short * out
        for across in (np.array(v, float) for v in ((1, 0, 0), (0, 1, 0), (-1, 0, 0), (0, -1, 0))):
            side = np.cross(out, across)
            corner = end - d / 2 * side
            frame = gp_Ax2(gp_Pnt(*corner), gp_Dir(*out), gp_Dir(*across))
            ways.append([arm(short), BRepPrimAPI_MakeBox(frame, long, d, d).Shape()])
    return ways


def placed_by(steps: list[dict], n: int) -> list[str]:
    """The solids in place when step ``n`` (index) is done: on the arm, every earlier arm step's
    and those of the modules already brought on; on the bench, its module's earlier steps'."""
    group = steps[n]["on_the_bench"]
    done = [s for s in steps[: n + 1]]
    if group:
        return [p for s in done if s["on_the_bench"] == group for p in s["solids"]]
    brought = {s["key"] for s in done}
    return [p for s in done if (s["on_the_bench"] or s["key"]) in brought for p in s["solids"]]


def key_arms() -> dict[float, tuple[float, float]]:
    """ISO 2936 keys' long and short arms (mm) by size, from the kit's data table."""
    return {float(r["key_mm"]): (float(r["long_arm_mm"]), float(r["short_arm_mm"]))
            for r in fs.table("iso2936")}  # fmt: skip


def is_screw(name: str) -> bool:
    """Whether a solid's name is a screw a key turns (ISO 4762, 7379 or 4029)."""
    return name.split(",")[0].split()[:2] in (["ISO", "4762"], ["ISO", "7379"], ["ISO", "4029"])


def blocked_screws(solids: dict, moves: dict, steps: list[dict], frames_of) -> tuple[list, int]:
    """Each screw of the sequence ``steps`` whose key (:func:`keys`, any of its ways) shares
    more than 1 mm^3 with a solid in place at its step (:func:`placed_by`), everything moved
    by ``frames_of(step)`` (the layout's frames and the step's pose's); and how many were
    checked."""
    arms, blocked, checked = key_arms(), [], 0
    for n, step in enumerate(steps):
        frames = frames_of(step)
        around = {p: moved(solids[p], moves[p], frames) for p in placed_by(steps, n)}
        for screw in filter(is_screw, step["solids"]):
            socket, out = socket_of(solids[screw])
            clear = (
                all(shared_mm3(moved(k, moves[screw], frames), solid) <= 1.0
                    for k in way for p, solid in around.items() if p != screw)
                for way in keys(screw, socket, out, arms)
            )  # fmt: skip
            if not any(clear):
                blocked.append(f"step {step['step']}: {screw}")
            checked += 1
    return blocked, checked


def named_fit(a: str, b: str) -> bool:
    """Whether two solids may share volume by design: a screw in a drive's tapped face (the
    drive is an envelope) or a heat-set insert in its printed link."""
    for one, other in ((a, b), (b, a)):
        screw = other.startswith(("ISO 4762 ", "DIN 976-1 "))
        into = (f"to drive {one[-1]},", f", drive {one[-1]} to cheek")
        if one.startswith("drive_") and screw and any(t in other for t in into):
            return True
        if "heat-set insert" in other and f"to {one.replace('_', ' ')}," in other:
            return True
    return False


def main(folder: str) -> None:
    """Print the shared volumes at the kit's pose and the blocked screws of a finished run."""
    from qsm import load_config
    from qsm.realization.kit.kit_assembly import poses
    from qsm.realization.kit.kit_layout import link_frames

    run = Path(folder)
    kit = json.loads((run / "results/realization/kit/kit.json").read_text())
    machine = json.loads((run / "results/realization/machine.json").read_text())
    design = np.asarray(machine["design_m"])
    layout, steps = kit["layout"], kit["assembly_sequence"]["steps"]
    tasks = [p for p in (run / "config/config.yaml", run / "task.yaml") if p.exists()]
    limits = load_config(*tasks)["operating_range"]
    step_file = run / "results/realization/kit/step/assembly.step"
    solids = named(read_assembly(step_file), layout["moves_with"])
    start = link_frames(design, *np.radians(layout["pose_deg"]))
    angles = poses(design, layout["pose_deg"], limits["theta1_deg"], limits["theta2_min_deg"])
    shared = overlaps(solids, layout["moves_with"], (start, start))
    fits = {pair: v for pair, v in shared.items() if named_fit(*pair)}
    print(f"{len(fits)} pairs share volume in the fits named (screws in the drives' tapped "
          "faces, heat-set inserts melted into their printed holes)")  # fmt: skip
    for pair, volume in sorted(shared.items()):
        if pair not in fits:
            print(f"shares {volume:.1f} mm^3: {pair[0]} | {pair[1]}")
    blocked, checked = blocked_screws(
        solids,
        layout["moves_with"],
        steps,
        lambda s: (start, link_frames(design, *angles[s["pose"]])),
    )
    if not kit["assembly_sequence"]["exists"]:
        print("no assembly sequence:", *kit["assembly_sequence"]["blocked"], sep="\n")
    print(f"{checked} screws checked, {len(blocked)} blocked", *blocked, sep="\n")


if __name__ == "__main__":
    main(sys.argv[1])
