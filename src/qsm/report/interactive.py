"""The interactive Pareto front: one self-contained HTML page (Plotly, a partial bundle inlined).

The page shows a verified front (:func:`qsm.optimization.verify.verify_front`) in 3D and in the
three pairwise views of its objectives, (eta, tau1, tau2) or (eta, drive mass, tau1) for a front
optimised on the drive mass (:func:`qsm.optimization.ranking.drawn_objectives`), coloured by the
scale factor l1. Each design is drawn at NSGA-II's values (the surrogate's predictions, the drive
mass on the loop's duty) and, in a second legend group switched off at first, at its true values
(Stage 1 and the MuJoCo dynamics). Hovering a design shows its rank
(:mod:`qsm.optimization.ranking`) with the command that exports it, its six lengths, NSGA-II's
and the true objectives, whether it truly holds the task and whether it is printable. Designs
that fail a check (the task, the printer, the strength, the drives) are drawn as crosses in the
pairs and as open circles in 3D.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np
import pandas as pd
import plotly.graph_objects as go
from plotly.subplots import make_subplots

from qsm.optimization.ranking import (
    OBJECTIVE_SETS,
    Objective,
    drawn_objectives,
    front_ranks,
    objectives_of,
)
from qsm.physics.kinematics import DESIGN_COLUMNS, DESIGN_NAMES
from qsm.report.plotly_page import write_figure_page

PAIRS: tuple[tuple[int, int], ...] = ((0, 1), (0, 2), (1, 2))
#: Every objective is minimised: the axis titles say so.
BETTER = ", lower is better"
COLOUR_TITLE = "scale factor l1 (m)"


def _yes_no(flag: object) -> str:
    return "yes" if bool(flag) else "NO"


def _number(value: float, digits: int) -> str:
    return f"{value:.{digits}f}" if np.isfinite(value) else "n/a"


def hover_texts(verified: pd.DataFrame, ranks: Sequence[int], front: str) -> list[str]:
    """One hover text per design (HTML with ``<br>``): rank and export command, lengths (mm),
    predicted and true objectives, whether it holds the task, whether it is printable and each
    motor's drive (when the table has the drive columns)."""
    texts = []
    n = len(verified)
    for rank, (_, row) in zip(ranks, verified.iterrows(), strict=True):
        lengths = ", ".join(
            f"{name} {1e3 * row[col]:.1f}"
            for name, col in zip(DESIGN_NAMES, DESIGN_COLUMNS, strict=True)
        )
        lines = [
            f"<b>rank {rank} of {n}</b>: qsm export --front {front} --rank {rank}",
            f"lengths (mm): {lengths}",
        ]
        shown = dict.fromkeys([*OBJECTIVE_SETS["torques"], *objectives_of(verified)])
        for o in shown:
            digits = 4 if o.name == "eta" else 2
            lines.append(
                f"{o.label}: predicted {_number(row[o.predicted], digits)}, "
                f"true {_number(row[o.true], digits)}"
            )
        lines.append(
            f"holds the task: {_yes_no(row['task_contained'])} "
            f"(margin {_number(1e3 * row['containment_margin_m'], 1)} mm)"
        )
        needed = " x ".join(
            _number(row[f"needed_volume_{k}_mm"], 0) for k in ("long", "mid", "short")
        )
        lines.append(f"printable: {_yes_no(row['printable'])} (needs {needed} mm)")
        lines += _stiffness_and_cycle(row)
        for j, motor in ((1, "lower arm"), (2, "crank")):
            if f"drive{j}_motor" not in row or not row[f"drive{j}_motor"]:
                continue
            ok = row[f"drive{j}_violation"] <= 0
            lines.append(
                f"motor {j} ({motor}): {row[f'drive{j}_motor']} + {row[f'drive{j}_gearbox']} "
                f"({_number(row[f'drive{j}_ratio'], 1)}:1, "
                f"{_number(row[f'drive{j}_mass_kg'], 2)} kg"
                + (")" if ok else "; NONE meets the duty, nearest shown)")
                + f", peak {_number(row[f'drive{j}_peak_torque_Nm'], 1)} N m"
            )
        texts.append("<br>".join(lines))
    return texts


def _stiffness_and_cycle(row: pd.Series) -> list[str]:
    """The hover lines of the tool's sag (g15's, the configured section) and the task's
    time-optimal cycle, where the table has them."""
    lines = []
    if "tool_sag_mm" in row:
        within = _yes_no(row["within_tolerance"]) if "within_tolerance" in row else "n/a"
        lines.append(
            f"tool sag under the payload: {_number(row['tool_sag_mm'], 2)} mm, within the "
            f"tolerance: {within}"
        )
    if "time_optimal_cycle_s" in row:
        time_s = row["time_optimal_cycle_s"]
        lines.append(
            f"time-optimal cycle: {_number(time_s, 2)} s, "
            f"{3600.0 / time_s:,.0f} per hour (not slowed for the tolerance or MuJoCo)"
            if np.isfinite(time_s)
            else f"time-optimal cycle: none ({row.get('cycle_note', '')})"
        )
    return lines


def _flag(verified: pd.DataFrame, column: str) -> pd.Series:
    """A boolean column of the verified table (True where the table lacks it)."""
    if column not in verified:
        return pd.Series(True, index=verified.index)
    return verified[column].fillna(False).astype(bool)


def front_figure(
    verified: pd.DataFrame, front: str, constraints: str = "", selected: int | None = None
) -> go.Figure:
    """The Plotly figure of a verified front (see the module docstring); ``selected`` is the row
    (position) of the design the run realised, marked with a star, when it comes from this
    front."""
    ranks = front_ranks(verified)
    texts = hover_texts(verified, ranks, front)
    drawn = drawn_objectives(verified)
    good = (
        _flag(verified, "task_contained")
        & _flag(verified, "printable")
        & _flag(verified, "holds_loads")
        & _flag(verified, "has_drives")
    )
    # 3D markers are drawn as font glyphs: "x" is an emoji that most fonts lack (an empty box)
    symbol_3d = np.where(good, "circle", "circle-open").tolist()
    symbol_2d = np.where(good, "circle", "x").tolist()
    colour = verified["scale_m"].to_numpy(float)
    fig = make_subplots(
        rows=3,
        cols=2,
        column_widths=[0.58, 0.42],
        specs=[[{"type": "scene", "rowspan": 3}, {"type": "xy"}], [None, {}], [None, {}]],
        horizontal_spacing=0.08,
        vertical_spacing=0.09,
    )
    symbols = (symbol_3d, symbol_2d)
    for group, which, visible in (("predicted", 0, True), ("true", 1, "legendonly")):
        _add_values(fig, verified, drawn, texts, (group, which, visible), symbols, colour)
    if selected is not None:
        _add_selected(fig, verified, drawn, texts, selected)
    _lay_out(fig, verified, front, constraints, good, drawn)
    return fig


def _add_values(
    fig: go.Figure,
    verified: pd.DataFrame,
    drawn: Sequence[Objective],
    texts: Sequence[str],
    which: tuple[str, int, bool | str],
    symbols: tuple[list[str], list[str]],
    colour: np.ndarray,
) -> None:
    """The front's designs in 3D and in each pair of objectives: ``which`` is (legend group,
    0 for NSGA-II's predicted values or 1 for the true ones, initial visibility)."""
    group, which, visible = which
    symbol_3d, symbol_2d = symbols
    values = [verified[o.true if which else o.predicted].to_numpy(float) for o in drawn]
    name = "NSGA-II's values" if which == 0 else "true values (physics)"
    common = {
        "mode": "markers",
        "name": name,
        "legendgroup": group,
        "visible": visible,
        "text": texts,
        "hovertemplate": "%{text}<extra></extra>",
    }
    marker = {"color": colour, "coloraxis": "coloraxis"}
    fig.add_trace(
        go.Scatter3d(
            x=values[0],
            y=values[1],
            z=values[2],
            marker={
                **marker,
                "size": 5 if which == 0 else 4,
                "symbol": symbol_3d if which == 0 else "diamond",
                "opacity": 0.9,
            },
            **common,
        ),
        row=1,
        col=1,
    )
    flat = {
        **marker,
        "size": 8 if which == 0 else 7,
        "symbol": symbol_2d if which == 0 else "diamond-open",
        # an outline keeps the colour scale's pale end visible on the light background
        "line": {"width": 1.5} if which == 1 else {"width": 0.6, "color": "#333"},
    }
    for row, (i, j) in enumerate(PAIRS, start=1):
        trace = go.Scatter(x=values[i], y=values[j], showlegend=False, marker=flat, **common)
        fig.add_trace(trace, row=row, col=2)
        fig.update_xaxes(title_text=f"{drawn[i].label}{BETTER}", row=row, col=2)
        fig.update_yaxes(title_text=f"{drawn[j].label}{BETTER}", row=row, col=2)


def _add_selected(
    fig: go.Figure,
    verified: pd.DataFrame,
    drawn: Sequence[Objective],
    texts: Sequence[str],
    selected: int,
) -> None:
    """The realised design (row ``selected``), starred at its true values in every view."""
    values = [verified[o.true].to_numpy(float)[selected] for o in drawn]
    star = {
        "mode": "markers",
        "name": "the realised design (true values)",
        "legendgroup": "selected",
        "text": [texts[selected]],
        "hovertemplate": "%{text}<extra></extra>",
        "marker": {"color": "red", "size": 16, "symbol": "star", "line": {"width": 1}},
    }
    three_d = {**star, "marker": {**star["marker"], "symbol": "diamond", "size": 9}}
    fig.add_trace(go.Scatter3d(x=[values[0]], y=[values[1]], z=[values[2]], **three_d), 1, 1)
    for row, (i, j) in enumerate(PAIRS, start=1):
        fig.add_trace(
            go.Scatter(x=[values[i]], y=[values[j]], showlegend=False, **star), row=row, col=2
        )


def _lay_out(
    fig: go.Figure,
    verified: pd.DataFrame,
    front: str,
    constraints: str,
    good: np.ndarray,
    drawn: Sequence[Objective],
) -> None:
    """The title with the front's counts (designs that hold the task, print, hold their loads,
    have drives, and all four), the 3D scene's axes, the colour axis, legend and the note."""
    labels = [f"{o.label}{BETTER}" for o in drawn]
    n_good, n = int(good.sum()), len(verified)
    held = int(verified["task_contained"].astype(bool).sum())
    printable = int(verified["printable"].astype(bool).sum())
    strong = int(_flag(verified, "holds_loads").sum())
    driven = int(_flag(verified, "has_drives").sum())
    fig.update_layout(
        title={
            "text": (
                f"{front} front: {n} Pareto designs; {held} truly hold the task, {printable} "
                f"printable, {strong} hold their loads, {driven} have drives, {n_good} all four "
                "(crosses, open in 3D: not all)"
                + (f"<br><sup>constraints: {constraints}</sup>" if constraints else "")
            ),
            "font": {"size": 15},
        },
        scene={
            "xaxis_title": labels[0],
            "yaxis_title": labels[1],
            "zaxis_title": labels[2],
            "aspectmode": "cube",
            "camera": {"eye": {"x": 1.8, "y": 1.8, "z": 1.2}},  # the axis titles in view
        },
        coloraxis={
            "colorscale": "Viridis",
            "colorbar": {"title": {"text": COLOUR_TITLE, "side": "right"}, "x": 1.01, "len": 0.9},
        },
        legend={"orientation": "h", "x": 0.0, "y": -0.06, "groupclick": "togglegroup"},
        height=780,
        margin={"l": 30, "r": 110, "t": 80, "b": 90},
        annotations=[
            {
                "text": (
                    "Hover a design for its lengths, predicted and true objectives and checks. "
                    "Rank 1 is the knee: closest to the ideal point of the true objectives "
                    "among the feasible, printable designs. Click the legend to show the true "
                    "values."
                ),
                "xref": "paper",
                "yref": "paper",
                "x": 0.0,
                "y": -0.12,
                "showarrow": False,
                "font": {"size": 11},
                "xanchor": "left",
            }
        ],
    )


def selected_row(verified: pd.DataFrame, design_m: Sequence[float]) -> int | None:
    """Position of the row of ``verified`` whose lengths are ``design_m`` (m), or None."""
    lengths = verified.loc[:, list(DESIGN_COLUMNS)].to_numpy(float)
    hits = np.flatnonzero(np.all(np.isclose(lengths, np.asarray(design_m), rtol=1e-12), axis=1))
    return int(hits[0]) if len(hits) else None


def write_front_html(
    verified: pd.DataFrame,
    front: str,
    path: str | Path,
    constraints: str = "",
    selected: int | None = None,
) -> Path:
    """Write the front as one self-contained HTML page (plotly.js's gl3d bundle inlined, see
    :mod:`qsm.report.plotly_page`; it opens offline and in the single-file report), with the
    realised design marked when ``selected`` gives its row."""
    return write_figure_page(
        front_figure(verified, front, constraints, selected),
        path,
        div_id="pareto-front",
        title=f"The {front} front",
        config={"displaylogo": False, "responsive": True},
    )
