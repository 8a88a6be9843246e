"""What a rule that runs the realised design on a cycle reads, in one place: the realisation
from its record with the tool flange it carries, its optimised links with the kit's moving
parts, the payload test's plant and controller, and the payload's largest peak force that keeps
the tool within the tolerance.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from qsm.config.settings import links, realization, simulation
from qsm.physics.cad import MassProperties
from qsm.realization.accuracy.accuracy_budget import largest_load_N
from qsm.realization.final.final_budget import measured_budget
from qsm.realization.kit.moving_parts import as_built
from qsm.realization.motion.payload import PayloadSettings
from qsm.realization.selection.machine import realization_from_record
from qsm.realization.selection.pipeline import Realization, RealizationSettings, carrying


@dataclass(frozen=True)
class CycleInputs:
    """The realisation ``done`` and its ``settings`` (carrying its tool flange), the optimised
    links' ``props``, the payload ``test``'s settings, ``limit_N`` (the payload's largest peak
    force, N, that keeps the tolerance; None: no limit), the duty's raster speed (deg/s) and
    whether the task was designed ``mirrored``."""

    done: Realization
    settings: RealizationSettings
    props: dict[str, MassProperties]
    test: PayloadSettings
    limit_N: float | None
    raster_speed_deg_s: float
    mirrored: bool


def _read(path: str) -> Any:
    return json.loads(Path(path).read_text())


def cycle_inputs(files: Mapping[str, str], params: Mapping[str, Any]) -> CycleInputs:
    """:class:`CycleInputs` from a cycle rule's input ``files`` (choice, machine, links,
    topology, payload, kit) and its ``params`` (load_case, strength, drives, task, motion,
    task_points, build_volume_mm, payload_test)."""
    p = params
    props = as_built(_read(files["links"]), _read(files["kit"]))  # with the kit's moving parts
    case = links.load_case(p["load_case"])
    settings = realization.realization(
        case, p["strength"], p["drives"], p["task"], p["motion"], p["task_points"],
        p["build_volume_mm"],
    )  # fmt: skip
    done = realization_from_record(_read(files["machine"]), settings)
    settings = carrying(settings, done.tool_kg)  # the tool flange at E, as realised
    (lo, hi), theta2_min = case.operating_range_deg
    op = {"theta1_deg": [lo, hi], "theta2_min_deg": theta2_min}
    test = simulation.payload_test(p["payload_test"], settings.motion.payload_kg, op)
    base = _read(files["kit"])["base"]["tool_error_mm"]
    parts = (_read(files["topology"]), props)
    budget = measured_budget(
        done, parts, _read(files["payload"]), settings, p["task_points"], None, base
    )
    mirrored = bool(_read(files["choice"]).get("task", {}).get("mirrored", False))
    return CycleInputs(
        done, settings, props, test, largest_load_N(budget), case.duty.peak_speed_deg_s, mirrored
    )
