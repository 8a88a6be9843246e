"""Whether each motor of a design has a drive in the catalogue, for one design or thousands.

:class:`DriveCheck` bundles what the check needs (catalogue, rule, section, payload and duty) and
evaluates designs in chunks, every step vectorised over the chunk: the joint torques come from
the Newton-Euler loads of :mod:`qsm.embodiment.strength.loads` (tested against MuJoCo), the speeds
and accelerations from the duty (both motors are absolute joint angles), the time weights are the
duty's ``weight_s``; :func:`qsm.embodiment.drives.selection.select_drives` then checks every
drive against every sample.

Reflected inertia: with ``reflected_inertia`` on, each candidate drive c is checked against the
torque ``tau + J_c theta''``, J_c = (J_motor + J_gear,in) N^2 its reflected inertia. That term is
exactly what MuJoCo's joint ``armature`` J_c on theta1 / theta2 adds to the inverse dynamics
(the motors' joints are the absolute angles, so G's rows for them are the unit vectors; tested
against a model with armature), so the choice and the torques agree without iterating. Motor
masses do not load the links: both motors sit at the base joint A.

It gives Stage 2's drive columns (:data:`DRIVE_COLUMNS`), the optimisation's g14 and its
drive-mass objective.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from functools import cached_property

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray

from qsm.embodiment.drives.catalogue import Catalogue, load_catalogue
from qsm.embodiment.drives.compliance import gear_compliance
from qsm.embodiment.drives.drive_columns import DRIVE_COLUMNS, MOTORS
from qsm.embodiment.drives.drive_table import drive_columns
from qsm.embodiment.drives.report import DriveReport, TaskMotionNeed
from qsm.embodiment.drives.selection import Selection, drive_violations, select_drives
from qsm.embodiment.drives.utilization import DriveArrays
from qsm.embodiment.strength.link_checks import StrengthCheck
from qsm.embodiment.strength.loads import Inertials, joint_loads
from qsm.physics.batch_mass import batch_mass_properties
from qsm.physics.cad import DEFAULT_CAD, CadSettings
from qsm.physics.duty import Duty, duty_cycle
from qsm.physics.dynamics import MIN_SIN_TRANSMISSION, loop_state
from qsm.physics.kinematics import as_design

#: Violation g14 gives a design whose loop does not close or is singular over the duty.
UNDEFINED_VIOLATION = 10.0
#: Designs evaluated together.
CHUNK = 128


def _default_catalogue() -> Catalogue:
    return load_catalogue()


@dataclass(frozen=True)
class DriveCheck:
    """What the drive check needs: the ``catalogue``, the selection ``rule`` (lightest or
    smallest_inertia), whether the drives' ``reflected_inertia`` loads the joints, the link
    section ``cad``, the payload (kg) at E, the duty, each motor's least gearbox torsional
    stiffness (N m/rad; 0: any) and the ``task_duty`` a realised design's drives must meet as
    well (the task's motion through its points; None: the duty alone)."""

    catalogue: Catalogue = field(default_factory=_default_catalogue)
    rule: str = "lightest"
    reflected_inertia: bool = True
    cad: CadSettings = DEFAULT_CAD
    payload_kg: float = 5.0
    duty: Duty = field(default_factory=duty_cycle)
    min_stiffness_Nm_rad: tuple[float, float] = (0.0, 0.0)
    task_duty: Duty | None = None

    def torques(
        self, designs: ArrayLike, scales: ArrayLike | None = None
    ) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
        """Motor torques (D, N, 2) in N m of designs (D, 6) m over the duty, without drives, and
        whether each design's loop closes, away from singularities, over the whole duty (D,);
        ``scales`` (D, 4): each link's section scale (sized sections)."""
        d = np.atleast_2d(as_design(designs))
        inertials = Inertials(*batch_mass_properties(d, self.cad, scales))
        du = self.duty
        state = loop_state(d, du.theta, du.dtheta, du.ddtheta)
        tau = joint_loads(d, inertials, self.payload_kg, state).tau
        good = state.closes.all(-1) & (
            np.nan_to_num(state.sin_transmission).min(-1) >= MIN_SIN_TRANSMISSION
        )
        return tau, good

    @cached_property
    def arrays(self) -> DriveArrays:
        """The catalogue's per-drive values, read once."""
        return DriveArrays.of(self.catalogue)

    @cached_property
    def stiffness_Nm_rad(self) -> NDArray[np.float64]:
        """Each drive's gearbox torsional stiffness (C,) N m/rad, given or assumed."""
        gears = self.catalogue.gearboxes.loc[self.catalogue.drives["gearbox"]]
        return np.array(
            [gear_compliance(g)["torsional_stiffness_Nm_rad"] for _, g in gears.iterrows()]
        )

    def _allowed(self, j: int) -> NDArray[np.bool_] | None:
        """The drives motor ``j`` (0, 1) may have: stiff enough (None: all)."""
        least = self.min_stiffness_Nm_rad[j]
        return None if least <= 0 else self.stiffness_Nm_rad >= least

    @cached_property
    def _columns(self) -> dict[str, NDArray]:
        """The catalogue's drive columns of :data:`DRIVE_COLUMNS` (C,), read once."""
        d = self.catalogue.drives
        return {
            "motor": d["motor"].to_numpy(object),
            "gearbox": d["gearbox"].to_numpy(object),
            "ratio": self.arrays.ratio,
            "mass_kg": self.arrays.mass,
            "reflected_inertia_kgm2": self.arrays.reflected_inertia,
        }

    def select(self, tau: ArrayLike, also: list[NDArray] | None = None) -> list[Selection]:
        """One :class:`Selection` per motor for motor torques (D, N, 2) N m over the duty;
        ``also``: per motor, each drive's violation (C,) of the task duty
        (:meth:`task_violations`)."""
        tau = np.asarray(tau, dtype=float)
        du = self.duty
        n_d = tau.shape[0]
        out = []
        for j in range(2):
            omega = np.broadcast_to(du.dtheta[:, j], (n_d, len(du.weight_s)))
            accel = np.broadcast_to(du.ddtheta[:, j], omega.shape)
            out.append(
                select_drives(
                    self.catalogue,
                    tau[..., j],
                    omega,
                    du.weight_s,
                    self.rule,
                    accel if self.reflected_inertia else None,
                    self.arrays,
                    self._allowed(j),
                    None if also is None else also[j],
                )
            )
        return out

    def _chunk(
        self, d: NDArray[np.float64], torques: tuple[NDArray, NDArray] | None = None
    ) -> dict[str, NDArray]:
        tau, good = self.torques(d) if torques is None else (torques[0].copy(), torques[1])
        tau[~good] = np.nan  # no drive, infinite violation
        return drive_columns(self.select(tau), good, self._columns)

    def evaluate(
        self, designs: ArrayLike, torques: tuple[NDArray, NDArray] | None = None
    ) -> pd.DataFrame:
        """:data:`DRIVE_COLUMNS` of designs (N, 6) m; NaN (and no drives) where the loop does not
        close or is singular on the duty. ``torques``: the motor torques (N, samples, 2) N m
        over this check's duty and where they are defined (N,), when computed elsewhere
        (:meth:`qsm.embodiment.strength.link_checks.StrengthCheck.evaluate_with_torques`)."""
        d = np.atleast_2d(as_design(designs))
        parts = [
            self._chunk(
                d[k : k + CHUNK],
                None if torques is None else (torques[0][k : k + CHUNK], torques[1][k : k + CHUNK]),
            )
            for k in range(0, len(d), CHUNK)
        ]
        if not parts:
            return pd.DataFrame(columns=list(DRIVE_COLUMNS))
        return pd.DataFrame({k: np.concatenate([p[k] for p in parts]) for k in DRIVE_COLUMNS})

    def violation_from_torques(
        self, designs: ArrayLike, tau: NDArray[np.float64], good: NDArray[np.bool_]
    ) -> NDArray[np.float64]:
        """:meth:`violation` from motor torques computed elsewhere (see :meth:`evaluate`)."""
        return violation_of(self.evaluate(designs, (tau, good)))

    def violation(self, designs: ArrayLike) -> NDArray[np.float64]:
        """g14: the larger motor violation of designs (N, 6) m (<= 0: each motor has a drive),
        or :data:`UNDEFINED_VIOLATION` where it is undefined (the loop does not close, or a
        value the check needs is missing)."""
        return self.violation_from_torques(designs, *self.torques(np.atleast_2d(designs)))

    @property
    def penalty_kg(self) -> float:
        """The drive-mass objective (kg) of a design without drives, less its g14 violation:
        twice the catalogue's heaviest drive."""
        return 2.0 * float(np.nanmax(self.arrays.mass))

    def mass_objective(self, table: pd.DataFrame) -> NDArray[np.float64]:
        """The drive-mass objective (kg) of designs from their :meth:`evaluate` table: the mass of
        both drives where each motor has one; else :attr:`penalty_kg` plus the g14 violation
        (:func:`violation_of`, read as kg), so every design with drives ranks ahead of every
        design without and the shortfall still guides the search."""
        mass = table["drive_mass_kg"].to_numpy(float)
        return np.where(
            table["has_drives"].to_numpy(bool), mass, self.penalty_kg + violation_of(table)
        )

    def task_violations(
        self, design: ArrayLike, scales: ArrayLike | None = None
    ) -> tuple[list[NDArray] | None, TaskMotionNeed | None]:
        """Per motor, each drive's violation (C,) of :attr:`task_duty` by one design (None: no
        task duty; infinite for every drive where the design's loop does not close along it, so
        that no drive meets it), and the task motion's required peak and RMS torques (N m,
        without the drives' inertia) for the report."""
        du = self.task_duty
        if du is None:
            return None, None
        tau, good = replace(self, duty=du, task_duty=None).torques(design, scales)
        if not good[0]:
            return [np.full(self.arrays.ratio.size, np.inf)] * 2, TaskMotionNeed(False)
        also = [
            drive_violations(self.arrays, tau[0, :, j], du.dtheta[:, j], du.weight_s,
                             du.ddtheta[:, j] if self.reflected_inertia else None)
            for j in range(2)
        ]  # fmt: skip
        w = du.weight_s / du.weight_s.sum()
        need = TaskMotionNeed(
            True,
            tuple(np.abs(tau[0]).max(axis=0).tolist()),
            tuple(np.sqrt((w[:, None] * tau[0] ** 2).sum(axis=0)).tolist()),
            float(du.weight_s.sum()),
        )
        return also, need

    def report(self, design: ArrayLike, scales: ArrayLike | None = None) -> DriveReport:
        """One design's drives: per motor the drive it is built with, its margins and what its
        duty requires (:meth:`Selection.report`), and what the task's motion asks
        (:meth:`task_violations`, which the drives meet as well); ``scales`` (1, 4) as
        :meth:`torques`."""
        d = np.atleast_2d(as_design(design))
        tau, good = self.torques(d, scales)
        if not good[0]:
            return DriveReport(defined=False, rule=self.rule)
        also, task = self.task_violations(d, scales)
        motors = {
            f"motor{j}": replace(sel.report(0), label=MOTORS[j])
            for j, sel in zip(MOTORS, self.select(tau, also), strict=True)
        }
        return DriveReport(
            defined=True,
            rule=self.rule,
            motors=motors,
            reflected_inertia=self.reflected_inertia,
            task_motion=task,
        )


def violation_of(table: pd.DataFrame) -> NDArray[np.float64]:
    """g14 of designs from their :meth:`DriveCheck.evaluate` table: the larger motor violation
    (<= 0: each motor has a drive), :data:`UNDEFINED_VIOLATION` where it is undefined."""
    v = table["drive_violation"].to_numpy(float)
    return np.where(np.isfinite(v), v, UNDEFINED_VIOLATION)


def same_loads(strength: StrengthCheck, drives: DriveCheck) -> bool:
    """Whether the strength check's motor torques are the drive check's: same link section,
    payload and duty."""
    return (
        strength.cad == drives.cad
        and strength.payload_kg == drives.payload_kg
        and all(
            np.array_equal(a, b, equal_nan=True)
            for a, b in zip(strength.duty, drives.duty, strict=True)
        )
    )
