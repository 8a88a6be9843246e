"""Time the workflow stage by stage on the full default config with ``snakemake --cores 2``.

Copies the workflow into a fresh directory (or ``--keep DIR``), then runs the targets of each
stage in turn so that each wall time covers that stage alone, and prints the per-job times and
peak memory from Snakemake's benchmark files.

    python benchmarks/bench_stages.py [--cores 2] [--stages 1 2 ...] [--keep DIR]

With every stage (the default) it then times a run of the default target with nothing to do.
"""

from __future__ import annotations

import argparse
import json
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import pandas as pd

ROOT = Path(__file__).resolve().parents[1]
STAGES = {
    "1": ["select_mechanisms", "plot_mechanisms"],
    "2": ["gather_dataset", "plot_dynamics"],
    "3": ["train_surrogate"],
    "4": ["compare_fronts"],
    "5": ["design_rules_summary"],
    "6": ["payload_test"],
}


def job_table(work: Path, since: float) -> list[str]:
    """Per-job lines from the benchmark files written after ``since`` (epoch seconds)."""
    lines = []
    for tsv in sorted((work / "results/benchmarks").rglob("*.tsv")):
        if tsv.stat().st_mtime >= since:
            row = pd.read_csv(tsv, sep="\t").iloc[0]
            name = tsv.relative_to(work / "results/benchmarks")
            lines.append(f"    {name}: {row['s']:.1f} s, max RSS {row['max_rss']:.0f} MB")
    return lines


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--cores", type=int, default=2)
    parser.add_argument("--stages", nargs="+", default=list(STAGES), choices=list(STAGES))
    parser.add_argument("--keep", type=Path, help="run here and keep the results")
    args = parser.parse_args()
    work = args.keep or Path(tempfile.mkdtemp(prefix="qsm-bench-"))
    work.mkdir(parents=True, exist_ok=True)
    shutil.copy2(ROOT / "Snakefile", work / "Snakefile")
    for name in ("workflow", "config", "profiles", "src"):  # fresh code, results kept
        shutil.rmtree(work / name, ignore_errors=True)
        shutil.copytree(ROOT / name, work / name, symlinks=True)
    total = 0.0
    for stage in args.stages:
        cmd = [sys.executable, "-m", "snakemake", *STAGES[stage], "--cores", str(args.cores), "-q"]
        start_epoch = time.time()
        start = time.perf_counter()
        subprocess.run(cmd, cwd=work, check=True)
        wall = time.perf_counter() - start
        total += wall
        print(f"Stage {stage} wall time with --cores {args.cores}: {wall:.1f} s")
        print("\n".join(job_table(work, start_epoch)))
    print(f"Total: {total:.1f} s")
    if args.stages == list(STAGES):
        cmd = [sys.executable, "-m", "snakemake", "--cores", str(args.cores), "-q"]
        subprocess.run(cmd, cwd=work, check=True)  # the default target: nothing may be left
        start = time.perf_counter()
        subprocess.run(cmd, cwd=work, check=True, capture_output=True)
        print(f"A run with nothing to do: {time.perf_counter() - start:.2f} s")
    for report in ("mechanisms/filter_report.json", "dynamics/status.json"):
        path = work / "results" / report
        if path.exists():
            data = json.loads(path.read_text())
            data.pop("failures", None)
            print(f"{report}: {json.dumps(data)}")
    if not args.keep:
        shutil.rmtree(work)


if __name__ == "__main__":
    main()
