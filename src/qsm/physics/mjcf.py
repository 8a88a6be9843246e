"""MuJoCo model of one scaled mechanism (built with MjSpec, exportable as standalone MJCF XML).

Kinematic tree (all hinges about +z, gravity (0, -9.81, 0), x-y is the mechanism plane):

* ``lower_arm`` on the world at A, joint ``theta1`` (motor 1, absolute angle of AB);
  * ``upper_arm`` at B = (l1, 0) in the lower-arm frame, joint ``q_upper`` = phi - theta1;
* ``crank`` on the world at A, joint ``theta2`` (motor 2, absolute angle of AC: both motors are
  grounded and coaxial at A);
  * ``coupler`` at C = (l2, 0) in the crank frame, joint ``q_coupler`` = psi - theta2, psi the
    absolute angle of CD.

The loop is closed by an equality ``connect`` between the sites ``d_coupler`` and ``d_upper`` (D on
each body); ``site1``/``site2`` are used because a body+anchor connect infers the anchor at qpos0,
where the loop is open. Body frames are the link frames of :mod:`qsm.physics.cad`; every body
carries an explicit inertial from the CAD mass properties, the payload is a point mass at E merged
into the upper arm's inertial (site ``payload`` marks E). Geoms are visual only (no collisions), so
the model compiles in well under a millisecond. Motors ``motor1``/``motor2`` apply torque (N m) to
``theta1``/``theta2``. The equality uses stiff settings (solref 0.002, solimp 0.99 0.999 0.001) and
the option block a 0.5 ms implicitfast step, which a forward simulation needs to track the closed
chain; inverse dynamics (:mod:`qsm.physics.dynamics`) does not depend on them.
"""

from __future__ import annotations

import itertools

import mujoco
import numpy as np
from numpy.typing import ArrayLike

from qsm.physics.cad import DEFAULT_CAD, CadSettings, MassProperties, mass_properties
from qsm.physics.kinematics import as_design
from qsm.physics.mirror import mirror_spec

GRAVITY_M_S2 = 9.81
TIMESTEP_S = 0.0005
EQ_SOLREF = (0.002, 1.0)
EQ_SOLIMP = (0.99, 0.999, 0.001, 0.5, 2.0)
JOINT_NAMES: tuple[str, ...] = ("theta1", "q_upper", "theta2", "q_coupler")


def planar_spec(name: str, timestep_s: float, gravity_m_s2: float = GRAVITY_M_S2) -> mujoco.MjSpec:
    """An empty spec for a planar model: explicit inertials, gravity along -y, an implicitfast
    step of ``timestep_s``."""
    spec = mujoco.MjSpec()
    spec.modelname = name
    spec.compiler.inertiafromgeom = mujoco.mjtInertiaFromGeom.mjINERTIAFROMGEOM_FALSE
    spec.option.gravity = [0.0, -gravity_m_s2, 0.0]
    spec.option.timestep = timestep_s
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    return spec


def combined(a: MassProperties, b: MassProperties) -> MassProperties:
    """Rigid bodies ``a`` and ``b`` (same frame, SI units) as one: the masses added, the centre
    of mass their weighted mean, each inertia moved to it (parallel axes) and added."""
    total = a.mass_kg + b.mass_kg
    if b.mass_kg == 0.0:
        return a
    com = (a.mass_kg * np.asarray(a.com_m) + b.mass_kg * np.asarray(b.com_m)) / total

    def shift(m: float, r: np.ndarray) -> np.ndarray:
        return m * (r @ r * np.eye(3) - np.outer(r, r))

    inertia = (
        a.inertia_kg_m2
        + shift(a.mass_kg, a.com_m - com)
        + b.inertia_kg_m2
        + shift(b.mass_kg, b.com_m - com)
    )
    return MassProperties(float(total), com, inertia)


def add_point_mass(props: MassProperties, mass_kg: float, point_m: ArrayLike) -> MassProperties:
    """Rigid body ``props`` plus a point mass at ``point_m`` (same frame, SI units)."""
    point = MassProperties(float(mass_kg), np.asarray(point_m, dtype=float), np.zeros((3, 3)))
    return combined(props, point)


def body_inertials(
    design: ArrayLike,
    props: dict[str, MassProperties],
    payload_kg: float = 0.0,
) -> dict[str, tuple[tuple[float, float, float], MassProperties]]:
    """Position in the parent frame (m) and inertial of each body, in tree order (lower_arm,
    upper_arm, crank, coupler): the links' mass properties, with the payload (kg) merged into the
    upper arm's at E."""
    l1, l2, _, _, ee_x, ee_y = (float(v) for v in as_design(design))
    return {
        "lower_arm": ((0.0, 0.0, 0.0), props["lower_arm"]),
        "upper_arm": (
            (l1, 0.0, 0.0),
            add_point_mass(props["upper_arm"], payload_kg, [ee_x, -ee_y, 0.0]),
        ),
        "crank": ((0.0, 0.0, 0.0), props["crank"]),
        "coupler": ((l2, 0.0, 0.0), props["coupler"]),
    }


def _set_inertial(body: mujoco.MjsBody, props: MassProperties) -> None:
    i = props.inertia_kg_m2
    body.explicitinertial = True
    body.mass = props.mass_kg
    body.ipos = props.com_m
    body.fullinertia = [i[0, 0], i[1, 1], i[2, 2], i[0, 1], i[0, 2], i[1, 2]]


def _visual(body: mujoco.MjsBody, points: list[tuple[float, float]], z: float, r: float) -> None:
    """Visual-only capsules along a polyline at height z (m), radius r (m)."""
    for (x0, y0), (x1, y1) in itertools.pairwise(points):
        body.add_geom(
            type=mujoco.mjtGeom.mjGEOM_CAPSULE,
            fromto=[x0, y0, z, x1, y1, z],
            size=[r, 0.0, 0.0],
            contype=0,
            conaffinity=0,
        )


def model_spec(
    design: ArrayLike,
    settings: CadSettings = DEFAULT_CAD,
    payload_kg: float = 0.0,
    props: dict[str, MassProperties] | None = None,
    armature: tuple[float, float] = (0.0, 0.0),
) -> mujoco.MjSpec:
    """MjSpec of the mechanism; ``props`` (link mass properties) default to
    :mod:`qsm.physics.cad`'s; ``armature`` (kg m^2) on theta1 and theta2 is each drive's
    reflected inertia (J_motor + J_gear,in) N^2."""
    l1, l2, l3, l4, ee_x, ee_y = (float(v) for v in as_design(design))
    if props is None:
        props = mass_properties(design, settings)
    spec = planar_spec("qsm_mechanism", TIMESTEP_S)
    r, dz = settings.width_m / 2, 1.5 * settings.thickness_m  # visual layers of the two chains
    hinge = {"type": mujoco.mjtJoint.mjJNT_HINGE, "axis": [0.0, 0.0, 1.0]}

    bodies = body_inertials(design, props, payload_kg)
    lower = spec.worldbody.add_body(name="lower_arm", pos=bodies["lower_arm"][0])
    lower.add_joint(name="theta1", armature=float(armature[0]), **hinge)
    _set_inertial(lower, bodies["lower_arm"][1])
    _visual(lower, [(0.0, 0.0), (l1, 0.0)], 0.0, r)

    upper = lower.add_body(name="upper_arm", pos=bodies["upper_arm"][0])
    upper.add_joint(name="q_upper", **hinge)
    _set_inertial(upper, bodies["upper_arm"][1])
    _visual(upper, [(-l4, 0.0), (ee_x, 0.0), (ee_x, -ee_y)], 0.0, r)
    upper.add_site(name="d_upper", pos=[-l4, 0.0, 0.0])
    upper.add_site(name="payload", pos=[ee_x, -ee_y, 0.0], size=[2 * r, 0.0, 0.0])

    crank = spec.worldbody.add_body(name="crank", pos=bodies["crank"][0])
    crank.add_joint(name="theta2", armature=float(armature[1]), **hinge)
    _set_inertial(crank, bodies["crank"][1])
    _visual(crank, [(0.0, 0.0), (l2, 0.0)], dz, r)

    coupler = crank.add_body(name="coupler", pos=bodies["coupler"][0])
    coupler.add_joint(name="q_coupler", **hinge)
    _set_inertial(coupler, bodies["coupler"][1])
    _visual(coupler, [(0.0, 0.0), (l3, 0.0)], dz, r)
    coupler.add_site(name="d_coupler", pos=[l3, 0.0, 0.0])

    spec.add_equality(
        name="loop_D",
        type=mujoco.mjtEq.mjEQ_CONNECT,
        objtype=mujoco.mjtObj.mjOBJ_SITE,
        name1="d_coupler",
        name2="d_upper",
        solref=EQ_SOLREF,
        solimp=EQ_SOLIMP,
    )
    for motor, joint in (("motor1", "theta1"), ("motor2", "theta2")):
        spec.add_actuator(
            name=motor, target=joint, trntype=mujoco.mjtTrn.mjTRN_JOINT, gear=[1, 0, 0, 0, 0, 0]
        )
    return spec


def build_model(
    design: ArrayLike, settings: CadSettings = DEFAULT_CAD, payload_kg: float = 0.0
) -> mujoco.MjModel:
    """Compiled MuJoCo model of ``design`` (6 lengths, m) with a payload (kg) at E."""
    return model_spec(design, settings, payload_kg).compile()


def mjcf_xml(
    design: ArrayLike,
    settings: CadSettings = DEFAULT_CAD,
    payload_kg: float = 0.0,
    home_qpos: ArrayLike | None = None,
    mirrored: bool = False,
    props: dict[str, MassProperties] | None = None,
    torque_limits_Nm: tuple[float, float] | None = None,
) -> str:
    """Standalone MJCF XML of the model of :func:`build_model` (link mass properties ``props``,
    default the CAD links), with a keyframe ``home`` at the joint positions ``home_qpos`` (rad,
    :data:`JOINT_NAMES` order) when given: a pose where the loop is closed, so a simulation
    loaded from it starts consistent. ``mirrored``: the arm
    mirrored through x = 0 (:func:`qsm.physics.mirror.mirror_spec`; same joint values), the one
    built for a task at x > 0. ``torque_limits_Nm``: each motor's torque limit (N m), written
    as its joint's ``actuatorfrcrange``, which MuJoCo holds the actuator's torque to.

    MuJoCo writes numbers with 6 significant digits, so a model loaded from this XML reproduces
    the torques of :func:`build_model` to about 1e-5 relative.
    """
    spec = model_spec(design, settings, payload_kg, props)
    for joint, limit in zip(("theta1", "theta2"), torque_limits_Nm or (), strict=False):
        spec.joint(joint).actfrclimited = mujoco.mjtLimited.mjLIMITED_TRUE
        spec.joint(joint).actfrcrange = [-float(limit), float(limit)]
    if mirrored:
        mirror_spec(spec)
    if home_qpos is not None:
        spec.add_key(name="home", qpos=[float(v) for v in np.asarray(home_qpos)])
    return spec.to_xml()
