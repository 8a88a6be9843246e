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

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray

from qsm.embodiment.parts.bearings import (
    BearingTable,
    astuple_shallow,
    load_catalogue,
)
from qsm.embodiment.strength.beam import Section
from qsm.embodiment.strength.loads import Inertials, joint_loads, link_motion
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
from qsm.embodiment.strength.strength_columns import STRENGTH_COLUMNS
from qsm.embodiment.strength.strength_table import StrengthCore, strength_columns
from qsm.embodiment.strength.stresses import link_strength
from qsm.physics.batch_mass import batch_mass_properties
from qsm.physics.cad import DEFAULT_CAD, CadSettings
from qsm.physics.duty import Duty, duty_cycle
from qsm.physics.dynamics import MIN_SIN_TRANSMISSION, loop_state
from qsm.physics.kinematics import LINK_NAMES, as_design

#: Violation g13 gives a design whose loop does not close or is singular over the duty.
UNDEFINED_VIOLATION = 10.0
#: Designs evaluated together (memory: about 0.4 MB per design on the default duty).
CHUNK = 128


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

    def core(self, d: NDArray[np.float64], sized: SizedSections | None = None) -> StrengthCore:
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
        return StrengthCore(
            sized, seat, loads, bad, per_link, stress_u, buckle_u, choice, row, table,
            bearing_util, link_util, util,
        )  # fmt: skip

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
            strength_columns(
                self.core(
                    d[k : k + CHUNK], None if sized is None else sized.rows(slice(k, k + CHUNK))
                ),
                self.cad,
                self.material.yield_strength_pa,
                np.degrees(self.duty.theta),
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
        cores = [self.core(d[k : k + CHUNK]) for k in range(0, len(d), CHUNK)]
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
