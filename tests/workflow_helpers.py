"""Run the Snakemake workflow on a copy of the repository in a temporary directory."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def copy_workflow(dest: Path) -> Path:
    """Copy what a run needs (Snakefile, workflow, config, .test, profiles, src) into ``dest``
    (config/test.yaml links to .test/config/config.yaml)."""
    dest.mkdir(parents=True, exist_ok=True)
    shutil.copy2(ROOT / "Snakefile", dest / "Snakefile")
    for name in ("workflow", "config", ".test", "profiles", "src"):
        shutil.copytree(
            ROOT / name,
            dest / name,
            symlinks=True,
            ignore=shutil.ignore_patterns("__pycache__", "*.egg-info"),
        )
    return dest


def snakemake(
    workdir: Path,
    *args: str,
    check: bool = True,
    configs: tuple[str, ...] = (),
    env: dict[str, str] | None = None,
) -> subprocess.CompletedProcess:
    """Run ``snakemake`` in ``workdir`` with the test config (and ``configs`` over it), with
    ``env`` added to the environment."""
    cmd = [sys.executable, "-m", "snakemake", *args]
    if "--cores" not in args and "--profile" not in args:
        cmd += ["--cores", "2"]
    cmd += ["--configfile", "config/test.yaml", *configs]  # last: it takes several values
    out = subprocess.run(
        cmd,
        cwd=workdir,
        capture_output=True,
        text=True,
        check=False,
        env={**os.environ, **(env or {})},
    )
    if check and out.returncode != 0:
        raise AssertionError(f"snakemake {' '.join(args)} failed:\n{out.stdout}\n{out.stderr}")
    return out


def copy_run(run: Path, dest: Path) -> Path:
    """A copy of a finished run (results and Snakemake's metadata included) to change freely."""
    shutil.copytree(run, dest, symlinks=True)
    return dest


def planned_jobs(workdir: Path, *args: str, configs: tuple[str, ...] = ()) -> dict[str, int]:
    """Rules a dry run would execute, with their job counts (empty when nothing is to be done)."""
    out = snakemake(workdir, "--dry-run", *args, configs=configs)
    text = out.stdout + out.stderr
    if "Nothing to be done" in text:
        return {}
    lines = text.split("Job stats:", 1)[1].splitlines()[3:]
    jobs = {}
    for line in lines:
        parts = line.split()
        if not parts or parts[0] == "total":
            break
        jobs[parts[0]] = int(parts[1])
    return jobs
