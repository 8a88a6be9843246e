"""The chosen design in motion: an animated GIF of the payload test (matplotlib + Pillow, Agg).

Left: the design drawn as the report's linkage figures (:func:`qsm.report.figures.draw_workspace`
and :func:`~qsm.report.figures.linkage_segments`) at the *simulated* motor angles of the payload
test, with its workspace, the task disk, the task points and the path of the end effector E so
far; E is a magenta square. Right: both motors' requested torques over the whole test (the axis
scaled to them, the limits dotted when in range) and a cursor at the frame's time, and bars of
|tau| / limit at that time. :mod:`qsm.report.motion_page` makes the GIF a page to pause and scrub.

The frames sample the payload test's time series (``payload_test_series.parquet``) every
``1 / fps`` seconds from its first to its last sample, so the first frame shows the start pose
and the last the end pose; the GIF plays in real time. :func:`motion_frames` gives the samples,
:func:`write_task_motion` the GIF and, for checks, where each frame's axes lie in pixels.
"""

from __future__ import annotations

import io
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from matplotlib.animation import AbstractMovieWriter
from matplotlib.axes import Axes
from numpy.typing import ArrayLike, NDArray
from PIL import Image

from qsm.physics.kinematics import LoopPose, as_design, pose
from qsm.physics.task import Disk
from qsm.physics.workspace import OperatingRange
from qsm.report.figures import draw_workspace, linkage_segments

#: Frames per second of the GIF (it plays in real time).
FRAME_RATE_HZ = 10.0
#: Colour of the end-effector marker (unused elsewhere in the figure, so a frame can be checked).
EE_COLOUR = "#ff00ff"
FIGSIZE_IN = (10.0, 4.5)  # 720 x 324 pixels at DPI
DPI = 72
#: Figure boxes (left, bottom, width, height) of the linkage, torque and torque-level axes.
AXES_BOXES = ((0.06, 0.11, 0.40, 0.78), (0.56, 0.40, 0.42, 0.45), (0.56, 0.11, 0.42, 0.15))


class PaletteGifWriter(AbstractMovieWriter):
    """A matplotlib movie writer of GIFs through Pillow, every frame in the first frame's palette.

    Like matplotlib's ``PillowWriter``, but the frames share one palette without dithering
    (quantising each frame on its own was half the run time, and a shared palette keeps the
    colours exact between frames).
    """

    @classmethod
    def isAvailable(cls) -> bool:
        """Pillow is a dependency of matplotlib."""
        return True

    def setup(self, fig: plt.Figure, outfile: str | Path, dpi: float | None = None) -> None:
        """Start a GIF of ``fig`` at ``dpi``."""
        super().setup(fig, outfile, dpi=dpi)
        self._images: list[Image.Image] = []

    def grab_frame(self, **savefig_kwargs: Any) -> None:
        """Draw the figure and keep it as the next frame."""
        buffer = io.BytesIO()
        self.fig.savefig(buffer, **{**savefig_kwargs, "format": "rgba", "dpi": self.dpi})
        rgb = Image.frombuffer("RGBA", self.frame_size, buffer.getbuffer()).convert("RGB")
        if self._images:
            frame = rgb.quantize(palette=self._images[0], dither=Image.Dither.NONE)
        else:
            frame = rgb.quantize(colors=256, method=Image.Quantize.MEDIANCUT)
        self._images.append(frame)

    def finish(self) -> None:
        """Write every frame, ``1 / fps`` seconds each, looping."""
        first, *rest = self._images
        first.save(
            self.outfile, save_all=True, append_images=rest, duration=1000 / self.fps, loop=0
        )


def motion_frames(series: pd.DataFrame, fps: float = FRAME_RATE_HZ) -> pd.DataFrame:
    """The rows of a payload-test series (:data:`qsm.report.payload_report.SERIES_COLUMNS`) shown
    as frames: the samples nearest to ``round(duration * fps) + 1`` evenly spaced times from the
    first to the last sample (both included), with the series' row as ``sample``."""
    t = series["t_s"].to_numpy(float)
    if len(t) < 2 or not np.all(np.diff(t) > 0):
        raise ValueError("a payload-test series needs at least two samples in time order")
    n = round((t[-1] - t[0]) * fps) + 1
    wanted = np.linspace(t[0], t[-1], max(n, 2))
    idx = np.clip(np.searchsorted(t, wanted), 1, len(t) - 1)
    idx -= (wanted - t[idx - 1]) < (t[idx] - wanted)  # the nearer neighbour
    frames = series.iloc[idx].reset_index(drop=True)
    frames.insert(0, "sample", idx)
    return frames


def _write_gif(fig: Any, draw: Callable[[int], None], n: int, out: Path, fps: float) -> None:
    """Draw frames 0..n-1 of ``fig`` with ``draw`` into the GIF ``out``."""
    out.parent.mkdir(parents=True, exist_ok=True)
    writer = PaletteGifWriter(fps=fps)
    with writer.saving(fig, out, DPI):
        for k in range(n):
            draw(k)
            writer.grab_frame()


def _over_background(background: np.ndarray, drawn: Sequence[Any]) -> tuple[Any, list[Any]]:
    """A figure showing the still ``background`` image (RGBA), with transparent twins of the
    ``drawn`` axes at their positions and limits, for the moving artists."""
    fig = plt.figure(figsize=FIGSIZE_IN, dpi=DPI)
    fig.figimage(background, origin="upper")
    live = []
    for source in drawn:
        twin = fig.add_axes(source.get_position())
        twin.set_xlim(source.get_xlim())
        twin.set_ylim(source.get_ylim())
        twin.set_axis_off()
        twin.set_zorder(2)  # above the background, which the figure draws after its axes
        live.append(twin)
    return fig, live


def write_task_motion(
    design: ArrayLike,
    series: pd.DataFrame,
    points: ArrayLike,
    disk: Disk,
    op: OperatingRange,
    limits_Nm: Sequence[float],
    path: str | Path,
    fps: float = FRAME_RATE_HZ,
    title: str = "",
    mirrored: bool = False,
) -> dict[str, Any]:
    """Write the GIF of ``design`` (6 lengths, m) moving through the payload-test ``series``.

    ``points`` (n, 2) m are the task points, ``disk`` the task disk, ``op`` the operating range,
    ``limits_Nm`` the two motor torque limits. Returns ``frames`` (the :func:`motion_frames`
    table), ``fps`` and ``geometry``: the linkage axes' data limits and their box in image pixels
    (``left, top, right, bottom``, origin at the top left), the same for every frame; and
    ``torque_geometry``, the same for the torque axes (scaled to the torques,
    :func:`torque_range`).
    ``mirrored``: the design is of a task's mirror image (:mod:`qsm.physics.mirror`); the linkage
    is drawn on the user's side, x reversed and its tick labels negated.

    Everything that does not move (workspace, task, torque curves, axes and labels) is drawn once
    into a background image; each frame draws only the moving artists over it and is grabbed by
    :class:`PaletteGifWriter`.
    """
    d = as_design(design)
    frames = motion_frames(series, fps)
    th = np.radians(frames[["theta1_deg", "theta2_deg"]].to_numpy(float))
    poses = pose(d, th[:, 0], th[:, 1])
    t = series["t_s"].to_numpy(float)
    tau = series[["tau1_requested_Nm", "tau2_requested_Nm"]].to_numpy(float)
    limits = np.asarray(limits_Nm, dtype=float)
    pts = np.asarray(points, dtype=float).reshape(-1, 2)
    colours = ("tab:blue", "tab:orange")

    still = plt.figure(figsize=FIGSIZE_IN, dpi=DPI)
    drawn = [still.add_axes(box) for box in AXES_BOXES]
    _draw_scene(drawn[0], d, poses, pts, disk, op, title, mirrored)
    _draw_torques(drawn[1], drawn[2], t, tau, limits, colours)
    still.canvas.draw()
    background = np.asarray(still.canvas.buffer_rgba()).copy()

    fig, live = _over_background(background, drawn)
    plt.close(still)
    ax, ax_tau, _ = live
    draw = _frame_drawer(fig, live, d, th, poses, tau, frames, limits, colours, t[0])
    _write_gif(fig, draw, len(frames), Path(path), fps)
    geometry = _axes_geometry(fig, ax)
    torque_geometry = _axes_geometry(fig, ax_tau)
    plt.close(fig)
    return {
        "frames": frames,
        "fps": fps,
        "geometry": geometry,
        "torque_geometry": torque_geometry,
    }


def _frame_drawer(
    fig: plt.Figure,
    live: Sequence[Axes],
    d: NDArray[np.float64],
    th: NDArray[np.float64],
    poses: LoopPose,
    tau: NDArray[np.float64],
    frames: pd.DataFrame,
    limits: NDArray[np.float64],
    colours: Sequence[str],
    t0: float,
) -> Callable[[int], None]:
    """The moving artists on the ``live`` axes (linkage, torques, bars) and a function that sets
    them to frame ``k``: the pose at motor angles ``th[k]`` (rad), the trail of the end
    effector, the torques (N m) at the frame's sample and the clock (the cursor starts at
    ``t0`` s)."""
    ax, ax_tau, ax_bar = live
    start = pose(d, th[0, 0], th[0, 1])
    bars = [ax.plot([], [], style, lw=2.5)[0] for *_, style in linkage_segments(start)]
    (joints,) = ax.plot([], [], "o", color="k", ms=4)
    (trail,) = ax.plot([], [], "-", color="tab:orange", lw=1)
    (tip,) = ax.plot([], [], "s", color=EE_COLOUR, ms=7, mec=EE_COLOUR)
    dots = [ax_tau.plot([], [], "o", color=c, ms=6)[0] for c in colours]
    cursor = ax_tau.axvline(t0, color="k", lw=0.8)
    level = ax_bar.barh([1, 0], [0, 0], color=colours, height=0.6)
    clock = fig.text(0.56, 0.95, "", fontsize=9)

    def draw(k: int) -> None:
        p = pose(d, th[k, 0], th[k, 1])
        for line, (a, b, _) in zip(bars, linkage_segments(p), strict=True):
            line.set_data([a[0], b[0]], [a[1], b[1]])
        joints.set_data([0.0, p.B[0], p.C[0], p.D[0]], [0.0, p.B[1], p.C[1], p.D[1]])
        trail.set_data(poses.E[: k + 1, 0], poses.E[: k + 1, 1])
        tip.set_data([p.E[0]], [p.E[1]])
        now = tau[frames["sample"].iat[k]]
        tk = frames["t_s"].iat[k]
        cursor.set_xdata([tk, tk])
        for j, dot in enumerate(dots):
            dot.set_data([tk], [now[j]])
        for j, rect in enumerate(level):
            rect.set_width(100 * abs(now[j]) / limits[j])
        clock.set_text(
            f"t = {tk:5.2f} s   tau1 {now[0]:7.1f} / {limits[0]:g} N m   "
            f"tau2 {now[1]:7.1f} / {limits[1]:g} N m"
        )

    return draw


def _draw_scene(
    ax: Axes,
    d: NDArray[np.float64],
    poses: LoopPose,
    pts: NDArray[np.float64],
    disk: Disk,
    op: OperatingRange,
    title: str,
    mirrored: bool,
) -> None:
    """The still part of the linkage axes: workspace, task disk and points, base, the view that
    holds the whole motion; x reversed for a mirrored design."""
    draw_workspace(ax, d, op, 80)
    ax.add_patch(plt.Circle(disk.centre, disk.radius, fill=False, color="tab:red", lw=1.2))
    ax.plot(pts[:, 0], pts[:, 1], "x", color="tab:red", ms=7, mew=2)
    ax.plot(0.0, 0.0, "^", color="k", ms=7)
    _fit_view(ax, poses, pts, disk, d, op)
    ax.set_aspect("equal")
    ax.grid(alpha=0.3)
    ax.set_xlabel("x (m)")
    if mirrored:
        ax.invert_xaxis()
        ax.xaxis.set_major_formatter(lambda v, _: f"{-v + 0.0:g}")
    ax.set_ylabel("y (m)")
    ax.set_title(title, fontsize=9)


def _draw_torques(
    ax_tau: Axes,
    ax_bar: Axes,
    t: NDArray[np.float64],
    tau: NDArray[np.float64],
    limits: NDArray[np.float64],
    colours: Sequence[str],
) -> None:
    """The still part of the torque axes (requested torques (N m) against time (s), the limits
    dotted) and of the bars of |tau| / limit (%)."""
    for j, c in enumerate(colours):
        ax_tau.plot(t, tau[:, j], color=c, lw=1, label=f"tau{j + 1} requested")
        for sign in (1, -1):
            ax_tau.axhline(sign * limits[j], color=c, ls=":", lw=1)
    ax_tau.set_xlim(t[0], t[-1])
    ax_tau.set_ylim(*torque_range(tau))
    ax_tau.set_xlabel("time (s)", labelpad=1)
    ax_tau.set_ylabel("torque (N m)")
    ax_tau.set_title(
        f"motor torques; limits ±{limits[0]:.1f} / ±{limits[1]:.1f} N m (dotted when in range)",
        fontsize=9,
    )
    ax_tau.legend(fontsize=7, loc="upper right")
    ax_tau.grid(alpha=0.3)
    ax_bar.axvline(100.0, color="tab:red", lw=1.5)
    ax_bar.set_xlim(0, max(110.0, 105 * float((np.abs(tau) / limits).max())))
    ax_bar.set_ylim(-0.6, 1.6)
    ax_bar.set_yticks([1, 0], ["motor 1", "motor 2"], fontsize=8)
    ax_bar.set_xlabel("|tau| / limit (%)", labelpad=1)


def torque_range(tau_Nm: NDArray) -> tuple[float, float]:
    """Torque-axis limits (N m) scaled to the torques drawn: their span and zero, 8 % margin."""
    lo, hi = min(float(tau_Nm.min()), 0.0), max(float(tau_Nm.max()), 0.0)
    pad = 0.08 * max(hi - lo, 1e-9)
    return lo - pad, hi + pad


def _fit_view(
    ax: plt.Axes, poses: LoopPose, pts: NDArray, disk: Disk, d: NDArray, op: OperatingRange
) -> None:
    """Limits holding the base, every drawn pose, the task and the whole workspace."""
    g1, g2 = np.meshgrid(
        np.linspace(op.theta1_min, op.theta1_max, 40), np.linspace(op.theta2_min, op.theta1_max, 40)
    )
    reach = pose(d, g1.ravel(), np.minimum(g1, g2).ravel()).E
    xy = np.vstack([np.zeros((1, 2)), poses.B, poses.C, poses.D, poses.E, pts, reach])
    lo = np.minimum(xy.min(axis=0), np.asarray(disk.centre) - disk.radius)
    hi = np.maximum(xy.max(axis=0), np.asarray(disk.centre) + disk.radius)
    pad = 0.05 * float(d[0])
    ax.set_xlim(lo[0] - pad, hi[0] + pad)
    ax.set_ylim(lo[1] - pad, hi[1] + pad)


def _axes_geometry(fig: plt.Figure, ax: plt.Axes) -> dict[str, Any]:
    """Data limits and pixel box (image coordinates) of ``ax`` as the frames were drawn."""
    fig.canvas.draw()
    box = ax.get_window_extent()
    height = fig.get_figheight() * fig.dpi
    return {
        "xlim": [float(v) for v in ax.get_xlim()],
        "ylim": [float(v) for v in ax.get_ylim()],
        "box_px": [float(box.x0), float(height - box.y1), float(box.x1), float(height - box.y0)],
        "size_px": [round(fig.get_figwidth() * fig.dpi), round(height)],
    }


def frames_record(result: Mapping[str, Any], design: ArrayLike) -> dict[str, Any]:
    """JSON-friendly record of a :func:`write_task_motion` result: the frames' sample rows,
    times (s), motor angles (deg) and end-effector positions (m), fps and geometry."""
    frames = result["frames"]
    th = np.radians(frames[["theta1_deg", "theta2_deg"]].to_numpy(float))
    e = pose(as_design(design), th[:, 0], th[:, 1]).E
    return {
        "n_frames": len(frames),
        "fps": result["fps"],
        "sample": frames["sample"].astype(int).tolist(),
        "t_s": frames["t_s"].tolist(),
        "theta_deg": frames[["theta1_deg", "theta2_deg"]].to_numpy(float).tolist(),
        "ee_m": e.tolist(),
        "geometry": result["geometry"],
    }
