"""``choice.json``: the design Stage 6 realises, its realisation and the verdict that states it
with this run's numbers, and the figure of the design over its workspace.
:mod:`qsm.report.accuracy_report` completes it, with the accuracy budget, into ``selected.json``."""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from numpy.typing import NDArray

from qsm.embodiment.parts.printing import (
    advice_sentence,
    box_fits,
    link_printability,
    smallest_build_volume,
)
from qsm.embodiment.strength.advice import advice_sentences as strength_sentences
from qsm.embodiment.strength.advice import strength_advice
from qsm.embodiment.strength.verdict import strength_verdict
from qsm.physics.cad import CadSettings
from qsm.physics.clearance import disk_clearance_m
from qsm.physics.kinematics import DESIGN_COLUMNS
from qsm.physics.mirror import task_record
from qsm.physics.task import Disk, min_enclosing_circle
from qsm.physics.workspace import OperatingRange
from qsm.realization.choice import (
    advice_sentences,
    candidate_pool,
    choose_design,
    printing_advice,
)
from qsm.realization.outputs import selection_record
from qsm.realization.pipeline import Realization, RealizationSettings, realize
from qsm.report.drive_text import drive_sentences
from qsm.report.figures import draw_design

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


def _tier(how: Mapping[str, Any]) -> tuple[bool, bool, bool]:
    """What a chosen design met: printable, holds its loads, has drives."""
    return bool(how["printable"]), bool(how["holds_loads"]), bool(how["has_drives"])


def _buildable(
    choose: Callable[[list[NDArray[np.float64]]], tuple[pd.Series, dict[str, Any]]],
    settings: RealizationSettings,
) -> tuple[pd.Series, dict[str, Any], Realization]:
    """The design ``choose`` gives (:func:`choose_design` without the designs it is passed),
    realised: the best that the realisation can build for the tolerance (its structure within
    the target, :mod:`qsm.realization.accuracy_sizing`) among the first :data:`TRIES` of the
    first one's tier (printable, holds its loads, has drives), each one skipped named in
    ``fallback`` with its numbers; the first when none can."""
    skipped: list[NDArray[np.float64]] = []
    notes: list[str] = []
    tried: list[tuple[pd.Series, dict[str, Any], Realization]] = []
    for _ in range(TRIES):
        try:
            row, how = choose(skipped)
        except ValueError:  # nothing left once these are skipped
            break
        if tried and _tier(how) != _tier(tried[0][1]):  # a worse tier: keep the first's
            break
        done = realize(selection_record(row)["design_m"], settings)
        tried.append((row, how, done))
        if done.accuracy.meets is not False:
            break
        skipped.append(done.design)
        record = done.accuracy.record()
        structure = record["structure_mm"]
        notes.append(
            f"{how['source']} design {np.round(1e3 * done.design, 1).tolist()} mm: the "
            f"realisation cannot build it for the tolerance (structure "
            + ("not defined" if structure is None else f"{structure:.2f} mm")
            + f", target {record['target_mm']:.2f} mm)"
        )
    row, how, done = tried[-1]
    if done.accuracy.meets is False:  # none can: the rule's own choice, which the verdict judges
        row, how, done = tried[0]
        notes = []
    how["fallback"] = [*notes[: len(tried) - 1], *how["fallback"]]
    return row, how, done


def selected_record(
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
    (:func:`qsm.realization.choice.choose_design`), realised (:func:`realize`): the record of
    ``choice.json`` (its row, how it was found, the task (the user's points; the design's are
    ``task_points``), the clearance (m), strength, drives, the advice where a check fails, and
    the verdict) and the realisation, which ``machine.json`` holds."""
    cad = settings.parts.cad
    disk = min_enclosing_circle(task_points)

    def choose(skipped: list[NDArray[np.float64]]) -> tuple[pd.Series, dict[str, Any]]:
        kept = {name: _without(t, skipped) for name, t in fronts.items()}
        return choose_design(kept, primary, _without(dataset, skipped), rule, cad, volume_mm)

    row, how, done = _buildable(choose, settings)
    record = machine_top(row, how, done, volume_mm)
    record["task"] = task_record(user_points)
    record["clearance_m"] = disk_clearance_m(record["design_m"], op, disk)
    verdicts = []
    if not record["holds_loads"]:
        record["strength_advice"] = strength_advice(record["design_m"], settings.strength)
        verdicts.append(_strength_failure(record, how, settings))
    if not done.has_drives:
        verdicts.append(
            "NO DRIVE for each motor in the catalogue"
            + ("" if how["has_drives"] else ", for any design of the fronts or the dataset")
            + ": "
            + "; ".join(drive_sentences(done.drives))
        )
    if not how["printable"]:
        verdicts.append(_printing_failure(record, fronts, dataset, cad, volume_mm, disk))
    elif not record["printable"]:
        verdicts.append(_grown_past_printer(record, volume_mm))
    record["verdict"] = ". ".join(verdicts) + "." if verdicts else _ready(record, volume_mm)
    return record, done


#: The candidate's fields that are the realised machine's as well: its lengths and how it was
#: chosen. Every other column of the candidate's row describes it at the section it was chosen
#: with, and stays in ``candidate``.
SHARED_KEYS = (
    *("design_m", "scale_m", "l1_m", "l2_m", "l3_m", "l4_m", "ee_x_m", "ee_y_m"),
    *("formulation", "mechanism_id", "selection_rule", "selection_score", "n_candidates"),
)


def machine_top(
    row: pd.Series, how: Mapping[str, Any], done: Realization, volume_mm: tuple[float, ...]
) -> dict[str, Any]:
    """The top of ``choice.json``: the realised machine (its lengths, how it was chosen, its
    printer fit, strength and drives as realised) and, in ``candidate``, the optimiser's
    candidate as it was chosen (every column of its row; ``printable``, ``holds_loads`` and
    ``has_drives`` of the tier it was chosen in)."""
    candidate = selection_record(row)
    candidate.update({k: how[k] for k in ("printable", "holds_loads", "has_drives")})
    fit = link_printability(done.design, done.part_settings.cad, done.scale, volume_mm)["links"]
    record = {k: candidate[k] for k in SHARED_KEYS if k in candidate}
    record["source"], record["fallback"] = how["source"], how["fallback"]
    record["printable"] = all(link["fits"] for link in fit.values())
    record["printer_box_mm"] = {name: list(link["dims_mm"]) for name, link in fit.items()}
    record["holds_loads"] = bool(done.strength["holds_loads"])
    record["has_drives"] = done.has_drives
    record["strength"], record["drives"] = done.strength, done.drives
    record["candidate"] = candidate
    return record


def _grown_past_printer(record: Mapping[str, Any], volume_mm: tuple[float, ...]) -> str:
    """The verdict of a candidate that fits the printer at the section it was chosen with, and
    not at the sections it was realised with."""
    over = [
        f"the {name.replace('_', ' ')} {' x '.join(f'{v:.0f}' for v in box)} mm"
        for name, box in record["printer_box_mm"].items()
        if not box_fits(box, np.sort(np.asarray(volume_mm, dtype=float)))
    ]
    return (
        f"NOT PRINTABLE on {' x '.join(f'{v:g}' for v in volume_mm)} mm at the sections the "
        f"realisation gave its links: {', '.join(over)}"
    )


def _strength_failure(
    record: Mapping[str, Any], how: Mapping[str, Any], settings: RealizationSettings
) -> str:
    return (
        strength_verdict(record["strength"])
        + (
            ""
            if how["holds_loads"]
            else ", and no design of the fronts or the dataset holds its loads"
        )
        + ". What would change that: "
        + "; ".join(strength_sentences(record["strength_advice"], settings.strength))
    )


def _printing_failure(
    record: dict[str, Any],
    fronts: Mapping[str, pd.DataFrame],
    dataset: pd.DataFrame,
    cad: CadSettings,
    volume_mm: tuple[float, float, float],
    disk: Disk,
) -> str:
    """The not-printable verdict; adds ``printing_advice`` to ``record``."""
    advice = printing_advice(record["design_m"], cad, volume_mm, disk)
    pool = candidate_pool(fronts, dataset)
    strong = pool["holds_loads"].astype(bool)
    advice["smallest_over_designs"] = smallest_build_volume(
        pool, strong if record["holds_loads"] else np.ones(len(pool), bool), cad
    )
    record["printing_advice"] = advice
    return (
        "NOT PRINTABLE on the configured printer: no design of the fronts or the dataset "
        + ("that holds its loads " if record["holds_loads"] else "")
        + "fits it. What would change that: "
        + "; ".join(
            [
                advice_sentence(advice["smallest_over_designs"], volume_mm),
                *advice_sentences(advice, cad)[1:],
            ]
        )
    )


def _ready(record: Mapping[str, Any], volume_mm: tuple[float, float, float]) -> str:
    return (
        f"printable on {' x '.join(f'{v:g}' for v in volume_mm)} mm, every link holds its loads "
        f"({strength_verdict(record['strength'])}), each motor has a drive "
        f"({'; '.join(drive_sentences(record['drives']))}), chosen from the "
        f"{record['source']} {'designs' if record['source'] == 'dataset' else 'front'}"
    )


def selected_figure(
    record: Mapping[str, Any],
    rule: str,
    op: OperatingRange,
    task_points: Sequence[Sequence[float]],
    path: str | Path,
) -> None:
    """PNG: the selected design over its workspace with the task disk, titled with what it
    fails, how it was chosen and its true objectives."""
    fig, ax = plt.subplots(figsize=(6, 6))
    cand = record["candidate"]
    title = (
        f"selected ({rule}, {record['formulation']}"
        f"{'' if record['printable'] else ', NOT PRINTABLE'}"
        f"{'' if record['holds_loads'] else ', NOT STRONG ENOUGH'}"
        f"{'' if record['drives']['has_drives'] else ', NO DRIVES'}"
        f"{', designed MIRRORED (x -> -x)' if record['task']['mirrored'] else ''}): "
        f"l1 {record['scale_m']:.3f} m\n"
        f"eta {cand['eta_true']:.3f}, tau1 {cand['tau1_true_Nm']:.1f} N m, "
        f"tau2 {cand['tau2_true_Nm']:.1f} N m (as chosen)"
    )
    disk = min_enclosing_circle(task_points)
    draw_design(ax, np.asarray(record["design_m"]), op, disk, title)
    fig.savefig(path, dpi=110, bbox_inches="tight")
    plt.close(fig)
