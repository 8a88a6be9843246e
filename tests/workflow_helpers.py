"""Run the Snakemake workflow on a copy of the repository in a temporary directory."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def copy_workflow(dest: Path) -> Path:
    """Copy what a run needs (Snakefile, workflow, config, src) into ``dest``."""
    dest.mkdir(parents=True, exist_ok=True)
    shutil.copy2(ROOT / "Snakefile", dest / "Snakefile")
    for name in ("workflow", "config", "src"):
        shutil.copytree(
            ROOT / name,
            dest / name,
            symlinks=True,
            ignore=shutil.ignore_patterns("__pycache__", "*.egg-info"),
        )
    return dest


def snakemake(workdir: Path, *args: str, check: bool = True) -> subprocess.CompletedProcess:
    """Run ``snakemake`` in ``workdir`` with the test config; output captured."""
    cmd = [sys.executable, "-m", "snakemake", *args]
    if "--cores" not in args:
        cmd += ["--cores", "2"]
    cmd += ["--configfile", "config/test.yaml"]  # last: it takes several values
    out = subprocess.run(cmd, cwd=workdir, capture_output=True, text=True, check=False)
    if check and out.returncode != 0:
        raise AssertionError(f"snakemake {' '.join(args)} failed:\n{out.stdout}\n{out.stderr}")
    return out
