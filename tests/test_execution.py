"""Execution modes: the generic cluster executor through Stage 4, and resuming after a SIGKILL.

The whole DAG goes through a cluster executor in tests/test_slurm.py (real SLURM, as root)."""

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


def test_local_cluster_profile_runs_stages_1_to_4_as_a_local_run_does(run, tmp_path):
    """Every job from the samples to a front, each through the profile's submit script."""
    work = copy_workflow(tmp_path / "cluster")
    names = ("dataset.parquet", "optimization/ratios/pareto.parquet")
    out = snakemake(work, "--profile", "profiles/local-cluster", *(f"results/{n}" for n in names))
    assert "steps (100%) done" in out.stdout + out.stderr
    exits = list((work / ".snakemake/local-cluster").glob("*.exit"))
    assert len(exits) == 9  # sample, filter, 2 fit and 3 dynamics shards, surrogate, optimize
    for name in names:
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
