"""Checks across keys and unit slips (qsm.config.checks): each names the key and the cause."""

import copy
import csv
import io
import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import yaml

from qsm.config.checks import config_warnings, first_mode_bound_hz, largest_reach
from qsm.config.reading import ConfigError, load_config, merge_config, validate_config
from qsm.embodiment.stiffness.frame import FrameSections
from qsm.embodiment.stiffness.modes import loaded_first_mode_hz
from qsm.physics.kinematics import end_effector

ROOT = Path(__file__).resolve().parents[1]

# (config, the key named, the value or cause the message must also hold)
ERRORS = [
    (
        {"optimization": {"bounds": {"l2_m": [0.3, 0.1]}}},
        "optimization.bounds.l2_m",
        "min 0.3 is not below max 0.1",
    ),
    (
        {"optimization": {"bounds": {"l2_m": [0.0, 0.1]}}},
        "optimization.bounds.l2_m",
        "min 0.0 is not positive",
    ),
    (
        {"optimization": {"bounds": {"l1_m": [-0.3, 0.5]}}},
        "optimization.bounds.l1_m",
        "min -0.3 is not positive",
    ),
    (
        {"optimization": {"bounds": {"l1_m": [300, 500]}}},
        "optimization.bounds.l1_m",
        "looks like millimetres",
    ),
    (
        {"optimization": {"bounds": {"ee_x_m": [5.0, 6.0]}}},
        "optimization.bounds.ee_x_m",
        "would only extrapolate",
    ),
    ({"sampling": {"bounds": {"l2": [0.0, 0.6]}}}, "sampling.bounds.l2", "min 0.0 is not positive"),
    (
        {"sampling": {"bounds": {"ee_y": [-0.2, 0.7]}}},
        "sampling.bounds.ee_y",
        "min -0.2 is not positive",
    ),
    (
        {"sampling": {"bounds": {"l2": [0.5, 0.6], "l3": [1.2, 1.3]}}},
        "sampling.bounds",
        "no sample can be a crank-rocker",
    ),
    (
        {"operating_range": {"theta2_min_deg": 45}},
        "operating_range.theta2_min_deg",
        "must be below theta1's minimum 45",
    ),
    (
        {"operating_range": {"theta2_min_deg": 90}},
        "operating_range.theta2_min_deg",
        "range would be empty",
    ),
    (
        {"operating_range": {"theta1_deg": [-200, 200]}},
        "operating_range.theta1_deg",
        "more than a turn",
    ),
    (
        {"operating_range": {"theta1_deg": [0.785, 3.1416], "theta2_min_deg": -0.654}},
        "operating_range.theta1_deg",
        "looks like radians",
    ),
    ({"operating_range": {"theta1_deg": [45, 46]}}, "operating_range.theta1_deg", "spans 1 deg"),
    (
        {"task": {"payload_kg": 5000}},
        "task.payload_kg",
        "looks like grams: task.payload_kg is in kilograms",
    ),
    (
        {"task": {"payload_kg": 300}, "payload_test": {"torque_limits_Nm": [150, 100]}},
        "task.payload_kg",
        "at most 36.4 kg",
    ),
    (
        {"task": {"payload_kg": 40}, "payload_test": {"torque_limits_Nm": [150, 100]}},
        "task.payload_kg",
        "150 + 100 N m (payload_test.torque_limits_Nm)",
    ),
    # without the override: twice the strongest drive of the shipped catalogue, the Harmonic
    # Drive CSF-32-100 at 333 N m repeated peak: 666 / (9.81 x 0.70) = 97.0 kg
    ({"task": {"payload_kg": 120}}, "task.payload_kg", "at most 97 kg"),
    ({"task": {"payload_kg": 120}}, "task.payload_kg", "strongest drive of drives.catalogue"),
    (
        {"task": {"payload_kg": 2000}, "payload_test": {"torque_limits_Nm": [1e5, 1e5]}},
        "task.payload_kg",
        "material.yield_strength_pa",
    ),
    (
        {"printing": {"build_volume_mm": [0.6, 0.35, 0.35]}},
        "printing.build_volume_mm",
        "looks like metres",
    ),
    (
        {"printing": {"build_volume_mm": [600, 350, 5]}},
        "printing.build_volume_mm",
        "a side below 10 mm",
    ),
    ({"printing": {"build_volume_mm": [100, 100, 15]}}, "printing.build_volume_mm", "fits no link"),
    (
        {"task": {"points": [[-530, 170], [-700, 20], [-600, 20]]}},
        "task.points",
        "looks like millimetres: task.points are in metres",
    ),
    ({"task": {"points": [[-6.0, 0.0], [-5.8, 0.1]]}}, "scale.max_m", "must be at least 2.34 m"),
    ({"scale": {"max_m": 0.05}}, "scale.max_m", "0.05 m is too small for the task"),
    ({"scale": {"safety_margin_m": 10.0}}, "scale.max_m", "scale.safety_margin_m 10.0 m"),
    (
        {"cad": {"width_m": 40, "thickness_m": 20, "boss_radius_m": 25}},
        "cad.boss_radius_m",
        "looks like millimetres",
    ),
    ({"material": {"density_kg_m3": 1.04}}, "material.density_kg_m3", "looks like g/cm^3"),
    ({"material": {"youngs_modulus_pa": 2.2}}, "material.youngs_modulus_pa", "looks like GPa"),
    ({"material": {"yield_strength_pa": 31}}, "material.yield_strength_pa", "looks like MPa"),
    (
        {"optimization": {"objectives": "drive_mass", "constraints": {"drives": False}}},
        "optimization.objectives",
        "set optimization.constraints.drives: true",
    ),
    ({"task": {"points": [[0.0, 0.0], [-0.3, 0.1]]}}, "task.points", "covers the base joint"),
    ({"task": {"points": [[-0.1, 0.0], [0.1, 0.05]]}}, "task.points", "covers the base joint"),
    ({"task": {"points": [[-0.05, 0.0], [-0.6, 0.0]]}}, "task.points", "a ratio of 12; no design"),
    (
        {"task": {"points": [[-0.15, 0.0], [-0.35, 0.0]]}, "scale": {"safety_margin_m": 0.12}},
        "task.points",
        "grown by scale.safety_margin_m 0.12 m",
    ),
    ({"sampling": {"n_mechanisms": 1}}, "sampling.n_mechanisms", "1 is too few"),
    ({"sampling": {"n_mechanisms": 4}}, "sampling.n_mechanisms", "at least 6"),
    (
        {"sampling": {"n_mechanisms": 10}, "surrogate": {"test_fraction": 0.05}},
        "sampling.n_mechanisms",
        "at least 21",
    ),
    ({"operating_range": {"theta1_deg": [45, 400]}}, "operating_range.theta1_deg", "400 deg"),
    (
        {"operating_range": {"theta1_deg": [-365, -100]}},
        "operating_range.theta1_deg",
        "-365 deg is past a full turn",
    ),
    ({"task": {"cycle": {"order": [1, 9]}}}, "task.cycle.order", "[9] are not among the 5"),
    ({"task": {"cycle": {"order": [1, 2, 2]}}}, "task.cycle.order", "point 2 follows itself"),
    ({"task": {"cycle": {"order": [0, 2]}}}, "task.cycle.order.0", "less than the minimum of 1"),
    ({"task": {"cycle": {"dwell_s": -1}}}, "task.cycle.dwell_s", "less than the minimum of 0"),
    (
        {"task": {"min_first_mode_hz": 10000}},
        "task.min_first_mode_hz",
        "10000 Hz is more than any arm of this task can reach",
    ),
]


@pytest.mark.parametrize(("config", "key", "cause"), ERRORS)
def test_error_names_key_and_cause(config, key, cause):
    with pytest.raises(ConfigError) as info:
        validate_config(copy.deepcopy(config))
    assert f"config key '{key}'" in str(info.value)
    assert cause in str(info.value)


def test_a_bad_drive_catalogue_fails_at_config_time_naming_file_line_column(tmp_path):
    from qsm.embodiment.drives.catalogue import default_catalogue_folder

    folder = tmp_path / "cat"
    folder.mkdir()
    for f in default_catalogue_folder().glob("*.csv"):
        (folder / f.name).write_text(f.read_text())
    gearboxes = folder / "gearboxes.csv"
    lines = gearboxes.read_text().splitlines()
    row = next(i for i, line in enumerate(lines) if line.startswith("MM_203113,"))
    lines[row] = lines[row].replace(",1,3.5,", ",1,-3.5,")  # a negative ratio
    gearboxes.write_text("\n".join(lines) + "\n")
    with pytest.raises(ConfigError) as info:
        validate_config({"drives": {"catalogue": str(folder)}})
    msg = str(info.value)
    assert "config key 'drives.catalogue'" in msg
    assert f"gearboxes.csv, line {row + 1}, column 'ratio'" in msg
    validate_config({"drives": {"catalogue": str(default_catalogue_folder())}})


@pytest.mark.parametrize(
    ("old", "new", "cause"),
    [
        (",6,M4,71,", ",6,M7,71,", "column 'flange_thread': 'M7' is not in ISO 4762's table"),
        ("TM_AK80-6_GB,flange,", "TM_AK80-6_GB,spline,", "'shaft' or 'flange', got 'spline'"),
        (",85,8,M3,", ",85,4.7,M3,", "column 'mount_bolts': a whole number of bolts, got '4.7'"),
        ("SO_EG17-G50,shaft,", "SO_EG17-G5O,shaft,", "key 'SO_EG17-G5O' is no gearbox"),
        ("SO_EG17-G50,shaft,", "TM_AK80-6_GB,shaft,", "key 'TM_AK80-6_GB' has a row above"),
    ],
)
def test_a_bad_interface_row_fails_at_config_time(tmp_path, old, new, cause):
    """interfaces.csv is checked before the run: a thread the kit has no screw for, an output
    of neither kind, a fraction of a bolt, a key of no gearbox and a key given twice."""
    from qsm.embodiment.drives.catalogue import default_catalogue_folder

    folder = tmp_path / "cat"
    folder.mkdir()
    for f in default_catalogue_folder().glob("*.csv"):
        (folder / f.name).write_text(f.read_text())
    interfaces = folder / "interfaces.csv"
    assert old in interfaces.read_text()
    interfaces.write_text(interfaces.read_text().replace(old, new, 1))
    with pytest.raises(ConfigError) as info:
        validate_config({"drives": {"catalogue": str(folder)}})
    assert "config key 'drives.catalogue'" in str(info.value)
    assert "interfaces.csv" in str(info.value) and cause in str(info.value)


def test_an_interface_table_in_a_subfolder_is_found_and_checked(tmp_path):
    """interfaces.csv is found wherever the other tables are: in a subfolder its rows are read
    and checked; a key given in two interface files is refused, naming the second."""
    from qsm.embodiment.drives.catalogue import default_catalogue_folder
    from qsm.embodiment.kit.interfaces import read_interfaces

    folder = tmp_path / "cat"
    (folder / "kit").mkdir(parents=True)
    for f in default_catalogue_folder().glob("*.csv"):
        target = folder / "kit" / f.name if f.name == "interfaces.csv" else folder / f.name
        target.write_text(f.read_text())
    shipped = read_interfaces(default_catalogue_folder())
    assert read_interfaces(folder) == shipped and shipped  # found one level down
    moved = folder / "kit" / "interfaces.csv"
    moved.write_text(moved.read_text().replace(",6,M4,71,", ",6,M7,71,", 1))
    with pytest.raises(ConfigError, match=r"kit/interfaces\.csv, line \d+, column 'flange_thread'"):
        validate_config({"drives": {"catalogue": str(folder)}})
    moved.write_text((default_catalogue_folder() / "interfaces.csv").read_text())
    (folder / "more_interfaces.csv").write_text(moved.read_text())
    with pytest.raises(ConfigError, match="has a row above already"):
        validate_config({"drives": {"catalogue": str(folder)}})


def test_the_smallest_dataset_splits_into_two_designs_each_side():
    """scikit-learn's split of the smallest count gives two designs to test and two to train
    on, and one fewer does not (the rule behind sampling.n_mechanisms' minimum)."""
    from sklearn.model_selection import train_test_split

    from qsm.config.checks import smallest_dataset

    for fraction in (0.05, 0.2, 0.5, 0.9):
        n = smallest_dataset(fraction)
        train, test = train_test_split(np.arange(n), test_size=fraction, random_state=0)
        assert min(len(train), len(test)) == 2
        train, test = train_test_split(np.arange(n - 1), test_size=fraction, random_state=0)
        assert min(len(train), len(test)) < 2


def test_the_reach_ratio_bounds_every_design_of_the_ranges():
    """A brute-force search over the sampled ranges: designs that are crank-rockers and close
    their loop over the operating range (what Stage 1 keeps), their end effector's nearest and
    farthest distance from the base over 2001 poses. The nearest stays above the folded-arm
    bound hypot(ee_x - 1, ee_y), the ratio of farthest to nearest below reach_ratio_bound, which
    the search comes within 15 % of (the supremum lies where l2 + l3 = 1 + l4)."""
    from qsm.config.checks import folded_arm_applies, reach_ratio_bound
    from qsm.mechanisms.filters import crank_rocker
    from qsm.physics.kinematics import loop_closes_everywhere
    from qsm.physics.workspace import OperatingRange, arcs

    config = load_config()
    bounds = config["sampling"]["bounds"]
    op = OperatingRange.from_degrees(config["operating_range"]["theta1_deg"], -37.5)
    rng = np.random.default_rng(1)
    lo = np.array([bounds[k][0] for k in ("l2", "l3", "l4", "ee_x", "ee_y")])
    hi = np.array([bounds[k][1] for k in ("l2", "l3", "l4", "ee_x", "ee_y")])
    u = rng.random((20000, 5))
    u[:10000, 3:] **= 6  # half of them near the smallest ee_x and ee_y, where the ratio peaks
    ratios = lo + u * (hi - lo)
    ratios = ratios[crank_rocker(ratios) & loop_closes_everywhere(ratios, op.delta_max)]
    rho, _, _ = arcs(ratios, op, 2001)
    near, far = rho.min(axis=1), rho.max(axis=1)
    assert folded_arm_applies(bounds)
    assert (near > np.hypot(ratios[:, 3] - 1, ratios[:, 4])).all()
    bound = reach_ratio_bound(bounds)
    assert (far / near).max() <= bound
    assert (far / near).max() > 0.85 * bound


def test_a_task_just_inside_the_reach_ratio_is_accepted():
    from qsm.config.checks import reach_ratio_bound

    ratio = reach_ratio_bound(load_config()["sampling"]["bounds"])
    near = 0.6 / (0.99 * ratio)  # a disk on the x axis from near to 0.6 m
    validate_config({"task": {"points": [[-near, 0.0], [-0.6, 0.0]]}})


def test_a_task_near_the_base_needs_a_small_scale_only():
    near = {"scale": {"max_m": 0.3}, "task": {"points": [[-0.2, 0.05], [-0.15, 0.05]]}}
    validate_config(near)


def test_largest_reach_bounds_every_end_effector():
    """1 + hypot(ee_x, ee_y) is never exceeded by a design of the ranges in any pose."""
    bounds = load_config()["sampling"]["bounds"]
    rng = np.random.default_rng(0)
    ratios = np.column_stack([rng.uniform(*bounds[k], 2000) for k in bounds])
    design = np.column_stack([np.ones(2000), ratios])
    theta = rng.uniform(-np.pi, np.pi, (2, 2000))
    e = end_effector(design, *theta)
    ok = np.isfinite(e).all(axis=-1)
    assert ok.mean() > 0.5
    reach = np.hypot(*e[ok].T)
    assert reach.max() <= largest_reach(bounds)
    assert reach.max() > 0.95 * largest_reach(bounds)  # and it is nearly reached


def test_integers_written_as_floats_are_taken_as_integers():
    c = validate_config(
        {
            "sampling": {"n_samples": 30000.0, "n_mechanisms": 2.0e3},
            "surrogate": {"hidden_layers": [100.0]},
        }
    )
    assert c["sampling"]["n_samples"] == 30000 and type(c["sampling"]["n_samples"]) is int
    assert type(c["sampling"]["n_mechanisms"]) is int
    assert (
        c["surrogate"]["hidden_layers"] == [100] and type(c["surrogate"]["hidden_layers"][0]) is int
    )
    assert type(c["task"]["payload_kg"]) is float  # numbers stay numbers
    with pytest.raises(ConfigError, match=r"'sampling\.n_samples': 30000\.5 is not of type"):
        validate_config({"sampling": {"n_samples": 30000.5}})


def test_integers_from_yaml(tmp_path):
    path = tmp_path / "floats.yaml"
    path.write_text("sampling: {n_samples: 2.0e+5, n_mechanisms: 11080.0}\n")
    c = load_config(path)
    assert (c["sampling"]["n_samples"], c["sampling"]["n_mechanisms"]) == (200000, 11080)
    assert type(c["sampling"]["n_samples"]) is int


@pytest.mark.parametrize(
    ("text", "where"),
    [
        ("task:\n\tpayload_kg: 5\n", "line 2, column 1"),
        ("task:\n  points: [[1, 2]\n  payload_kg: 5\n", "line 3, column 3"),
        ("task:\n  payload_kg: 5\n sampling: 3\n", "line 3, column 2"),
    ],
    ids=["tab", "unclosed", "indent"],
)
def test_yaml_errors_name_file_line_and_column(tmp_path, text, where):
    path = tmp_path / "mine.yaml"
    path.write_text(text)
    with pytest.raises(ConfigError) as info:
        load_config(path)
    assert f"config file '{path}', {where}: not valid YAML" in str(info.value)


def test_files_merge_as_snakemake_merges_them(tmp_path):
    a, b = tmp_path / "a.yaml", tmp_path / "b.yaml"
    a.write_text("task: {payload_kg: 2.0}\nsampling: {n_samples: 5000, n_mechanisms: 100}\n")
    b.write_text("sampling: {n_samples: 6000}\n")
    c = load_config(a, b)
    assert (c["task"]["payload_kg"], c["sampling"]["n_samples"]) == (2.0, 6000)
    assert c["sampling"]["n_mechanisms"] == 100
    assert merge_config({"x": {"y": 1}}, {"x": [2]}) == {"x": [2]}


def test_defaults_have_no_warnings():
    assert config_warnings(load_config()) == []


def test_many_points_warn_that_a_subset_is_visited():
    pts = np.random.default_rng(0).normal(size=(10_000, 2)) * 0.05 + [-0.6, 0.1]
    (warning,) = config_warnings(validate_config({"task": {"points": pts.tolist()}}))
    assert "config key 'task.points': 10000 points" in warning
    assert "visit 8 of them" in warning


def test_points_at_positive_x_warn_that_the_task_is_mirrored():
    (warning,) = config_warnings(validate_config({"task": {"points": [[0.3, 0.1], [0.4, 0.1]]}}))
    assert "config key 'task.points': the task's enclosing disk has its centre at" in warning
    assert "designed as its mirror image" in warning


@pytest.mark.parametrize(("xs", "side"), [((-0.1, 0.5), "x > 0"), ((-0.5, 0.1), "x <= 0")])
def test_a_task_on_both_sides_is_designed_on_its_centre_side(xs, side):
    cfg = validate_config({"task": {"points": [[xs[0], 0.5], [xs[1], 0.5]]}})
    warnings = config_warnings(cfg)
    assert any(
        f"designed on the side of its enclosing disk's centre ({side})" in w for w in warnings
    )
    assert any("mirror image" in w for w in warnings) == (side == "x > 0")


def test_check_config_command(tmp_path, capsys):
    from qsm.app.cli import main

    mine = tmp_path / "mine.yaml"
    mine.write_text("task: {points: [[0.3, 0.1], [0.4, 0.1]]}\n")
    assert main(["check-config", "config/config.yaml", str(mine)]) == 0
    assert "designed as its mirror image" in capsys.readouterr().out
    mine.write_text("task:\n\tpayload_kg: 5\n")
    assert main(["check-config", str(mine)]) == 2
    assert f"config file '{mine}', line 2, column 1" in capsys.readouterr().err
    mine.write_text("task: {payload_kg: 5000}\n")
    assert main(["check-config", str(mine)]) == 2
    assert "looks like grams" in capsys.readouterr().err


@pytest.mark.workflow  # starts Snakemake
@pytest.mark.parametrize(
    ("text", "where"),
    [
        ("task:\n\tpayload_kg: 5\n", "line 2, column 1: not valid YAML"),
        ("task:\n  payload_kg: 5\n   points: [[-0.6, 0.1]]\n", "line 3, column 10: not valid"),
    ],
)
def test_snakemake_names_file_line_and_column_of_a_yaml_error(tmp_path, text, where):
    """Through the workflow profile (profiles/default), before Snakemake's own message."""
    bad = tmp_path / "bad.yaml"
    bad.write_text(text)
    cmd = [sys.executable, "-m", "snakemake", "--dry-run", "--cores", "1", "--configfile", bad]
    env = {**os.environ, "PYTHONPATH": str(ROOT / "src")}
    out = subprocess.run(cmd, cwd=ROOT, env=env, capture_output=True, text=True, timeout=120)
    assert out.returncode != 0
    assert f"qsm: config file '{bad}', {where}" in out.stderr
    assert ("never tabs" in out.stderr) == ("\t" in text)


def _catalogue_copy(tmp_path):
    from qsm.embodiment.drives.catalogue import default_catalogue_folder

    folder = tmp_path / "cat"
    folder.mkdir()
    for f in default_catalogue_folder().glob("*.csv"):
        (folder / f.name).write_bytes(f.read_bytes())
    return folder


def test_an_interface_table_is_checked_at_config_time_naming_file_line_column(tmp_path):
    """A unit typed into interfaces.csv fails check-config, naming the file, line and column;
    a byte-order mark from a spreadsheet reads through; Latin-1 text names its file."""
    folder = _catalogue_copy(tmp_path)
    table = folder / "interfaces.csv"
    text = table.read_text()
    lines = text.splitlines()
    header = next(i for i, x in enumerate(lines) if x.strip() and not x.startswith("#"))
    column = next(c for c in lines[header].split(",") if c.endswith("_mm"))
    at = lines[header].split(",").index(column)
    cells = lines[header + 1].split(",")
    cells[at] = cells[at] + "mm"
    lines[header + 1] = ",".join(cells)
    table.write_text("\n".join(lines) + "\n")
    with pytest.raises(ConfigError) as info:
        validate_config({"drives": {"catalogue": str(folder)}})
    assert f"interfaces.csv, line {header + 2}, column '{column}'" in str(info.value)
    table.write_text("\ufeff" + text, encoding="utf-8")  # Excel's "CSV UTF-8"
    validate_config({"drives": {"catalogue": str(folder)}})
    motors = folder / "motors.csv"
    motors.write_bytes(motors.read_bytes() + "# Schrittmotor, Gehäuse\n".encode("latin-1"))
    with pytest.raises(ConfigError, match=r"motors\.csv: not UTF-8 text"):
        validate_config({"drives": {"catalogue": str(folder)}})


def test_a_number_yaml_reads_as_text_says_how_to_write_it():
    """YAML 1.1 reads 5e-1 (no dot) as a string: the error says so and how to write it."""
    with pytest.raises(ConfigError) as info:
        validate_config(yaml.safe_load("task: {payload_kg: 5e-1}"))
    assert "config key 'task.payload_kg'" in str(info.value)
    assert "YAML reads 5e-1 as text" in str(info.value) and "0.5" in str(info.value)
    with pytest.raises(ConfigError) as info:
        validate_config(yaml.safe_load("task: {payload_kg: five}"))
    assert "YAML reads" not in str(info.value)
    validate_config(yaml.safe_load("task: {payload_kg: 5.0e-1}"))


@pytest.mark.parametrize(("text", "value"), [("5e-1", 0.5), ("2.25e9", 2.25e9), ("1e-7", 1e-7)])
def test_both_ways_the_hint_offers_read_as_the_number(text, value):
    """The two spellings the hint gives (a dot and a signed exponent, or positional) are each
    read by YAML as the number meant."""
    from qsm.config.reading import _yaml_hint

    class Error:
        validator, instance = "type", text

    hint = _yaml_hint(Error())
    scientific, positional = re.search(r"exponent, (\S+), or as (\S+)\)", hint).groups()
    assert scientific != positional
    for spelled in (scientific, positional):
        assert yaml.safe_load(spelled) == pytest.approx(value, rel=1e-12), spelled


@pytest.mark.parametrize(
    ("file", "column", "value", "says"),
    [
        ("motors.csv", "max_int_torque", "nan", "not a finite number"),
        ("gearboxes.csv", "max_cont_torque", "inf", "not a finite number"),
        ("motors.csv", "mass", "1500", "the column is in kg (1500 g is 1.5 kg)"),
        ("gearboxes.csv", "direction", "5", "1 (output turns as the input) or -1"),
        ("gearboxes.csv", "stages", "-2", "a whole number, 1 or more"),
    ],
)
def test_an_implausible_catalogue_cell_fails_at_config_time(tmp_path, file, column, value, says):
    """Cells that read as numbers but cannot be a drive's: named by file, line and column."""
    folder = _catalogue_copy(tmp_path)
    table = folder / file
    lines = table.read_text().splitlines()
    header = next(i for i, x in enumerate(lines) if x.strip() and not x.startswith("#"))
    at = lines[header].split(",").index(column)
    row = header + 1
    cells = next(csv.reader([lines[row]]))
    cells[at] = value
    out = io.StringIO()
    csv.writer(out, lineterminator="").writerow(cells)
    lines[row] = out.getvalue()
    table.write_text("\n".join(lines) + "\n")
    with pytest.raises(ConfigError) as info:
        validate_config({"drives": {"catalogue": str(folder)}})
    assert f"{file}, line {row + 1}, column '{column}'" in str(info.value)
    assert says in str(info.value)


def test_the_first_mode_bound_is_the_hand_formula_and_bounds_the_frame_model():
    """The default config's bound is sqrt(4 E A / (r m)) / 2 pi by hand (the largest section
    80 x 40 mm, the farthest default point 0.7102 m out, 5 kg); and the frame model of an arm
    of that section everywhere, gearboxes of 1e9 N m/rad and nearly massless links, reaching
    that far, rings below it at two poses: no arm the realisation builds passes it."""
    config = load_config()
    by_hand = np.sqrt(4 * 2.2e9 * 0.08 * 0.04 / (np.hypot(-0.70, 0.12) * 5.0)) / (2 * np.pi)
    assert first_mode_bound_hz(config) == pytest.approx(by_hand, rel=1e-9)
    design = np.array([0.55, 0.22, 0.5, 0.16, 0.42, 0.12])  # m
    sections = FrameSections(np.full(4, 0.08), np.full(4, 0.04), 2.2e9, 0.35)
    for t1, t2 in np.radians([[60.0, 150.0], [120.0, 180.0]]):
        reach = float(np.hypot(*end_effector(design, t1, t2)))
        config["task"]["points"] = [[-reach, 0.0], [-0.5 * reach, 0.0]]
        f = loaded_first_mode_hz(design, t1, t2, sections, np.full(4, 1e-6), 5.0,
                                 np.full(2, 1e9), np.zeros(2))  # fmt: skip
        assert 0 < f < first_mode_bound_hz(config)
