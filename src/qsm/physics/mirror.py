"""Tasks on the right of the base (x > 0): designed as their mirror image through x = 0.

With the paper's operating range this family's workspace lies on the x < 0 side of the base
joint A. A task whose region (the enclosing disk of its points) has its centre at x > 0 is
therefore designed on its mirror image (x -> -x): every stage runs on the mirrored points, and the
arm to build is the mirror image of the design. Gravity (along -y) is the same in both, so the
mirrored arm needs the same joint torques at the mirrored poses. Its links are the same planar
plates turned over; its MuJoCo model is the design's with every x negated and every hinge axis
reversed (:func:`mirror_spec`). A task with points on both sides is designed on the side of its
disk's centre (and needs a design whose workspace holds the whole disk, as any task does).
Lengths in metres.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from qsm.physics.task import min_enclosing_circle

if TYPE_CHECKING:  # the settings layer imports this module; MuJoCo only where a model is mirrored
    import mujoco

#: What a mirrored design's outputs say about the arm to build.
MIRROR_NOTE = (
    "the task lies at x > 0 (its enclosing disk's centre), so it was designed as its mirror image "
    "through x = 0 (x -> -x) and the arm to build is the mirror image of this design: the same "
    "link plates turned over, motor angles and torques counted clockwise instead of "
    "anticlockwise"
)


def mirror_points(points: ArrayLike) -> NDArray[np.float64]:
    """``points`` (n, 2) m mirrored through x = 0."""
    p = np.array(points, dtype=float).reshape(-1, 2)
    p[:, 0] = -p[:, 0]
    return p


def is_mirrored(points: ArrayLike) -> bool:
    """Whether a task of ``points`` (n, 2) m is designed mirrored: its disk's centre at x > 0."""
    return min_enclosing_circle(points).centre[0] > 0.0


def design_points(points: ArrayLike) -> list[list[float]]:
    """The task points every stage designs for: ``points`` (n, 2) m as given, or mirrored when
    :func:`is_mirrored`. Idempotent: designed points are never mirrored again."""
    p = mirror_points(points) if is_mirrored(points) else np.asarray(points, dtype=float)
    return p.reshape(-1, 2).tolist()


def task_record(points: ArrayLike) -> dict[str, object]:
    """What an output says of its task: the user's ``points_m``, whether it was ``mirrored``, the
    ``designed_points_m`` every stage used and, when mirrored, the ``note`` for the builder."""
    mirrored = is_mirrored(points)
    record: dict[str, object] = {
        "points_m": np.asarray(points, dtype=float).reshape(-1, 2).tolist(),
        "mirrored": mirrored,
        "designed_points_m": design_points(points),
    }
    if mirrored:
        record["note"] = MIRROR_NOTE
    return record


def _flip(v: ArrayLike) -> list[float]:
    """A 3-vector (or fromto 6-vector) with its x components negated."""
    out = [float(c) for c in np.asarray(v, dtype=float)]
    for k in range(0, len(out), 3):
        out[k] = -out[k]
    return out


def mirror_spec(spec: mujoco.MjSpec) -> mujoco.MjSpec:
    """Mirror the planar model ``spec`` through the plane x = 0, in place, and return it.

    Reflection M = diag(-1, 1, 1): body, site and geom positions, centres of mass and capsule
    ends have x negated; a hinge about z turns the other way (M Rz(q) M = Rz(-q)), so its axis is
    reversed and each joint angle keeps its value; full inertias keep their diagonal and negate
    Ixy and Ixz (M I M). Bodies, sites and geoms must carry no rotation (the planar models of
    :mod:`qsm.physics.mjcf` carry none)."""
    for body in spec.bodies:
        if body.name == "world":
            continue
        body.pos = _flip(body.pos)
        body.ipos = _flip(body.ipos)
        xx, yy, zz, xy, xz, yz = (float(v) for v in body.fullinertia)
        if not np.isnan(xx):
            body.fullinertia = [xx, yy, zz, -xy, -xz, yz]
    for joint in spec.joints:
        joint.axis = [-float(v) for v in joint.axis]
    for site in spec.sites:
        site.pos = _flip(site.pos)
    for geom in spec.geoms:
        geom.pos = _flip(geom.pos)
        if not np.isnan(geom.fromto[0]):
            geom.fromto = _flip(geom.fromto)
    return spec
