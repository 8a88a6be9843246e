"""Settings of the arm's geometry and motion: motor ranges, the scale-up, link solids, duty."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from qsm.mechanisms.scale import FitSettings
from qsm.physics.cad import CadSettings
from qsm.physics.duty import DutySettings
from qsm.physics.mirror import design_points
from qsm.physics.task import min_enclosing_circle
from qsm.physics.workspace import OperatingRange, Resolution

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


def scale_up(section: Section) -> FitSettings:
    """:func:`fit` of Stage 1's share (:func:`qsm.config.sections.mechanisms_section`): the
    scale-up of the candidates the kinematic filters passed (their filters are not checked
    again)."""
    return fit(
        section["operating_range"], section["task_points"], section["scale"], section["workspace"]
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
    return CadSettings(
        width_m=section["width_m"],
        thickness_m=section["thickness_m"],
        boss_radius_m=section["boss_radius_m"],
        density_kg_m3=material_section["density_kg_m3"],
        segments_per_circle=section["segments_per_circle"],
        corner_fillet_ratio=section["corner_fillet_ratio"],
    )


def duty(section: Section, operating_range_section: Section) -> DutySettings:
    """``dynamics.duty`` with ``operating_range``: the duty cycle's sampling."""
    lo, hi = operating_range_section["theta1_deg"]
    return DutySettings(
        theta1_min_deg=lo,
        theta1_max_deg=hi,
        theta2_min_deg=operating_range_section["theta2_min_deg"],
        **section,
    )
