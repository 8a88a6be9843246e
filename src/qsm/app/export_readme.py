"""The README of an exported design's folder: what each file is, in words."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from qsm.physics.urdf import LOOP_NOTE


def fmt(value: float | None, digits: int) -> str:
    """``value`` with ``digits`` decimals, or "n/a" when missing or not finite."""
    return "n/a" if value is None or not np.isfinite(value) else f"{value:.{digits}f}"


def describe_source(source: Mapping[str, Any]) -> str:
    kind = source.get("kind")
    if kind == "front":
        return f"{source['front']} front, rank {source['rank']} of {source['n_designs']}"
    if kind == "dataset":
        return f"dataset mechanism {source['mechanism_id']}"
    if kind == "ratios":
        return "ratios " + ", ".join(f"{k} {v:.4g}" for k, v in source["ratios"].items())
    if kind == "lengths":
        return "lengths (m) " + ", ".join(f"{k} {v:.4g}" for k, v in source["lengths_m"].items())
    return "design"


def export_readme(record: Mapping[str, Any], title: str) -> str:
    heading = title.replace("\n", "; ")
    return (
        f"# {describe_source(record['source'])}\n\n{heading}.\n\n"
        "| file | what |\n| --- | --- |\n"
        "| `model.xml` | MuJoCo model (MJCF): the closed chain, its loop closed by an equality "
        "`connect` at D |\n"
        "| `stl/*.stl` | the four links to print, in millimetres, in their link frames: solid "
        "plates (not topology-optimised; the workflow's `realization/stl/after` has those) with "
        "a through bore per joint, sized for the joint's bearing (seat at B, C, D, pin or motor "
        "shaft in the other link; `design.json`, `strength.bearings`) |\n"
        "| `drawing.svg`, `drawing.png` | the dimensioned drawing of the links: lengths, hole "
        "centres, bore diameters, section |\n"
        "| `model.urdf` | the spanning tree of the closed chain (see below) |\n"
        "| `design.json` | the design, its source, its true performance from a fresh "
        "evaluation and its printability |\n"
        "| `design.png` | the design with workspace, task and link outlines |\n\n"
        "The MJCF's keyframe `home` is a pose with the loop closed (the middle of the motor "
        "ranges). The payload and the tool flange "
        f"({record['tool_flange_kg']:.3f} kg) are a point mass at E merged into the upper arm's "
        "inertial (the site `payload` marks E). Each motor's joint carries its drive's torque "
        "limit as `actuatorfrcrange`: "
        + " and ".join(f"{t:.1f} N m" for t in record["torque_limits_Nm"])
        + " (motor 1 and 2), which the controller keeps and the kit is sized for.\n\n"
        f"URDF and the closed loop: {LOOP_NOTE}\n"
        + (
            f"\nMirrored: {record['task']['note']}. `model.xml` is the mirrored arm (x negated, "
            "hinge axes reversed; its end effector visits your points); the STLs are the plates "
            "to print (turn them over to assemble); `design.png`, the drawing and `model.urdf` "
            "show the design as computed, at x < 0.\n"
            if record["task"]["mirrored"]
            else ""
        )
    )
