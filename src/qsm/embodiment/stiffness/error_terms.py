"""The tool's placing error at a pose, term by term: elastic sag, lost motion from backlash.

* sag: the tool's displacement ``C F`` under a force ``F`` at E, with ``C`` the compliance of
  :func:`qsm.embodiment.stiffness.frame.tool_compliance`;
* peak dynamic sag: the largest displacement under the payload's peak inertial and weight force
  over a motion, in the worst direction (the largest singular value of ``C`` times |F|);
* lost motion: each drive's backlash ``b`` (rad) at its joint moves the tool by ``|J_j| b``,
  ``J`` the closed chain's Jacobian, where the joint's torque changes sign along the motion;
  where one sign holds throughout (gravity keeps the gear loaded on one flank) it does not.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from qsm.physics.kinematics import end_effector

#: Standard gravity (m/s^2), along -y.
GRAVITY_M_S2 = 9.80665
#: Angle step (rad) of the central differences of :func:`tool_jacobian`.
JACOBIAN_STEP_RAD = 1e-6
#: Time step (s) of the central differences of :func:`tool_acceleration`.
ACCELERATION_STEP_S = 1e-4


def tool_jacobian(design: ArrayLike, theta1: ArrayLike, theta2: ArrayLike) -> NDArray[np.float64]:
    """The tool's Jacobian dE/d(theta1, theta2) (..., 2, 2) m/rad at the poses, by central
    differences of :func:`qsm.physics.kinematics.end_effector` (columns: the two motors)."""
    h = JACOBIAN_STEP_RAD
    t1, t2 = np.asarray(theta1, dtype=float), np.asarray(theta2, dtype=float)
    d1 = (end_effector(design, t1 + h, t2) - end_effector(design, t1 - h, t2)) / (2 * h)
    d2 = (end_effector(design, t1, t2 + h) - end_effector(design, t1, t2 - h)) / (2 * h)
    return np.stack([d1, d2], axis=-1)


def tool_acceleration(
    design: ArrayLike, theta: ArrayLike, dtheta: ArrayLike, ddtheta: ArrayLike
) -> NDArray[np.float64]:
    """The tool's acceleration (..., 2) m/s^2 where the motors move at angles ``theta``, speeds
    ``dtheta`` and accelerations ``ddtheta`` (..., 2): the second central difference of E along
    the motion's second-order path theta + dtheta h + ddtheta h^2 / 2 (exact to O(h^2))."""
    th, v, a = (np.asarray(x, dtype=float) for x in (theta, dtheta, ddtheta))
    h = ACCELERATION_STEP_S

    def at(step: float) -> NDArray[np.float64]:
        q = th + v * step + a * step * step / 2
        return end_effector(design, q[..., 0], q[..., 1])

    return (at(h) - 2 * at(0.0) + at(-h)) / (h * h)


def payload_force_N(payload_kg: float, acceleration: ArrayLike) -> NDArray[np.float64]:
    """The force (..., 2) N the payload puts on the tool: its weight less its mass times its
    acceleration (m/s^2)."""
    g = np.array([0.0, -GRAVITY_M_S2])
    return payload_kg * (g - np.asarray(acceleration, dtype=float))


def sag_m(compliance: ArrayLike, force: ArrayLike) -> NDArray[np.float64]:
    """The tool's displacement (...) m under ``force`` (..., 2) N: |C F|."""
    c, f = np.asarray(compliance, dtype=float), np.asarray(force, dtype=float)
    return np.linalg.norm(np.einsum("...ij,...j->...i", c, f), axis=-1)


def peak_sag_m(compliance: ArrayLike, peak_force_N: float) -> NDArray[np.float64]:
    """The largest displacement (...) m under a force of magnitude ``peak_force_N`` in any
    direction: the largest singular value of C times the force."""
    return np.linalg.norm(np.asarray(compliance, dtype=float), ord=2, axis=(-2, -1)) * peak_force_N


def torque_reverses(torques: ArrayLike, tol_Nm: float = 0.0) -> NDArray[np.bool_]:
    """Whether each joint's torque (..., samples, 2) N m changes sign along the motion: it
    exceeds ``tol_Nm`` one way and the other."""
    tau = np.asarray(torques, dtype=float)
    return (tau.max(axis=-2) > tol_Nm) & (tau.min(axis=-2) < -tol_Nm)


def lost_motion_m(
    jacobian: ArrayLike, backlash_rad: ArrayLike, reverses: ArrayLike
) -> NDArray[np.float64]:
    """The tool's lost motion (...) m: sum over the joints whose torque ``reverses`` (2,) of the
    Jacobian column's length times the joint's backlash (2,) rad (a worst-case sum)."""
    j = np.asarray(jacobian, dtype=float)
    play = np.asarray(backlash_rad, dtype=float) * np.asarray(reverses, dtype=bool)
    return (np.linalg.norm(j, axis=-2) * play).sum(axis=-1)
