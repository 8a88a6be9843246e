"""The time-optimal cycle's outputs (:mod:`qsm.realization.final.cycle_check`): its record for JSON
(``selected.json``'s ``cycle``), its trajectory as a table, its torques against each drive's
envelope as a figure, and its lines of ``summary.md``."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from qsm.embodiment.drives.envelope import OutputEnvelope
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
        f"slowed {cycle['slowed_by']:g}x from {cycle['time_optimal_s']:.2f} s: "
        + "; ".join(cycle["slowed_for"])
        if cycle["slowed_by"] > 1.0
        else "as planned"
    )
    sim = cycle["simulation"]
    return [
        "## Cycle",
        f"- {cycle['cycle_time_s']:.2f} s per cycle, {cycle['cycles_per_hour']:.0f} cycles per "
        f"hour ({slowed}); {cycle['faster_than_raster']:.1f}x as fast as the raster's speed "
        f"({cycle['raster_cycle_s']:.2f} s); dwell {cycle['dwell_s']:g} s at each point.",
        f"- moves (what binds the time-optimal timing): {moves}.",
        f"- peak power {_pair(cycle['peak_power_W'], 0)} W, RMS {_pair(cycle['rms_power_W'], 0)} "
        f"W, energy {cycle['energy_per_cycle_J']:.0f} J per cycle; RMS torque "
        f"{_pair(cycle['rms_torque_Nm'], 1)} N m against {_pair(cycle['continuous_torque_Nm'], 1)}"
        f" N m continuous (thermal use {_pair(cycle['thermal_use'], 2)}, gear losses by the "
        f"torque's direction); links at {cycle['strength_utilisation']:.2f} of their strength.",
        f"- MuJoCo: {'passed' if sim['passed'] else 'FAILED'} ({sim['reason']}), tracking "
        f"{sim['max_tracking_error_deg']:.3f} deg, at the points "
        f"{max(sim['point_error_mm']):.2f} mm at most.",
        "",
    ]


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


def cycle_figure(cycle: Cycle | None, arm: Arm, path: str | Path, reason: str = "") -> Path:
    """Each motor's |torque| against its |speed| over the cycle, over its drive's envelope at
    the joint (driving direction); the envelopes and ``reason`` alone without a cycle."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(10, 4), constrained_layout=True)
    if cycle is None:
        fig.suptitle(f"no cycle: {reason}"[:120], fontsize=9)
    if cycle is not None:
        _, _, qd, tau = cycle_torques(cycle, arm, one_period=False)
    for j, (ax, env) in enumerate(zip(axes, arm.drives, strict=True)):
        _envelope(ax, env)
        if cycle is not None:
            ax.plot(np.abs(qd[:, j]), np.abs(tau[:, j]), ".", ms=2, label="cycle")
        ax.set(xlabel="|speed| at the joint (rad/s)", ylabel="|torque| at the joint (N m)",
               title=f"motor {j + 1}: {env.name}")  # fmt: skip
        ax.legend()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return Path(path)


def _envelope(ax: Any, env: OutputEnvelope) -> None:
    """The drive's torque (N m) at the joint against speed (rad/s), driving, on ``ax``."""
    speed = np.linspace(0.0, top_speed(env), 200)
    ax.plot(speed, env.limit(np.ones_like(speed), speed), "k-", label="drive envelope")
