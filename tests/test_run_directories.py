"""Two tasks in two run directories keep their results side by side; `qsm export` reads either.

The second task is the default one mirrored to x > 0 (qsm.physics.mirror), run through Stage 2
only: its dataset must be the default run's (same designs, same torques), and its export the
mirrored arm of the same design.
"""

import json
import os
import subprocess
import sys

import numpy as np
import pytest
from workflow_helpers import snakemake

from qsm.config.reading import load_config
from qsm.physics.kinematics import DESIGN_COLUMNS
from qsm.physics.mirror import mirror_points
from qsm.workflow.tables import read_table

pytestmark = pytest.mark.workflow

SAME = [*DESIGN_COLUMNS, "eta", "tau1_Nm", "tau2_Nm"]


def mtimes(work):
    return {p: p.stat().st_mtime_ns for p in (work / "results").rglob("*") if p.is_file()}


def export(work, results, out, *configs):
    """``qsm export --id`` of the first sound mechanism of ``results``; its design.json."""
    table = read_table(results / "dataset.parquet")
    first = int(table.loc[table["status"].eq("ok"), "mechanism_id"].iloc[0])
    cmd = [sys.executable, "-m", "qsm", "export", "--id", str(first), "--results", results]
    cmd += ["--out", out, "--config", "config/test.yaml", *configs]
    env = {**os.environ, "PYTHONPATH": str(work / "src")}
    subprocess.run(cmd, cwd=work, env=env, check=True, capture_output=True, text=True)
    return json.loads((out / "design.json").read_text())


def test_two_tasks_in_two_directories_keep_their_results(run, tmp_path):
    before = mtimes(run)
    default = read_table(run / "results/dataset.parquet")
    task = tmp_path / "mirrored.yaml"
    config = load_config(run / "config/config.yaml", run / "config/test.yaml")
    points = mirror_points(config["task"]["points"])
    task.write_text(f"task: {{points: {points.tolist()}}}\n")
    other = tmp_path / "runs" / "mirrored"
    snakemake(run, "--directory", str(other), "results/dataset.parquet", configs=(str(task),))
    assert mtimes(run) == before
    mirrored = read_table(other / "results/dataset.parquet")
    assert len(mirrored) == len(default)
    np.testing.assert_allclose(mirrored[SAME], default[SAME], rtol=1e-9)

    first = export(run, run / "results", tmp_path / "export-default")
    second = export(run, other / "results", tmp_path / "export-mirrored", str(task))
    assert not first["task"]["mirrored"]
    assert second["task"]["mirrored"]
    assert second["task"]["points_m"] == points.tolist()
    assert second["design"] == first["design"]
    for key in ("eta_true", "tau1_true_Nm", "tau2_true_Nm"):
        got, want = second["true_performance"][key], first["true_performance"][key]
        assert got == pytest.approx(want, rel=1e-9)
    assert 'axis="0 0 -1"' in (tmp_path / "export-mirrored/model.xml").read_text()
    assert 'axis="0 0 -1"' not in (tmp_path / "export-default/model.xml").read_text()
    assert mtimes(run) == before
