"""URDF of one scaled mechanism: the spanning tree of its closed chain, with the cut stated.

URDF describes trees only, so it cannot hold the loop A-B-D-C. This file is the same tree as the
MJCF of :mod:`qsm.physics.mjcf` (bodies, joints, frames and inertials alike, the payload merged
into the upper arm) *without* the loop: the chain is cut at the pin D, and the two halves of the
pin are the frames ``d_upper`` (on the upper arm) and ``d_coupler`` (on the coupler). The XML
says so in a comment at its top (:data:`LOOP_NOTE`), and a consumer must add the constraint
``d_upper == d_coupler`` (a point constraint, like the MJCF's ``connect`` equality) or set the
passive joints ``q_upper`` and ``q_coupler`` from the motor angles
(:func:`qsm.physics.kinematics.pose`); without it the passive joints are free.

The motors' coupled range theta2 <= theta1 is not expressible as URDF joint limits either; each
motor carries its own range. Visuals and collisions reference the link STLs (millimetres, scaled
by 0.001). A ``<mujoco>`` block keeps MuJoCo's URDF import from merging the fixed frames.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from xml.etree import ElementTree as ET

import numpy as np
from numpy.typing import ArrayLike

from qsm.physics.cad import DEFAULT_CAD, CadSettings, MassProperties, mass_properties
from qsm.physics.kinematics import as_design
from qsm.physics.mjcf import add_point_mass

LOOP_NOTE = (
    "URDF cannot express closed kinematic loops. This is the spanning tree of the closed chain "
    "A-B-D-C (the tree of model.xml without its loop equality): the chain is cut at the pin D, "
    "whose halves are the frames d_upper (upper arm) and d_coupler (coupler). Add the constraint "
    "d_upper == d_coupler (a point constraint, as model.xml's equality 'connect' does) or set "
    "the passive joints q_upper and q_coupler from the motor angles theta1, theta2 "
    "(qsm.physics.kinematics.pose); without it the passive joints are free and the dynamics "
    "are wrong. The motors' coupled range theta2 <= theta1 is not in the joint limits either."
)


def _fmt(values: Sequence[float]) -> str:
    return " ".join(f"{float(v):.9g}" for v in values)


def _link(
    robot: ET.Element, name: str, props: MassProperties | None, mesh: str | None
) -> ET.Element:
    link = ET.SubElement(robot, "link", name=name)
    if props is not None:
        inertial = ET.SubElement(link, "inertial")
        ET.SubElement(inertial, "origin", xyz=_fmt(props.com_m), rpy="0 0 0")
        ET.SubElement(inertial, "mass", value=f"{props.mass_kg:.9g}")
        i = np.asarray(props.inertia_kg_m2)
        ET.SubElement(
            inertial,
            "inertia",
            ixx=f"{i[0, 0]:.9g}",
            ixy=f"{i[0, 1]:.9g}",
            ixz=f"{i[0, 2]:.9g}",
            iyy=f"{i[1, 1]:.9g}",
            iyz=f"{i[1, 2]:.9g}",
            izz=f"{i[2, 2]:.9g}",
        )
    if mesh is not None:
        for kind in ("visual", "collision"):
            element = ET.SubElement(link, kind)
            geometry = ET.SubElement(element, "geometry")
            ET.SubElement(geometry, "mesh", filename=mesh, scale="0.001 0.001 0.001")
    return link


def _joint(
    robot: ET.Element,
    name: str,
    kind: str,
    parent: str,
    child: str,
    xyz: Sequence[float],
    limit: Mapping[str, float] | None = None,
) -> None:
    joint = ET.SubElement(robot, "joint", name=name, type=kind)
    ET.SubElement(joint, "parent", link=parent)
    ET.SubElement(joint, "child", link=child)
    ET.SubElement(joint, "origin", xyz=_fmt(xyz), rpy="0 0 0")
    if kind != "fixed":
        ET.SubElement(joint, "axis", xyz="0 0 1")
    if limit is not None:
        ET.SubElement(joint, "limit", {k: f"{v:.9g}" for k, v in limit.items()})


def urdf_xml(
    design: ArrayLike,
    settings: CadSettings = DEFAULT_CAD,
    payload_kg: float = 0.0,
    motor_range_deg: Sequence[Sequence[float]] = ((45.0, 180.0), (-37.5, 180.0)),
    effort_Nm: Sequence[float] = (150.0, 100.0),
    velocity_rad_s: float = math.radians(45.0),
    mesh_dir: str = "stl",
    props: Mapping[str, MassProperties] | None = None,
) -> str:
    """URDF text of ``design`` (6 lengths, m) with the payload (kg) at E (see the module
    docstring). ``motor_range_deg`` is each motor's range (deg), ``effort_Nm`` and
    ``velocity_rad_s`` the URDF limits of the motor joints, ``mesh_dir`` the folder of the link
    STLs (relative to the URDF), ``props`` the link mass properties (default: the CAD links)."""
    l1, l2, l3, l4, ee_x, ee_y = (float(v) for v in as_design(design))
    mp = dict(props) if props is not None else mass_properties(design, settings)
    mp["upper_arm"] = add_point_mass(mp["upper_arm"], payload_kg, [ee_x, -ee_y, 0.0])
    robot = ET.Element("robot", name="qsm_mechanism")
    robot.append(ET.Comment(f" {LOOP_NOTE} "))
    mujoco = ET.SubElement(robot, "mujoco")
    ET.SubElement(mujoco, "compiler", fusestatic="false", discardvisual="false", strippath="false")
    _link(robot, "base", None, None)
    for name in ("lower_arm", "upper_arm", "crank", "coupler"):
        _link(robot, name, mp[name], f"{mesh_dir}/{name}.stl")
    for name in ("d_upper", "d_coupler", "end_effector"):
        _link(robot, name, None, None)

    def motor(k: int) -> dict[str, float]:
        lo, hi = (math.radians(v) for v in motor_range_deg[k])
        return {"lower": lo, "upper": hi, "effort": effort_Nm[k], "velocity": velocity_rad_s}

    _joint(robot, "theta1", "revolute", "base", "lower_arm", (0, 0, 0), motor(0))
    _joint(robot, "q_upper", "continuous", "lower_arm", "upper_arm", (l1, 0, 0))
    _joint(robot, "theta2", "revolute", "base", "crank", (0, 0, 0), motor(1))
    _joint(robot, "q_coupler", "continuous", "crank", "coupler", (l2, 0, 0))
    _joint(robot, "cut_d_upper", "fixed", "upper_arm", "d_upper", (-l4, 0, 0))
    _joint(robot, "cut_d_coupler", "fixed", "coupler", "d_coupler", (l3, 0, 0))
    _joint(robot, "tool", "fixed", "upper_arm", "end_effector", (ee_x, -ee_y, 0))
    ET.indent(robot)
    return '<?xml version="1.0"?>\n' + ET.tostring(robot, encoding="unicode") + "\n"
