"""profiles/slurm against a real single-node SLURM with accounting (scripts/slurm_local.sh).

The account and partition are given as a user gives them, through SBATCH_ACCOUNT and
SBATCH_PARTITION, without editing the profile. The test cluster makes neither the user's default
(the default account is `root`, the default partition `batch`), so a profile that ignored them
would show in sacct.
"""

import os
import re
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
import yaml
from workflow_helpers import ROOT, copy_run, copy_workflow, snakemake

pytestmark = [pytest.mark.slurm, pytest.mark.workflow]

SETUP = ROOT / "scripts" / "slurm_local.sh"


def controller_up() -> bool:
    if shutil.which("scontrol") is None:
        return False
    return subprocess.run(["scontrol", "ping"], capture_output=True, check=False).returncode == 0


@pytest.fixture(scope="module")
def slurm():
    """SLURM up (started here, and stopped afterwards, unless it was already running)."""
    if os.geteuid() != 0:
        pytest.skip("needs root: scripts/slurm_local.sh installs SLURM with apt and starts it")
    if shutil.which("sbatch") is None and shutil.which("apt-get") is None:
        pytest.skip("no SLURM and no apt-get here: scripts/slurm_local.sh cannot install SLURM")
    was_up = controller_up()
    out = subprocess.run([SETUP, "start"], capture_output=True, text=True, check=False)
    assert out.returncode == 0, f"{SETUP} start failed:\n{out.stdout}\n{out.stderr}"
    yield dict(item.split("=", 1) for item in out.stdout.split())
    if not was_up:
        subprocess.run([SETUP, "stop"], capture_output=True, check=False)


@pytest.fixture
def user_env(slurm, monkeypatch):
    """The account and partition set the way the profile's header tells users to."""
    monkeypatch.setenv("SBATCH_ACCOUNT", slurm["account"])
    monkeypatch.setenv("SBATCH_PARTITION", slurm["partition"])
    return slurm


def sacct(run_id: str, *ids: str) -> list[dict[str, str]]:
    """sacct's rows (one per job or array task) of a run, waiting until ``ids`` are all listed."""
    fields = ["JobID", "Account", "Partition", "State", "TimelimitRaw"]
    cmd = ["sacct", "-X", "-n", "-P", "--name", run_id, "-S", "now-1days", "-o", ",".join(fields)]
    deadline = time.monotonic() + 30  # accounting reaches slurmdbd asynchronously
    while True:
        out = subprocess.run(cmd, capture_output=True, text=True, check=True).stdout
        rows = [dict(zip(fields, line.split("|"), strict=True)) for line in out.splitlines()]
        listed = {row["JobID"].split("_")[0] for row in rows}
        if set(ids) <= listed or time.monotonic() > deadline:
            return rows
        time.sleep(0.5)


def submitted(log: str) -> tuple[str, set[str]]:
    """The run's SLURM run ID and the job IDs it submitted (an array counts once)."""
    run_id = re.search(r"SLURM run ID: (\S+)", log).group(1)
    ids = set(re.findall(r"with SLURM jobid (\d+)", log))
    ids |= set(re.findall(r"and SLURM job ID (\d+)", log))
    return run_id, ids


def same_bytes(work: Path, reference: Path, names: list[str]) -> None:
    for name in names:
        assert (work / "results" / name).read_bytes() == (
            reference / "results" / name
        ).read_bytes(), name


def test_the_plain_profile_command_runs_the_dag_as_a_local_run_does(run, user_env, tmp_path):
    work = copy_workflow(tmp_path / "slurm")
    out = snakemake(work, "--profile", "profiles/slurm")  # + --configfile config/test.yaml
    log = out.stdout + out.stderr
    assert "steps (100%) done" in log
    run_id, ids = submitted(log)
    assert ids, "no job went to SLURM"
    rows = sacct(run_id, *ids)
    assert {row["JobID"].split("_")[0] for row in rows} == ids
    for row in rows:
        assert row["State"] == "COMPLETED", row
        assert row["Account"] == user_env["account"], row
        assert row["Partition"] == user_env["partition"], row
        assert row["TimelimitRaw"].isdigit(), row  # the profile's runtime arrived
    front = yaml.safe_load((ROOT / "config/config.yaml").read_text())["optimization"]["formulation"]
    same_bytes(
        work,
        run,
        [
            "dataset.parquet",
            f"optimization/{front}/pareto.parquet",
            f"optimization/{front}/verification.parquet",
            "realization/selected.json",
        ],
    )


def test_a_cancelled_shard_job_is_reported_and_run_again(run, user_env, tmp_path):
    work = copy_run(run, tmp_path / "cancel")
    (work / "results/dataset.parquet").unlink()
    log_path = tmp_path / "snakemake.log"
    cmd = [sys.executable, "-m", "snakemake", "gather_dataset", "--forcerun", "dynamics"]
    cmd += ["--profile", "profiles/slurm", "--configfile", "config/test.yaml"]
    with log_path.open("w") as log_file:
        proc = subprocess.Popen(
            cmd, cwd=work, stdout=log_file, stderr=subprocess.STDOUT, start_new_session=True
        )
    try:
        cancelled = cancel_a_running_dynamics_job(proc, log_path)
        proc.wait(timeout=300)  # a cancellation never noticed hangs here
    except subprocess.TimeoutExpired:
        pytest.fail(f"Snakemake did not notice the cancelled job:\n{log_path.read_text()[-3000:]}")
    finally:
        if proc.poll() is None:  # end Snakemake, and its jobs, which outlive a SIGKILL
            os.killpg(proc.pid, signal.SIGKILL)
            found = re.search(r"SLURM run ID: (\S+)", log_path.read_text())
            if found:
                subprocess.run(["scancel", "--name", found.group(1)], check=False)
    log = log_path.read_text()
    assert proc.returncode == 0, log[-3000:]
    assert f"SLURM-job '{cancelled}' failed, SLURM status is: 'CANCELLED'" in log
    assert "Error in rule dynamics" in log
    run_id, ids = submitted(log)
    states = {row["JobID"]: row["State"] for row in sacct(run_id, *ids)}
    assert states[cancelled].startswith("CANCELLED")
    assert len(states) > 3  # the 3 shards, and the cancelled one again
    same_bytes(work, run, ["dataset.parquet"])


def cancel_a_running_dynamics_job(proc: subprocess.Popen, log_path: Path) -> str:
    """scancel a dynamics shard job of the run as soon as one runs; its SLURM ID."""
    deadline = time.monotonic() + 300
    while time.monotonic() < deadline:
        assert proc.poll() is None, f"Snakemake ended early:\n{log_path.read_text()[-3000:]}"
        found = re.search(r"SLURM run ID: (\S+)", log_path.read_text())
        if found:
            queue = subprocess.run(
                ["squeue", "-h", "-t", "R", "--name", found.group(1), "-o", "%i|%k"],
                capture_output=True,
                text=True,
                check=True,
            ).stdout
            for line in queue.splitlines():
                job, comment = line.split("|", 1)
                if "dynamics" in comment:
                    subprocess.run(["scancel", job], check=True)
                    return job
        time.sleep(0.2)
    raise AssertionError(f"no dynamics job ran:\n{log_path.read_text()[-3000:]}")
