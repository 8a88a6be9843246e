"""Sampling, filters, sharding, tables and the command line of Stage 1."""

import contextlib
import functools
import io
import json
import subprocess

import numpy as np
import pandas as pd
import pyarrow.parquet as pq
import pytest
from scipy.stats import qmc

from qsm.app.cli import main
from qsm.config.reading import load_config
from qsm.config.settings import physics
from qsm.mechanisms.filters import added, filter_batches, kinematic_filters
from qsm.mechanisms.sampling import latin_hypercube, lhs_batches
from qsm.mechanisms.scale import (
    examined_fits,
    fit_counts,
    fit_designs,
    gathered_fits,
    select_mechanisms,
    shard_quota,
)
from qsm.physics.kinematics import RATIO_NAMES, pose
from qsm.physics.workspace import OperatingRange
from qsm.workflow.sharding import shard_count, shard_slice
from qsm.workflow.tables import (
    ROW_GROUP,
    TableError,
    read_batches,
    read_meta,
    read_table,
    write_batches,
    write_table,
)

OP = OperatingRange.from_degrees([45.0, 180.0], -37.5)
BOUNDS = load_config()["sampling"]["bounds"]


def test_lhs_in_batches_is_scipys_sample_and_streams_through_parquet(tmp_path):
    """The batches (three, the last short) hold scipy's Latin hypercube, scaled by qmc.scale,
    bit for bit; written one at a time and read back in other batches they are one table, and
    the filters of its batches are the filters of the whole."""
    lo = np.array([BOUNDS[n][0] for n in RATIO_NAMES])
    hi = np.array([BOUNDS[n][1] for n in RATIO_NAMES])
    expected = qmc.scale(qmc.LatinHypercube(d=5, seed=4).random(2500), lo, hi)
    path = tmp_path / "samples.parquet"
    assert write_batches(lhs_batches(2500, BOUNDS, 4, rows=1000), path, {"k": 1}) == 2500
    table = read_table(path)
    np.testing.assert_array_equal(table[list(RATIO_NAMES)].to_numpy(), expected)
    np.testing.assert_array_equal(table["sample_id"], np.arange(2500))
    assert read_meta(path)["k"] == 1
    whole = kinematic_filters(table, OP, 30.0)
    parts = list(
        filter_batches(read_batches(path, ["sample_id", *RATIO_NAMES], rows=700), OP, 30.0)
    )
    assert len(parts) == 4
    pd.testing.assert_frame_equal(pd.concat([t for t, _ in parts], ignore_index=True), whole[0])
    assert functools.reduce(added, [c for _, c in parts], {}) == whole[1]
    assert 0 < whole[1]["transmission_angle"] < 2500
    with pytest.raises(TableError, match="lacks column"):
        next(read_batches(path, ["sample_id", "tau1_Nm"]))


def test_a_large_table_is_written_in_groups_with_one_schema(tmp_path):
    """Three row groups; a text column that the first holds only as None stays text."""
    n = 2 * ROW_GROUP + 10
    reason = np.where(np.arange(n) < ROW_GROUP + 5, None, "too thin").astype(object)
    table = pd.DataFrame({"sample_id": np.arange(n), "reason": pd.Series(reason, dtype=object)})
    write_table(table, tmp_path / "t.parquet")
    assert pq.ParquetFile(tmp_path / "t.parquet").num_row_groups == 3
    back = read_table(tmp_path / "t.parquet")
    assert back["reason"].isna().sum() == ROW_GROUP + 5 and back["reason"].iloc[-1] == "too thin"


def test_lhs_is_seeded_within_bounds_and_stratified():
    a = latin_hypercube(500, BOUNDS, seed=3)
    b = latin_hypercube(500, BOUNDS, seed=3)
    pd.testing.assert_frame_equal(a, b)
    assert not a.equals(latin_hypercube(500, BOUNDS, seed=4))
    for name in RATIO_NAMES:
        lo, hi = BOUNDS[name]
        bins = np.floor((a[name] - lo) / (hi - lo) * 500).astype(int)
        assert sorted(bins) == list(range(500))  # one sample per stratum: a Latin hypercube
    assert list(a["sample_id"]) == list(range(500))


def test_filter_counts_follow_the_definitions():
    samples = latin_hypercube(20000, BOUNDS, seed=1)
    kept, counts = kinematic_filters(samples, OP, min_transmission_angle_deg=20.0)
    r = samples[list(RATIO_NAMES)].to_numpy()
    assert counts["crank_rocker"] == int(np.sum(r[:, 1] + r[:, 0] < 1 + r[:, 2]))
    assert counts["samples"] >= counts["crank_rocker"] >= counts["loop_closes"]
    assert counts["loop_closes"] > counts["transmission_angle"] == len(kept)
    # every kept design closes its loop on a dense grid of the operating range
    t1, t2 = np.meshgrid(
        np.radians(np.linspace(45, 180, 40)), np.radians(np.linspace(-37.5, 180, 60))
    )
    keep = t2 <= t1
    design = np.column_stack([np.ones(len(kept)), kept[list(RATIO_NAMES)].to_numpy()])
    p = pose(
        design[:, None, :],
        np.broadcast_to(t1[keep], (len(kept), keep.sum())),
        np.broadcast_to(t2[keep], (len(kept), keep.sum())),
    )
    assert p.closes.all()


@pytest.mark.parametrize(("n", "k"), [(10, 1), (10, 3), (7, 7), (3, 5), (11080, 8)])
def test_shards_cover_every_row_once(n, k):
    rows = np.concatenate([np.arange(n)[shard_slice(n, k, i)] for i in range(k)])
    np.testing.assert_array_equal(rows, np.arange(n))


@pytest.mark.parametrize(
    ("n", "least", "most", "count"),
    [(11080, 2, 50000, 2), (110800, 2, 50000, 4), (1108000, 2, 50000, 24), (5, 3, 1000, 3)],
)
def test_no_shard_holds_more_than_its_rows(n, least, most, count):
    assert shard_count(n, least, most) == count and count % least == 0  # full rounds of jobs
    sizes = [len(range(n)[shard_slice(n, count, i)]) for i in range(count)]
    assert max(sizes) <= most and sum(sizes) == n


def test_shard_arguments_are_checked():
    with pytest.raises(ValueError, match="at least 1"):
        shard_slice(10, 0, 0)
    with pytest.raises(ValueError, match="outside"):
        shard_slice(10, 2, 2)


def test_selection_does_not_depend_on_sharding():
    config = load_config()
    fit_settings = physics.fit(
        config["operating_range"], config["task"]["points"], config["scale"], config["workspace"]
    )
    candidates, _ = kinematic_filters(latin_hypercube(600, BOUNDS, seed=9), OP, 0.0)
    whole = fit_designs(candidates, fit_settings)
    parts = pd.concat(
        [
            fit_designs(candidates.iloc[shard_slice(len(candidates), 3, i)], fit_settings)
            for i in (2, 0, 1)
        ],
        ignore_index=True,
    )
    a, b = select_mechanisms(whole, 50), select_mechanisms(parts, 50)
    pd.testing.assert_frame_equal(a, b)
    assert a["mechanism_id"].is_monotonic_increasing and len(a) == 50
    np.testing.assert_allclose(a["l3_m"], a["l3"] * a["scale_m"])

    # interleaved shards that stop after their quota give the same selection and counts, the
    # candidates fitted on where the quotas fell short (a quota of 4 in 4 shards: 16 < 30)
    first = select_mechanisms(whole, 30)
    for n_shards, quota in ((1, shard_quota(30, 1)), (2, shard_quota(30, 2)), (4, 4)):
        stopped = pd.concat(
            [
                fit_designs(candidates.iloc[i::n_shards], fit_settings, stop_after=quota)
                for i in range(n_shards)
            ],
            ignore_index=True,
        )
        assert len(stopped) < len(whole)
        examined = gathered_fits(
            stopped,
            candidates["sample_id"],
            lambda last: candidates[candidates["sample_id"] > last].iloc[::-1],
            30,
            fit_settings,
        )
        pd.testing.assert_frame_equal(select_mechanisms(examined, 30), first)
        counts = fit_counts(examined)
        assert counts == fit_counts(examined_fits(whole, 30))
        assert counts["task_fits"] == 30
        assert (
            counts["task_fit_examined"] == (whole["sample_id"] <= first["mechanism_id"].max()).sum()
        )
    # asking for more than there are examines everything
    assert fit_counts(examined_fits(whole, 10_000))["task_fit_examined"] == len(whole)


def test_tables_keep_metadata_and_name_bad_files(tmp_path):
    path = tmp_path / "t.parquet"
    write_table(pd.DataFrame({"a": [1.0, 2.0]}), path, {"settings_hash": "abc"})
    assert read_meta(path)["settings_hash"] == "abc"
    assert "numpy" in read_meta(path)["package_versions"]
    with pytest.raises(TableError, match=r"t\.parquet.*lacks column\(s\) b"):
        read_table(path, ["a", "b"])
    truncated = tmp_path / "cut.parquet"
    truncated.write_bytes(path.read_bytes()[:40])
    with pytest.raises(TableError, match=r"cut\.parquet"):
        read_table(truncated)


def run_cli(*args):
    """``qsm ARGS`` in this process, with its exit code and output (``python -m qsm`` itself
    runs as a process in test_dataset.py)."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = main(list(args))
        except SystemExit as exc:  # argparse's usage errors
            code = exc.code if isinstance(exc.code, int) else 1
    return subprocess.CompletedProcess(args, code, out.getvalue(), err.getvalue())


def test_cli_evaluate_agrees_with_the_library():
    out = run_cli("evaluate", "--ratios", "0.3", "1.0", "0.5", "1.2", "0.4")
    assert out.returncode == 0, out.stderr
    result = json.loads(out.stdout)
    assert result["feasible"] is True
    config = load_config()
    fit_settings = physics.fit(
        config["operating_range"], config["task"]["points"], config["scale"], config["workspace"]
    )
    table = pd.DataFrame([[0, 0.3, 1.0, 0.5, 1.2, 0.4]], columns=["sample_id", *RATIO_NAMES])
    direct = fit_designs(table, fit_settings).iloc[0]
    assert result["scale"] == pytest.approx(direct["scale_m"], rel=1e-12)
    assert result["eta"] == pytest.approx(direct["eta"], rel=1e-12)
    assert result["eta"] == pytest.approx(
        np.pi * result["task_disk"]["radius_m"] ** 2 / result["workspace_area_m2"]
    )


def test_cli_reports_infeasible_designs_and_bad_input(tmp_path):
    far = run_cli(
        "evaluate",
        "--ratios",
        "0.3",
        "1.0",
        "0.5",
        "1.2",
        "0.4",
        "--task-points",  # a thin annulus about the base, which this crescent does not hold
        "-0.063",
        "0",
        "-0.6",
        "0",
    )
    assert far.returncode == 0 and json.loads(far.stdout)["feasible"] is False
    crossed = json.loads(run_cli("evaluate", "--ratios", "0.6", "1.3", "0.3", "1.2", "0.4").stdout)
    assert crossed["feasible"] is False and "crank_rocker" in crossed["reason"]
    odd = run_cli("evaluate", "--ratios", "0.3", "1.0", "0.5", "1.2", "0.4", "--task-points", "1")
    assert odd.returncode == 2 and "pairs" in odd.stderr
    bad = tmp_path / "bad.yaml"
    bad.write_text("task:\n  payload_kg: heavy\n")
    out = run_cli("evaluate", "--ratios", "0.3", "1.0", "0.5", "1.2", "0.4", "--config", str(bad))
    assert out.returncode == 2 and "task.payload_kg" in out.stderr


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--ratios", "0.3", "1.0", "0.5", "1.2", "nan"], "--ratios: ratios must be finite and"),
        (["--ratios", "-0.3", "1.0", "0.5", "1.2", "0.4"], "--ratios: ratios must be finite and"),
        (["--ratios", "0.3", "1.0", "0.5", "1.2", "0.4", "--task-points", "-0.6", "0.1"],
         "--task-points: config key 'task.points': the points span a circle"),
        (["--ratios", "0.3", "1.0", "0.5", "1.2", "0.4", "--task-points", "-0.6", "nan", "0", "1"],
         "--task-points: config key 'task.points': every coordinate must be a finite"),
    ],
)  # fmt: skip
def test_cli_names_the_bad_argument(args, message):
    out = run_cli("evaluate", *args)
    assert out.returncode == 2 and message in out.stderr and not out.stdout
