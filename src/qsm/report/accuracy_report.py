"""``selected.json``: the chosen design's record (``choice.json``) completed, once its plates are
optimised and its payload test has run, with its final accuracy budget; its verdict sentence, and
the figure of the tool's sag over the task region."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

import matplotlib.pyplot as plt
import numpy as np
from matplotlib import patheffects
from matplotlib.patches import Circle
from numpy.typing import ArrayLike, NDArray

from qsm.embodiment.stiffness.error_terms import payload_force_N, sag_m
from qsm.embodiment.stiffness.frame import tool_compliance
from qsm.physics.batch_ik import batch_joint_angles
from qsm.physics.cad import MassProperties
from qsm.physics.task import min_enclosing_circle
from qsm.realization.final.final_budget import plate_factors
from qsm.realization.selection.pipeline import (
    Realization,
    RealizationSettings,
    arm_model,
)


def final_verdict(record: Mapping[str, Any]) -> str:
    """The final ``record``'s verdict: the selection's, with the budget's sentence and, where
    the task asks for a repeatability the arm misses, that added."""
    rp = repeatability_problem(record.get("iso9283"))
    extra = f" {rp[0].upper()}{rp[1:]}." if rp else ""
    return f"{record['verdict'].rstrip('.')}. {accuracy_sentence(record['stiffness'])}.{extra}"


def repeatability_problem(iso: Mapping[str, Any] | None) -> str | None:
    """Where the ISO 9283 record ``iso`` misses the task's repeatability: the sentence with its
    numbers; None where it meets it or none is asked."""
    if not iso or not iso["simulated"] or iso["meets_repeatability"] is not False:
        return None
    i = iso["worst_point"] - 1
    return (
        f"not repeatable enough: ISO 9283 pose repeatability RP {iso['rp_mm'][i]:.3f} mm at "
        f"test point P{i + 1}, {iso['repeatability_mm']:g} mm required (main random term: "
        f"{iso['main_random_term']}, {iso['rp_alone_mm'][iso['main_random_term']][i]:.3f} mm "
        f"alone)"
    )


def accuracy_sentence(budget: Mapping[str, Any]) -> str:
    """The budget's verdict, and what would meet the tolerance where it fails."""
    if budget["meets_requirements"]:
        return "Accurate enough: " + budget["verdict"]
    return budget["verdict"] + ". What would meet it: " + "; ".join(budget["would_meet"])


def _cell(value: float | None) -> str:
    """A table cell: the value to 0.01, or - where there is none."""
    return "-" if value is None or not np.isfinite(value) else f"{value:.2f}"


def accuracy_lines(budget: Mapping[str, Any] | None) -> list[str]:
    """``summary.md``'s accuracy section: the budget per task point, its verdict and the
    assumptions on the gearboxes."""
    if budget is None:
        return []
    per = budget["per_point"]
    head = "| point | " + " | ".join(k.replace("_", " ") for k in per) + " |"
    rows = [head, "|" + " --- |" * (len(per) + 1)]
    for k in range(len(budget["points_m"])):
        cells = [_cell(None if v is None else v[k]) for v in per.values()]
        rows.append(f"| {k + 1} | " + " | ".join(cells) + " |")
    spared = {
        True: "counted: its torque reverses along the task",
        False: "spared: its torque "
        "keeps one sign along the task (gravity keeps the gear loaded on one flank)",
    }
    joints = [
        f"- {name}: {j.get('gearbox')}, backlash {j.get('backlash_arcmin')} arcmin "
        f"({j.get('backlash_from')}), {spared[j['torque_reverses']]}; "
        f"stiffness {stiffness_text(j)} N m/rad ({j.get('stiffness_from')})."
        for name, j in budget["joints"].items()
    ]
    serial = budget.get("serial_arm")
    return [
        "## Accuracy",
        f"- {accuracy_sentence(budget)}.",
        *_built_for(budget.get("built_for_tolerance")),
        *([f"- the paper's claim, measured: {serial['verdict']}."] if serial else []),
        f"- model: {budget['model']}.",
        *joints,
        "",
        *rows,
        "",
    ]


def _built_for(built: Mapping[str, Any] | None) -> list[str]:
    """What the realisation did for the tolerance: its target, the sections and gearboxes."""
    if not built or built["target_mm"] is None:
        return []
    scales = ", ".join(f"{k.replace('_', ' ')} {v:.2f}x" for k, v in built["section_scale"].items())
    least = ", ".join(
        f"motor {m}: " + ("any gearbox" if k == 0 else f"a gearbox of at least {k:,.0f} N m/rad")
        for m, k in enumerate(built["min_gearbox_stiffness_Nm_rad"], start=1)
    )
    error = built["structure_mm"]
    met = "meets it" if built["meets_target"] else "comes nearest"
    return [
        f"- built for the tolerance: the structure (sag, dynamic sag, creep and lost motion, solid "
        f"links) "
        f"may take {built['target_mm']:.2f} mm ({100 * built['structure_share']:.0f} %, the rest "
        f"kept for tracking); the realised arm {met} at "
        f"{'-' if error is None else f'{error:.2f}'} mm with sections {scales} the configured "
        f"one ({least})."
    ]


def _sag_grid(
    done: Any, settings: RealizationSettings, props: dict[str, MassProperties] | None,
    factor: ArrayLike, points: NDArray, n: int = 15,
) -> tuple[NDArray, NDArray, NDArray]:  # fmt: skip
    """The tool's sag (n, n) mm under the payload's weight on a grid over the task disk (NaN
    where the design cannot reach), with the grid's x and y (n,) m."""
    disk = min_enclosing_circle(points)
    (cx, cy), r = disk.centre, max(disk.radius, 0.02)
    xs, ys = np.linspace(cx - r, cx + r, n), np.linspace(cy - r, cy + r, n)
    model = arm_model(done, settings, props, factor)
    gx, gy = np.meshgrid(xs, ys)
    grid = np.column_stack([gx.ravel(), gy.ravel()])
    motion = settings.motion
    angles = batch_joint_angles(done.design, grid, *motion.operating_range.degrees)[0].reshape(
        n, n, 2
    )
    angles[np.hypot(gx - cx, gy - cy) > r] = np.nan
    ok = np.isfinite(angles[..., 0])
    sag = np.full((n, n), np.nan)
    rigid = not np.isfinite(model.drive_stiffness).all()
    c = tool_compliance(
        done.design, angles[ok][:, 0], angles[ok][:, 1],
        model.sections._replace(factor=model.factor), None if rigid else model.drive_stiffness,
    )  # fmt: skip
    sag[ok] = 1e3 * sag_m(c, payload_force_N(settings.motion.payload_kg, np.zeros(2)))
    return xs, ys, sag


#: The budget's terms as the bars stack them: label, the ``per_point`` keys (the larger taken).
BAR_TERMS: tuple[tuple[str, tuple[str, ...]], ...] = (
    ("sag (static or dynamic)", ("sag_mm", "dynamic_sag_mm")),
    ("creep", ("creep_mm",)),
    ("lost motion", ("lost_motion_mm",)),
    ("tracking", ("tracking_error_mm",)),
    ("base", ("base_mm",)),
)


def budget_bars(ax: plt.Axes, budget: Mapping[str, Any]) -> None:
    """The ``budget``'s terms at each task point, stacked to its placing error (mm), against
    its tolerance, every bar and the tolerance inside the axes."""
    per = budget["per_point"]
    n = len(per["error_budget_mm"])
    k, bottom = np.arange(1, n + 1), np.zeros(n)
    for label, keys in BAR_TERMS:
        columns = [[v or 0.0 for v in per.get(key) or [0.0] * n] for key in keys]  # None: 0
        values = np.max(np.asarray(columns, dtype=float), axis=0)
        ax.bar(k, values, bottom=bottom, label=label)
        bottom = bottom + values
    ax.axhline(budget["tolerance_mm"], color="r", ls="--", label="tolerance")
    ax.set_ylim(0.0, 1.12 * max(float(bottom.max()), budget["tolerance_mm"]))
    ax.set(xlabel="task point", ylabel="placing error (mm)", xticks=k)
    ax.set_title("accuracy budget: " + ("met" if budget["meets_requirements"] else "NOT met"))
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.15), ncol=3, fontsize="small")


def accuracy_figure(
    record: Mapping[str, Any],
    done: Realization,
    topology: Mapping[str, Any],
    props: dict[str, MassProperties],
    settings: RealizationSettings,
    points: ArrayLike,
    path: str | Path,
) -> None:
    """PNG: left, the tool's sag under the payload's weight over the task region (the printed
    links and the drives' stiffness); right, the budget's terms at each task point against the
    tolerance."""
    pts = np.asarray(points, dtype=float).reshape(-1, 2)
    xs, ys, sag = _sag_grid(done, settings, props, plate_factors(topology), pts)
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.5))
    mesh = left.pcolormesh(xs, ys, sag, shading="nearest", cmap="viridis")
    disk = min_enclosing_circle(pts)
    rim = Circle(disk.centre, max(disk.radius, 0.02), fill=False, lw=0.8)
    left.add_patch(rim)
    mesh.set_clip_path(rim)  # the cells at the rim end at the task disk
    fig.colorbar(mesh, ax=left, label="sag under the payload's weight (mm)")
    left.plot(pts[:, 0], pts[:, 1], "wo", mec="k")
    for k, (x, y) in enumerate(pts, start=1):
        label = left.annotate(str(k), (x, y), textcoords="offset points", xytext=(4, 4), color="w")
        label.set_path_effects([patheffects.withStroke(linewidth=2, foreground="k")])
    left.set(xlabel="x (m)", ylabel="y (m)", aspect="equal", title="tool sag over the task region")
    budget_bars(right, record["stiffness"])
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def stiffness_text(drive: dict[str, Any]) -> str:
    """A gearbox's torsional stiffness (N m/rad) to the newton metre, ``-`` when unknown."""
    k = drive.get("torsional_stiffness_Nm_rad")
    return "-" if k is None else f"{k:,.0f}"
