"""Time Stage 1 on the full default config (200,000 samples -> 11,080 mechanisms).

Runs ``snakemake --cores 2`` up to the Stage 1 targets in a fresh copy of the workflow and prints
the wall time, the per-job times from the benchmark files and the filter counts.

    python benchmarks/bench_stage1.py [--cores 2] [--keep DIR]
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
TARGETS = ["select_mechanisms", "plot_mechanisms"]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--cores", type=int, default=2)
    parser.add_argument("--keep", type=Path, help="run here and keep the results")
    args = parser.parse_args()
    work = args.keep or Path(tempfile.mkdtemp(prefix="qsm-bench-"))
    shutil.copy2(ROOT / "Snakefile", work / "Snakefile")
    for name in ("workflow", "config", "src"):
        shutil.copytree(ROOT / name, work / name, symlinks=True, dirs_exist_ok=True)
    cmd = [sys.executable, "-m", "snakemake", *TARGETS, "--cores", str(args.cores), "--quiet"]
    start = time.perf_counter()
    subprocess.run(cmd, cwd=work, check=True)
    wall = time.perf_counter() - start
    report = json.loads((work / "results/mechanisms/filter_report.json").read_text())
    print(f"Stage 1 wall time with --cores {args.cores}: {wall:.1f} s")
    for tsv in sorted((work / "results/benchmarks").rglob("*.tsv")):
        row = pd.read_csv(tsv, sep="\t").iloc[0]
        print(
            f"  {tsv.relative_to(work / 'results/benchmarks')}: {row['s']:.1f} s, "
            f"max RSS {row['max_rss']:.0f} MB"
        )
    print(json.dumps(report, indent=2))
    if not args.keep:
        shutil.rmtree(work)


if __name__ == "__main__":
    main()
