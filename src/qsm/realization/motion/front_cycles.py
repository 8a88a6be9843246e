"""The task's time-optimal cycle for every design of a verified front (true values).

Each design that truly holds the task, whose dynamics ran and whose motors have drives gets the
cycle the realised design gets (:func:`qsm.realization.motion.cycle.plan_cycle`: the same visits,
dwells, planner and TOPP-RA bounds) with the drives the verification chose for it and its solid
links at the strength's sections, at four speed bounds (:data:`FRONT_FRACTIONS`, against the
realised design's seven: half the time, and on 25 designs of the default front at most 0.4 %
slower, never faster). It is the time-optimal plan only: without the jerk limit, and not slowed
for the tolerance, the drives' RMS or MuJoCo's run, which the realised design's cycle adds
(:mod:`qsm.realization.final.cycle_check`). The column ``time_optimal_cycle_s`` ranks the front
(``printing.selection_rule: fastest``) and shows in the interactive front.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from qsm.embodiment.drives.catalogue import Catalogue
from qsm.embodiment.drives.envelope import OutputEnvelope
from qsm.embodiment.strength.link_checks import StrengthCheck
from qsm.embodiment.strength.loads import Inertials
from qsm.physics.batch_mass import batch_mass_properties
from qsm.physics.inverse_kinematics import joint_path
from qsm.physics.kinematics import DESIGN_COLUMNS
from qsm.physics.mjcf import TIMESTEP_S
from qsm.physics.task_points import TaskCycle
from qsm.realization.motion.cycle import Arm, plan_cycle
from qsm.realization.motion.payload import PayloadSettings

#: The speed bounds each front design's moves are planned at (fractions of each drive's top speed).
FRONT_FRACTIONS: tuple[float, ...] = (0.3, 0.5, 0.7, 0.9)
#: The columns :func:`front_cycles` gives, with their units.
CYCLE_COLUMNS: dict[str, str] = {
    "time_optimal_cycle_s": "the task's time-optimal cycle with the design's drives and solid "
    "links, not slowed for the tolerance, the drives' RMS or MuJoCo (s; NaN: not planned)",
    "time_optimal_cycles_per_hour": "3600 / time_optimal_cycle_s (1/h)",
    "cycle_note": "why no cycle was planned (empty: planned)",
}


def _arm(row: pd.Series, check: StrengthCheck, catalogue: Catalogue, payload_kg: float) -> Arm:
    """The planner's arm of one verified design: its solid links at the strength's sections and
    the drives the verification chose."""
    d = row[list(DESIGN_COLUMNS)].to_numpy(float)
    sized = check.section_scales(d[None])
    scale = None if sized is None else sized.scale[0]
    inertials = Inertials(*batch_mass_properties(d, check.cad, scale))
    drives = [
        OutputEnvelope.of(catalogue, row[f"drive{j}_motor"], row[f"drive{j}_gearbox"])
        for j in (1, 2)
    ]
    return Arm(d, inertials, payload_kg, drives)


def _planned(row: pd.Series) -> str:
    """Why a verified design gets no cycle (empty: it gets one)."""
    if not (bool(row["feasible"]) and row["dynamics_status"] == "ok"):
        return "does not truly hold the task"
    if not bool(row.get("has_drives", False)):
        return "no drive of the catalogue for each motor"
    return ""


def _cycle_time(
    row: pd.Series, check: StrengthCheck, catalogue: Catalogue, task: TaskCycle,
    test: PayloadSettings,
) -> tuple[float, str]:  # fmt: skip
    """One verified design's time-optimal cycle (s; NaN) and why there is none (empty)."""
    note = _planned(row)
    if note:
        return np.nan, note
    arm = _arm(row, check, catalogue, test.payload_kg)
    try:
        angles = joint_path(arm.design, task.points, *test.operating_range.degrees)
        cycle = plan_cycle(arm, angles, task.dwell_s, TIMESTEP_S, task.returns, FRONT_FRACTIONS)
    except ValueError as exc:  # out of reach, or the drives cannot hold the arm
        return np.nan, str(exc)
    return cycle.time_s, ""


def front_cycles(
    verified: pd.DataFrame,
    check: StrengthCheck,
    catalogue: Catalogue,
    task: TaskCycle,
    test: PayloadSettings,
) -> pd.DataFrame:
    """:data:`CYCLE_COLUMNS` for every row of a ``verified`` front: the ``task``'s time-optimal
    cycle with each design's drives (from ``catalogue``), its links at ``check``'s sections,
    the payload and operating range of ``test``."""
    rows = [_cycle_time(row, check, catalogue, task, test) for _, row in verified.iterrows()]
    t = np.array([r[0] for r in rows], dtype=float)
    return pd.DataFrame(
        {
            "time_optimal_cycle_s": t,
            "time_optimal_cycles_per_hour": 3600.0 / t,
            "cycle_note": [r[1] for r in rows],
        },
        index=verified.index,
    )
