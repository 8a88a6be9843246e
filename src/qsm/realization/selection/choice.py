"""The design to realise, on any task: strong enough and printable if anything is, truly
feasible always.

Order of the search (:func:`choose_design`), each step applying the selection rule of
:func:`select_design` (:func:`qsm.optimization.ranking.rule_scores`) to its candidates, taken
first from the primary front (``optimization.formulation``), then the other fronts in order,
then the dataset (every design of which truly holds the task, with true dynamics):

1. the truly feasible designs whose links hold their loads, whose motors each have a drive in the
   catalogue (:mod:`qsm.embodiment.drives.drive_checks`) and that fit the printer; among them,
   those whose tool sag stays within the tolerance (a front's ``within_tolerance``) when any does;
2. without one: those that hold their loads and have drives, marked *not printable*, with what
   it would take to print them (:func:`printing_advice`);
3. without one: steps 1 and 2 among the designs that hold their loads without drives for both
   motors (the outputs then say which motor has none, by how much, and what the strongest drive
   offers);
4. without one: the truly feasible design whose links come nearest to holding (the smallest
   strength utilisation), marked *not strong enough*; a part that breaks is worse than a motor
   you must source elsewhere, which is worse than a part that needs a larger printer: strength
   comes first, then drives, then printability.

Every step that is skipped is recorded with its counts, so the output says why it fell back.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray

from qsm.dataset.columns import DRIVE_COLUMNS, STRENGTH_COLUMNS
from qsm.embodiment.parts.printing import (
    BUILD_VOLUME_MM,
    advice_sentence,
    all_links_fit,
    fits_build_volume,
    printability_violation_mm,
    round_up_mm,
    section_excess_mm,
    section_needed_mm,
    section_shortfall_m,
)
from qsm.optimization.ranking import OBJECTIVES, RULES, rule_scores, true_columns
from qsm.physics.cad import DEFAULT_CAD, CadSettings
from qsm.physics.kinematics import DESIGN_COLUMNS
from qsm.physics.task import Disk


@dataclass(frozen=True)
class HowChosen:
    """How :func:`choose_design` found a design: the front or ``dataset`` it came from
    (``source``), whether it fits the printer, holds its loads and has a drive in the catalogue
    for each motor, and one line per step skipped, with its counts (``fallback``)."""

    source: str
    printable: bool
    holds_loads: bool
    has_drives: bool
    fallback: tuple[str, ...]

    def tier(self) -> tuple[bool, bool, bool]:
        """What the design met: printable, holds its loads, has drives."""
        return self.printable, self.holds_loads, self.has_drives


class NoFeasibleDesign(ValueError):
    """Neither a front nor the dataset holds a truly feasible design."""


#: The dataset's columns a design taken from it carries (:func:`dataset_candidates`): the rule
#: reads these, not the whole table.
CANDIDATE_COLUMNS: tuple[str, ...] = (
    "mechanism_id", *DESIGN_COLUMNS, "scale_m", "eta", "tau1_Nm", "tau2_Nm", "status",
    *STRENGTH_COLUMNS, *DRIVE_COLUMNS,
)  # fmt: skip


def dataset_candidates(dataset: pd.DataFrame) -> pd.DataFrame:
    """Dataset rows (every one holds the task at its scale) in the shape of a verified front."""
    renamed = {"eta": "eta_true", "tau1_Nm": "tau1_true_Nm", "tau2_Nm": "tau2_true_Nm"}
    columns = ["mechanism_id", *DESIGN_COLUMNS, "scale_m", *renamed, "status"]
    out = dataset.loc[:, [*columns, *STRENGTH_COLUMNS, *DRIVE_COLUMNS]].reset_index(drop=True)
    out = out.rename(columns={**renamed, "status": "dynamics_status"})
    at = columns.index("status")  # concatenated, not inserted: Arrow's blocks stay as read
    feasible = pd.Series(True, index=out.index, name="feasible")
    return pd.concat([out.iloc[:, :at], feasible, out.iloc[:, at:]], axis=1)


def _feasible(table: pd.DataFrame) -> pd.DataFrame:
    return table[_feasible_rows(table)]


def _feasible_rows(table: pd.DataFrame) -> NDArray[np.bool_]:
    """Which rows are feasible, dynamically verified and have finite true values."""
    ok = (table["feasible"].astype(bool) & table["dynamics_status"].eq("ok")).to_numpy()
    return ok & np.isfinite(table.loc[:, true_columns(table)].to_numpy(float)).all(axis=1)


def _tiers(table: pd.DataFrame) -> tuple[NDArray[np.bool_], ...]:
    """Row masks of ``table``: truly feasible; of those, holding their loads; of those, with a
    drive for each motor (masks, not copies: the dataset's tiers hold most of its rows)."""
    feasible = _feasible_rows(table)
    strong = feasible.copy()  # read on the feasible rows alone, where holds_loads is set
    strong[feasible] = table.loc[feasible, "holds_loads"].astype(bool).to_numpy()
    return feasible, strong, strong & _has_drives(table).to_numpy()


def _printable(table: pd.DataFrame, cad: CadSettings, volume_mm: tuple[float, ...]) -> pd.Series:
    """Whether every link fits, decided by :func:`qsm.embodiment.parts.printing.all_links_fit` on
    the outlines (the closed-form boxes only pre-screen the designs clearly too large)."""
    designs = table.loc[:, list(DESIGN_COLUMNS)].to_numpy(float)
    near = printability_violation_mm(designs, cad, volume_mm) <= 0.5
    fits = np.zeros(len(table), dtype=bool)
    fits[near] = [all_links_fit(d, cad, volume_mm) for d in designs[near]]
    return pd.Series(fits, index=table.index)


def select_design(
    verified: pd.DataFrame,
    rule: str = "knee",
    cad: CadSettings = DEFAULT_CAD,
    volume_mm: tuple[float, float, float] = BUILD_VOLUME_MM,
) -> pd.Series:
    """The row of ``verified`` chosen by ``rule`` (see the module docstring) among the feasible,
    dynamically verified (``dynamics_status == 'ok'``) designs whose links all fit ``volume_mm``.

    The returned row (a copy, same index label) gains ``selection_rule``, ``selection_score``,
    ``n_candidates`` (rows that fit) and, per link, ``<link>_box_mm`` (x, y, thickness).
    Raises ``ValueError`` when no row qualifies or the rule is unknown.
    """
    if rule not in RULES:
        raise ValueError(f"unknown selection rule {rule!r}; choose one of {RULES}")
    missing = [
        c
        for c in (*DESIGN_COLUMNS, *OBJECTIVES, "feasible", "dynamics_status")
        if c not in verified.columns
    ]
    if missing:
        raise ValueError(f"verified table lacks columns {missing}")
    ok = np.flatnonzero(_feasible_rows(verified))
    designs = verified.loc[:, list(DESIGN_COLUMNS)].to_numpy(float)[ok]
    fit = np.array([all_links_fit(d, cad, volume_mm) for d in designs], dtype=bool)
    cand = verified.iloc[ok[fit]]
    if cand.empty:
        raise ValueError(
            f"no design qualifies: {len(verified)} rows, {len(ok)} feasible with dynamics 'ok', "
            f"none of them has every link within the build volume {tuple(volume_mm)} mm"
        )
    scores = rule_scores(cand, rule)
    k = int(np.argmin(scores))
    row = cand.iloc[k].copy()
    row["selection_rule"] = rule
    row["selection_score"] = float(scores[k])
    row["n_candidates"] = len(cand)
    for name, info in fits_build_volume(designs[fit][k], cad, volume_mm).items():
        row[f"{name}_box_mm"] = info["dims_mm"]
    return row


def _printable_count(
    n_table: int,
    strong: pd.DataFrame,
    cad: CadSettings,
    volume_mm: tuple[float, float, float],
) -> str:
    """The fallback line's printer count: none of the ``n_table`` designs prints; when there are
    none (no design with drives), how many of the ``strong`` designs (their lengths) would."""
    volume = " x ".join(f"{v:g}" for v in volume_mm)
    if n_table or not len(strong):
        return f", 0 of those printable on {volume} mm"
    n = int(_printable(strong, cad, volume_mm).sum())
    return f" ({n} of the {len(strong)} that hold their loads printable on {volume} mm)"


def within_tolerance_first(table: pd.DataFrame) -> pd.DataFrame:
    """The designs whose tool sag is within the tolerance (the verification's
    ``within_tolerance``, g15 on the full task), when there are any; ``table`` otherwise."""
    if "within_tolerance" not in table:
        return table
    within = table["within_tolerance"].astype("boolean").fillna(False).astype(bool)
    return table[within] if within.any() else table


def choose_design(
    fronts: Mapping[str, pd.DataFrame],
    primary: str,
    dataset: pd.DataFrame,
    rule: str,
    cad: CadSettings,
    volume_mm: tuple[float, float, float],
) -> tuple[pd.Series, HowChosen]:
    """The design to realise (see the module docstring) and how it was found."""
    sources = {name: fronts[name] for name in [primary, *(k for k in fronts if k != primary)]}
    sources["dataset"] = dataset_candidates(dataset)
    tiers = {name: _tiers(table) for name, table in sources.items()}
    skipped: list[str] = []
    for tier, has_drives in ((2, True), (1, False)):
        for name, table in sources.items():
            rows = np.flatnonzero(tiers[name][tier])
            lengths = table.loc[:, list(DESIGN_COLUMNS)].iloc[rows]
            fits = _printable(lengths, cad, volume_mm).to_numpy()
            if fits.any():
                chosen = within_tolerance_first(table.iloc[rows[fits]])
                row = select_design(chosen, rule, cad, volume_mm)
                how = HowChosen(name, True, True, has_drives, tuple(skipped))
                return _tag(row, name, True), how
            skipped.append(_skipped_line(name, table, tiers[name], has_drives, cad, volume_mm))
        for name, table in sources.items():
            if tiers[name][tier].any():
                row = select_design(table[tiers[name][tier]], rule, cad, (np.inf,) * 3)
                how = HowChosen(name, False, True, has_drives, tuple(skipped))
                return _tag(row, name, False), how
        if has_drives:
            skipped.append(
                "no truly feasible design of the fronts or the dataset that holds its loads has "
                "a drive in the catalogue for each motor"
            )
    skipped.append("no truly feasible design of the fronts or the dataset holds its loads")
    for name, table in sources.items():
        if tiers[name][0].any():
            return _least_utilised(table, tiers[name][0], name, cad, volume_mm, skipped)
    raise NoFeasibleDesign(
        "no truly feasible design on any front nor in the dataset: " + "; ".join(skipped)
    )


def _skipped_line(
    name: str,
    table: pd.DataFrame,
    tiers: tuple[NDArray[np.bool_], ...],
    has_drives: bool,
    cad: CadSettings,
    volume_mm: tuple[float, float, float],
) -> str:
    """Why a source's tier gave no printable design, with its counts."""
    feasible, strong, driven = (int(mask.sum()) for mask in tiers)
    n_tier = driven if has_drives else strong
    strong_lengths = table.loc[tiers[1], list(DESIGN_COLUMNS)]
    return (
        f"{name} {'front' if name != 'dataset' else 'designs'}: {len(table)} designs, "
        f"{feasible} truly feasible, {strong} of them hold their loads"
        + (f", {driven} of those have drives" if has_drives else "")
        + _printable_count(n_tier, strong_lengths, cad, volume_mm)
    )


def _least_utilised(
    table: pd.DataFrame,
    feasible: NDArray[np.bool_],
    name: str,
    cad: CadSettings,
    volume_mm: tuple[float, float, float],
    skipped: list[str],
) -> tuple[pd.Series, HowChosen]:
    """The truly feasible design of ``table`` nearest to holding its loads, and how it was found."""
    use = table.loc[feasible, "strength_utilisation"].astype(float)
    row = table.loc[use.idxmin()].copy()
    row["selection_rule"] = "least strength utilisation"
    row["selection_score"] = float(row["strength_utilisation"])
    row["n_candidates"] = len(use)
    printable = bool(_printable(table.loc[[row.name]], cad, volume_mm).iloc[0])
    has_drives = bool(_has_drives(table.loc[[row.name]]).iloc[0])
    how = HowChosen(name, printable, False, has_drives, tuple(skipped))
    return _tag(row, name, printable), how


def candidate_pool(fronts: Mapping[str, pd.DataFrame], dataset: pd.DataFrame) -> pd.DataFrame:
    """The truly feasible designs of every front and of the dataset in one table, each with its
    ``source`` (the front's name or ``dataset``)."""
    tables = {
        name: _feasible(table)
        for name, table in {**fronts, "dataset": dataset_candidates(dataset)}.items()
    }
    pool = pd.concat(tables.values(), ignore_index=True).drop(columns="source", errors="ignore")
    sizes = [len(table) for table in tables.values()]
    source = pd.Series(np.repeat(list(tables), sizes), name="source")
    return pd.concat([pool, source], axis=1)  # a column of its own: Arrow's split blocks stay


def _has_drives(table: pd.DataFrame) -> pd.Series:
    """Whether each design has a drive for each motor (False where the column is missing)."""
    if "has_drives" not in table:
        return pd.Series(False, index=table.index)
    return table["has_drives"].fillna(False).astype(bool)


def _tag(row: pd.Series, source: str, printable: bool) -> pd.Series:
    row = row.copy()
    row["formulation"] = source
    row["printable"] = printable
    return row


def printing_advice(
    design: np.ndarray,
    cad: CadSettings,
    volume_mm: tuple[float, float, float],
    disk: Disk,
    scale: ArrayLike | None = None,
) -> dict[str, Any]:
    """What would make ``design`` (6 lengths, m) printable, each with numbers for this design at
    its links' sections: ``cad``'s, scaled link by link by ``scale`` (4,) as realised (None:
    ``cad``'s for every link).

    ``needed_volume_mm``: the smallest build volume (sorted, mm); ``smallest_scale``: the
    smallest factor k <= 1 of the lengths at which every link still holds its bosses (None if
    none, and then no scale is advised);
    ``scale_factor``: the largest k <= 1 with k x design printable, the sections kept and every
    link holding its bosses (None if none), and the task it then holds (the task disk scaled by
    k about the base: containment does not depend on the scale); ``max_boss_radius_mm``: the
    largest ``cad.boss_radius_m`` (mm), at most the configured one, that lets every link fit
    with the bar width and the links' scales unchanged (None if even width_m / 2 is too large).
    """
    d = np.asarray(design, dtype=float)
    vol = np.sort(np.asarray(volume_mm, dtype=float))

    def fits(lengths: NDArray[np.float64], section: CadSettings) -> bool:
        return section_excess_mm(lengths, section, scale, vol) <= 0

    out: dict[str, Any] = {
        "needed_volume_mm": section_needed_mm(d, cad, scale).tolist(),
        "build_volume_mm": [float(v) for v in volume_mm],
    }
    # too short a link cannot hold its bosses: the scale is sought above that
    shortest = _smallest(lambda k: section_shortfall_m(d * k, cad, scale) <= 0, 1e-6, 1.0)
    k = None if shortest is None else _largest(lambda k: fits(d * k, cad), shortest, 1.0)
    out["scale_factor"], out["smallest_scale"] = k, shortest
    if k is not None:
        out["scaled_l1_m"] = float(k * d[0])
        out["scaled_task_distance_m"] = k * disk.distance
        out["scaled_task_radius_m"] = k * disk.radius
    smallest = 500 * cad.width_m * (1 + 1e-9)  # the bosses must be wider than the bar
    out["max_boss_radius_mm"] = _largest(
        lambda r: fits(d, replace(cad, boss_radius_m=r * 1e-3)), smallest, 1e3 * cad.boss_radius_m
    )
    return out


def _smallest(fits: Callable[[float], bool], lo: float, hi: float) -> float | None:
    """Smallest x in [lo, hi] with ``fits(x)`` for a ``fits`` false below some threshold and
    true above it (to 1e-9 relative); None if ``fits(hi)`` is false."""
    if fits(lo):
        return lo
    return _bracket(fits, lo, hi, False)[1] if fits(hi) else None


def _largest(fits: Callable[[float], bool], lo: float, hi: float) -> float | None:
    """Largest x in [lo, hi] with ``fits(x)`` for a ``fits`` true below some threshold and false
    above it (to 1e-9 relative); None if ``fits(lo)`` is false."""
    if not fits(lo):
        return None
    return hi if fits(hi) else _bracket(fits, lo, hi, True)[0]


def _bracket(
    test: Callable[[float], bool], lo: float, hi: float, at_lo: bool
) -> tuple[float, float]:
    """Where ``test`` changes its answer from ``at_lo`` (at ``lo``) to the other (at ``hi``): a
    bracket 1e-9 of ``hi`` wide, by bisection."""
    while hi - lo > 1e-9 * hi:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if test(mid) == at_lo else (lo, mid)
    return lo, hi


def printer_sentence(advice: Mapping[str, Any]) -> str:
    """The printer this design needs (``advice``'s ``needed_volume_mm``, whole mm up) against
    the configured one."""
    need = " x ".join(f"{math.ceil(v - 1e-6)}" for v in advice["needed_volume_mm"])
    have = " x ".join(f"{v:g}" for v in advice["build_volume_mm"])
    return f"a printer of at least {need} mm (configured: {have} mm)"


def printer_fix(
    advice: Mapping[str, Any], holds_loads: bool, volume_mm: Sequence[float]
) -> str | None:
    """The printer that would make a design printable and strong, from ``advice``: for a design
    that ``holds_loads``, its own as realised (``needed_volume_mm``), the
    ``smallest_over_designs``' instead where that one holds its loads as realised and needs no
    side larger and one smaller (whole mm, sides from the largest), both where neither does;
    for one that does not, only the other's, where it holds its loads (None: no printer)."""
    other = advice.get("smallest_over_designs")
    strong = other is not None and other.get("holds_loads", True)
    if not holds_loads:
        return advice_sentence(other, volume_mm) if strong else None
    own = printer_sentence(advice)
    if not strong:
        return own
    mine = np.asarray(round_up_mm(advice["needed_volume_mm"]))
    theirs = np.asarray(other["needed_volume_mm"])
    if (mine <= theirs).all():
        return own
    if (theirs <= mine).all():
        return advice_sentence(other, volume_mm)
    return own + "; or " + advice_sentence(other, volume_mm)


def advice_sentences(advice: Mapping[str, Any], cad: CadSettings) -> list[str]:
    """The advice as plain sentences, every number from ``advice``."""
    lines = [printer_sentence(advice)]
    k = advice.get("scale_factor")
    if k is not None:
        lines.append(
            f"a nearer, smaller task: this design's lengths scaled by {k:.3f}, its links' "
            f"sections kept (l1 {advice['scaled_l1_m']:.3f} m), fit and hold the task circle "
            "scaled by the same factor towards the base (centre "
            f"{advice['scaled_task_distance_m']:.3f} m from the base, radius "
            f"{advice['scaled_task_radius_m']:.3f} m)"
        )
    elif advice.get("smallest_scale") is not None:
        lines.append(
            "no nearer, smaller task: this design's links hold their bosses only with its lengths "
            f"scaled by {advice['smallest_scale']:.3f} or more, where a link still exceeds the "
            "printer"
        )
    r = advice.get("max_boss_radius_mm")
    if r is not None:
        lines.append(
            f"smaller bosses: cad.boss_radius_m of {r:.1f} mm or less (now "
            f"{1e3 * cad.boss_radius_m:g} mm), the bar width and each link's section scale kept"
        )
    else:
        lines.append(
            "no smaller bosses: with the smallest the bar width allows "
            f"(cad.width_m / 2 = {500 * cad.width_m:g} mm) a link still exceeds the printer"
        )
    return lines
