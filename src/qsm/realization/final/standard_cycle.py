"""The standard pick-and-place cycle, as small arms are compared on it: 25 mm up, 305 mm across,
25 mm down and back, at a stated payload (an industry convention, not part of ISO 9283).

The 305 mm stroke runs horizontally, centred on the task disk's centre, with the 25 mm rises
vertical above its ends (:func:`standard_route`); where the arm cannot make the whole stroke, the
longest it can, and the record says so. Each payload's cycle is the task's planner and checks
(:func:`qsm.realization.final.cycle_run.run_cycle`: time-optimal with the chosen drives within
their torque limits, the links' strength, the drives' heat, MuJoCo's run), without a dwell.
Lengths in m unless named otherwise.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from qsm.physics.batch_ik import batch_joint_angles
from qsm.physics.cad import MassProperties
from qsm.physics.task_points import TaskCycle
from qsm.realization.final.cycle_run import run_cycle
from qsm.realization.motion.payload import PayloadSettings
from qsm.realization.selection.pipeline import Realization, RealizationSettings

#: The standard cycle's stroke across and its rise (m).
STROKE_M = 0.305
RISE_M = 0.025
#: The light payload the standard cycle is also quoted at (kg).
LIGHT_PAYLOAD_KG = 1.0
#: Points along each edge of the cycle's rectangle whose reach :func:`standard_route` checks.
EDGE_SAMPLES = 31


@dataclass(frozen=True)
class StandardRoute:
    """The cycle's rectangle: its lower edge's centre ``centre_m`` (the task disk's centre), the
    ``stroke_m`` across and the ``rise_m``; ``scaled`` where the stroke is shorter than
    :data:`STROKE_M` because the arm reaches no longer one."""

    centre_m: tuple[float, float]
    stroke_m: float
    rise_m: float = RISE_M

    @property
    def scaled(self) -> bool:
        return self.stroke_m < STROKE_M - 1e-9

    def corners(self) -> NDArray[np.float64]:
        """Lower left, upper left, upper right, lower right (4, 2) m."""
        x, y = self.centre_m
        h = self.stroke_m / 2
        return np.array([[x - h, y], [x - h, y + self.rise_m], [x + h, y + self.rise_m],
                         [x + h, y]])  # fmt: skip

    def visits(self) -> NDArray[np.float64]:
        """The cycle's points (7, 2) m: up, across, down, and back the same way."""
        c = self.corners()
        return c[[0, 1, 2, 3, 2, 1, 0]]


def _edges(route: StandardRoute) -> NDArray[np.float64]:
    c = route.corners()
    s = np.linspace(0.0, 1.0, EDGE_SAMPLES)[:, None]
    return np.vstack([a + s * (b - a) for a, b in itertools.pairwise(c)])


def standard_route(
    design: ArrayLike, centre: ArrayLike, theta1_range_deg: tuple[float, float],
    theta2_min_deg: float, resolution_m: float = 1e-3,
) -> StandardRoute | None:  # fmt: skip
    """The longest stroke up to :data:`STROKE_M` (to ``resolution_m``) about ``centre`` whose
    rectangle's edges ``design`` reaches within the operating range; None where not even the
    rise at the centre is reached."""
    d, c = np.asarray(design, dtype=float), (float(centre[0]), float(centre[1]))
    op = (tuple(theta1_range_deg), theta2_min_deg)

    def reaches(stroke: float) -> bool:
        edges = _edges(StandardRoute(c, stroke))
        return bool(np.isfinite(batch_joint_angles(d, edges, *op)).all())

    if reaches(STROKE_M):
        return StandardRoute(c, STROKE_M)
    if not reaches(0.0):
        return None
    low, high = 0.0, STROKE_M
    while high - low > resolution_m / 2:
        mid = (low + high) / 2
        low, high = (mid, high) if reaches(mid) else (low, mid)
    return StandardRoute(c, low)


def _summary(record: dict[str, Any], payload_kg: float) -> dict[str, Any]:
    """What the datasheet states of one payload's cycle, from its ``record`` (run_cycle's)."""
    if not record["planned"]:
        return {"payload_kg": payload_kg, "planned": False, "ok": False,
                "reason": record["reason"]}  # fmt: skip
    keys = ("cycle_time_s", "time_optimal_s", "slowed_by", "slowed_for", "thermal_use", "ok",
            "links_hold", "thermal_ok", "strength_utilisation")  # fmt: skip
    sim = record["simulation"]
    return {"payload_kg": payload_kg, "planned": True, **{k: record[k] for k in keys},
            "simulation_passed": sim["passed"], "simulation_reason": sim["reason"]}  # fmt: skip


def standard_cycles(
    done: Realization, props: dict[str, MassProperties], settings: RealizationSettings,
    test: PayloadSettings, route: StandardRoute, raster_speed_deg_s: float,
    max_load_N: float | None = None, jerk_time_s: float | None = None,
) -> list[dict[str, Any]]:  # fmt: skip
    """The standard cycle along ``route`` at the rated payload (``test``'s, which carries the
    tool flange too) and at :data:`LIGHT_PAYLOAD_KG` on the same flange (one cycle where they
    are the same), each planned and checked as the task's (:func:`run_cycle`, ``max_load_N``
    the tolerance's force, ``jerk_time_s`` the moves' jerk time, s)."""
    task = TaskCycle([1, 2, 3, 4, 3, 2, 1], route.visits().tolist(), 0.0)
    rated = round(test.payload_kg - done.tool_kg, 9)
    out = []
    for kg in dict.fromkeys((rated, LIGHT_PAYLOAD_KG)):
        at = replace(test, payload_kg=kg + done.tool_kg)
        record, _, _ = run_cycle(
            done, props, settings, at, task, raster_speed_deg_s, max_load_N, (jerk_time_s,)
        )
        out.append(_summary(record, kg) | {"tool_flange_kg": done.tool_kg})
    return out


def standard_record(
    route: StandardRoute | None, cycles: list[dict[str, Any]], mirrored: bool
) -> dict[str, Any]:
    """JSON-ready record: where the cycle runs (in the user's frame: x mirrored back when the
    task was designed ``mirrored``), its stroke and rise (mm), whether it was scaled, and each
    payload's cycle (:func:`standard_cycles`)."""
    if route is None:
        return {"planned": False, "reason": "the arm reaches no 25 mm rise at the task disk's "
                "centre within its operating range", "payloads": []}  # fmt: skip
    sign = -1.0 if mirrored else 1.0
    return {
        "planned": True,
        "stroke_mm": 1e3 * route.stroke_m,
        "rise_mm": 1e3 * route.rise_m,
        "scaled": route.scaled,
        "centre_m": [sign * route.centre_m[0], route.centre_m[1]],
        "corners_m": (route.corners() * [sign, 1.0]).tolist(),
        "dwell_s": 0.0,
        "payloads": cycles,
    }
