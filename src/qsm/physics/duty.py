"""The duty cycle over which peak motor torques are taken (the same for every mechanism).

The operating range is a domain of joint space, theta1_min <= theta1 <= theta1_max and
theta2_min <= theta2 <= theta1, so one joint-space duty serves all mechanisms. It has two parts:

* a boustrophedon raster: ``raster_lines`` lines of constant theta1 (evenly spaced, both ends of
  the range included) along which theta2 sweeps the whole admissible interval, alternately up and
  down, joined by theta1 moves at the end of each sweep. Every segment is a rest-to-rest
  minimum-jerk move along a straight line in joint space whose faster joint peaks at
  ``peak_speed_deg_s``; ``samples_per_segment`` samples are taken uniformly in time per segment;
* static holding poses on a grid: ``static_theta1_count`` values of theta1 times
  ``static_theta2_count`` values of theta2 spanning [theta2_min, theta1], zero velocity and
  acceleration.

The paper (RecurDyn, "the movement range of the frame and crank are input") states no speeds; the
defaults give 377 samples (313 moving, 64 static) and a 49 s raster.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from qsm.schema.defaults import default

# peak speed of a unit minimum-jerk move of unit duration
MIN_JERK_PEAK_SPEED = 1.875


@dataclass(frozen=True)
class DutySettings:
    """Operating range (deg) and sampling of the duty.

    theta1_min_deg, theta1_max_deg: range of the lower arm angle, default 45 and 180 deg.
    theta2_min_deg: lower limit of the crank angle (upper limit is theta1), default -37.5 deg.
    raster_lines: number of constant-theta1 sweep lines, default 7.
    samples_per_segment: samples per minimum-jerk segment (after its start point), default 24.
    peak_speed_deg_s: peak joint speed of each segment, default 45 deg/s.
    static_theta1_count, static_theta2_count: static holding grid size, default 8 x 8.
    """

    theta1_min_deg: float = default("operating_range.theta1_deg")[0]
    theta1_max_deg: float = default("operating_range.theta1_deg")[1]
    theta2_min_deg: float = default("operating_range.theta2_min_deg")
    raster_lines: int = default("dynamics.duty.raster_lines")
    samples_per_segment: int = default("dynamics.duty.samples_per_segment")
    peak_speed_deg_s: float = default("dynamics.duty.peak_speed_deg_s")
    static_theta1_count: int = default("dynamics.duty.static_theta1_count")
    static_theta2_count: int = default("dynamics.duty.static_theta2_count")

    def __post_init__(self) -> None:
        if not self.theta2_min_deg < self.theta1_min_deg < self.theta1_max_deg:
            raise ValueError("need theta2_min_deg < theta1_min_deg < theta1_max_deg")
        if self.raster_lines < 2 or self.samples_per_segment < 2 or self.peak_speed_deg_s <= 0:
            raise ValueError("need raster_lines >= 2, samples_per_segment >= 2, speed > 0")
        if self.static_theta1_count < 0 or self.static_theta2_count < 0:
            raise ValueError("static grid sizes must be >= 0")


DEFAULT_DUTY = DutySettings()


class Duty(NamedTuple):
    """Duty samples: theta (N, 2) rad, dtheta (N, 2) rad/s, ddtheta (N, 2) rad/s^2 for
    (theta1, theta2); static (N,) bool marks holding poses; time_s (N,) time along the raster
    (NaN for static poses); weight_s (N,) time weight of each sample for time averages (trapezoid
    rule within each segment, 0 for static poses)."""

    theta: NDArray[np.float64]
    dtheta: NDArray[np.float64]
    ddtheta: NDArray[np.float64]
    static: NDArray[np.bool_]
    time_s: NDArray[np.float64]
    weight_s: NDArray[np.float64]


def minimum_jerk(
    start: ArrayLike, end: ArrayLike, duration_s: float, t: ArrayLike
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Rest-to-rest minimum-jerk move from ``start`` to ``end`` (shape (2,)) at times ``t`` (s).

    Returns position, velocity and acceleration, each (len(t), 2); t is clipped to [0, duration].
    """
    q0, q1 = np.asarray(start, dtype=float), np.asarray(end, dtype=float)
    tau = np.clip(np.asarray(t, dtype=float) / duration_s, 0.0, 1.0)[:, None]
    s = tau**3 * (10 - 15 * tau + 6 * tau**2)
    ds = 30 * tau**2 * (1 - tau) ** 2 / duration_s
    dds = 60 * tau * (1 - tau) * (1 - 2 * tau) / duration_s**2
    delta = q1 - q0
    return q0 + s * delta, ds * delta, dds * delta


def raster_waypoints(settings: DutySettings = DEFAULT_DUTY) -> NDArray[np.float64]:
    """Corner points (M, 2) of the boustrophedon raster in rad."""
    s = settings
    lines = np.radians(np.linspace(s.theta1_min_deg, s.theta1_max_deg, s.raster_lines))
    low = np.radians(s.theta2_min_deg)
    points = []
    for i, t1 in enumerate(lines):
        ends = [(t1, low), (t1, t1)]
        points.extend(ends if i % 2 == 0 else ends[::-1])
    return np.asarray(points)


def duty_cycle(settings: DutySettings = DEFAULT_DUTY) -> Duty:
    """The duty samples for ``settings`` (a pure function of the settings)."""
    s = settings
    speed = np.radians(s.peak_speed_deg_s)
    way = raster_waypoints(s)
    thetas, dthetas, ddthetas = [way[:1]], [np.zeros((1, 2))], [np.zeros((1, 2))]
    times, weights = [np.zeros(1)], [np.zeros(1)]
    t_start = 0.0
    for q0, q1 in itertools.pairwise(way):
        duration = MIN_JERK_PEAK_SPEED * np.abs(q1 - q0).max() / speed
        t = np.linspace(0.0, duration, s.samples_per_segment + 1)
        q, dq, ddq = minimum_jerk(q0, q1, duration, t)
        dt = duration / s.samples_per_segment
        w = np.full(s.samples_per_segment + 1, dt)
        w[[0, -1]] = dt / 2
        weights[-1][-1] += w[0]  # the segment's start sample is the previous segment's end
        thetas.append(q[1:])
        dthetas.append(dq[1:])
        ddthetas.append(ddq[1:])
        times.append(t_start + t[1:])
        weights.append(w[1:])
        t_start += duration
    lines = np.radians(np.linspace(s.theta1_min_deg, s.theta1_max_deg, s.static_theta1_count))
    grid = [
        (t1, t2)
        for t1 in lines
        for t2 in np.linspace(np.radians(s.theta2_min_deg), t1, s.static_theta2_count)
    ]
    n_static = len(grid)
    theta = np.concatenate([*thetas, np.reshape(grid, (n_static, 2))])
    zeros = np.zeros((n_static, 2))
    return Duty(
        theta=theta,
        dtheta=np.concatenate([*dthetas, zeros]),
        ddtheta=np.concatenate([*ddthetas, zeros]),
        static=np.concatenate([np.zeros(len(theta) - n_static, bool), np.ones(n_static, bool)]),
        time_s=np.concatenate([*times, np.full(n_static, np.nan)]),
        weight_s=np.concatenate([*weights, np.zeros(n_static)]),
    )
