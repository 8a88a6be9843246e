"""Bad input through Snakemake: a clear error naming the key or file; earlier results intact."""

import hashlib
import subprocess
import sys
from pathlib import Path

import pyarrow.parquet as pq
import pytest
from workflow_helpers import copy_run, snakemake

pytestmark = pytest.mark.workflow

CATALOGUE = Path(__file__).resolve().parents[1] / "src/qsm/embodiment/drives/data"


def snapshot(work):
    """Modification time and SHA-256 of every result file."""
    return {
        p: (p.stat().st_mtime_ns, hashlib.sha256(p.read_bytes()).hexdigest())
        for p in (work / "results").rglob("*")
        if p.is_file()
    }


@pytest.fixture
def finished(run, tmp_path):
    return copy_run(run, tmp_path / "copy")


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("dynamics: {shardz: 2}", "config key 'dynamics.shardz' is unknown"),
        ("sampling: {n_samples: many}", "config key 'sampling.n_samples': 'many' is not of type"),
        ("workspace: {n_levels: 3}", "config key 'workspace.n_levels': 3 is less than"),
        ("sampling: {bounds: {l3: [1.3, 0.8]}}", "config key 'sampling.bounds.l3': min 1.3"),
        ("dynamics: {shards: 0}", "config key 'dynamics.shards': 0 is less than the minimum of 1"),
        ("optimization: {formulation: best}", "config key 'optimization.formulation'"),
        ("task: {points: [[-0.6, 0.1]]}", "config key 'task.points': the points span a circle"),
        ("cad: {width_m: 5.0}", "config key 'cad.boss_radius_m': 0.025 m must exceed half"),
        ("task: {points: [[-0.6, .nan], [-0.5, 0.1]]}", "config key 'task.points': every"),
        (
            "optimization: {formulation: paper, formulations: [ratios]}",
            "config key 'optimization.formulation': 'paper' is not among",
        ),
        ("task: {payload_kg: 5000}", "looks like grams: task.payload_kg is in kilograms"),
        ("printing: {build_volume_mm: [0.6, 0.35, 0.35]}", "looks like metres: printing."),
        ("operating_range: {theta1_deg: [0.785, 3.1416]}", "looks like radians: operating_range"),
        ("task: {points: [[-530, 170], [-700, 20]]}", "looks like millimetres: task.points"),
        ("scale: {max_m: 0.05}", "config key 'scale.max_m': 0.05 m is too small for the task"),
        ("optimization: {bounds: {l2_m: [0.3, 0.1]}}", "'optimization.bounds.l2_m': [0.3, 0.1]"),
        ("operating_range: {theta2_min_deg: 60}", "'operating_range.theta2_min_deg': 60 must be"),
        ("task: {points: [[0.0, 0.0], [-0.3, 0.1]]}", "covers the base joint (0, 0)"),
        ("task: {points: [[-0.05, 0.0], [-0.6, 0.0]]}", "no design of sampling.bounds holds it"),
        ("sampling: {n_mechanisms: 1}", "config key 'sampling.n_mechanisms': 1 is too few"),
        ("sampling: {n_mechanisms: 4}", "config key 'sampling.n_mechanisms': 4 is too few"),
        ("operating_range: {theta1_deg: [45, 400]}", "400 deg is past a full turn"),
        ("task: {repeatability_mm: 0}", "config key 'task.repeatability_mm': 0 is less than"),
        ("iso9283: {cycles: 10}", "config key 'iso9283.cycles': 10 is less than the minimum of 30"),
        ("task: {cycle: {jerk_time_s: 0}}", "config key 'task.cycle.jerk_time_s': 0 is less than"),
        ("", "bad.yaml' is empty: it must hold a mapping"),
        ("- 1\n- 2\n", "bad.yaml' must hold a mapping of config keys, not a list"),
        (f"drives: {{catalogue: {CATALOGUE / 'motors.csv'}}}", "motors.csv is a file"),
    ],
)
def test_bad_config_names_the_key_and_keeps_results(finished, tmp_path, text, message):
    before = snapshot(finished)
    bad = tmp_path / "bad.yaml"
    bad.write_text(text)
    out = snakemake(finished, check=False, configs=(str(bad),))
    assert out.returncode != 0
    assert message in out.stdout + out.stderr
    assert snapshot(finished) == before


def test_a_missing_config_file_is_one_line(finished, tmp_path):
    before = snapshot(finished)
    out = snakemake(finished, check=False, configs=(str(tmp_path / "nowhere.yaml"),))
    assert out.returncode != 0
    assert f"qsm: config file '{tmp_path / 'nowhere.yaml'}' does not exist" in out.stderr
    assert "Traceback" not in out.stdout + out.stderr
    assert snapshot(finished) == before


def test_a_stepper_without_its_pull_out_curve_is_named(finished, tmp_path):
    folder = tmp_path / "cat"
    folder.mkdir()
    for name in ("motors.csv", "gearboxes.csv", "compatibility.csv"):  # no torque_speed.csv
        (folder / name).write_text((CATALOGUE / name).read_text())
    bad = tmp_path / "bad.yaml"
    bad.write_text(f"drives: {{catalogue: {folder}}}")
    before = snapshot(finished)
    out = snakemake(finished, check=False, configs=(str(bad),))
    assert out.returncode != 0
    assert "config key 'drives.catalogue'" in out.stderr
    assert "motor 'SO_17HS19-2004S1' is of type 'stepper'" in out.stderr
    assert snapshot(finished) == before


def test_a_run_that_fails_late_marks_the_last_good_results_not_current(finished, tmp_path):
    """A task the config checks accept (its reach ratio 9.5 is within the family's 10.2) that no
    sampled design holds: Stage 1 fails, naming its rule, and the last good run's summary,
    datasheet and design files are marked NOT CURRENT with the key that changed."""
    verdict = (finished / "results/summary.md").read_text().split("\n\n")[1]
    assert verdict.startswith(("**Ready to build", "**NOT READY TO BUILD"))
    late = tmp_path / "late.yaml"
    late.write_text("task: {points: [[-0.063, 0.0], [-0.6, 0.0]]}")
    out = snakemake(finished, check=False, configs=(str(late),))
    assert out.returncode != 0
    assert (
        "no design holds the task" in (finished / "results/logs/select_mechanisms.log").read_text()
    )
    changed = "the run failed in select_mechanisms, and the config changed since the last good"
    assert f"{changed} run (task.points)" in out.stderr
    for name in ("summary.md", "datasheet.md"):
        text = (finished / "results" / name).read_text()
        assert text.startswith("> **NOT CURRENT**: a later run failed in select_mechanisms")
    assert "(task.points)" in (finished / "results/realization/NOT_CURRENT.md").read_text()


def test_a_run_while_another_holds_the_directory_is_refused_and_changes_nothing(finished):
    """A process holds the workflow's lock (as a run started a moment earlier would; Snakemake's
    own lock set aside with ``--nolock``, as a race in the same second does): a run asked to
    redo the cycle is refused, naming the holder, and leaves the results as they were,
    unmarked."""
    lock = finished / ".snakemake" / "qsm_run.lock"
    holder = subprocess.Popen(
        [sys.executable, "-c",
         "from qsm.workflow.run_state import hold_run_lock; import time\n"
         f"hold_run_lock({str(lock)!r}); print('held', flush=True); time.sleep(600)"],
        stdout=subprocess.PIPE, text=True,
    )  # fmt: skip
    cycle = finished / "results/realization/cycle.json"
    before = (cycle.read_bytes(), cycle.stat().st_mtime_ns)
    try:
        assert holder.stdout.readline().strip() == "held"
        out = snakemake(finished, "--nolock", "--forcerun", "cycle_time", "--until",
                        "cycle_time", check=False)  # fmt: skip
    finally:
        holder.kill()
        holder.wait()
    assert out.returncode != 0
    text = out.stdout + out.stderr
    assert f"another qsm run is working in this directory (process {holder.pid}" in text
    assert (cycle.read_bytes(), cycle.stat().st_mtime_ns) == before
    assert not (finished / "results/realization/NOT_CURRENT.md").exists()


def test_truncated_parquet_between_stages_names_the_file(finished):
    table = finished / "results/mechanisms/mechanisms.parquet"
    table.write_bytes(table.read_bytes()[:200])
    samples = (finished / "results/mechanisms/samples.parquet").read_bytes()
    out = snakemake(finished, "gather_dataset", check=False)
    assert out.returncode != 0
    assert "cannot read table 'results/mechanisms/mechanisms.parquet'" in out.stdout + out.stderr
    assert (finished / "results/mechanisms/samples.parquet").read_bytes() == samples


def test_missing_column_names_column_and_file(finished):
    path = finished / "results/dataset.parquet"
    table = pq.read_table(path)
    pq.write_table(table.drop_columns(["tau2_Nm"]), path)
    out = snakemake(finished, "train_surrogate", check=False)
    assert out.returncode != 0
    text = out.stdout + out.stderr
    assert "table 'results/dataset.parquet' lacks column(s) tau2_Nm" in text
    assert (finished / "results/mechanisms/mechanisms.parquet").exists()
