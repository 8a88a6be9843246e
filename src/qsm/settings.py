"""The one settings layer: the validated config's sections as the library's frozen dataclasses.

One function per section; scripts, the command line and ``qsm.app.evaluate`` build their settings
here and nowhere else. Each function takes the section(s) as validated by :mod:`qsm.config`
(every default filled from the schema) and passes every field on, so the schema's defaults are
the ones a run uses; the dataclasses' own defaults, for direct notebook calls, are read from the
same schema (:mod:`qsm.defaults`).

The heavier dataclasses are imported inside their functions: a workflow script's rerun hash
(:mod:`qsm.workflow.provenance`) follows module-level imports, so importing this module does not
tie every rule to the surrogate, the optimiser, pyMOTO and MuJoCo; each script imports the
module that uses the settings it builds anyway.
"""

from __future__ import annotations

import dataclasses
import functools
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

from qsm.mechanisms.scale import FitSettings
from qsm.physics.mirror import design_points
from qsm.physics.task import min_enclosing_circle
from qsm.physics.workspace import OperatingRange, Resolution

if TYPE_CHECKING:
    from qsm.embodiment.drive_checks import DriveCheck
    from qsm.embodiment.drives.catalogue import Catalogue
    from qsm.embodiment.link_checks import StrengthCheck
    from qsm.embodiment.material import Material, StrengthSettings
    from qsm.embodiment.parts import PartSettings
    from qsm.embodiment.sizing import SizingSettings
    from qsm.optimization.constraint_set import ExtraConstraints
    from qsm.physics.cad import CadSettings
    from qsm.physics.duty import DutySettings
    from qsm.realization.fe import TopologySettings
    from qsm.realization.payload import PayloadSettings
    from qsm.surrogate.model import SurrogateSettings

Section = Mapping[str, Any]


def operating_range(section: Section) -> OperatingRange:
    """``operating_range``: motor ranges in radians."""
    return OperatingRange.from_degrees(section["theta1_deg"], section["theta2_min_deg"])


def fit(
    operating_range_section: Section,
    task_points: Sequence[Sequence[float]],
    scale: Section,
    workspace: Section,
    filters: Section | None = None,
) -> FitSettings:
    """``operating_range``, ``task.points``, ``scale``, ``workspace`` (and ``filters`` for checks
    outside Stage 1): what the scale-up needs. The task disk is that of the points as designed: a
    task at x > 0 mirrored through x = 0 (:mod:`qsm.physics.mirror`)."""
    return FitSettings(
        op=operating_range(operating_range_section),
        disk=min_enclosing_circle(design_points(task_points)),
        scale_max=float(scale["max_m"]),
        safety_margin=float(scale["safety_margin_m"]),
        resolution=Resolution(int(workspace["n_delta"]), int(workspace["n_levels"])),
        n_scan=int(workspace["n_scan"]),
        min_transmission_angle_deg=float((filters or {}).get("min_transmission_angle_deg", 0)),
    )


def fit_of(config: Section) -> FitSettings:
    """:func:`fit` of a whole validated config, its filters included (the checks of one design
    outside the stages: ``qsm evaluate``, ``qsm export``)."""
    return fit(
        config["operating_range"],
        config["task"]["points"],
        config["scale"],
        config["workspace"],
        config["filters"],
    )


def cad(section: Section, material_section: Section) -> CadSettings:
    """``cad`` with ``material``'s density: the link solids."""
    from qsm.physics.cad import CadSettings

    return CadSettings(
        width_m=section["width_m"],
        thickness_m=section["thickness_m"],
        boss_radius_m=section["boss_radius_m"],
        density_kg_m3=material_section["density_kg_m3"],
        segments_per_circle=section["segments_per_circle"],
        corner_fillet_ratio=section["corner_fillet_ratio"],
    )


def material(section: Section) -> Material:
    """``material``: the printed material of every link."""
    from qsm.embodiment.material import Material

    return Material(**section)


def parts(
    cad_section: Section, material_section: Section, strength_section: Section
) -> PartSettings:
    """The bored parts: the link solids and ``strength.boss_wall_m`` around the bearing seats."""
    from qsm.embodiment.parts import PartSettings

    return PartSettings(
        cad(cad_section, material_section), boss_wall_m=strength_section["boss_wall_m"]
    )


def strength(section: Section) -> StrengthSettings:
    """``strength``: what every link must hold."""
    from qsm.embodiment.material import StrengthSettings

    return StrengthSettings(**section)


def strength_check(
    cad_section: Section,
    material_section: Section,
    strength_section: Section,
    payload_kg: float,
    duty_settings: DutySettings,
) -> StrengthCheck:
    """The link check of a design: section, material, requirements, payload (kg) and duty."""
    from qsm.embodiment.link_checks import StrengthCheck
    from qsm.physics.duty import duty_cycle

    return StrengthCheck(
        cad(cad_section, material_section),
        material(material_section),
        strength(strength_section),
        float(payload_kg),
        duty_cycle(duty_settings),
        sizing=sizing(cad_section),
    )


def sizing(section: Section) -> SizingSettings | None:
    """``cad.section`` and ``cad.sized``: None for the fixed section, else the sizing bounds."""
    from qsm.embodiment.sizing import SizingSettings

    if section.get("section", "fixed") == "fixed":
        return None
    sized = section["sized"]
    return SizingSettings(
        width_m=tuple(sized["width_m"]),
        thickness_m=tuple(sized["thickness_m"]),
        max_iterations=sized["max_iterations"],
        tolerance=sized["tolerance"],
    )


@functools.lru_cache(maxsize=4)
def _catalogue(folder: str | None) -> Catalogue:
    from qsm.embodiment.drives.catalogue import default_catalogue_folder, read_catalogue

    return read_catalogue(default_catalogue_folder() if folder is None else folder)


def catalogue(section: Section) -> Catalogue:
    """``drives.catalogue``: the drive catalogue (null: the one shipped with qsm), read once per
    process."""
    return _catalogue(section["catalogue"])


def drive_check(
    drives_section: Section,
    cad_section: Section,
    material_section: Section,
    payload_kg: float,
    duty_settings: DutySettings,
) -> DriveCheck:
    """The drive check of a design: catalogue, rule, reflected inertia, link section, payload
    (kg) and duty."""
    from qsm.embodiment.drive_checks import DriveCheck
    from qsm.physics.duty import duty_cycle

    return DriveCheck(
        catalogue(drives_section),
        drives_section["rule"],
        bool(drives_section["reflected_inertia"]),
        cad(cad_section, material_section),
        float(payload_kg),
        duty_cycle(duty_settings),
    )


def duty(section: Section, operating_range_section: Section) -> DutySettings:
    """``dynamics.duty`` with ``operating_range``: the duty cycle's sampling."""
    from qsm.physics.duty import DutySettings

    lo, hi = operating_range_section["theta1_deg"]
    return DutySettings(
        theta1_min_deg=lo,
        theta1_max_deg=hi,
        theta2_min_deg=operating_range_section["theta2_min_deg"],
        **section,
    )


def surrogate(section: Section) -> SurrogateSettings:
    """``surrogate``: network and training."""
    from qsm.surrogate.model import SurrogateSettings

    return SurrogateSettings(**{**section, "hidden_layers": tuple(section["hidden_layers"])})


def topology(
    section: Section, material_section: Section, strength_section: Section
) -> TopologySettings:
    """``topology`` with ``material``'s elasticity and strength and ``strength``'s safety
    factor: SIMP and the stress check of the printed plates."""
    from qsm.realization.fe import TopologySettings

    return TopologySettings(
        **section,
        youngs_modulus_pa=material_section["youngs_modulus_pa"],
        poisson_ratio=material_section["poisson_ratio"],
        yield_strength_pa=material_section["yield_strength_pa"],
        safety_factor=strength_section["safety_factor"],
    )


def payload_test(
    section: Section, payload_kg: float, operating_range_section: Section
) -> PayloadSettings:
    """``payload_test`` with ``task.payload_kg`` and ``operating_range``."""
    from qsm.realization.payload import PayloadSettings

    return PayloadSettings(
        payload_kg=payload_kg,
        torque_limits_Nm=(
            None if section["torque_limits_Nm"] is None else tuple(section["torque_limits_Nm"])
        ),
        segment_duration_s=section["segment_duration_s"],
        dwell_s=section["dwell_s"],
        return_to_start=section["return_to_start"],
        kp_Nm_rad=tuple(section["kp_Nm_rad"]),
        kd_Nms_rad=tuple(section["kd_Nms_rad"]),
        tracking_tolerance_deg=section["tracking_tolerance_deg"],
        plant_mass_error=section["plant_mass_error"],
        theta1_range_deg=tuple(operating_range_section["theta1_deg"]),
        theta2_min_deg=operating_range_section["theta2_min_deg"],
    )


def constraints(section: Section, fit_settings: FitSettings) -> ExtraConstraints:
    """``optimization.constraints`` as one formulation's rule passes it: ``containment``,
    ``printable``, ``strong`` and, when on, ``tolerance_m``, ``cad`` and ``material`` (sections),
    ``build_volume_mm``, for g13 ``strength``, ``payload_kg``, ``duty`` and
    ``operating_range``, and for g14 (``drives``) the ``drives_section`` with ``cad``,
    ``material``, ``payload_kg``, ``duty`` and ``operating_range``. g13 and g14 run on the
    optimisation's coarser duty (:func:`qsm.optimization.constraint_set.loop_duty`), and the
    front's final check on the full duty."""
    from qsm.optimization.constraint_set import LOOP_ALLOWANCE, ExtraConstraints, loop_duty
    from qsm.physics.cad import DEFAULT_CAD

    printable, strong = bool(section["printable"]), bool(section.get("strong", False))
    drives = bool(section.get("drives", False))
    checks: dict[str, Any] = {}  # g13 and g14 on the loop's duty, and on the full duty
    if strong or drives:
        full = duty(section["duty"], section["operating_range"])
        for name, duty_settings in (("full", full), ("loop", loop_duty(full))):
            if drives:
                checks[f"{name}_drives"] = drive_check(
                    section["drives_section"],
                    section["cad"],
                    section["material"],
                    section["payload_kg"],
                    duty_settings,
                )
            if strong:
                checks[f"{name}_strength"] = strength_check(
                    section["cad"],
                    section["material"],
                    section["strength"],
                    section["payload_kg"],
                    duty_settings,
                )
    check = checks.get("loop_strength")
    if check is not None and check.sizing is not None:  # sized within g13's allowance
        target = check.sizing.target / (1 + LOOP_ALLOWANCE)
        check = dataclasses.replace(check, sizing=dataclasses.replace(check.sizing, target=target))
    return ExtraConstraints(
        containment=bool(section["containment"]),
        printable=printable,
        fit=fit_settings,
        cad=cad(section["cad"], section["material"]) if printable else DEFAULT_CAD,
        volume_mm=tuple(section.get("build_volume_mm", (600.0, 350.0, 350.0))),
        tolerance_m=float(section.get("tolerance_m", 0.0)),
        strength=check,
        drives=checks.get("loop_drives"),
        full_strength=checks.get("full_strength"),
        full_drives=checks.get("full_drives"),
    )
