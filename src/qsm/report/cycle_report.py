"""The time-optimal cycle's outputs (:mod:`qsm.realization.final.cycle_check`): its record for JSON
(``selected.json``'s ``cycle``), its trajectory as a table, its torques against each drive's
envelope as a figure, and its lines of ``summary.md``."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from qsm.embodiment.drives.envelope import OutputEnvelope
from qsm.prose import fixed
from qsm.realization.final.cycle_check import (
    cycle_torques,
)
from qsm.realization.motion.cycle import Arm, Cycle, top_speed


def cycle_lines(cycle: dict[str, Any] | None) -> list[str]:
    """``summary.md``'s cycle section."""
    if not cycle:
        return []
    if not cycle["planned"]:
        return ["## Cycle", f"- no cycle could be planned on the task: {cycle['reason']}.", ""]
    moves = ", ".join(
        f"{m['from']}->{m['to']} {m['time_s']:.2f} s ({m['optimal_binding']})"
        for m in cycle["moves"]
    )
    slowed = (
        f"its moves slowed {cycle['slowed_by']:g}x, the dwells kept, from "
        f"{cycle['time_optimal_s']:.2f} s: " + "; ".join(cycle["slowed_for"])
        if cycle["slowed_by"] > 1.0
        else "as planned"
    )
    sim = cycle["simulation"]
    return [
        "## Cycle",
        f"- {cycle['cycle_time_s']:.2f} s per cycle, {cycle['cycles_per_hour']:,.0f} cycles per "
        f"hour ({slowed}); {cycle['faster_than_raster']:.1f}x as fast as the raster's speed "
        f"({cycle['raster_cycle_s']:.2f} s); {dwell_text(cycle)}.",
        f"- moves (what binds the time-optimal timing): {moves}; {jerk_text(cycle.get('jerk'))}.",
        *_settling_lines(cycle),
        f"- peak power {_pair(cycle['peak_power_W'], 0)} W, RMS {_pair(cycle['rms_power_W'], 0)} "
        f"W, energy {cycle['energy_per_cycle_J']:.0f} J per cycle; RMS torque "
        f"{_pair(cycle['rms_torque_Nm'], 1)} N m against {_pair(cycle['continuous_torque_Nm'], 1)}"
        f" N m continuous (thermal use {_pair(cycle['thermal_use'], 2)}, gear losses by the "
        f"torque's direction); links at {cycle['strength_utilisation']:.2f} of their strength.",
        f"- MuJoCo: {'passed' if sim['passed'] else 'FAILED'} ({sim['reason']}), tracking "
        f"{fixed(sim['max_tracking_error_deg'], 3)} deg, at the points "
        f"{fixed(max(sim['point_error_mm']), 2)} mm at most.",
        "",
    ]


def dwell_text(cycle: Mapping[str, Any]) -> str:
    """The cycle's dwells: the configured one at each point, or longer where the arm settles,
    with the largest ringing on arrival (``cycle.json``'s ``dwells_s`` and ``settling``)."""
    dwells, stops = cycle.get("dwells_s") or [cycle["dwell_s"]], cycle.get("settling") or []
    text = f"{cycle['dwell_s']:g} s dwell at each point"
    if max(dwells) > cycle["dwell_s"]:
        text = (f"dwells of {min(dwells):.2f}-{max(dwells):.2f} s: {cycle['dwell_s']:g} s (the "
                "gripper's), longer where the arm must settle")  # fmt: skip
    if stops:
        ringing = max(s["ringing_mm"] for s in stops)
        text += f", the tool ringing at most {ringing:.2f} mm on arrival"
        elastic = [
            s["elastic_ringing_mm"] for s in stops if s.get("elastic_ringing_mm") is not None
        ]
        if elastic:
            text += f" ({max(elastic):.2f} mm in the elastic model)"
    return text


def jerk_text(jerk: Mapping[str, Any] | None) -> str:
    """How a cycle's moves limit their jerk (``cycle.json``'s ``jerk``)."""
    if not jerk or jerk["jerk_time_s"] is None:
        return "moves timed by TOPP-RA without a jerk limit"
    ramp = f"each move's acceleration ramped over {1e3 * jerk['jerk_time_s']:.0f} ms"
    if jerk["first_mode_hz"] is None:
        stated = jerk.get("stated_s")
        if stated and not math.isclose(stated, jerk["jerk_time_s"]):  # slowed with the moves
            return f"{ramp} (task.cycle.jerk_time_s, {1e3 * stated:.0f} ms, times the slow-down)"
        return f"{ramp} (task.cycle.jerk_time_s)"
    periods = jerk.get("periods") or 1.0
    count = "one period" if math.isclose(periods, 1.0) else f"{periods:.2g} periods"
    text = f"{ramp}, {count} of the arm's {jerk['first_mode_hz']:.2f} Hz first mode"
    if jerk.get("chosen_with_slow_down"):
        text += " (chosen with the slow-down: the shortest cycle once each stop has settled)"
    return text


def _settling_lines(cycle: dict[str, Any]) -> list[str]:
    """Each stop's ringing on arrival and its settling time (``cycle.json``'s ``settling``)."""
    stops = cycle.get("settling") or []
    if not stops:
        return []

    def settle(s: dict[str, Any]) -> str:
        if s["settling_s"] is None:
            return "never within the tolerance (its static terms miss it)"
        times = [t for t in (s["settling_s"], s.get("elastic_settling_s")) if t is not None]
        return "within the tolerance on arrival" if max(times) == 0 else (
            f"within the tolerance after {max(times):.2f} s")  # fmt: skip

    def elastic(s: dict[str, Any]) -> str:
        ring = s.get("elastic_ringing_mm")
        return "" if ring is None else f" ({ring:.2f} mm in the elastic model)"

    text = "; ".join(
        f"point {s['point']}: {s['ringing_mm']:.2f} mm at {s['first_mode_hz']:.1f} Hz"
        f"{elastic(s)}, {settle(s)}, dwell {s['dwell_s']:.2f} s"
        for s in stops
    )
    return [f"- the tool's ringing on arrival (first mode, damping assumed): {text}."]


def cycle_problems(cycle: dict[str, Any] | None) -> list[str]:
    """What keeps the task's cycle from running as a machine would, with the numbers: a drive
    whose RMS torque exceeds its continuous torque, links past their strength, or MuJoCo's run
    failing even at the slowest tried."""
    if not cycle:
        return []
    if not cycle["planned"]:
        return [f"no time-optimal cycle could be planned on the task: {cycle['reason']}"]
    out = []
    if cycle["thermal_ok"] is False:
        rows = zip(
            cycle["rms_torque_Nm"], cycle["continuous_torque_Nm"], cycle["thermal_use"], strict=True
        )
        over = [
            f"motor {j + 1} {r:.1f} N m RMS, {u:.2f} of its continuous rating ({c:.1f} N m)"
            for j, (r, c, u) in enumerate(rows)
            if u > 1.0
        ]
        out.append(
            f"DRIVES OVERHEAT on the cycle ({cycle['cycle_time_s']:.2f} s): {', '.join(over)}"
        )
    if not cycle["links_hold"]:
        out.append(
            f"the links reach {cycle['strength_utilisation']:.2f} of their strength on the cycle"
        )
    if not cycle["simulation"]["passed"]:
        out.append(f"MuJoCo's run of the cycle fails: {cycle['simulation']['reason']}")
    return out


def _pair(values: Sequence[float | None], digits: int) -> str:
    """Two values, motor 1 / motor 2, to ``digits`` decimals (- where there is none)."""
    return " / ".join("-" if v is None else f"{v:.{digits}f}" for v in values)


def cycle_figure(
    cycle: Cycle | None,
    arm: Arm,
    path: str | Path,
    reason: str = "",
    elastic: tuple[NDArray, NDArray, float] | None = None,
) -> Path:
    """Each motor's |torque| against its |speed| over the cycle, over its drive's envelope at
    the joint (driving direction); the envelopes and ``reason`` alone without a cycle. With
    ``elastic`` (times s, the tool's elastic displacement along its first mode mm, and the
    ringing the tolerance allows mm), a third panel draws it over time."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    panels = 2 if elastic is None else 3
    fig, axes = plt.subplots(1, panels, figsize=(5 * panels, 4), constrained_layout=True)
    if elastic is not None:
        _elastic_panel(axes[2], *elastic)
    if cycle is None:
        fig.suptitle(f"no cycle: {reason}"[:120], fontsize=9)
    if cycle is not None:
        _, _, qd, tau = cycle_torques(cycle, arm, one_period=False)
    for j, (ax, env) in enumerate(zip(axes[:2], arm.drives, strict=True)):
        _envelope(ax, env)
        if cycle is not None:
            ax.plot(np.abs(qd[:, j]), np.abs(tau[:, j]), ".", ms=2, label="cycle")
        ax.set(xlabel="|speed| at the joint (rad/s)", ylabel="|torque| at the joint (N m)",
               title=f"motor {j + 1}: {env.name}")  # fmt: skip
        ax.legend()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return Path(path)


def _elastic_panel(ax: Any, t: NDArray, x_mm: NDArray, allowed_mm: float) -> None:
    """The tool's elastic displacement (mm) along its first mode over time (s), with the ringing
    the tolerance allows above the static terms."""
    ax.plot(t, x_mm, "-", lw=0.8, label="tool along its first mode")
    for sign in (1, -1):
        ax.axhline(sign * allowed_mm, color="r", ls="--", lw=0.8,
                   label="tolerance less the static terms" if sign > 0 else None)  # fmt: skip
    ax.set(xlabel="time (s)", ylabel="elastic displacement (mm)",
           title="the tool's elastic error over the cycle")  # fmt: skip
    ax.legend(fontsize=7)


def _envelope(ax: Any, env: OutputEnvelope) -> None:
    """The drive's torque (N m) at the joint against speed (rad/s), driving, on ``ax``."""
    speed = np.linspace(0.0, top_speed(env), 200)
    ax.plot(speed, env.limit(np.ones_like(speed), speed), "k-", label="drive envelope")
