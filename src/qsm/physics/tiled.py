"""Generalized forces of one mechanism's open tree at many states in one ``mj_inverse`` call.

A MuJoCo model holding one copy of the open tree of :mod:`qsm.physics.mjcf` (the same bodies in
the same order, hinges about +z, gravity along -y; no loop equality, visuals or actuators) per
state is compiled once per process and size. A design's body positions, masses and inertials are
written into it in place: the principal inertias and their frame come from ``mju_eig3``, as the
compiler derives them from a full inertia. The copies do not interact, so one call gives the
generalized force of every state: the numbers of one call per state on the design's own model
(tested to 1e-12 relative), without compiling a model per design or a Python loop per state.
"""

from __future__ import annotations

import functools

import mujoco
import numpy as np
from numpy.typing import NDArray

from qsm.physics.cad import MassProperties
from qsm.physics.mjcf import GRAVITY_M_S2

#: Bodies of one tree copy, in the order of :mod:`qsm.physics.mjcf` (and of its joints' dofs).
BODY_ORDER: tuple[str, ...] = ("lower_arm", "upper_arm", "crank", "coupler")
#: Largest number of states per compiled model; more are evaluated in chunks.
TILE_STATES = 512


@functools.lru_cache(maxsize=4)
def _tiled_model(n_states: int) -> tuple[mujoco.MjModel, mujoco.MjData]:
    """Model with ``n_states`` copies of the open tree (placeholder inertials) and its data."""
    spec = mujoco.MjSpec()
    spec.compiler.inertiafromgeom = mujoco.mjtInertiaFromGeom.mjINERTIAFROMGEOM_FALSE
    spec.option.gravity = [0.0, -GRAVITY_M_S2, 0.0]
    hinge = {"type": mujoco.mjtJoint.mjJNT_HINGE, "axis": [0.0, 0.0, 1.0]}
    for k in range(n_states):
        for root, child in (BODY_ORDER[:2], BODY_ORDER[2:]):
            parent = spec.worldbody
            for name in (root, child):
                body = parent.add_body(name=f"{name}_{k}")
                body.add_joint(name=f"{name}_joint_{k}", **hinge)
                # off-centre and rotated, so that no body is compiled with its inertial frame
                # merged into its body frame: every design writes its own
                body.explicitinertial = True
                body.mass = 1.0
                body.ipos = [0.1, 0.01, 0.0]
                body.fullinertia = [1.0, 2.0, 2.5, 0.1, 0.0, 0.0]
                parent = body
    model = spec.compile()
    if model.body_sameframe[1:].any():
        raise RuntimeError("a tiled body was compiled with a merged inertial frame")
    return model, mujoco.MjData(model)


def _principal(props: MassProperties) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Principal inertias (kg m^2) and the quaternion of their frame, as MuJoCo compiles them."""
    inertia, vectors, quat = np.zeros(3), np.zeros(9), np.zeros(4)
    mujoco.mju_eig3(inertia, vectors, quat, props.inertia_kg_m2.ravel())
    return inertia, quat


def tree_forces(
    bodies: dict[str, tuple[tuple[float, float, float], MassProperties]],
    q: NDArray[np.float64],
    qd: NDArray[np.float64],
    qdd: NDArray[np.float64],
    armature: tuple[float, float] = (0.0, 0.0),
) -> NDArray[np.float64]:
    """``qfrc_inverse`` (N, 4) of the open tree with ``bodies`` (from
    :func:`qsm.physics.mjcf.body_inertials`) at joint positions, velocities and accelerations
    (N, 4) in :data:`qsm.physics.mjcf.JOINT_NAMES` order (rad, rad/s, rad/s^2), with the joint
    ``armature`` (kg m^2) on theta1 and theta2 (the drives' reflected inertia)."""
    pos = np.array([bodies[b][0] for b in BODY_ORDER])
    mass = np.array([bodies[b][1].mass_kg for b in BODY_ORDER])
    ipos = np.array([bodies[b][1].com_m for b in BODY_ORDER])
    principal = [_principal(bodies[b][1]) for b in BODY_ORDER]
    inertia = np.array([p[0] for p in principal])
    quat = np.array([p[1] for p in principal])
    out = np.empty((len(q), 4))
    for start in range(0, len(q), TILE_STATES):
        rows = slice(start, min(start + TILE_STATES, len(q)))
        n = rows.stop - rows.start
        model, data = _tiled_model(n)
        # each copy's rows, written through (n, 4, ...) views of the model's arrays
        model.body_pos[1:].reshape(n, 4, 3)[:] = pos
        model.body_mass[1:].reshape(n, 4)[:] = mass
        model.body_ipos[1:].reshape(n, 4, 3)[:] = ipos
        model.body_inertia[1:].reshape(n, 4, 3)[:] = inertia
        model.body_iquat[1:].reshape(n, 4, 4)[:] = quat
        model.dof_armature.reshape(n, 4)[:] = (armature[0], 0.0, armature[1], 0.0)
        data.qpos[:] = q[rows].ravel()
        data.qvel[:] = qd[rows].ravel()
        data.qacc[:] = qdd[rows].ravel()
        mujoco.mj_inverse(model, data)
        out[rows] = data.qfrc_inverse.reshape(n, 4)
    return out
