"""Two commits side by side on this machine: the whole default DAG from scratch and a no-op rerun.

Each commit is exported (``git archive``) into a fresh directory and run with ``snakemake --cores
N`` on its own default config, its own ``qsm`` first on ``PYTHONPATH``. Runs alternate between
the commits (base, head, base, head, ...) so that drift of the machine hits both alike. Per run it
records the wall time, then a second invocation with nothing to do; per stage it sums the job
times of Snakemake's benchmark files. It prints the medians per commit and the ratio head / base.

    python benchmarks/compare_commits.py [--base e845efc] [--head HEAD] [--runs 2] [--cores 2]
        [--keep DIR]
"""

from __future__ import annotations

import argparse
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import pandas as pd

ROOT = Path(__file__).resolve().parents[1]
#: Stage of each rule (both layouts: before and after the per-formulation optimisation rules).
STAGES: dict[str, str] = {
    "sample": "1",
    "filter_kinematics": "1",
    "fit_task": "1",
    "select_mechanisms": "1",
    "dynamics": "2",
    "train_surrogate": "3",
    "optimize": "4",
    "optimize_ratios": "4",
    "verify_pareto": "4",
    "verify_pareto_ratios": "4",
    "sobol": "5",
    "eta_derivatives": "5",
    "topology_optimize": "6",
    "payload_test": "6",
    "kit_files": "6",
    "cycle_time": "6",
    "standard_cycle": "6",
    "study_lengths": "study",
    "study_table3": "study",
    "pareto_html": "exploration",
    "task_motion": "exploration",
}


def export(commit: str, dest: Path) -> Path:
    """The tree of ``commit`` in ``dest``."""
    dest.mkdir(parents=True)
    archive = subprocess.run(
        ["git", "archive", commit], cwd=ROOT, check=True, capture_output=True
    ).stdout
    subprocess.run(["tar", "-x", "-C", str(dest)], input=archive, check=True)
    return dest


def stage_seconds(work: Path) -> dict[str, float]:
    """Summed job seconds per stage from the Snakemake benchmark files of a finished run."""
    out: dict[str, float] = {}
    for tsv in (work / "results" / "benchmarks").rglob("*.tsv"):
        rel = tsv.relative_to(work / "results" / "benchmarks")
        rule = rel.parts[0].removesuffix(".tsv")
        stage = STAGES.get(rule)
        if stage is not None:
            out[stage] = out.get(stage, 0.0) + float(pd.read_csv(tsv, sep="\t")["s"].iloc[-1])
    return out


def run_once(
    commit: str, cores: int, tmp: Path, k: int, keep: Path | None = None
) -> dict[str, float]:
    """One from-scratch run and one no-op rerun of ``commit``: wall seconds and stage seconds;
    the finished working directory moves to ``keep`` when given (else it is deleted)."""
    work = export(commit, tmp / f"{commit.replace('/', '_')}-{k}")
    env = {**os.environ, "PYTHONPATH": str(work / "src")}
    cmd = [sys.executable, "-m", "snakemake", "--cores", str(cores)]
    start = time.perf_counter()
    subprocess.run(cmd, cwd=work, env=env, check=True, capture_output=True)
    full = time.perf_counter() - start
    start = time.perf_counter()
    subprocess.run(cmd, cwd=work, env=env, check=True, capture_output=True)
    noop = time.perf_counter() - start
    result = {"whole DAG": full, "no-op rerun": noop}
    result.update({f"stage {s} (job s)": v for s, v in sorted(stage_seconds(work).items())})
    if keep is not None:
        shutil.rmtree(keep, ignore_errors=True)
        shutil.move(work, keep)
    else:
        shutil.rmtree(work)
    return result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--base", default="e845efc")
    parser.add_argument("--head", default="HEAD")
    parser.add_argument("--runs", type=int, default=2)
    parser.add_argument("--cores", type=int, default=2)
    parser.add_argument("--keep", type=Path, help="keep the head's last run in this directory")
    args = parser.parse_args()
    results: dict[str, list[dict[str, float]]] = {args.base: [], args.head: []}
    with tempfile.TemporaryDirectory(prefix="qsm-compare-") as tmp:
        for k in range(args.runs):
            for commit in (args.base, args.head):
                keep = args.keep if commit == args.head and k == args.runs - 1 else None
                results[commit].append(run_once(commit, args.cores, Path(tmp), k, keep))
                print(f"run {k + 1} {commit}: {results[commit][-1]}", flush=True)
    keys = [key for key in results[args.base][0] if key in results[args.head][0]]
    print(f"\n| measure | {args.base} (s) | {args.head} (s) | ratio {args.head} / {args.base} |")
    print("| --- | --- | --- | --- |")
    for key in keys:
        base = statistics.median(r[key] for r in results[args.base])
        head = statistics.median(r[key] for r in results[args.head])
        print(f"| {key} | {base:.1f} | {head:.1f} | {head / base:.2f} |")
    print(f"\nmedians of {args.runs} interleaved runs each, --cores {args.cores}")


if __name__ == "__main__":
    main()
