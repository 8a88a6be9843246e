"""ISO 9283 pose accuracy (AP) and pose repeatability (RP) of a realised arm, simulated.

The standard measures a robot at five points of a plane of its test cube: the cube's centre P1
and P2-P5 on the plane's diagonals, 10 % of the diagonal in from each corner, over 30 cycles
(P1, P5, P4, P3, P2 in turn; here each cycle's draws are independent, so the order does not
enter). This arm is planar, so its test plane is its own plane: the largest
square, sides horizontal and vertical, centred on the task disk's centre, that the arm reaches
within its operating range (:func:`largest_plane`); the standard's cube has no third dimension here.

Each attained pose is the commanded one plus

* systematic terms, the same every cycle: the tool's static sag under the payload's weight
  (the machine's frame model with its drives, :func:`qsm.embodiment.stiffness.frame
  .tool_compliance`) and the base's compliance at the tool, taken along the sag (its record
  gives its size, not its direction);
* random terms, drawn afresh each cycle (:class:`RandomTerms`): each gearbox's backlash where
  its play opens (:func:`play_opens`) and each motor's encoder quantum, uniform within their
  widths, the motor's friction held by the servo, uniform within +- its deflection, each
  through the tool's Jacobian, and the servo's settling error at the tool, uniform in
  direction and within the payload test's largest error at the end of a hold.

AP is the distance from the commanded pose to the barycentre of the attained ones; RP is
l-bar + 3 S_l, the mean distance of the attained poses from their barycentre plus three
standard deviations of it. The dynamic sag is not in either: the standard measures a pose once
the arm has come to rest, when the payload's inertial force is gone (the settling term counts
what the servo leaves). AP is the new arm's; ``service_ap_mm`` adds the tool's drift once the
printed links have crept over their service time
(:func:`qsm.realization.accuracy.accuracy_budget.creep_drift_m`). Lengths in m unless named
otherwise.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from qsm.embodiment.stiffness.error_terms import payload_force_N, tool_jacobian, torque_reverses
from qsm.embodiment.stiffness.frame import tool_compliance
from qsm.embodiment.strength.loads import joint_loads
from qsm.physics.batch_ik import batch_joint_angles
from qsm.physics.dynamics import loop_state
from qsm.prose import point
from qsm.realization.accuracy.accuracy_budget import ArmModel, creep_drift_m

#: Cycles the standard asks at each point.
ISO_CYCLES = 30
#: Where P2-P5 stand from the centre: 1 - 2 x 10 % of the diagonal, as a fraction of the
#: centre-to-corner distance.
CORNER_FRACTION = 0.8
#: Grid points along each side of the square whose reach :func:`largest_plane` checks.
PLANE_GRID = 21
#: The random terms' names, as the record and the datasheet give them.
RANDOM_TERMS = ("backlash", "encoder", "friction", "settling")


@dataclass(frozen=True)
class IsoPlane:
    """The test square: ``centre_m`` (2,), side ``side_m`` and the five points ``points_m``
    (5, 2), P1 the centre and P2-P5 from the corner (-, -) anticlockwise."""

    centre_m: tuple[float, float]
    side_m: float
    points_m: NDArray[np.float64]


@dataclass(frozen=True)
class RandomTerms:
    """Per motor (2,) rad at the joint: ``backlash_rad`` (each gearbox's, full width),
    ``encoder_rad`` (one count over the ratio), ``friction_rad`` (the motor's friction torque
    at the joint over the servo's stiffness, each way), and ``settling_mm``, the servo's largest
    error at the tool at the end of a hold."""

    backlash_rad: NDArray[np.float64]
    encoder_rad: NDArray[np.float64]
    friction_rad: NDArray[np.float64]
    settling_mm: float


@dataclass(frozen=True)
class PoseCharacteristics:
    """AP and RP (5,) mm at the test plane's points, with ``static_sag_mm`` and ``base_mm``
    (5,), the systematic terms, and ``random_mean_mm`` (5,), the length of the random terms'
    mean over the cycles (AP lies within it of the systematic terms' sum);
    ``compensated_ap_mm`` (5,), the AP left once a controller takes out the modelled static
    sag; ``rp_alone_mm`` (4, 5), the RP of each random term alone
    (:data:`RANDOM_TERMS`); ``cycles`` and ``seed`` of the Monte Carlo; ``creep_mm`` (5,), the
    tool's drift once the printed links have crept over their service time, and
    ``service_ap_mm`` (5,), the AP with it, after ``service_time_h`` (h)."""

    plane: IsoPlane
    ap_mm: NDArray[np.float64]
    rp_mm: NDArray[np.float64]
    static_sag_mm: NDArray[np.float64]
    base_mm: NDArray[np.float64]
    random_mean_mm: NDArray[np.float64]
    compensated_ap_mm: NDArray[np.float64]
    rp_alone_mm: NDArray[np.float64]
    cycles: int
    seed: int
    creep_mm: NDArray[np.float64]
    service_ap_mm: NDArray[np.float64]
    service_time_h: float

    @property
    def main_random_term(self) -> str:
        """The random term whose RP alone is largest at the point of the largest RP."""
        i = int(np.argmax(self.rp_mm))
        return RANDOM_TERMS[int(np.argmax(self.rp_alone_mm[:, i]))]


def plane_points(centre: ArrayLike, side_m: float) -> NDArray[np.float64]:
    """The standard's five points (5, 2) m of a square of ``side_m`` about ``centre``."""
    c = np.asarray(centre, dtype=float)
    corners = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]], dtype=float) * side_m / 2
    return np.vstack([c, c + CORNER_FRACTION * corners])


def _reaches(design: NDArray, centre: NDArray, half: float, op: tuple) -> bool:
    """Whether ``design`` reaches every grid point of the square of half-side ``half``."""
    u = np.linspace(-half, half, PLANE_GRID)
    grid = centre + np.stack(np.meshgrid(u, u), axis=-1).reshape(-1, 2)
    return bool(np.isfinite(batch_joint_angles(design, grid, *op)).all())


def largest_plane(
    design: ArrayLike, centre: ArrayLike, theta1_range_deg: tuple[float, float],
    theta2_min_deg: float, resolution_m: float = 1e-3,
) -> IsoPlane:  # fmt: skip
    """The largest square (to ``resolution_m``), sides horizontal and vertical, about
    ``centre`` (m) whose every point of a :data:`PLANE_GRID` grid ``design`` reaches within the
    operating range (bisection: a smaller square about the same centre lies within a larger)."""
    d, c = np.asarray(design, dtype=float), np.asarray(centre, dtype=float)
    op = (tuple(theta1_range_deg), theta2_min_deg)
    low, high = 0.0, 2.0 * float(d[0] + np.hypot(d[4], d[5]))
    if not _reaches(d, c, 0.0, op):
        raise ValueError(f"the task disk's centre {point(c, 4)} is out of reach")
    while high - low > resolution_m / 2:
        mid = (low + high) / 2
        low, high = (mid, high) if _reaches(d, c, mid, op) else (low, mid)
    return IsoPlane((float(c[0]), float(c[1])), 2 * low, plane_points(c, 2 * low))


def play_opens(
    model: ArmModel, angles: NDArray[np.float64], payload_kg: float, task_reverses: ArrayLike
) -> NDArray[np.bool_]:
    """Whether each joint's play opens between cycles (2,): its torque reverses along the
    task's motion (``task_reverses``, the accuracy budget's) or its holding torque under the
    payload changes sign between the plane's points (motor ``angles`` (5, 2) rad); elsewhere
    gravity keeps the play closed on one side, and backlash does not scatter the pose."""
    zero = np.zeros_like(angles)
    tau = joint_loads(
        model.design, model.inertials, payload_kg, loop_state(model.design, angles, zero, zero)
    ).tau
    return np.asarray(task_reverses, dtype=bool) | torque_reverses(tau)


def _draws(
    terms: RandomTerms, jac: NDArray, cycles: int, rng: np.random.Generator
) -> NDArray[np.float64]:
    """Each random term's tool error (4, cycles, 5, 2) m, in :data:`RANDOM_TERMS`' order."""
    n = jac.shape[0]

    def joint(width: NDArray) -> NDArray:
        dq = rng.uniform(-0.5, 0.5, size=(cycles, n, 2)) * width
        return np.einsum("pij,cpj->cpi", jac, dq)

    radius = rng.uniform(0.0, terms.settling_mm * 1e-3, size=(cycles, n))
    angle = rng.uniform(0.0, 2 * np.pi, size=(cycles, n))
    settle = radius[..., None] * np.stack([np.cos(angle), np.sin(angle)], axis=-1)
    return np.stack([
        joint(terms.backlash_rad), joint(terms.encoder_rad), joint(2 * terms.friction_rad), settle,
    ])  # fmt: skip


def ap_rp_mm(attained: ArrayLike, commanded: ArrayLike) -> tuple[NDArray, NDArray]:
    """ISO 9283's AP and RP (n,) mm of ``attained`` poses (cycles, n, 2) m at the ``commanded``
    ones (n, 2) m: the barycentre's distance from the command, and l-bar + 3 S_l (S_l with
    cycles - 1 degrees of freedom)."""
    p = np.asarray(attained, dtype=float)
    bary = p.mean(axis=0)
    ap = np.linalg.norm(bary - np.asarray(commanded, dtype=float), axis=-1)
    dist = np.linalg.norm(p - bary, axis=-1)
    return 1e3 * ap, 1e3 * (dist.mean(axis=0) + 3 * dist.std(axis=0, ddof=1))


def pose_characteristics(
    model: ArmModel, plane: IsoPlane, angles: NDArray[np.float64], payload_kg: float,
    terms: RandomTerms, base_mm: float = 0.0, cycles: int = ISO_CYCLES, seed: int = 9283,
) -> PoseCharacteristics:  # fmt: skip
    """AP and RP of ``model`` carrying ``payload_kg`` at the ``plane``'s points (its motor
    ``angles`` (5, 2) rad), by Monte Carlo over ``cycles`` cycles drawn from ``seed``."""
    t1, t2 = angles[:, 0], angles[:, 1]
    printed = model.sections._replace(factor=model.factor)
    k = model.drive_stiffness if np.isfinite(model.drive_stiffness).all() else None
    compliance = tool_compliance(model.design, t1, t2, printed, k)
    sag = np.einsum("pij,j->pi", compliance, payload_force_N(payload_kg, np.zeros(2)))
    along = sag / np.maximum(np.linalg.norm(sag, axis=-1, keepdims=True), 1e-12)
    systematic = sag + 1e-3 * base_mm * along
    jac = tool_jacobian(model.design, t1, t2)
    draws = _draws(terms, jac, cycles, np.random.default_rng(seed))
    pts, random = plane.points_m, draws.sum(axis=0)
    ap, rp = ap_rp_mm(pts + systematic + random, pts)
    compensated, _ = ap_rp_mm(pts + systematic - sag + random, pts)
    drift = creep_drift_m(model, t1, t2, payload_kg)
    service, _ = ap_rp_mm(pts + systematic + drift + random, pts)
    alone = np.array([ap_rp_mm(pts + d, pts)[1] for d in draws])
    mean_mm = 1e3 * np.linalg.norm(random.mean(axis=0), axis=-1)
    return PoseCharacteristics(
        plane, ap, rp, 1e3 * np.linalg.norm(sag, axis=-1), np.full(len(pts), float(base_mm)),
        mean_mm, compensated, alone, cycles, seed, 1e3 * np.linalg.norm(drift, axis=-1), service,
        0.0 if model.printed is None else model.printed.service_time_h,
    )  # fmt: skip
