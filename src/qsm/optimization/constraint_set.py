"""The constraint set of Stage 4: the names of the columns g1..g15 and :class:`ExtraConstraints`,
which of g11..g15 are on and their values (g11 m, g12 mm, g13 and g14 utilisation less 1, g15
mm); see :mod:`qsm.optimization.problems`.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from qsm.embodiment.drives.drive_checks import DriveCheck, same_loads, violation_of
from qsm.embodiment.parts.printing import printability_violation_mm
from qsm.embodiment.stiffness.sag_check import SagCheck
from qsm.embodiment.strength.link_checks import UNDEFINED_VIOLATION, StrengthCheck
from qsm.mechanisms.scale import FitSettings
from qsm.optimization.constraints import containment_margin_m
from qsm.physics.cad import CadSettings
from qsm.physics.duty import DutySettings

#: g13 and g14 of a candidate that fails a cheaper constraint (not evaluated there): the
#: violation of a design whose check is undefined.
NOT_EVALUATED = UNDEFINED_VIOLATION

PAPER_CONSTRAINTS: tuple[str, ...] = (
    "g1_eta_positive",
    "g2_tau1_positive",
    "g3_tau2_positive",
    "g4_crank_rocker",
    "g5_eta_low",
    "g6_eta_high",
    "g7_tau1_low",
    "g8_tau1_high",
    "g9_tau2_low",
    "g10_tau2_high",
)
G11 = "g11_task_contained"
G12 = "g12_printable"
G13 = "g13_links_hold"
#: The optimisation's g13 and g14 sample each duty segment this many times fewer (the peaks of a
#: smooth minimum-jerk move change little), and keep :data:`LOOP_ALLOWANCE` in hand for it: on
#: 600 designs of the default dataset (2026-11-23) the full duty's strength utilisation was at
#: most 7.1 % above the coarse duty's (99th percentile 0.6 %) and the drive violation at most
#: 0.0016 above. A design may still pass the loop and fail the full duty: the front is checked on
#: the full duty at the end (:meth:`ExtraConstraints.full_duty_failures`), as verification does.
LOOP_SAMPLES_DIVISOR = 4
LOOP_ALLOWANCE = 0.02
G14 = "g14_drives_exist"
G15 = "g15_tool_within_tolerance"
#: The optimisation's g15 checks at most this many of the task points (spread over them, by
#: :func:`qsm.physics.task_points.visited_points`); the front is checked at every one at the end.
LOOP_SAG_POINTS = 5


def loop_duty(settings: DutySettings) -> DutySettings:
    """The coarser duty of the optimisation's g13 and g14: each segment sampled
    :data:`LOOP_SAMPLES_DIVISOR` times fewer, the holding poses all kept."""
    fewer = max(2, settings.samples_per_segment // LOOP_SAMPLES_DIVISOR)
    return replace(settings, samples_per_segment=fewer)


@dataclass(frozen=True)
class ExtraConstraints:
    """g11, g12, g13, g14 and g15: which are on and what they need.

    ``containment`` (g11, paper formulation only): the task disk of ``fit`` grown by
    ``tolerance_m`` (m) lies in the workspace, a Euclidean clearance of ``tolerance_m`` (the
    ratios formulation holds the task by its scale, fitted to the same grown disk);
    ``printable`` (g12) for the link section ``cad`` and the printer
    ``volume_mm`` (W, L, H in mm); ``strength`` (g13, every formulation, when given): every link
    holds its loads over the duty (:class:`qsm.embodiment.strength.link_checks.StrengthCheck`);
    ``drives`` (g14, every formulation, when given): each motor has a drive in the catalogue
    that meets its duty (:class:`qsm.embodiment.drives.drive_checks.DriveCheck`); ``drive_mass``
    (when given): the drive check whose selection gives the drive-mass objective (kept when g14 is
    dropped). ``strength`` and ``drives`` run on the loop's coarser duty (:func:`loop_duty`);
    ``full_strength`` and ``full_drives`` are the same checks on the full duty, which the front
    must pass at the end (:meth:`full_duty_failures`). ``sag`` (g15, every formulation, when
    given): the tool's sag at the task points (a coarse set of them) stays within the
    tolerance; ``full_sag`` the same at every point, for the end.
    """

    containment: bool
    printable: bool
    fit: FitSettings
    cad: CadSettings
    volume_mm: tuple[float, float, float]
    tolerance_m: float = 0.001
    strength: StrengthCheck | None = None
    drives: DriveCheck | None = None
    drive_mass: DriveCheck | None = None
    full_strength: StrengthCheck | None = None
    full_drives: DriveCheck | None = None
    sag: SagCheck | None = None
    full_sag: SagCheck | None = None

    def names(self, formulation: str) -> tuple[str, ...]:
        """Constraint columns of ``formulation`` in order: g1..g10, then g11, g12, g13, g14,
        g15 if on."""
        extra = (G11,) if self.containment and formulation == "paper" else ()
        extra += (G12,) if self.printable else ()
        extra += (G13,) if self.strength is not None else ()
        extra += (G14,) if self.drives is not None else ()
        return PAPER_CONSTRAINTS + extra + ((G15,) if self.sag is not None else ())

    def label(self, formulation: str) -> str:
        """Human-readable constraint set, e.g. 'g1..g10 (the paper's) + g12 printable'."""
        names = self.names(formulation)
        text = "g1..g10 (the paper's)"
        spare = f"{1e3 * self.tolerance_m:g} mm to spare"
        if G11 in names:
            text += f" + g11 task contained ({spare})"
        elif formulation == "ratios":
            text += f" + task contained by the scale ({spare})"
        if G12 in names:
            volume = " x ".join(f"{v:g}" for v in self.volume_mm)
            text += f" + g12 printable on {volume} mm"
        if G13 in names:
            text += " + g13 links hold their loads"
        if G14 in names:
            text += " + g14 each motor has a drive"
        if G15 in names:
            text += (
                f" + g15 tool sag within {self.sag.tolerance_mm:g} mm (configured section, rigid "
                "drives)"
            )
        return text

    def columns(
        self, formulation: str, design: NDArray[np.float64], g: NDArray[np.float64] | None = None
    ) -> list[NDArray]:
        """The g11 / g12 / g13 / g14 columns (``G <= 0``) for scaled designs (N, 6) (see
        :meth:`evaluate`)."""
        return self.evaluate(formulation, design, g)[0]

    def evaluate(
        self, formulation: str, design: NDArray[np.float64], g: NDArray[np.float64] | None = None
    ) -> tuple[list[NDArray], NDArray | None]:
        """:meth:`columns` and the drive-mass objective (N,) in kg (None without
        ``drive_mass``), from one drive selection. g13, g14 and the drive mass are evaluated
        only for the designs that meet every cheaper constraint (``g``, the g1..g10 columns
        (N, 10) when given, and g11, g12); the others are infeasible already: they read
        :data:`NOT_EVALUATED` in g13 and g14, so that failing a cheaper constraint never ranks
        above meeting them all, and among themselves their cheaper violations rank them; their
        drive mass is the penalty of a design without drives."""
        cols = []
        if self.containment and formulation == "paper":
            disk = self.fit.disk
            grown = disk.radius + self.fit.safety_margin + self.tolerance_m
            margin = containment_margin_m(
                design, self.fit.op, type(disk)(disk.centre, grown), self.fit.resolution.n_delta
            )
            cols.append(-margin)
        if self.printable:
            cols.append(printability_violation_mm(design, self.cad, self.volume_mm))
        if self.strength is None and (self.drives or self.drive_mass or self.sag) is None:
            return cols, None
        cheap = [np.asarray(c).reshape(len(design), -1) for c in ([] if g is None else [g])]
        cheap += [np.asarray(c).reshape(len(design), -1) for c in cols]
        todo = np.all(np.column_stack(cheap) <= 0, axis=1) if cheap else np.ones(len(design), bool)
        expensive, mass = self._expensive(design[todo])
        for col in expensive:
            full = np.full(len(design), NOT_EVALUATED)
            full[todo] = col
            cols.append(full)
        if mass is None:
            return cols, None
        every = np.full(len(design), self.drive_mass.penalty_kg)
        every[todo] = mass
        return cols, every

    def _expensive(self, design: NDArray[np.float64]) -> tuple[list[NDArray], NDArray | None]:
        """The g13 / g14 columns of scaled designs (N, 6), with :data:`LOOP_ALLOWANCE`, and
        their drive-mass objective (None without ``drive_mass``)."""
        cols = []
        torques = None
        if self.strength is not None:
            g13, *torques = self.strength.violation_and_torques(design, LOOP_ALLOWANCE)
            cols.append(g13)
        check = self.drives or self.drive_mass
        mass = None
        if check is not None:
            shared = torques is not None and same_loads(self.strength, check)
            table = check.evaluate(design, tuple(torques) if shared else None)
            if self.drives is not None:
                cols.append(violation_of(table) + LOOP_ALLOWANCE)
            mass = None if self.drive_mass is None else self.drive_mass.mass_objective(table)
        if self.sag is not None:
            cols.append(self.sag.violation(design))
        return cols, mass

    def full_duty_failures(self, design: NDArray[np.float64]) -> NDArray[np.bool_]:
        """Which scaled designs (N, 6) fail g13 or g14 (those on, with their full-duty checks
        given) on the full duty, without the loop's allowance: what verification will find."""
        fails = np.zeros(len(design), dtype=bool)
        torques = None
        if self.strength is not None and self.full_strength is not None:
            g13, *torques = self.full_strength.violation_and_torques(design)
            fails |= g13 > 0
        if self.drives is not None and self.full_drives is not None:
            shared = torques is not None and same_loads(self.full_strength, self.full_drives)
            table = self.full_drives.evaluate(design, tuple(torques) if shared else None)
            fails |= violation_of(table) > 0
        if self.sag is not None and self.full_sag is not None:
            fails |= self.full_sag.violation(design) > 0
        return fails
