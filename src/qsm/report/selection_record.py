"""The verdict of ``choice.json``: the chosen design
(:mod:`qsm.realization.selection.chosen_machine`) stated with this run's numbers, and the figure of
the design over its workspace.
:mod:`qsm.report.accuracy_report` completes the verdict, with the accuracy budget, in
``selected.json``."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import matplotlib.pyplot as plt
import numpy as np

from qsm.embodiment.parts.printing import box_fits
from qsm.embodiment.strength.advice import advice_sentences as strength_sentences
from qsm.embodiment.strength.link_checks import StrengthCheck
from qsm.embodiment.strength.verdict import strength_verdict
from qsm.physics.cad import CadSettings
from qsm.physics.task import min_enclosing_circle
from qsm.physics.workspace import OperatingRange
from qsm.realization.selection.choice import advice_sentences, printer_fix
from qsm.report.drive_text import drive_sentences
from qsm.report.figures import draw_design


def selection_verdict(
    record: Mapping[str, Any],
    strength: StrengthCheck,
    cad: CadSettings,
    volume_mm: tuple[float, float, float],
) -> str:
    """The verdict of a chosen machine's ``record`` (:func:`~qsm.realization.selection.
    chosen_machine.chosen_machine`): each check it fails with its numbers and what would change
    it, else what it meets."""
    tier = record["candidate"]
    verdicts = []
    if not record["holds_loads"]:
        verdicts.append(_strength_failure(record, tier, strength))
    if not record["has_drives"]:
        verdicts.append(
            "NO DRIVE for each motor in the catalogue"
            + ("" if tier["has_drives"] else ", for any design of the fronts or the dataset")
            + ": "
            + "; ".join(drive_sentences(record["drives"]))
        )
    if not tier["printable"]:
        verdicts.append(_printing_failure(record, cad, volume_mm))
    elif not record["printable"]:
        verdicts.append(_grown_past_printer(record, volume_mm))
    if not record["fixed_point"]["converged"]:
        verdicts.append(_unsettled(record))
    return ". ".join(verdicts) + "." if verdicts else _ready(record, volume_mm)


def _strength_failure(
    record: Mapping[str, Any], how: Mapping[str, Any], strength: StrengthCheck
) -> str:
    return (
        strength_verdict(record["strength"])
        + (
            ""
            if how["holds_loads"]
            else ", and no design of the fronts or the dataset holds its loads"
        )
        + ". What would change that: "
        + "; ".join(strength_sentences(record["strength_advice"], strength))
    )


def _printing_failure(
    record: Mapping[str, Any], cad: CadSettings, volume_mm: tuple[float, float, float]
) -> str:
    """The not-printable verdict, from the record's ``printing_advice``: for a design that
    holds its loads, what would make it or another printable; for one that does not, only a
    printer for a design that holds them (a printer alone would leave it too weak)."""
    advice = record["printing_advice"]
    head = "NOT PRINTABLE on the configured printer: no design of the fronts or the dataset "
    fix = printer_fix(advice, record["holds_loads"], volume_mm)
    if record["holds_loads"]:
        fixes = [fix, *advice_sentences(advice, cad)[1:]]
        return head + "that holds its loads fits it. What would change that: " + "; ".join(fixes)
    if fix is None:
        other = advice["smallest_over_designs"]
        why = (
            "none holds its loads"
            if other is None
            else "the design that holds them with the smallest printer at the configured "
            "section does not as realised (strength utilisation "
            f"{other['strength_utilisation']:.2f})"
        )
        return (
            head + f"fits it, and no larger printer would help: {why}, so a printer alone "
            "would leave it NOT STRONG ENOUGH"
        )
    return (
        head + "fits it. A larger printer alone would leave this design NOT STRONG ENOUGH; "
        "instead, " + fix
    )


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


def _unsettled(record: Mapping[str, Any]) -> str:
    """The verdict of a realisation whose loop stopped before the tool flange's mass settled."""
    point = record["fixed_point"]
    return (
        f"NOT SETTLED: the realisation stopped after {point['iterations']} realisations "
        f"(kit.fixed_point_iterations) with the tool flange's mass still changing: the last "
        f"carried {point['tool_kg'][-1]:.3f} kg at E and chose a flange of "
        f"{record['tool_flange'].get('moving_mass_kg', 0.0):.3f} kg"
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
