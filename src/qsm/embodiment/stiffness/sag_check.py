"""g15 and the dataset's stiffness column: the tool's largest sag at the task points under the
payload's weight, for thousands of designs at once (solid links of the section, rigid drives).

This is the part of the accuracy budget a design's lengths and section decide; the realised design's
full budget (:mod:`qsm.realization.accuracy.accuracy_budget`) adds its drives' stiffness and play,
the optimised plates and the payload test's tracking, and decides its verdict.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray

from qsm.embodiment.stiffness.error_terms import payload_force_N, sag_m
from qsm.embodiment.stiffness.frame import FrameSections, tool_compliance
from qsm.embodiment.strength.material import DEFAULT_MATERIAL, Material
from qsm.physics.batch_ik import batch_joint_angles
from qsm.physics.cad import DEFAULT_CAD, CadSettings
from qsm.physics.kinematics import as_design
from qsm.physics.workspace import OperatingRange
from qsm.schema.defaults import default

#: g15 of a design that cannot reach a task point in the operating range (mm over tolerance).
UNREACHABLE_MM = 1e6


@dataclass(frozen=True)
class SagCheck:
    """The tool's sag at task ``points`` (P, 2) m under ``payload_kg`` for links of the ``cad``
    section (times each link's scale when sized) and ``material``, rigid drives, against
    ``tolerance_mm``; the motor angles of :func:`qsm.physics.batch_ik.batch_joint_angles` (each
    point alone, the largest transmission margin; the payload test's path may take another
    branch from its second point on), in the operating range."""

    points: tuple[tuple[float, float], ...]
    tolerance_mm: float = default("task.tolerance_mm")
    cad: CadSettings = DEFAULT_CAD
    material: Material = DEFAULT_MATERIAL
    payload_kg: float = default("task.payload_kg")
    operating_range: OperatingRange = field(default_factory=OperatingRange)

    def sag_mm(self, designs: ArrayLike, scales: ArrayLike | None = None) -> NDArray[np.float64]:
        """The largest sag (N,) mm over the points of designs (N, 6) m (``scales`` (N, 4): each
        link's section factor); inf where a point is out of reach."""
        d = np.atleast_2d(as_design(designs)).astype(float)
        angles = batch_joint_angles(d, self.points, *self.operating_range.degrees)
        reach = np.isfinite(angles).all(axis=(-1, -2))
        f = np.ones((len(d), 4)) if scales is None else np.asarray(scales, dtype=float)
        sections = FrameSections(
            width_m=self.cad.width_m * f[reach],
            thickness_m=self.cad.thickness_m * f[reach],
            youngs_pa=self.material.youngs_modulus_pa,
            poisson=self.material.poisson_ratio,
        )
        a = angles[reach]
        c = tool_compliance(d[reach], a[..., 0], a[..., 1], sections)
        out = np.full(len(d), np.inf)
        out[reach] = 1e3 * sag_m(c, payload_force_N(self.payload_kg, np.zeros(2))).max(axis=-1)
        return out

    def violation(self, designs: ArrayLike, scales: ArrayLike | None = None) -> NDArray:
        """g15 (N,) mm: the largest sag less the tolerance (<= 0: within it), or
        :data:`UNREACHABLE_MM` where a point is out of reach."""
        sag = self.sag_mm(designs, scales)
        return np.where(np.isfinite(sag), sag - self.tolerance_mm, UNREACHABLE_MM)
