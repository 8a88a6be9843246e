"""Many task points: task.points_file, the numpy check of long task.points, and the reduced task
the workflow's stages get (qsm.config.points, qsm.physics.task_points.design_task)."""

import copy
import itertools
import math
import re

import numpy as np
import pytest

from qsm.config.reading import ConfigError, load_config, validate_config
from qsm.physics.mirror import design_points, is_mirrored
from qsm.physics.task_points import MAX_VISITED_POINTS, design_task, visited_points

DEFAULT = [[-0.53, 0.17], [-0.70, 0.02], [-0.60, 0.02], [-0.70, 0.12], [-0.60, 0.12]]
# By hand: the default task's farthest pair (-0.53, 0.17), (-0.70, 0.02) is a diameter of its
# enclosing disk, centre their midpoint, radius half their distance hypot(0.17, 0.15) / 2; the
# other three points lie 0.077, 0.089 and 0.029 m from that centre, inside it.
CENTRE = (-0.615, 0.095)
RADIUS = 0.5 * math.hypot(0.17, 0.15)


def _many(n=10_000, seed=1):
    """The default task's five points, then points strictly inside its disk."""
    rng = np.random.default_rng(seed)
    r = 0.99 * RADIUS * np.sqrt(rng.random(n - 5))
    a = 2 * np.pi * rng.random(n - 5)
    inside = np.c_[CENTRE[0] + r * np.cos(a), CENTRE[1] + r * np.sin(a)]
    return np.vstack([DEFAULT, inside])


def _brute_disk(points):
    """The smallest of the circles through every pair (as diameter) and triple of ``points``
    that holds them all: centre (m) and radius (m)."""
    p = np.asarray(points, dtype=float)
    best = (None, math.inf)
    candidates = []
    for a, b in itertools.combinations(p, 2):
        candidates.append(((a + b) / 2, math.hypot(*(a - b)) / 2))
    for a, b, c in itertools.combinations(p, 3):
        d = 2 * ((a[0] - c[0]) * (b[1] - c[1]) - (b[0] - c[0]) * (a[1] - c[1]))
        if abs(d) < 1e-15:
            continue
        sa, sb = (a - c) @ (a + c), (b - c) @ (b + c)
        centre = (
            np.array(
                [sa * (b[1] - c[1]) - sb * (a[1] - c[1]), sb * (a[0] - c[0]) - sa * (b[0] - c[0])]
            )
            / d
        )
        candidates.append((centre, math.hypot(*(a - centre))))
    for centre, radius in candidates:
        if radius < best[1] and (np.hypot(*(p - centre).T) <= radius * (1 + 1e-12)).all():
            best = (centre, radius)
    return best


def _csv(path, points, header="x_m,y_m"):
    path.write_text(
        header + "\n" + "".join(f"{x!r},{y!r}\n" for x, y in np.asarray(points).tolist())
    )
    return path


def test_the_brute_force_disk_of_the_default_task_is_the_hand_computed_one():
    centre, radius = _brute_disk(DEFAULT)
    assert np.allclose(centre, CENTRE, atol=1e-12) and radius == pytest.approx(RADIUS, rel=1e-12)


@pytest.mark.parametrize("how", ["inline", "file"])
def test_ten_thousand_points_validate_to_the_task_disk_and_the_visited_subset(
    how, tmp_path, monkeypatch
):
    points = _many()
    monkeypatch.chdir(tmp_path)  # points_file is relative to the working directory
    if how == "file":
        _csv(tmp_path / "points.csv", points)
        (tmp_path / "mine.yaml").write_text("task: {points_file: points.csv}\n")
        config = load_config("mine.yaml")
    else:
        config = validate_config({"task": {"points": points.tolist()}})
    assert config["task"]["points"] == points.tolist()
    assert "points_file" not in config["task"]
    mirrored, task = design_task(config["task"]["points"])
    assert not mirrored
    assert len(task) == MAX_VISITED_POINTS
    # the subset the payload test visits of all the points, found on its own
    assert task == points[visited_points(points)].tolist()
    centre, radius = _brute_disk(task)
    assert np.allclose(centre, CENTRE, atol=1e-12) and radius == pytest.approx(RADIUS, rel=1e-12)


@pytest.mark.parametrize("points", [DEFAULT, [[-x, y] for x, y in DEFAULT], DEFAULT[:2]])
def test_a_task_of_few_points_is_designed_on_all_of_them_as_before(points):
    assert design_task(points) == (is_mirrored(points), design_points(points))


def test_a_mirrored_task_of_many_points_gets_the_mirrored_subset():
    points = _many() * [-1, 1]
    mirrored, task = design_task(points)
    assert mirrored
    assert task == (points[visited_points(points)] * [-1, 1]).tolist()


def test_a_points_file_of_the_default_task_is_the_default_config(tmp_path):
    _csv(tmp_path / "p.csv", DEFAULT)
    (tmp_path / "mine.yaml").write_text(f"task: {{points_file: '{tmp_path / 'p.csv'}'}}\n")
    assert load_config("config/config.yaml", tmp_path / "mine.yaml") == load_config()


def test_a_long_points_list_with_a_bad_pair_gets_the_schemas_message():
    points = _many(1000).tolist()
    points[500] = [0.1, "a"]
    with pytest.raises(ConfigError, match=r"config key 'task\.points\.500\.1': 'a' is not of"):
        validate_config({"task": {"points": points}})
    points[500] = [0.1, float("nan")]
    with pytest.raises(ConfigError, match=r"'task\.points': every coordinate must be a finite"):
        validate_config({"task": {"points": points}})


@pytest.mark.parametrize(
    ("text", "message"),
    [
        (None, "file '{f}' cannot be read"),
        ("x,y\n-0.6,0.1\n", "file '{f}': the first line must be the header 'x_m,y_m'"),
        ("x_m,y_m\n", "file '{f}' holds no points below its header"),
        ("x_m,y_m\n-0.6,0.1\n-0.5,abc\n", "file '{f}', line 3: '-0.5,abc' is not two numbers"),
        ("x_m,y_m\n-0.6,0.1,0.0\n", "file '{f}', line 2: '-0.6,0.1,0.0' is not two numbers"),
        ("x_m,y_m\n-0.6,0.1\n-0.5,nan\n", "file '{f}', line 3: every coordinate must be a finite"),
    ],
    ids=["missing", "header", "empty", "not-a-number", "three-cells", "nan"],
)
def test_a_bad_points_file_is_named_with_its_key(tmp_path, text, message):
    path = tmp_path / "pts.csv"
    if text is not None:
        path.write_text(text)
    config = {"task": {"points_file": str(path)}}
    expected = "config key 'task.points_file': " + message.format(f=path)
    with pytest.raises(ConfigError, match=re.escape(expected)):
        validate_config(config)


def test_points_and_points_file_together_are_an_error_naming_both(tmp_path):
    path = _csv(tmp_path / "p.csv", DEFAULT)
    config = {"task": {"points": [[-0.6, 0.1], [-0.5, 0.1]], "points_file": str(path)}}
    with pytest.raises(ConfigError, match=r"'task\.points' and 'task\.points_file' are both given"):
        validate_config(copy.deepcopy(config))
