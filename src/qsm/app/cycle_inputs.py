"""What a rule that runs the realised design on a cycle reads, in one place: the realisation
from its record with the tool flange it carries, its optimised links with the kit's moving
parts, the payload test's plant and controller, and the payload's largest peak force that keeps
the tool within the tolerance.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from qsm.config.settings import links, realization, simulation
from qsm.physics.cad import MassProperties
from qsm.realization.accuracy.accuracy_budget import ArmModel, largest_load_N
from qsm.realization.final.elastic_arm import elastic_arm
from qsm.realization.final.final_budget import measured_budget, plate_factors
from qsm.realization.final.settling import Settling
from qsm.realization.kit.moving_parts import as_built
from qsm.realization.motion.payload import PayloadSettings
from qsm.realization.selection.machine import realization_from_record
from qsm.realization.selection.pipeline import (
    Realization,
    RealizationSettings,
    arm_model,
    carrying,
)


@dataclass(frozen=True)
class CycleInputs:
    """The realisation ``done`` and its ``settings`` (carrying its tool flange), the optimised
    links' ``props``, the payload ``test``'s settings, ``limit_N`` (the payload's largest peak
    force, N, that keeps the tolerance; None: no limit), the duty's raster speed (deg/s),
    whether the task was designed ``mirrored``, the moves' ``jerk`` time (:class:`JerkTime`)
    and the stops' ``settling`` check (None: the rule does not lengthen its dwells)."""

    done: Realization
    settings: RealizationSettings
    props: dict[str, MassProperties]
    test: PayloadSettings
    limit_N: float | None
    raster_speed_deg_s: float
    mirrored: bool
    jerk: JerkTime
    settling: Settling | None


#: The jerk times weighed with the slow-down (:func:`qsm.realization.final.cycle_check.fastest`),
#: in periods of the arm's first mode; the first is the one kept where they cannot be weighed.
JERK_PERIODS: tuple[float, ...] = (1.0, 0.5, 2.0)


@dataclass(frozen=True)
class JerkTime:
    """The time (s) over which each move of a cycle ramps its acceleration: ``task.cycle
    .jerk_time_s``, else one period of the arm's lowest first mode at the task points
    (``first_mode_hz``, Hz, from the accuracy budget; None: the key's); None: neither is known,
    and the moves keep TOPP-RA's timing."""

    jerk_time_s: float | None
    first_mode_hz: float | None

    @classmethod
    def of(cls, key_s: float | None, budget: Mapping[str, Any]) -> JerkTime:
        """From the key (s; None: unset) and an accuracy ``budget`` (its ``per_point``'s
        ``first_mode_hz``)."""
        modes = [f for f in budget["per_point"].get("first_mode_hz", []) if f]
        mode = min(modes) if modes else None
        if key_s is not None:
            return cls(float(key_s), None)
        return cls(None if mode is None else 1.0 / mode, mode)

    def candidates(self) -> tuple[float | None, ...]:
        """The jerk times (s) a cycle may weigh, the stated one first: the key's alone, else
        :data:`JERK_PERIODS` periods of the first mode."""
        if self.first_mode_hz is None:
            return (self.jerk_time_s,)
        return tuple(p / self.first_mode_hz for p in JERK_PERIODS)

    def record(self, kept_s: float | None = None, chosen: bool = False) -> dict[str, Any]:
        """JSON: the time (``kept_s``, s: the ramps of a cycle as run; else the stated one), in
        periods of the first mode, where it comes from, and whether a cycle ``chosen`` it with
        its slow-down among :meth:`candidates`."""
        jerk = self.jerk_time_s if kept_s is None else kept_s
        source = "task.cycle.jerk_time_s" if self.first_mode_hz is None else "first mode"
        if jerk is None:
            source = "none: no first mode known"
        periods = None if jerk is None or self.first_mode_hz is None else jerk * self.first_mode_hz
        return {"jerk_time_s": jerk, "stated_s": self.jerk_time_s, "from": source,
                "first_mode_hz": self.first_mode_hz, "periods": periods,
                "chosen_with_slow_down": chosen}  # fmt: skip


def _read(path: str) -> Any:
    return json.loads(Path(path).read_text())


def cycle_inputs(files: Mapping[str, str], params: Mapping[str, Any]) -> CycleInputs:
    """:class:`CycleInputs` from a cycle rule's input ``files`` (choice, machine, links,
    topology, payload, kit) and its ``params`` (realization: the realisation's share of the
    config, :func:`qsm.config.sections.realization_section`; payload_test, jerk_time_s and
    settling)."""
    p = params
    props = as_built(_read(files["links"]), _read(files["kit"]))  # with the kit's moving parts
    case = links.load_case_of(p["realization"])
    settings = realization.realization_of(p["realization"])
    points = [list(xy) for xy in settings.task_points_m]
    done = realization_from_record(_read(files["machine"]), settings)
    settings = carrying(settings, done.tool_kg)  # the tool flange at E, as realised
    test = simulation.payload_test(
        p["payload_test"], settings.motion.payload_kg, case.operating_range
    )
    base = _read(files["kit"])["base"]["tool_error_mm"]
    parts = (_read(files["topology"]), props)
    budget = measured_budget(done, parts, _read(files["payload"]), settings, points, None, base)
    mirrored = bool(_read(files["choice"]).get("task", {}).get("mirrored", False))
    jerk = JerkTime.of(p["jerk_time_s"], budget)
    model = arm_model(done, settings, props, plate_factors(parts[0]))
    check = settling_check(model, settings.motion.payload_kg, budget, p.get("settling"))
    return CycleInputs(
        done, settings, props, test, largest_load_N(budget), case.duty.peak_speed_deg_s, mirrored,
        jerk, check,
    )  # fmt: skip


def settling_check(
    model: ArmModel, payload_kg: float, budget: Mapping[str, Any], section: Mapping | None
) -> Settling | None:
    """The stops' settling check (:class:`~qsm.realization.final.settling.Settling`) of the arm
    ``model`` carrying ``payload_kg`` (kg), with the ``settling`` config ``section`` (None:
    none), held to the largest static part of ``budget``'s placing error over its points (all
    its terms but the dynamic sag); its elastic model (:mod:`qsm.realization.final.elastic_arm`)
    damps its first mode, the lowest over the budget's points, at the section's ratio (none
    where the budget has no first mode)."""
    if section is None:
        return None
    per = budget["per_point"]
    static = [
        total - max(sag, dynamic or 0.0) + sag
        for total, sag, dynamic in zip(
            per["error_budget_mm"], per["sag_mm"], per["dynamic_sag_mm"], strict=True
        )
    ]
    tolerance, zeta = float(budget["tolerance_mm"]), float(section["damping_ratio"])
    omega = 2 * math.pi * float(budget["worst"]["first_mode_hz"] or math.nan)
    elastic = elastic_arm(model, payload_kg, 2 * zeta / omega) if omega > 0 else None
    return Settling(model, payload_kg, zeta, tolerance, max(static), elastic)
