"""Whether every link and joint bearing of a design holds its loads over the duty, for one design
or thousands.

:class:`StrengthCheck` bundles what the check needs (section, material, requirements, bearing
catalogue, payload and duty) and evaluates designs in chunks, every step vectorised over the chunk:
link mass properties (:func:`qsm.physics.batch_mass.batch_mass_properties`), the loop state, the
joint loads (:mod:`qsm.embodiment.strength.loads`), the bearing of every joint
(:mod:`qsm.embodiment.parts.bearings`: the smallest whose static rating covers the joint's peak
force with the bearing safety factor, among those whose seat leaves ``boss_wall_m`` of the boss and
no wider than the plate, whose bore takes a steel pin in shear, and at A a motor shaft in torsion
under the larger motor torque), and the link stresses with those bores
(:mod:`qsm.embodiment.strength.stresses`: the bearing's seat at B, C, D, its bore, the motor shaft,
at A). It gives Stage 2's strength columns (:data:`STRENGTH_COLUMNS`) and the optimisation's g13:
the largest of the links' utilisation less 1 and the bearings' violation.

The link masses are those of solid bosses (:mod:`qsm.physics.cad`): the bores make the printed
links lighter, so these loads bound the bored parts' from above (the realised design reports the
difference).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray

from qsm.embodiment.parts.bearings import (
    BearingChoice,
    BearingTable,
    astuple_shallow,
    load_catalogue,
)
from qsm.embodiment.strength.beam import Section
from qsm.embodiment.strength.loads import Inertials, JointLoads, joint_loads, link_motion
from qsm.embodiment.strength.material import (
    DEFAULT_MATERIAL,
    DEFAULT_STRENGTH,
    Material,
    StrengthSettings,
)
from qsm.embodiment.strength.sizing import (
    SizedSections,
    SizingSettings,
    fitting_bores,
    joint_bearings,
    seat_limit,
    size_sections,
)
from qsm.embodiment.strength.stresses import JOINTS, LinkStrength, link_strength
from qsm.mechanisms.dataset import JOINT_COLUMNS, STRENGTH_COLUMNS
from qsm.physics.batch_mass import batch_mass_properties
from qsm.physics.cad import DEFAULT_CAD, CadSettings
from qsm.physics.duty import Duty, duty_cycle
from qsm.physics.dynamics import MIN_SIN_TRANSMISSION, loop_state
from qsm.physics.kinematics import LINK_NAMES, as_design

#: Violation g13 gives a design whose loop does not close or is singular over the duty.
UNDEFINED_VIOLATION = 10.0
#: Designs evaluated together (memory: about 0.4 MB per design on the default duty).
CHUNK = 128


class _Core(NamedTuple):
    """What the full table and g13 share for a chunk of designs: the sized sections (None with
    the fixed section) and each link's need for its bearing seats, the joint loads, where the
    check is undefined, each link's peaks and its stress and buckling utilisations, the bearing
    choice (its rows in ``table``) and utilisation, each link's utilisation and the largest."""

    sized: SizedSections | None
    seat: NDArray[np.float64]
    loads: JointLoads
    bad: NDArray[np.bool_]
    per_link: dict[str, LinkStrength]
    stress_u: dict[str, NDArray[np.float64]]
    buckle_u: dict[str, NDArray[np.float64]]
    choice: BearingChoice
    row: NDArray[np.intp]
    table: BearingTable
    bearing_util: NDArray[np.float64]
    link_util: NDArray[np.float64]
    util: NDArray[np.float64]


@dataclass(frozen=True)
class StrengthCheck:
    """What the link check needs: the CAD section, the material, the requirements, the payload
    (kg) at E, the duty, and ``sizing`` (None: every link has the CAD section; else each link's
    section is sized by strength, :mod:`qsm.embodiment.strength.sizing`)."""

    cad: CadSettings = DEFAULT_CAD
    material: Material = DEFAULT_MATERIAL
    strength: StrengthSettings = DEFAULT_STRENGTH
    payload_kg: float = 5.0
    duty: Duty = field(default_factory=duty_cycle)
    bearings: BearingTable = field(default_factory=load_catalogue, compare=False, repr=False)
    sizing: SizingSettings | None = None

    def usable_bearings(self) -> BearingTable:
        """The catalogue's bearings whose seat fits the boss with its wall and whose width fits
        the plate."""
        t, cad = self.bearings, self._largest()
        r, wall = cad.boss_radius_m, self.strength.boss_wall_m
        keep = (t.D_m / 2 + wall <= r * (1 + 1e-12)) & (t.B_m <= cad.thickness_m * (1 + 1e-12))
        if not keep.any():
            raise ValueError(
                f"no bearing of the catalogue fits a boss of radius {r} m with a {wall} m wall "
                f"in a plate {cad.thickness_m} m thick"
            )
        return BearingTable(*(np.asarray(v)[keep] for v in astuple_shallow(t)))

    @property
    def allowable_stress_pa(self) -> float:
        """Largest allowed stress (Pa)."""
        return self.strength.allowable_stress_pa(self.material)

    def _largest(self) -> CadSettings:
        """The largest section a link may get: the CAD section, or its upper sizing bound."""
        return self.cad if self.sizing is None else self.cad.scaled(self.sizing.bounds(self.cad)[1])

    def section_scales(self, designs: ArrayLike) -> SizedSections | None:
        """Each link's section of designs (N, 6) m sized by strength
        (:func:`qsm.embodiment.strength.sizing.size_sections`), None with the fixed section."""
        if self.sizing is None:
            return None
        d = np.atleast_2d(as_design(designs))
        args = (self.cad, self.material, self.strength, self.payload_kg, self.duty)
        parts = [
            size_sections(d[k : k + CHUNK], *args, self.usable_bearings(), self.sizing)
            for k in range(0, len(d), CHUNK)
        ]
        if not parts:
            return SizedSections(np.ones((0, 4)), np.zeros(0, dtype=np.intp))
        return SizedSections(*(np.concatenate(x) for x in zip(*parts, strict=True)))

    def _core(self, d: NDArray[np.float64], sized: SizedSections | None = None) -> _Core:
        """Sections, loads, bearings and link peaks of the designs ``d`` (n, 6) m, and their
        utilisations; ``sized``: their sections when sized already."""
        table = self.usable_bearings()
        if self.sizing is not None and sized is None:
            args = (self.cad, self.material, self.strength, self.payload_kg, self.duty)
            sized = size_sections(d, *args, table, self.sizing)
        scale = None if sized is None else sized.scale
        sec: Section | dict[str, Section] = Section.of(self.cad)
        if scale is not None:
            sec = {k: Section.of(self.cad, scale[:, i]) for i, k in enumerate(LINK_NAMES)}
        inertials = Inertials(*batch_mass_properties(d, self.cad, scale))
        du = self.duty
        state = loop_state(d, du.theta, du.dtheta, du.ddtheta)
        motion = link_motion(d, state)
        loads = joint_loads(d, inertials, self.payload_kg, state, motion)
        choice, row, bores = joint_bearings(loads, table, self.strength)
        seat = np.zeros((len(d), 4))  # each link's need for its bores over its section
        if scale is not None:
            seat = seat_limit(row, table, self.cad, self.strength.boss_wall_m) / scale
            bores = fitting_bores(bores, scale, self.cad)
        per_link = link_strength(
            d, sec, self.material, self.strength, inertials, loads, motion, bores
        )
        bad = ~state.closes.all(-1) | (
            np.nan_to_num(state.sin_transmission).min(-1) < MIN_SIN_TRANSMISSION
        )
        yield_pa = self.material.yield_strength_pa
        stress_u = {
            k: v.stress_pa * self.strength.safety_factor / yield_pa for k, v in per_link.items()
        }
        buckle_u = {
            k: v.compression_N * self.strength.buckling_safety_factor / v.euler_N
            for k, v in per_link.items()
        }
        link_util = np.stack(
            [
                np.maximum(np.maximum(stress_u[k], buckle_u[k]), seat[:, i])
                for i, k in enumerate(per_link)
            ],
            -1,
        )
        # the chosen bearing's s0 F / C0 and needed / actual bore; 1 + violation where none fits
        bearing_util = np.where(
            choice.index < 0,
            1.0 + choice.violation,
            np.maximum(choice.required_C0_N / table.C0_N[row], choice.min_bore_m / table.d_m[row]),
        )
        util = np.concatenate([link_util, bearing_util], axis=-1).max(-1)
        return _Core(
            sized, seat, loads, bad, per_link, stress_u, buckle_u, choice, row, table,
            bearing_util, link_util, util,
        )  # fmt: skip

    def _chunk(
        self, d: NDArray[np.float64], sized: SizedSections | None = None
    ) -> dict[str, NDArray]:
        """The :data:`STRENGTH_COLUMNS` of the designs ``d`` (n, 6) m, and their motor torques;
        ``sized``: their sections when sized already."""
        core = self._core(d, sized)
        choice, row, table, bad, seat = core.choice, core.row, core.table, core.bad, core.seat
        forces, bearing_util = core.loads._asdict(), core.bearing_util
        yield_pa = self.material.yield_strength_pa
        out: dict[str, NDArray] = {}
        for k, (link, res) in enumerate(core.per_link.items()):
            with np.errstate(divide="ignore"):
                out[f"buckling_factor_{link}"] = res.euler_N / res.compression_N
            out[f"stress_peak_{link}_MPa"] = res.stress_pa / 1e6
            out[f"safety_factor_{link}"] = yield_pa / res.stress_pa
            stress_u, buckle_u = core.stress_u[link], core.buckle_u[link]
            labels = np.array([*res.labels, "buckling"], dtype=object)
            check = np.where(buckle_u > stress_u, labels[-1], labels[res.where])
            seated = ~(seat[:, k] > 1.0)  # the seat's sliver of boss is what fails
            out[f"_check_{link}"] = np.where(seated, check, "bearing seat")
        for k, joint in enumerate(JOINTS):
            out[f"bearing_{joint}"] = np.where(
                choice.index[..., k] < 0, "", table.designation[row[..., k]]
            ).astype(object)
        out["bearing_violation"] = choice.violation.max(-1)
        out["bearing_utilisation"] = bearing_util.max(-1)
        out["strength_utilisation"] = core.util
        # the chosen bearing sits near its rating by design: name it only when it fails
        weakest = np.concatenate(
            [core.link_util, np.where(bearing_util > 1.0, bearing_util, 0.0)], axis=-1
        ).argmax(-1)
        names = [*LINK_NAMES, *(f"bearing {j}" for j in JOINTS)]
        out["weakest_link"] = np.asarray(names, dtype=object)[weakest]
        checks = np.stack(
            [out.pop(f"_check_{k}") for k in LINK_NAMES]
            + [np.full(len(d), "static load rating", dtype=object)] * len(JOINTS),
            -1,
        )
        out["weakest_check"] = np.take_along_axis(checks, weakest[:, None], -1)[:, 0]
        theta = np.degrees(self.duty.theta)
        for suffix, name in JOINT_COLUMNS.items():
            x, y = forces[name][..., 0], forces[name][..., 1]
            square = np.nan_to_num(x * x + y * y, nan=-1.0)  # the magnitude's order, cheaply
            k = square.argmax(-1)
            peak = np.take_along_axis(square, k[:, None], -1)[:, 0]
            out[f"joint_force_peak_{suffix}_N"] = np.where(peak < 0, -1.0, np.sqrt(np.abs(peak)))
            out[f"joint_force_peak_{suffix}_theta1_deg"] = theta[k, 0]
            out[f"joint_force_peak_{suffix}_theta2_deg"] = theta[k, 1]
        for col in out.values():
            col[bad] = np.nan if col.dtype.kind == "f" else ""
        out["holds_loads"] = out["strength_utilisation"] <= 1.0
        factor = np.ones((len(d), 4)) if core.sized is None else core.sized.scale
        for i, link in enumerate(LINK_NAMES):
            out[f"section_width_{link}_mm"] = 1e3 * self.cad.width_m * factor[:, i]
            out[f"section_thickness_{link}_mm"] = 1e3 * self.cad.thickness_m * factor[:, i]
        out["section_iterations"] = (
            np.zeros(len(d), dtype=np.intp) if core.sized is None else core.sized.iterations
        )
        out["_tau"], out["_good"] = core.loads.tau, ~bad
        return out

    def evaluate(self, designs: ArrayLike) -> pd.DataFrame:
        """:data:`STRENGTH_COLUMNS` of designs (N, 6) m; NaN (and not holding) where the loop
        does not close or is singular on the duty."""
        return self.evaluate_with_torques(designs)[0]

    def evaluate_with_torques(
        self, designs: ArrayLike, sized: SizedSections | None = None
    ) -> tuple[pd.DataFrame, NDArray[np.float64], NDArray[np.bool_]]:
        """:meth:`evaluate`, and the motor torques (N, samples, 2) in N m over the duty and where
        they are defined (N,), for the drive check to reuse; ``sized``: the sections of
        :meth:`section_scales` when computed already."""
        d = np.atleast_2d(as_design(designs))
        parts = [
            self._chunk(
                d[k : k + CHUNK], None if sized is None else sized.rows(slice(k, k + CHUNK))
            )
            for k in range(0, len(d), CHUNK)
        ]
        if not parts:
            empty = np.zeros((0, len(self.duty.theta), 2))
            return pd.DataFrame(columns=list(STRENGTH_COLUMNS)), empty, np.zeros(0, bool)
        table = pd.DataFrame({k: np.concatenate([p[k] for p in parts]) for k in STRENGTH_COLUMNS})
        tau = np.concatenate([p["_tau"] for p in parts])
        return table, tau, np.concatenate([p["_good"] for p in parts])

    def violation(self, designs: ArrayLike) -> NDArray[np.float64]:
        """g13: strength utilisation - 1 of designs (N, 6) m (<= 0 holds), or
        :data:`UNDEFINED_VIOLATION` where it is undefined."""
        return self.violation_and_torques(designs)[0]

    def violation_and_torques(
        self, designs: ArrayLike, allowance: float = 0.0
    ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.bool_]]:
        """g13 of designs (N, 6) m (:meth:`violation`), and the motor torques (N, samples, 2) in
        N m over the duty and where they are defined (N,), for the drive check to reuse.

        ``allowance``: the links' utilisation is taken ``1 + allowance`` times larger (a coarser
        duty's peaks kept in hand). The bearings' is not: the chosen bearing is the smallest that
        covers its joint's force, so it sits near its rating by design, and a larger one is
        chosen when the force grows; a joint's utilisation exceeds 1 only where no bearing fits.
        """
        d = np.atleast_2d(as_design(designs))
        cores = [self._core(d[k : k + CHUNK]) for k in range(0, len(d), CHUNK)]
        if not cores:
            return np.zeros(0), np.zeros((0, len(self.duty.theta), 2)), np.zeros(0, bool)
        util = np.concatenate(
            [
                np.where(
                    c.bad,
                    np.nan,
                    np.maximum(c.link_util.max(-1) * (1.0 + allowance), c.bearing_util.max(-1)),
                )
                for c in cores
            ]
        )
        good = np.concatenate([~c.bad for c in cores])
        tau = np.concatenate([c.loads.tau for c in cores])
        return np.where(np.isfinite(util), util - 1.0, UNDEFINED_VIOLATION), tau, good
