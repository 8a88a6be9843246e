"""Sections and gearboxes for the tolerance: the lightest realised arm whose structure places the
payload within its share of ``task.tolerance_mm``.

The strength check gives each link's section (sized, or the configured one) and the drive check
the lightest drives for the duty. Where the tool's structural error at the task points (the
accuracy budget without the tracking error: max(sag, dynamic sag) + creep + lost motion, with the
plates that topology optimisation cuts at ``topology.min_stiffness_factor`` of their solid
stiffness, which it keeps, :mod:`qsm.realization.topology.topology`) exceeds
:data:`STRUCTURE_SHARE` of the tolerance, :func:`accuracy_choice` tries every least gearbox
stiffness per motor that the catalogue offers and, for each, the smallest common factor on
the sections that meets it, each link's capped at ``cad.sized``'s largest section and at what its
length takes (none when ``task.grow_for_tolerance`` is off); it keeps the lightest arm (links and
drives).
The rest of the tolerance is kept for the payload test's tracking error, which is measured after
the realisation; the final budget counts it.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, replace
from itertools import product
from typing import Any

import numpy as np
from numpy.typing import NDArray

from qsm.embodiment.drives.drive_checks import DriveCheck
from qsm.embodiment.drives.report import DriveReport
from qsm.embodiment.parts.printing import box_fits, link_boxes_mm
from qsm.embodiment.stiffness.error_terms import torque_reverses
from qsm.embodiment.stiffness.frame import FrameSections
from qsm.embodiment.strength.link_checks import StrengthCheck
from qsm.embodiment.strength.loads import Inertials
from qsm.embodiment.strength.material import Material
from qsm.embodiment.strength.printed import PrintedMaterial
from qsm.embodiment.strength.sizing import fit_limit
from qsm.physics.batch_mass import batch_mass_properties
from qsm.physics.cad import CadSettings, link_settings
from qsm.physics.inverse_kinematics import joint_path
from qsm.physics.kinematics import LINK_NAMES
from qsm.realization.accuracy.accuracy_budget import (
    AccuracySettings,
    ArmModel,
    budget_mm,
    drive_terms,
    peak_payload_force_N,
    point_terms,
    smallest_factor,
    task_motion_torques,
)
from qsm.realization.motion.payload import PayloadSettings
from qsm.realization.topology import OPTIMIZED_LINKS

#: The share of the tolerance the structure may take; the rest is kept for the tracking error.
STRUCTURE_SHARE = 0.7


@dataclass(frozen=True)
class AccuracyChoice:
    """What the tolerance asks of a design: each link's section ``scale`` (4,) on the configured
    one, each motor's least gearbox stiffness (N m/rad; 0: any), the structural error (mm) it
    gives, the ``target_mm`` it had to meet, whether it meets it (None: not built for the
    tolerance) and, when it does not, the limits the search stopped at (:func:`limits_reached`)."""

    scale: NDArray[np.float64]
    min_stiffness_Nm_rad: tuple[float, float]
    structure_mm: float
    target_mm: float
    meets: bool | None
    stopped_at: tuple[str, ...] = ()

    def record(self) -> dict[str, Any]:
        """JSON-ready account: the share and target, the structural error (None: not computed),
        each link's section scale and each motor's least gearbox stiffness."""
        finite = math.isfinite(self.structure_mm)
        return {
            "structure_share": STRUCTURE_SHARE,
            "target_mm": self.target_mm if math.isfinite(self.target_mm) else None,
            "structure_mm": self.structure_mm if finite else None,
            "meets_target": self.meets,
            "section_scale": dict(zip(LINK_NAMES, self.scale.tolist(), strict=True)),
            "min_gearbox_stiffness_Nm_rad": list(self.min_stiffness_Nm_rad),
            "stopped_at": list(self.stopped_at),
        }


def frame_sections(
    cad: CadSettings, material: Material, scale: NDArray[np.float64] | None
) -> FrameSections:
    """Each link's solid section at ``scale`` (4,) of ``cad`` (None: ``cad``) in ``material``."""
    sections = link_settings(cad, scale)
    return FrameSections(
        width_m=np.array([sections[k].width_m for k in LINK_NAMES]),
        thickness_m=np.array([sections[k].thickness_m for k in LINK_NAMES]),
        youngs_pa=material.youngs_modulus_pa,
        poisson=material.poisson_ratio,
    )


def floor_factors(plate_factor: float) -> NDArray[np.float64]:
    """Each link's stiffness factor (4,) with its plate optimised (:data:`OPTIMIZED_LINKS`) at
    ``plate_factor`` of the solid plate's stiffness, the others solid (1)."""
    return np.array([plate_factor if name in OPTIMIZED_LINKS else 1.0 for name in LINK_NAMES])


def structure_mm(
    design: NDArray[np.float64],
    scale: NDArray[np.float64],
    drives: DriveReport,
    strength: StrengthCheck,
    motion: PayloadSettings,
    angles: NDArray[np.float64],
    reflected: bool = True,
    plate_factor: float = 1.0,
    printed: PrintedMaterial | None = None,
) -> float:
    """The worst structural error (mm) over the task points' motor ``angles`` (n, 2) rad of the
    links at ``scale`` (4,), the optimised plates at ``plate_factor`` of the solid stiffness and
    the masses of the solid links (the plates weigh less: their inertial loads are bounded), with
    the ``drives`` of a drive report and the ``printed`` material's creep (None: none)."""
    stiffness, play, inertia, mass, _ = drive_terms(drives)
    model = ArmModel(
        design=design,
        sections=frame_sections(strength.cad, strength.material, scale),
        factor=floor_factors(plate_factor),
        inertials=Inertials(*batch_mass_properties(design, strength.cad, scale)),
        drive_stiffness=stiffness,
        backlash_rad=play,
        reflected_kgm2=inertia if reflected else np.zeros(2),
        drive_mass_kg=mass,
        printed=printed,
    )
    reverses = torque_reverses(task_motion_torques(model, angles, motion))
    du = strength.duty
    peak_N = peak_payload_force_N(design, motion.payload_kg, du.theta, du.dtheta, du.ddtheta)
    terms = point_terms(model, angles, motion.payload_kg, peak_N, reverses)
    return float(budget_mm(terms, None).max())


#: How much smaller than the printer's build volume, in each dimension, a grown link's box
#: stays (mm).
PRINT_MARGIN_MM = 0.5


def growth_limit(
    design: NDArray[np.float64],
    base: NDArray[np.float64],
    cad: CadSettings,
    largest: float,
    volume_mm: Sequence[float],
) -> NDArray[np.float64]:
    """Each link's largest section scale (4,) of ``cad``: within the ``largest`` scale, the
    link's length and, where it fits the printer's ``volume_mm`` at ``base``, that volume less
    :data:`PRINT_MARGIN_MM` (the printed part's mesh, not only its outline, must still fit: a
    link at the printer's edge does not grow), and at least its ``base`` (4,)."""
    upper = np.maximum(base, np.minimum(largest, fit_limit(design, cad) * (1 - 1e-9)))
    room = np.asarray(volume_mm, dtype=float) - PRINT_MARGIN_MM
    for k in range(4):

        def fits(f: float, k: int = k, within: Sequence[float] = room) -> bool:
            box = link_boxes_mm(design[None], None, cad.scaled(f * base[k]))[0, k]
            return box_fits(box, within)

        if not fits(1.0, within=volume_mm):  # it does not fit at all: the printer sets no limit
            continue
        if not fits(1.0):
            upper[k] = base[k]
        elif not fits(upper[k] / base[k]):
            low, high = 1.0, upper[k] / base[k]
            while high / low > 1.001:
                mid = math.sqrt(low * high)
                low, high = (mid, high) if fits(mid) else (low, mid)
            upper[k] = low * base[k]
    return upper


def limits_reached(
    design: NDArray[np.float64],
    choice: AccuracyChoice,
    upper: NDArray[np.float64],
    cad: CadSettings,
    accuracy: AccuracySettings,
    stiffest: Sequence[float],
) -> tuple[str, ...]:
    """What stopped the search of ``choice`` (its sections at ``upper`` (4,), the largest
    :func:`growth_limit` gives): each link held at its largest section, with the bound that sets
    it (``cad.sized``'s largest section, the link's length, or the printer's build volume) and
    its number, and the ``stiffest`` (2,) gearbox stiffness (N m/rad) it tried per motor."""
    fit = fit_limit(design, cad) * (1 - 1e-9)
    out = []
    for k, name in enumerate(LINK_NAMES):
        if choice.scale[k] < upper[k] * (1 - 1e-9):
            continue
        if upper[k] < min(accuracy.max_section_scale, fit[k]) * (1 - 1e-6):
            box = " x ".join(f"{v:g}" for v in accuracy.build_volume_mm)
            why = f"the most the printer's {box} mm build volume takes"
        elif fit[k] < accuracy.max_section_scale:
            why = "the most its length takes"
        else:
            why = "cad.sized's largest section"
        out.append(f"the {name.replace('_', ' ')} at {upper[k]:.2f}x its section, {why}")
    least = [f"{k:,.0f} N m/rad for motor {i}" for i, k in enumerate(stiffest, 1) if k]
    out.append(
        f"gearboxes of at least {' and '.join(least)}, the stiffest among drives that meet the duty"
        if least
        else "the lightest drives for the duty: the catalogue has no stiffer ones that meet it"
    )
    return tuple(out)


def accuracy_choice(
    design: NDArray[np.float64],
    base: NDArray[np.float64],
    strength: StrengthCheck,
    drives: DriveCheck,
    accuracy: AccuracySettings,
    motion: PayloadSettings,
) -> AccuracyChoice:
    """The lightest sections (a common factor on ``base`` (4,), each link's capped) and least
    gearbox stiffnesses whose structural error at ``accuracy.points_m`` meets
    :data:`STRUCTURE_SHARE` of the tolerance; when none does, the nearest (the largest sections
    with the stiffness that errs least), and ``base`` when no stiffer drives meet the duty or the
    design does not reach every point (``qsm export`` of any lengths; its budget says why)."""
    target = STRUCTURE_SHARE * accuracy.tolerance_mm
    points = np.asarray(accuracy.points_m, dtype=float).reshape(-1, 2)
    try:
        angles = joint_path(design, points, *motion.operating_range.degrees)
    except ValueError:  # a point out of reach
        return AccuracyChoice(base, (0.0, 0.0), math.inf, target, False)
    upper = growth_limit(
        design, base, strength.cad, accuracy.max_section_scale, accuracy.build_volume_mm
    )
    high = float(np.max(upper / base))
    levels = [0.0, *sorted(set(drives.stiffness_Nm_rad.tolist()))[1:]]
    lightest: tuple[float, AccuracyChoice] | None = None
    nearest = AccuracyChoice(base, (0.0, 0.0), math.inf, target, False)
    stiffest = [0.0, 0.0]
    for least in product(levels, levels):
        report = replace(drives, min_stiffness_Nm_rad=least).report(design, base[None])
        if not report.has_drives:
            continue
        stiffest = np.maximum(stiffest, least).tolist()

        def error(f: float, report: DriveReport = report) -> float:
            scale = np.minimum(f * base, upper)
            return structure_mm(
                design, scale, report, strength, motion, angles, drives.reflected_inertia,
                accuracy.plate_factor, accuracy.printed,
            )  # fmt: skip

        f = 1.0 if error(1.0) <= target else smallest_factor(lambda x: error(x) <= target, high)
        if f is None:
            if error(high) < nearest.structure_mm:
                nearest = AccuracyChoice(
                    np.minimum(high * base, upper), least, error(high), target, False
                )
            continue
        if f == 1.0 and least == (0.0, 0.0):  # the lightest arm of all meets it
            return AccuracyChoice(base, least, error(f), target, True)
        choice = AccuracyChoice(np.minimum(f * base, upper), least, error(f), target, True)
        mass = batch_mass_properties(design, strength.cad, choice.scale)[0].sum()
        mass += sum(m.drive.mass_kg for m in report.motors.values())
        if lightest is None or mass < lightest[0]:
            lightest = (mass, choice)
    if lightest is not None:
        return lightest[1]
    limits = limits_reached(design, nearest, upper, strength.cad, accuracy, stiffest)
    return replace(nearest, stopped_at=limits)


def as_realised(
    choice: AccuracyChoice,
    design: NDArray[np.float64],
    scale: NDArray[np.float64],
    drives: DriveReport,
    strength: StrengthCheck,
    accuracy: AccuracySettings,
    motion: PayloadSettings,
    reflected: bool = True,
) -> AccuracyChoice:
    """``choice`` with the structural error of the arm as realised: its sections ``scale``
    (4,) and the ``drives`` of its drive report (chosen at those sections, which may differ from
    the search's at the strength's)."""
    if choice.meets is None or not math.isfinite(choice.structure_mm):
        return choice
    points = np.asarray(accuracy.points_m, dtype=float).reshape(-1, 2)
    angles = joint_path(design, points, *motion.operating_range.degrees)
    error = structure_mm(
        design,
        scale,
        drives,
        strength,
        motion,
        angles,
        reflected,
        accuracy.plate_factor,
        accuracy.printed,
    )
    return replace(choice, scale=scale, structure_mm=error, meets=error <= choice.target_mm)
