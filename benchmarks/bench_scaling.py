"""The whole default DAG at multiples of the paper's dataset: wall time, job seconds per stage and
every job's peak memory.

For each multiple k (1, 10, 100, ...), a commit's tree (``git archive``; the working tree with
``--commit WORKTREE``) is run from scratch with ``snakemake --cores N`` on its default config
with ``sampling.n_samples = k x 200,000`` and ``sampling.n_mechanisms = k x 11,080``, its own
``qsm`` first on ``PYTHONPATH``. From Snakemake's benchmark files it reads each job's seconds and
peak memory (max RSS), and it writes one JSON record per run to ``--out`` (appended) and a table
to stdout. Runs of two commits side by side alternate (``--commit A --commit B``).

    python benchmarks/bench_scaling.py [--multiples 1 10] [--commit HEAD] [--cores 2]
        [--out benchmarks/scaling.jsonl] [--keep DIR]

100x takes hours on 2 cores: run it alone (``--multiples 100``), not in CI.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import pandas as pd
import yaml
from compare_commits import STAGES, export

ROOT = Path(__file__).resolve().parents[1]
#: The paper's dataset (Lee, Yang, Kang): LHS samples and mechanisms kept.
PAPER = {"n_samples": 200_000, "n_mechanisms": 11_080}


def tree(commit: str, dest: Path) -> Path:
    """``commit``'s files in ``dest``; WORKTREE: this checkout's files as they are."""
    if commit != "WORKTREE":
        return export(commit, dest)
    shutil.copytree(ROOT, dest, ignore=shutil.ignore_patterns(".git", "results", ".snakemake"))
    return dest


def jobs(work: Path) -> pd.DataFrame:
    """One row per benchmarked job of a finished run: rule, stage, seconds, peak MB."""
    rows = []
    base = work / "results" / "benchmarks"
    for tsv in sorted(base.rglob("*.tsv")):
        rule = tsv.relative_to(base).parts[0].removesuffix(".tsv")
        last = pd.read_csv(tsv, sep="\t").iloc[-1]
        rows.append({"job": str(tsv.relative_to(base).with_suffix("")), "rule": rule,
                     "stage": STAGES.get(rule, "-"), "s": float(last["s"]),
                     "peak_MB": float(last["max_rss"])})  # fmt: skip
    return pd.DataFrame(rows)


def run(commit: str, k: int, cores: int, tmp: Path, keep: Path | None = None) -> dict:
    """One from-scratch run of ``commit`` at ``k`` times the paper's dataset: its record; the
    finished directory moves into ``keep`` when given (else it is deleted)."""
    work = tree(commit, tmp / f"{commit.replace('/', '_')}-{k}x")
    size = {key: k * n for key, n in PAPER.items()}
    (work / "size.yaml").write_text(yaml.safe_dump({"sampling": size}))
    env = {**os.environ, "PYTHONPATH": str(work / "src")}
    cmd = [sys.executable, "-m", "snakemake", "--cores", str(cores), "--configfile"]
    cmd += ["config/config.yaml", "size.yaml"]
    start = time.perf_counter()
    out = subprocess.run(cmd, cwd=work, env=env, capture_output=True, text=True)
    wall = time.perf_counter() - start
    table = jobs(work)
    summary = (work / "results" / "summary.md").read_text() if out.returncode == 0 else ""
    verdict = next((x.strip("*") for x in summary.splitlines() if x.startswith("**")), "failed")
    if keep is None:
        shutil.rmtree(work)
    else:
        keep.mkdir(parents=True, exist_ok=True)
        shutil.move(work, keep / work.name)
    largest = table.loc[table["peak_MB"].idxmax()] if len(table) else None
    return {
        "commit": commit, "multiple": k, "cores": cores, "wall_s": round(wall, 1),
        "returncode": out.returncode, "verdict": verdict[:120],
        "job_s_per_stage": table.groupby("stage")["s"].sum().round(1).to_dict(),
        "largest_job": None if largest is None else largest["job"],
        "largest_job_MB": None if largest is None else round(float(largest["peak_MB"])),
        "jobs": table.round(1).to_dict(orient="records"),
    }  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--multiples", type=int, nargs="+", default=[1, 10])
    parser.add_argument("--commit", action="append", help="commits side by side (HEAD)")
    parser.add_argument("--cores", type=int, default=2)
    parser.add_argument("--out", type=Path, default=ROOT / "benchmarks" / "scaling.jsonl")
    parser.add_argument("--keep", type=Path, help="keep each finished run in this folder")
    args = parser.parse_args()
    commits = args.commit or ["HEAD"]
    with tempfile.TemporaryDirectory(prefix="qsm-scaling-") as tmp:
        for k in args.multiples:
            for commit in commits:  # alternating, so that the machine's drift hits both
                record = run(commit, k, args.cores, Path(tmp), args.keep)
                with args.out.open("a") as fh:
                    fh.write(json.dumps(record) + "\n")
                line = (
                    f"{commit} {k}x: {record['wall_s']} s wall, job s per stage "
                    f"{record['job_s_per_stage']}, largest job {record['largest_job']} "
                    f"{record['largest_job_MB']} MB; {record['verdict']}"
                )
                print(line, flush=True)


if __name__ == "__main__":
    main()
