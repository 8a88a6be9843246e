"""The task-motion page (play/pause/scrub over the GIF's frames) and the torque axes' scale."""

import base64
import io
import json
import re

import numpy as np
import pytest
from PIL import Image
from test_exploration import DESIGN, synthetic_series

from qsm.config.settings import physics
from qsm.physics.kinematics import pose
from qsm.physics.task import min_enclosing_circle
from qsm.report.animation import write_task_motion
from qsm.report.motion_page import gif_frames, write_viewer_html

LIMITS_NM = (150.0, 100.0)  # far above the synthetic torques (40 and 20 N m at most)


@pytest.fixture(scope="module")
def motion(tmp_path_factory):
    """A GIF of DESIGN moving through the synthetic series, and what write_task_motion returned."""
    series = synthetic_series(DESIGN)
    ends = series.iloc[[0, -1]][["theta1_deg", "theta2_deg"]].to_numpy(float)
    points = pose(DESIGN, *np.radians(ends).T).E
    op = physics.operating_range({"theta1_deg": [45.0, 180.0], "theta2_min_deg": -37.5})
    gif = tmp_path_factory.mktemp("motion") / "motion.gif"
    result = write_task_motion(
        DESIGN, series, points, min_enclosing_circle(points), op, LIMITS_NM, gif, fps=10
    )
    return gif, result, series


def replayed(page: str) -> list[np.ndarray]:
    """Every frame as the page's script draws it: the tile changes replayed from frame 0."""
    data = json.loads(re.search(r"id='motion-data'>(.*?)</script>", page).group(1))
    png = base64.b64decode(data["atlas"].split(",", 1)[1])
    atlas = np.asarray(Image.open(io.BytesIO(png)).convert("RGB"))
    width, height = (int(re.search(rf"{k}='(\d+)'", page).group(1)) for k in ("width", "height"))
    t = data["tile"]
    canvas = np.zeros((height + t, width + t, 3), np.uint8)
    frames = []
    for changes in data["frames"]:
        for slot, x, y in changes:
            sy, sx = divmod(slot, data["columns"])
            canvas[y : y + t, x : x + t] = atlas[sy * t : sy * t + t, sx * t : sx * t + t]
        frames.append(canvas[:height, :width].copy())
    assert data["frame_ms"] == pytest.approx(100.0)
    return frames


def test_the_page_replays_every_frame_of_the_gif(motion, tmp_path):
    gif, result, _ = motion
    page = write_viewer_html(gif, tmp_path / "motion.html", "a <title>", ["line & more"], 10.0)
    text = page.read_text()
    assert "a &lt;title&gt;" in text and "line &amp; more" in text
    assert "motion-slider" in text and "motion-play" in text
    expected = gif_frames(gif)
    frames = replayed(text)
    assert len(frames) == len(expected) == len(result["frames"]) == 21
    for k, (drawn, frame) in enumerate(zip(frames, expected, strict=True)):
        assert np.array_equal(drawn, frame), k
    assert page.stat().st_size < 1.5 * gif.stat().st_size


def test_the_torque_axes_span_the_torques_not_the_limits(motion):
    """tau1 = 40 sin(t) over 2 s climbs from 0 to 40 N m; in the left half of the torque axes
    (t < 1 s, clear of the legend) it reaches 33.7 N m: about half the axes' height when they
    span the torques (-20 to 40 N m), a tenth when they span the +-150 N m limits."""
    gif, result, _ = motion
    left, top, right, bottom = result["torque_geometry"]["box_px"]
    with Image.open(gif) as im:
        rgb = np.asarray(im.convert("RGB")).astype(int)
    box = rgb[round(top) + 2 : round(bottom) - 2, round(left) + 2 : round((left + right) / 2)]
    blue = np.abs(box - np.array([0x1F, 0x77, 0xB4])).sum(axis=2) < 60  # tab:blue, tau1
    limit_lines = blue.mean(axis=1) > 0.05  # the dotted limits (in view: 10 % of a row)
    rows = np.nonzero(blue.any(axis=1) & ~limit_lines)[0]
    assert (rows.max() - rows.min()) / (bottom - top) > 0.4
    lo, hi = result["torque_geometry"]["ylim"]
    assert lo < -20.0 < 40.0 < hi < 50.0
