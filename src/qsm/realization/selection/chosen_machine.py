"""The design Stage 6 realises: chosen by the selection rule (printable, strong enough and with
drives if any design is), realised (:func:`~qsm.realization.selection.pipeline.realize`), and the
top of ``choice.json``: the realised machine, how it was chosen and, in ``candidate``, the
optimiser's row. :mod:`qsm.report.selection_record` states its verdict."""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import replace
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from qsm.embodiment.drives.report import report_json
from qsm.embodiment.parts.printing import (
    link_printability,
    round_up_mm,
    section_needed_mm,
    smallest_build_volume,
)
from qsm.embodiment.strength.advice import strength_advice
from qsm.embodiment.strength.record import strength_json
from qsm.physics.clearance import disk_clearance_m
from qsm.physics.kinematics import DESIGN_COLUMNS
from qsm.physics.mirror import task_record
from qsm.physics.task import min_enclosing_circle
from qsm.physics.workspace import OperatingRange
from qsm.prose import listed
from qsm.realization.selection.choice import (
    HowChosen,
    candidate_pool,
    choose_design,
    printing_advice,
)
from qsm.realization.selection.machine import fixed_point_record
from qsm.realization.selection.outputs import selection_record
from qsm.realization.selection.pipeline import (
    Realization,
    RealizationSettings,
    carrying,
    realize,
)

#: How many designs, best first, the selection realises before it keeps one it cannot build
#: for the tolerance.
TRIES = 5


def _without(table: pd.DataFrame, designs: list[NDArray[np.float64]]) -> pd.DataFrame:
    """``table`` without the rows of ``designs`` (6 lengths, m, each)."""
    if not designs or table.empty:
        return table
    lengths = table[list(DESIGN_COLUMNS)].to_numpy(float)
    gone = np.zeros(len(table), bool)
    for d in designs:
        gone |= np.all(lengths == d, axis=1)
    return table[~gone]


def _buildable(
    choose: Callable[[list[NDArray[np.float64]]], tuple[pd.Series, HowChosen]],
    settings: RealizationSettings,
) -> tuple[pd.Series, HowChosen, Realization]:
    """The design ``choose`` gives (:func:`choose_design` without the designs it is passed),
    realised: the best that the realisation can build for the tolerance (its structure within
    the target, :mod:`qsm.realization.accuracy.accuracy_sizing`) among the first :data:`TRIES`
    of the first one's tier (printable, holds its loads, has drives), each one skipped named in
    ``fallback`` with its numbers; the first when none can."""
    skipped: list[NDArray[np.float64]] = []
    notes: list[str] = []
    tried: list[tuple[pd.Series, HowChosen, Realization]] = []
    for _ in range(TRIES):
        try:
            row, how = choose(skipped)
        except ValueError:  # nothing left once these are skipped
            break
        if tried and how.tier() != tried[0][1].tier():  # a worse tier: keep the first's
            break
        done = realize(selection_record(row)["design_m"], settings)
        tried.append((row, how, done))
        if done.accuracy.meets is not False:
            break
        skipped.append(done.design)
        record = done.accuracy.record()
        structure = record["structure_mm"]
        notes.append(
            f"{how.source} design of lengths {listed(1e3 * done.design, 1, 'mm')}: the "
            f"realisation cannot build it for the tolerance (structure "
            + ("not defined" if structure is None else f"{structure:.2f} mm")
            + f", target {record['target_mm']:.2f} mm)"
        )
    row, how, done = tried[-1]
    if done.accuracy.meets is False:  # none can: the rule's own choice, which the verdict judges
        row, how, done = tried[0]
        notes = []
    return row, replace(how, fallback=(*notes[: len(tried) - 1], *how.fallback)), done


def chosen_machine(
    fronts: Mapping[str, pd.DataFrame],
    primary: str,
    dataset: pd.DataFrame,
    rule: str,
    volume_mm: tuple[float, float, float],
    task_points: Sequence[Sequence[float]],
    user_points: Sequence[Sequence[float]],
    op: OperatingRange,
    settings: RealizationSettings,
) -> tuple[dict[str, Any], Realization]:
    """The design chosen by ``rule`` from the fronts (``primary`` first) or the dataset
    (:func:`~qsm.realization.selection.choice.choose_design`), realised (:func:`realize`): the
    record of ``choice.json`` without its verdict (:func:`machine_top`, the task (the user's
    points; the design's are ``task_points``), the clearance (m), and the advice where the
    strength or the printer fails) and the realisation, which ``machine.json`` holds."""
    cad = settings.parts.cad
    disk = min_enclosing_circle(task_points)

    def choose(skipped: list[NDArray[np.float64]]) -> tuple[pd.Series, HowChosen]:
        kept = {name: _without(t, skipped) for name, t in fronts.items()}
        return choose_design(kept, primary, _without(dataset, skipped), rule, cad, volume_mm)

    row, how, done = _buildable(choose, settings)
    record = machine_top(row, how, done, volume_mm)
    record["task"] = task_record(user_points)
    record["clearance_m"] = disk_clearance_m(record["design_m"], op, disk)
    if not record["holds_loads"]:
        carried = carrying(settings, done.tool_kg).strength  # the tool flange's mass included
        record["strength_advice"] = strength_advice(record["design_m"], carried)
    if not how.printable:
        advice = printing_advice(done.design, cad, volume_mm, disk, done.scale)
        pool = candidate_pool(fronts, dataset)
        advice["smallest_over_designs"] = _smallest_realised(pool, done, settings)
        record["printing_advice"] = advice
    return record, done


def _smallest_realised(
    pool: pd.DataFrame, done: Realization, settings: RealizationSettings
) -> dict[str, Any] | None:
    """The design of ``pool`` that holds its loads with the smallest printer at the configured
    section (:func:`smallest_build_volume`; a printer for a design that fails its strength fixes
    nothing), realised as this run realises ``done``: its ``needed_volume_mm`` (whole mm up) and
    ``exact_volume_mm`` those of its links as realised, with ``holds_loads``,
    ``strength_utilisation``, ``has_drives`` and the tolerance's ``meets_tolerance``,
    ``structure_mm`` and ``target_mm`` (mm) as realised; None when no design holds its loads."""
    cad = settings.parts.cad
    smallest = smallest_build_volume(pool, pool["holds_loads"].astype(bool), cad)
    if smallest is None:
        return None
    d = np.asarray(smallest["design_m"], dtype=float)
    other = done if np.array_equal(d, done.design) else realize(d, settings)
    need = section_needed_mm(other.design, cad, other.scale)
    tolerance = other.accuracy.record()
    smallest.update(
        needed_volume_mm=round_up_mm(need),
        exact_volume_mm=need.tolist(),
        holds_loads=other.strength.holds_loads,
        strength_utilisation=other.strength.utilisation,
        has_drives=other.has_drives,
        meets_tolerance=tolerance["meets_target"],
        structure_mm=tolerance["structure_mm"],
        target_mm=tolerance["target_mm"],
    )
    return smallest


#: The candidate's fields that are the realised machine's as well: its lengths and how it was
#: chosen. Every other column of the candidate's row describes it at the section it was chosen
#: with, and stays in ``candidate``.
SHARED_KEYS = (
    *("design_m", "scale_m", "l1_m", "l2_m", "l3_m", "l4_m", "ee_x_m", "ee_y_m"),
    *("formulation", "mechanism_id", "selection_rule", "selection_score", "n_candidates"),
)


def machine_top(
    row: pd.Series, how: HowChosen, done: Realization, volume_mm: tuple[float, ...]
) -> dict[str, Any]:
    """The top of ``choice.json``: the realised machine (its lengths, how it was chosen, its
    printer fit, strength and drives as realised) and, in ``candidate``, the optimiser's
    candidate as it was chosen (every column of its row; ``printable``, ``holds_loads`` and
    ``has_drives`` of the tier it was chosen in)."""
    candidate = selection_record(row)
    candidate.update(
        printable=how.printable, holds_loads=how.holds_loads, has_drives=how.has_drives
    )
    fit = link_printability(done.design, done.part_settings.cad, done.scale, volume_mm)["links"]
    record = {k: candidate[k] for k in SHARED_KEYS if k in candidate}
    record["source"], record["fallback"] = how.source, list(how.fallback)
    record["printable"] = all(link["fits"] for link in fit.values())
    record["printer_box_mm"] = {name: list(link["dims_mm"]) for name, link in fit.items()}
    record["printer_volume_mm"] = [float(v) for v in volume_mm]
    record["holds_loads"] = done.strength.holds_loads
    record["has_drives"] = done.has_drives
    record["strength"], record["drives"] = strength_json(done.strength), report_json(done.drives)
    flange = {} if done.tool_flange is None else done.tool_flange.record()
    record["tool_flange"], record["tool_flange_kg"] = flange, done.tool_kg
    record["fixed_point"] = fixed_point_record(done.fixed_point)
    record["torque_limits_Nm"] = list(done.torque_limits_Nm)
    record["candidate"] = candidate
    return record
