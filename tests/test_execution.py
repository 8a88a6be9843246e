"""Execution modes: the generic cluster executor end to end, and resuming after a SIGKILL."""

import os
import signal
import subprocess
import sys
import time

import pandas as pd
import pytest
from workflow_helpers import copy_workflow, snakemake

from qsm.workflow.tables import read_table

pytestmark = pytest.mark.workflow


def test_local_cluster_profile_runs_the_whole_dag(run, tmp_path):
    work = copy_workflow(tmp_path / "cluster")
    out = snakemake(work, "--profile", "profiles/local-cluster")
    assert "steps (100%) done" in out.stdout + out.stderr
    assert list((work / ".snakemake/local-cluster").glob("*.exit"))  # jobs went through submit.sh
    for name in ("dataset.parquet", "optimization/ratios/pareto.parquet"):
        pd.testing.assert_frame_equal(
            read_table(work / "results" / name), read_table(run / "results" / name)
        )


def test_resume_after_sigkill_in_the_dynamics_shards(run, tmp_path):
    work = copy_workflow(tmp_path / "killed")
    snakemake(work, "select_mechanisms")
    cmd = [
        sys.executable,
        "-m",
        "snakemake",
        "gather_dataset",
        "--cores",
        "1",
        "--configfile",
        "config/test.yaml",
    ]
    proc = subprocess.Popen(
        cmd, cwd=work, start_new_session=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL
    )
    started = work / "results/logs/dynamics"
    deadline = time.monotonic() + 120
    while not (started.exists() and any(started.iterdir())):
        assert proc.poll() is None and time.monotonic() < deadline, "no dynamics shard started"
        time.sleep(0.02)
    os.killpg(proc.pid, signal.SIGKILL)  # the whole process group, mid-shard
    proc.wait()
    assert not (work / "results/dataset.parquet").exists()
    locked = snakemake(work, "gather_dataset", check=False)
    assert locked.returncode != 0 and "lock" in (locked.stdout + locked.stderr).lower()
    # README's recovery steps
    snakemake(work, "--unlock")
    snakemake(work, "gather_dataset", "--rerun-incomplete")
    pd.testing.assert_frame_equal(
        read_table(work / "results/dataset.parquet"), read_table(run / "results/dataset.parquet")
    )
