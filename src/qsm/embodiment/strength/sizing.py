"""Sections sized by strength (``cad.section: sized``): each link's section is the smallest that
holds its loads, iterated with the dynamics its mass gives.

Rule: every length of a link's section scales by one factor ``s`` per link and design (width
``s w0``, thickness ``s t0``, boss radius ``s R0`` of the configured ``cad`` section), so the
outline keeps its proportions and the bosses keep exceeding half the width. ``s`` lies within

* the bounds of ``cad.sized`` (:meth:`SizingSettings.bounds`);
* the link's length: the bosses must leave a bar (:func:`fit_limit`);
* the link's bores: each bearing seat with ``strength.boss_wall_m`` of wall inside the boss
  (``s R0 >= D / 2 + wall``) and no wider than the plate (``s t0 >= B``); at A the motor shaft's
  bore with its wall (``s R0 >= d / 2 + wall``). The bearings are the smallest of the catalogue
  that hold each joint (:func:`joint_bearings`) among those that fit the largest section.

Within these, ``s`` is the smallest whose strength utilisation (the checks of
:mod:`qsm.embodiment.strength.stresses` with the configured safety factors: bar bending and axial
stress, net section at the bores, pin-loaded lugs, Euler buckling) is at most ``target`` under the
current loads (:func:`smallest_holding`); at fixed loads each check falls as ``s`` grows. Where
the upper bound does not hold, ``s`` is the upper bound and the link fails g13 (the strength
check names it).

Loads -> sections -> masses -> loads: from the configured section (within the bounds), each
iteration computes the joint loads with the current link masses and sizes every link for them.
A design's sections are frozen once its peak motor torques changed by less than ``tolerance``
(relative) from the previous iteration and its sections by less than ``tolerance`` from the
ones that gave these loads; at most ``max_iterations``. ``target`` (:data:`TARGET`) keeps the
final check (the sections' own masses and loads) within 1 after such a last step.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from qsm.embodiment.parts.bearings import BearingChoice, BearingTable, min_shaft_diameter_m
from qsm.embodiment.parts.bearings import select_bearings as _select
from qsm.embodiment.strength.beam import Section
from qsm.embodiment.strength.loads import Inertials, JointLoads, joint_loads, link_motion
from qsm.embodiment.strength.material import Material, StrengthSettings
from qsm.embodiment.strength.stresses import BORES, JOINTS, LinkLoads, link_loads, link_peaks
from qsm.physics.batch_mass import batch_mass_properties
from qsm.physics.cad import CadSettings
from qsm.physics.duty import Duty
from qsm.physics.dynamics import MIN_SIN_TRANSMISSION, loop_state
from qsm.physics.kinematics import LINK_NAMES
from qsm.schema.defaults import default

#: Utilisation a sized link is sized to (1 % in hand for the last iteration's change of loads).
TARGET = 0.99
#: Illinois steps of the search for the smallest holding section (:func:`smallest_holding`).
SEARCH_STEPS = 5


@dataclass(frozen=True)
class SizingSettings:
    """``cad.sized``: bounds (min, max) of the bar ``width_m`` and plate ``thickness_m`` (m), the
    cap on the loads -> sections iterations and their relative ``tolerance``, and the
    utilisation ``target`` a link is sized to (the optimisation's g13 sizes to less, to keep
    its allowance for the coarser duty). ``floor`` (4,): each link's smallest scale, where
    more than strength asks for a section (the realisation's accuracy; None: none)."""

    width_m: tuple[float, float] = default("cad.sized.width_m")
    thickness_m: tuple[float, float] = default("cad.sized.thickness_m")
    max_iterations: int = default("cad.sized.max_iterations")
    tolerance: float = default("cad.sized.tolerance")
    target: float = TARGET
    floor: tuple[float, ...] | None = None

    def __post_init__(self) -> None:
        for lo, hi in (self.width_m, self.thickness_m):
            if not 0 < lo <= hi:
                raise ValueError("sizing bounds must be positive and ordered (min <= max)")
        if self.max_iterations < 1 or not self.tolerance > 0 or not 0 < self.target <= 1:
            raise ValueError("max_iterations >= 1, tolerance > 0 and target in (0, 1] needed")

    def bounds(self, cad: CadSettings) -> tuple[float, float]:
        """Smallest and largest scale factor of ``cad``'s section within the width and thickness
        bounds; ``ValueError`` when no factor meets both."""
        w0, t0 = cad.width_m, cad.thickness_m
        lo = max(self.width_m[0] / w0, self.thickness_m[0] / t0)
        hi = min(self.width_m[1] / w0, self.thickness_m[1] / t0)
        if lo > hi:
            raise ValueError(
                f"no scale of the {w0} x {t0} m section meets both cad.sized bounds "
                f"(width {self.width_m}, thickness {self.thickness_m})"
            )
        return lo, hi


class SizedSections(NamedTuple):
    """Sized sections of designs: ``scale`` (N, 4) of each link's CAD section and the
    ``iterations`` (N,) each design took."""

    scale: NDArray[np.float64]
    iterations: NDArray[np.intp]

    def rows(self, index: slice | NDArray[np.bool_]) -> SizedSections:
        """These sections for the designs ``index`` selects."""
        return SizedSections(self.scale[index], self.iterations[index])


def fit_limit(designs: NDArray[np.float64], cad: CadSettings) -> NDArray[np.float64]:
    """Largest scale factor (..., 4) of ``cad``'s section each link of ``designs`` (..., 6) m
    takes (exclusive): bars longer than their two boss overlaps, the upper arm's legs longer
    than :attr:`qsm.physics.cad.CadSettings.leg_min_m` (:func:`qsm.physics.cad.link_outlines`)."""
    x0 = cad.boss_overlap_m
    l1, l2, l3, l4, ex, ey = np.moveaxis(designs, -1, 0)
    upper = np.minimum(l4 / (2 * x0), np.minimum(ex, ey) / cad.leg_min_m)
    return np.stack([l1 / (2 * x0), l2 / (2 * x0), l3 / (2 * x0), upper], -1)


def _peak(force: NDArray[np.float64]) -> NDArray[np.float64]:
    """Peak magnitude over the duty samples of forces (..., N, 2)."""
    x, y = force[..., 0], force[..., 1]
    return np.sqrt((x * x + y * y).max(-1))  # not hypot: 20x slower, the same to an ulp


def joint_bearings(
    loads: JointLoads, table: BearingTable, strength: StrengthSettings
) -> tuple[BearingChoice, NDArray[np.intp], NDArray[np.float64]]:
    """The bearing of every joint A-D from ``table`` for ``loads`` (the smallest whose static
    rating covers the peak force with the bearing safety factor and whose bore takes the pin, at
    A the motor shaft under the larger peak torque); the catalogue row used (the last where none
    fits) and the bores (..., 4) m: the shaft (bearing bore) at A, the seats (outer diameter) at
    B, C, D."""
    forces = loads._asdict()
    peak = np.stack(
        [
            np.maximum(_peak(forces["a_lower"]), _peak(forces["a_crank"])),
            _peak(forces["b"]),
            _peak(forces["c"]),
            _peak(forces["d"]),
        ],
        axis=-1,
    )
    sf, steel = strength.bearing_safety_factor, strength.pin_yield_strength_pa
    shaft = min_shaft_diameter_m(np.nan_to_num(np.abs(loads.tau).max(-2)).max(-1), steel, sf)
    choice = _select(
        np.nan_to_num(peak),
        table,
        sf,
        pin_yield_pa=steel,
        min_bore_m=np.stack([shaft, *[np.zeros_like(shaft)] * 3], axis=-1),
    )
    row = np.where(choice.index < 0, len(table) - 1, choice.index)
    bores = np.concatenate([table.d_m[row[..., :1]], table.D_m[row[..., 1:]]], axis=-1)
    return choice, row, bores


def seat_limit(
    row: NDArray[np.intp], table: BearingTable, cad: CadSettings, wall_m: float
) -> NDArray[np.float64]:
    """Smallest scale factor (..., 4) of ``cad``'s section each link needs for its bores (the
    catalogue ``row`` per joint A-D, :func:`joint_bearings`): every seat with ``wall_m`` inside
    the boss and no wider than the plate; at A the shaft bore with its wall."""
    seat = np.maximum(
        (table.D_m[row] / 2 + wall_m) / cad.boss_radius_m, table.B_m[row] / cad.thickness_m
    )
    seat[..., 0] = (table.d_m[row[..., 0]] / 2 + wall_m) / cad.boss_radius_m
    need = [seat[..., [JOINTS.index(j) for j, _ in BORES[link]]].max(-1) for link in LINK_NAMES]
    return np.stack(need, -1)


def fitting_bores(
    bores: NDArray[np.float64], scale: NDArray[np.float64], cad: CadSettings
) -> NDArray[np.float64]:
    """Bores (..., 4) at A-D kept inside the smallest boss at each joint of the links scaled by
    ``scale`` (..., 4): a seat that does not fit (the section at its upper bound) leaves a
    sliver of boss, whose stresses then fail the link, instead of a geometry the checks reject."""
    out = bores.copy()
    for j, joint in enumerate(JOINTS):
        links = [i for i, k in enumerate(LINK_NAMES) if joint in dict(BORES[k])]
        boss = cad.boss_radius_m * scale[..., links].min(-1)
        out[..., j] = np.minimum(bores[..., j], 2 * boss * (1 - 1e-6))
    return out


def utilization(
    links: dict[str, LinkLoads],
    scale: NDArray[np.float64],
    cad: CadSettings,
    material: Material,
    strength: StrengthSettings,
) -> NDArray[np.float64]:
    """Strength utilisation (..., 4) of each link with its section scaled by ``scale`` (..., 4)
    under fixed loads ``links`` (:func:`qsm.embodiment.strength.stresses.link_loads`): the larger of
    stress x safety factor / yield and compression x buckling factor / Euler load."""
    y = material.yield_strength_pa
    out = []
    for i, k in enumerate(LINK_NAMES):
        r = link_peaks(links[k], Section.of(cad, scale[..., i]), material, strength)
        out.append(
            np.maximum(
                r.stress_pa * strength.safety_factor / y,
                r.compression_N * strength.buckling_safety_factor / r.euler_N,
            )
        )
    return np.nan_to_num(np.stack(out, -1))


def smallest_holding(
    util: Callable[[NDArray[np.float64]], NDArray[np.float64]],
    lower: NDArray[np.float64],
    upper: NDArray[np.float64],
    target: float = TARGET,
) -> NDArray[np.float64]:
    """Smallest scale in [``lower``, ``upper``] (elementwise) whose ``util`` is at most
    ``target``, to :data:`SEARCH_STEPS` Illinois (regula falsi) steps on ``log util``
    against ``log s`` (nearly linear: every check falls as a power of s), ending on the holding
    side; ``upper`` where even it does not hold."""

    def f(y: NDArray[np.float64]) -> NDArray[np.float64]:
        return np.log(np.maximum(util(np.exp(y)), 1e-12) / target)

    y_lo, y_hi = np.log(lower), np.log(upper)
    f_lo, f_hi = f(y_lo), f(y_hi)
    done = (f_hi > 0) | (f_lo <= 0)
    y_hi = np.where(f_lo <= 0, y_lo, y_hi)
    side = np.zeros(lower.shape, dtype=np.int8)  # the end replaced last: -1 low, +1 high
    for _ in range(SEARCH_STEPS):
        with np.errstate(invalid="ignore", divide="ignore"):
            y = y_hi - f_hi * (y_hi - y_lo) / (f_hi - f_lo)
        y = np.where(done | ~np.isfinite(y), y_hi, np.clip(y, y_lo, y_hi))
        fy = f(y)
        holds = (fy <= 0) & ~done
        fails = (fy > 0) & ~done
        f_lo = np.where(holds & (side == 1), f_lo / 2, f_lo)
        f_hi = np.where(fails & (side == -1), f_hi / 2, f_hi)
        y_hi, f_hi = np.where(holds, y, y_hi), np.where(holds, fy, f_hi)
        y_lo, f_lo = np.where(fails, y, y_lo), np.where(fails, fy, f_lo)
        side = np.where(holds, 1, np.where(fails, -1, side)).astype(np.int8)
    return np.exp(y_hi)


def size_sections(
    designs: NDArray[np.float64],
    cad: CadSettings,
    material: Material,
    strength: StrengthSettings,
    payload_kg: float,
    duty: Duty,
    table: BearingTable,
    sizing: SizingSettings,
) -> SizedSections:
    """Scale factor (D, 4) of each link's section of ``designs`` (D, 6) m and the iterations
    (D,) each design took (see the module docstring); ``table``: the bearings that fit the
    largest section."""
    d = designs
    state = loop_state(d, duty.theta, duty.dtheta, duty.ddtheta)
    motion = link_motion(d, state)
    lo, hi = sizing.bounds(cad)
    upper = np.minimum(hi, fit_limit(d, cad) * (1 - 1e-9))
    floor = lo if sizing.floor is None else np.maximum(lo, np.asarray(sizing.floor, dtype=float))
    s = np.minimum(np.maximum(1.0, floor), upper)
    bad = ~state.closes.all(-1) | (
        np.nan_to_num(state.sin_transmission).min(-1) < MIN_SIN_TRANSMISSION
    )
    done = bad.copy()
    iterations = np.zeros(len(d), dtype=np.intp)
    tau_prev = np.full((len(d), 2), np.inf)
    for it in range(1, sizing.max_iterations + 1):
        inertials = Inertials(*batch_mass_properties(d, cad, s))
        loads = joint_loads(d, inertials, payload_kg, state, motion)
        tau = np.nan_to_num(np.abs(loads.tau)).max(-2)
        _, row, bores = joint_bearings(loads, table, strength)
        seat = seat_limit(row, table, cad, strength.boss_wall_m)
        lower = np.minimum(np.maximum(floor, seat), upper)
        bores = fitting_bores(bores, lower, cad)

        links = {
            k: link_loads(d, Section.of(cad, s[:, i]), inertials, loads, motion, bores, k)
            for i, k in enumerate(LINK_NAMES)
        }

        def util(x: NDArray[np.float64], links: dict = links) -> NDArray[np.float64]:
            return utilization(links, x, cad, material, strength)

        new = smallest_holding(util, lower, upper, sizing.target)
        change_tau = (np.abs(tau - tau_prev) / np.maximum(tau, 1e-12)).max(-1)
        change_s = (np.abs(new - s) / s).max(-1)
        active = ~done
        s = np.where(active[:, None], new, s)
        iterations = np.where(active, it, iterations)
        done |= (change_tau < sizing.tolerance) & (change_s < sizing.tolerance)
        if done.all():
            break
        tau_prev = tau
    return SizedSections(s, iterations)
