"""The run's verdict on the realised design: ready to build, or each check it fails, worst
first, with its number against its limit and, where the run computed one, the change that
would meet it.

:func:`failures` reads the records (``selected.json``, the topology record, the payload test) and
gives one :class:`Failure` per failed check; :func:`verdict_sentence` is the one bold line that
heads the summary and the datasheet, :func:`verdict_lines` the numbered list under it.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from qsm.embodiment.parts.printing import box_fits
from qsm.prose import fixed
from qsm.realization.accuracy.accuracy_budget import FIRST_MODE_FIX
from qsm.realization.selection.choice import printer_fix
from qsm.report.accuracy_report import repeatability_problem
from qsm.report.cycle_report import cycle_problems
from qsm.report.drive_text import shortfall
from qsm.report.headline_tables import factor_text


@dataclass(frozen=True)
class Failure:
    """One failed check: what fails with its number against its limit (``text``), how many
    times its limit it reaches (``ratio``, 1; None: no single number says it) and the change
    the run computed that would meet it (``fix``; None: none was computed)."""

    text: str
    ratio: float | None = None
    fix: str | None = None

    def line(self) -> str:
        """Markdown: the failure, its ratio and its fix."""
        ratio = "" if self.ratio is None else f" ({fixed(self.ratio, 2)} times its limit)"
        fix = "" if self.fix is None else f". What would meet it: {self.fix}"
        return f"{self.text}{ratio}{fix}."


def failures(
    selected: Mapping[str, Any], topology: Mapping[str, Any], payload: Mapping[str, Any]
) -> list[Failure]:
    """Each check the realised design fails, worst first (by how far past its limit; those
    without one number after, in the order of the build: print, strength, drives, payload
    test, accuracy, repeatability, cycle, kit)."""
    found = [
        *_printer_failures(selected, topology),
        *_strength_failures(selected["strength"]),
        *_part_failures(selected, topology),
        *[Failure(p) for p in drive_problems(selected.get("drives", {}).get("motors", {}))],
        *_payload_failures(payload),
        *_accuracy_failures(selected),
        *_cycle_failures(selected.get("cycle")),
    ]
    kit = topology.get("parts", {}).get("kit")
    if kit is not None and not kit["holds"]:
        found += [Failure(f"the builder's kit: {p}") for p in kit["problems"]]
    return sorted(found, key=lambda f: np.inf if f.ratio is None else -f.ratio)


def build_verdict(
    selected: Mapping[str, Any], topology: Mapping[str, Any], payload: Mapping[str, Any]
) -> tuple[bool, list[str]]:
    """Whether the realised design is ready to build, and each reason it is not (with the
    run's numbers), worst first (:func:`failures`)."""
    found = failures(selected, topology, payload)
    return not found, [f.text for f in found]


def verdict_sentence(
    selected: Mapping[str, Any], topology: Mapping[str, Any], payload: Mapping[str, Any]
) -> str:
    """The run's overall verdict in one line: ready to build, with its accuracy, or how many
    checks fail and the worst of them (:func:`failures`)."""
    ready, found = build_verdict(selected, topology, payload)
    if ready:
        worst = selected["stiffness"]["worst"]
        return (
            "Ready to build: printable, every part holds its loads, each motor has a drive, "
            f"payload test passed, placing error at most {worst['error_budget_mm']:.1f} mm "
            f"(tolerance {selected['stiffness']['tolerance_mm']:g} mm)."
        )
    if len(found) == 1:
        return f"NOT READY TO BUILD: {found[0]}."
    return f"NOT READY TO BUILD: {len(found)} checks fail; the worst: {found[0]}."


def verdict_lines(found: list[Failure]) -> list[str]:
    """Markdown: the failed checks, worst first, numbered, each with its fix (none where the
    design is ready)."""
    if not found:
        return []
    return [
        "What fails, worst first:",
        "",
        *(f"{k}. {f.line()}" for k, f in enumerate(found, start=1)),
        "",
    ]


def _printer_failures(selected: Mapping[str, Any], topology: Mapping[str, Any]) -> list[Failure]:
    """The printer: the design as chosen, then its parts as drawn (their boxes, mm, against
    the build volume; the advice's printer for a design that holds its loads)."""
    given = selected.get("printer_volume_mm")  # the record's, where it has one
    volume = None if given is None else np.sort(np.asarray(given, dtype=float))
    if not selected["printable"]:
        boxes = selected["printer_box_mm"]
        over = [f"the {n.replace('_', ' ')} ({' x '.join(f'{v:.0f}' for v in b)} mm)"
                for n, b in boxes.items() if not box_fits(b, volume)]  # fmt: skip
        where = f"the printer's {' x '.join(f'{v:g}' for v in selected['printer_volume_mm'])} mm"
        advice = selected.get("printing_advice")
        holds = selected["strength"]["holds_loads"]
        fix = None if advice is None else printer_fix(advice, holds, given)
        return [Failure(
            f"not printable: {', '.join(over)} {'does' if len(over) == 1 else 'do'} not fit "
            f"{where} build volume", _box_ratio(boxes.values(), volume), fix,
        )]  # fmt: skip
    return [
        Failure(
            f"the printed {link.replace('_', ' ')} "
            f"({' x '.join(f'{v:.1f}' for v in r['box_mm'])} mm) does not fit the printer",
            _box_ratio([r["box_mm"]], volume),
        )
        for link, r in topology.get("parts", {}).get("printer", {}).items()
        if not r["fits"]
    ]


def _box_ratio(boxes: Any, volume: np.ndarray | None) -> float | None:
    """The largest side of the sorted ``boxes`` (mm) over the sorted build ``volume``'s (None:
    no volume known)."""
    if volume is None:
        return None
    return max(float((np.sort(np.asarray(b, dtype=float)) / volume).max()) for b in boxes)


def _strength_failures(strength: Mapping[str, Any]) -> list[Failure]:
    """The links and bearings of a strength record that do not hold; one for the check as a
    whole where it fails and nothing names a link or a bearing."""
    found = []
    for link, r in strength["links"].items():
        if r["holds"]:
            continue
        ratio = r["stress_peak_MPa"] / r["allowable_MPa"]
        if r.get("buckling_factor"):  # the buckling factor's shortfall where it is larger
            ratio = max(ratio, r["required_buckling_factor"] / r["buckling_factor"])
        if link == strength["weakest_link"]:
            found.append(Failure(
                f"the {link.replace('_', ' ')} does not hold its loads: its "
                f"{strength['weakest_check']} is at {strength['utilisation']:.2f} of what it may "
                f"take ({r['stress_peak_MPa']:.1f} MPa peak stress, {r['allowable_MPa']:.1f} MPa "
                f"allowed)", strength["utilisation"],
            ))  # fmt: skip
        else:
            found.append(Failure(
                f"the {link.replace('_', ' ')} does not hold its loads "
                f"({r['stress_peak_MPa']:.1f} MPa, {r['allowable_MPa']:.1f} MPa allowed; "
                f"buckling factor {factor_text(r['buckling_factor'])}, "
                f"{r['required_buckling_factor']:g} required)", ratio,
            ))  # fmt: skip
    for joint, b in strength.get("bearings", {}).items():
        if not b["designation"]:
            found.append(Failure(
                f"no bearing of the catalogue fits joint {joint} ({b['peak_force_N']:.0f} N peak, "
                f"static safety {strength['required_bearing_safety']:g} required, within the boss)"
            ))  # fmt: skip
    if not strength["holds_loads"] and not found:
        found.append(Failure(
            f"the strength check fails: the {strength['weakest_link'].replace('_', ' ')}'s "
            f"{strength['weakest_check']} is at {strength['utilisation']:.2f} of what it may "
            "take (at most 1)", strength["utilisation"],
        ))  # fmt: skip
    return found


def _part_failures(selected: Mapping[str, Any], topology: Mapping[str, Any]) -> list[Failure]:
    """The parts as drawn: a section other than the one checked, an STL that is not watertight,
    an optimised plate past its allowable stress."""
    found = []
    drawn = topology.get("parts", {}).get("section_mm", {})
    for link, r in selected["strength"]["links"].items():
        checked, built = [r.get("width_mm"), r.get("thickness_mm")], drawn.get(link)
        if built and None not in checked and not np.allclose(checked, built, rtol=1e-6):
            found.append(Failure(
                f"the {link.replace('_', ' ')} was checked with the section "
                f"{checked[0]:.1f} x {checked[1]:.1f} mm, but its part, drawing and BOM are "
                f"drawn at {built[0]:.1f} x {built[1]:.1f} mm"
            ))  # fmt: skip
    for link, r in topology.get("parts", {}).get("printer", {}).items():
        if not r["watertight"]:
            found.append(Failure(
                f"the {link.replace('_', ' ')}'s STL is not watertight after trimesh's repairs: "
                "a slicer may not print it as drawn"
            ))  # fmt: skip
    for link, r in topology["links"].items():
        if not r["carries_loads"]:
            found.append(Failure(
                f"the printed {link.replace('_', ' ')} plate reaches "
                f"{r['max_von_mises_after_MPa']:.1f} MPa in the FE check, "
                f"{r['allowable_stress_MPa']:.1f} MPa allowed",
                r["max_von_mises_after_MPa"] / r["allowable_stress_MPa"],
            ))  # fmt: skip
    return found


def drive_problems(motors: Mapping[str, Any]) -> list[str]:
    """One verdict line per motor of a drive report's ``motors`` without a drive: why its
    nearest drive does not do, with its number."""
    return [
        f"motor {key.removeprefix('motor')} ({m['drives']}) has no drive in the catalogue "
        f"(the nearest {shortfall(m)})"
        for key, m in motors.items()
        if not m["has_drive"]
    ]


def _cycle_failures(cycle: Mapping[str, Any] | None) -> list[Failure]:
    """The cycle's problems (:func:`cycle_problems`, in its order: the drives' heat, the links'
    strength, MuJoCo's run): the heat with its largest thermal use and the continuous torque
    each hot motor would need (its use x its rating, N m), the links with their utilisation,
    MuJoCo's run with its tracking error over the tolerance and what its drives would need."""
    problems = cycle_problems(None if cycle is None else dict(cycle))
    if not problems or not cycle or not cycle["planned"]:
        return [Failure(p) for p in problems]
    found = []
    if cycle["thermal_ok"] is False:
        rows = enumerate(zip(cycle["thermal_use"], cycle["continuous_torque_Nm"], strict=True))
        need = [f"a drive for motor {j + 1} rated {fixed(_tenths_up(u * c), 1)} N m continuous "
                "or more" for j, (u, c) in rows if u > 1.0]  # fmt: skip
        found.append(Failure(problems[0], max(cycle["thermal_use"]), "; ".join(need)))
    if not cycle["links_hold"]:
        found.append(Failure(problems[len(found)], cycle["strength_utilisation"]))
    sim = cycle["simulation"]
    if not sim["passed"]:
        found.append(Failure(problems[len(found)], _tracking_ratio(sim), _drive_fix(sim)))
    return found


def _tenths_up(value: float) -> float:
    """``value`` rounded up to a tenth (what a rating must reach, not a rounding below it)."""
    return math.ceil(round(10 * value, 6)) / 10


def _payload_failures(payload: Mapping[str, Any]) -> list[Failure]:
    """The payload test, where it fails: why (its reason, which names the tracking error past
    its tolerance), its tracking error over the tolerance, and what its drives would need."""
    if payload["passed"]:
        return []
    error = payload["max_tracking_error_deg"]
    limit = payload.get("tracking_tolerance_deg")
    reason = payload.get("reason")
    if reason and reason != "ok":
        text = f"the payload test failed: {reason}"
    else:
        allowed = "" if limit is None else f", {limit:g} deg allowed"
        text = f"the payload test failed (max tracking error {fixed(error, 3)} deg{allowed})"
    return [Failure(text, _tracking_ratio(payload), _drive_fix(payload))]


def _tracking_ratio(run: Mapping[str, Any]) -> float | None:
    """A simulation's largest tracking error over its tolerance, where it is past it (None: it
    failed on its drives, or the record has no error)."""
    error, limit = run.get("max_tracking_error_deg"), run.get("tracking_tolerance_deg")
    return error / limit if error is not None and limit and error > limit else None


def _drive_fix(run: Mapping[str, Any]) -> str | None:
    """What a simulation's drives would need, from its record (the payload test's, the cycle's
    MuJoCo run): those past their top speed, slower moves or a faster drive; those at their
    torque limit, a drive with more torque."""
    fixes = []
    past = run.get("past_top_speed_fraction") or []
    uses = run.get("peak_torque_over_available") or []
    for k, use in enumerate(uses, start=1):
        share = past[k - 1] if k <= len(past) else None
        if share and share > 0:
            fixes.append(
                f"motor {k}'s drive runs past its top speed for {100 * share:.1f} % of the "
                "test: longer moves (payload_test.segment_duration_s) or a drive with a higher "
                "top speed"
            )
        elif use is not None and use >= 0.995:
            fixes.append(f"motor {k}'s drive gives {use:.2f} of its torque: a drive with more")
    return "; ".join(fixes) or None


def _accuracy_fix(fixes: list[str], note: list[str]) -> str | None:
    """The budget's advice as one fix: the tolerance's alternatives joined by "or", the first
    mode's need by "and"; where the sizing did not reach the tolerance (``note``), where to
    read why."""
    mode = [w for w in fixes if w.startswith(FIRST_MODE_FIX)]
    fix = "; and ".join(filter(None, ["; or ".join(w for w in fixes if w not in mode), *mode]))
    if fix and note:
        fix += " (why the sizing did not reach it: the summary's Accuracy section)"
    return fix or None


def _accuracy_failures(selected: Mapping[str, Any]) -> list[Failure]:
    """The accuracy budget past its tolerance (the run's own ``would_meet`` as the fix,
    :func:`_accuracy_fix`), and the ISO 9283 repeatability past the task's."""
    found = []
    budget = selected.get("stiffness")
    if budget is not None and not budget["meets_requirements"]:
        note = budget.get("sizing_note") or []  # what the sizing did: no change to make
        fixes = [w for w in budget.get("would_meet") or [] if w not in note]
        found.append(Failure(budget["verdict"], _budget_ratio(budget), _accuracy_fix(fixes, note)))
    if rp := repeatability_problem(selected.get("iso9283")):
        iso = selected["iso9283"]
        found.append(Failure(rp, iso["rp_mm"][iso["worst_point"] - 1] / iso["repeatability_mm"]))
    return found


def _budget_ratio(budget: Mapping[str, Any]) -> float | None:
    """How far a failed budget is past its limit: the placing error over the tolerance, else
    (a first mode too low) the required mode over the arm's; None where neither is past."""
    worst = budget["worst"]
    ratios = [worst["error_budget_mm"] / budget["tolerance_mm"]]
    wanted, mode = budget.get("min_first_mode_hz"), worst.get("first_mode_hz")
    if wanted and mode:
        ratios.append(wanted / mode)
    return max(ratios) if max(ratios) > 1.0 else None
