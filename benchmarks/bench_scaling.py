"""How the cost grows with the number of mechanisms: Stages 1-3 at 1x, 2x and 4x a base size.

For each multiple k, a fresh copy of the workflow runs ``snakemake --cores N`` on the default
config with ``sampling.n_samples = k * base_samples`` and ``sampling.n_mechanisms = k *
base_mechanisms``, one stage target after another (Stage 1: ``select_mechanisms``, Stage 2:
``gather_dataset``, Stage 3: ``train_surrogate``), timing each stage's wall time and reading the
peak memory (max RSS) of its jobs from Snakemake's benchmark files. It fits the exponent b of
time ~ k^b per stage and projects a run of ``--project-samples`` samples through the SLURM
profile on 1, 4 and 16 nodes, stating its assumptions.

    python benchmarks/bench_scaling.py [--base-samples 20000] [--base-mechanisms 1000]
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pandas as pd
import yaml

ROOT = Path(__file__).resolve().parents[1]
STAGES = {"1": "select_mechanisms", "2": "gather_dataset", "3": "train_surrogate"}
JOB_FOLDERS = {"1": ["fit_task"], "2": ["dynamics"], "3": ["train_surrogate"]}


def copy_workflow(dest: Path) -> None:
    shutil.copy2(ROOT / "Snakefile", dest / "Snakefile")
    for name in ("workflow", "config", "src"):
        shutil.copytree(ROOT / name, dest / name, symlinks=True)


def peak_mb(work: Path, stage: str) -> float:
    """Largest max RSS (MB) of the stage's benchmarked jobs."""
    peaks = [0.0]
    for name in JOB_FOLDERS[stage]:
        base = work / "results" / "benchmarks"
        for tsv in [*base.glob(f"{name}/*.tsv"), *base.glob(f"{name}.tsv")]:
            peaks.append(float(pd.read_csv(tsv, sep="\t")["max_rss"].iloc[-1]))
    return max(peaks)


def run_size(samples: int, mechanisms: int, cores: int) -> dict[str, float]:
    """Wall seconds and peak MB per stage for one size."""
    out: dict[str, float] = {}
    with tempfile.TemporaryDirectory(prefix="qsm-scaling-") as tmp:
        work = Path(tmp)
        copy_workflow(work)
        overlay = {"sampling": {"n_samples": samples, "n_mechanisms": mechanisms}}
        (work / "size.yaml").write_text(yaml.safe_dump(overlay))
        for stage, target in STAGES.items():
            cmd = [sys.executable, "-m", "snakemake", target, "--cores", str(cores)]
            cmd += ["--configfile", "config/config.yaml", "size.yaml"]
            start = time.perf_counter()
            subprocess.run(cmd, cwd=work, check=True, capture_output=True)
            out[f"stage {stage} s"] = time.perf_counter() - start
            out[f"stage {stage} MB"] = peak_mb(work, stage)
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--base-samples", type=int, default=20_000)
    parser.add_argument("--base-mechanisms", type=int, default=1_000)
    parser.add_argument("--multiples", type=int, nargs="+", default=[1, 2, 4])
    parser.add_argument("--cores", type=int, default=2)
    parser.add_argument("--project-samples", type=int, default=2_000_000)
    parser.add_argument("--cores-per-node", type=int, default=32)
    args = parser.parse_args()
    rows = []
    for k in args.multiples:
        row = {"k": k, "mechanisms": k * args.base_mechanisms}
        row.update(run_size(k * args.base_samples, k * args.base_mechanisms, args.cores))
        rows.append(row)
        print(row, flush=True)
    table = pd.DataFrame(rows)
    print("\n| mechanisms | " + " | ".join(f"stage {s} (s / MB)" for s in STAGES) + " |")
    print("| --- |" + " --- |" * len(STAGES))
    for _, r in table.iterrows():
        cells = [f"{r[f'stage {s} s']:.1f} / {r[f'stage {s} MB']:.0f}" for s in STAGES]
        print(f"| {int(r['mechanisms']):,} | " + " | ".join(cells) + " |")
    marginal = {}
    for s in STAGES:
        k, t = table["k"].to_numpy(float), table[f"stage {s} s"].to_numpy(float)
        b = np.polyfit(np.log(k), np.log(t), 1)[0]
        slope, fixed = np.polyfit(k, t, 1)  # t = fixed + slope * k
        marginal[s] = slope / args.base_mechanisms  # wall s per mechanism (Stage 1: per share)
        print(
            f"stage {s}: time ~ mechanisms^{b:.2f}; linear fit {fixed:.1f} s fixed + "
            f"{1e3 * marginal[s]:.2f} ms wall per mechanism"
        )
    # projection from the marginal (linear) cost: it is what grows; the fixed part does not
    factor = args.project_samples / args.base_samples  # multiples of the base size
    work = {s: marginal[s] * args.base_mechanisms * factor * args.cores for s in STAGES}
    print(
        f"\nProjection of {args.project_samples:,} samples ({factor * args.base_mechanisms:,.0f} "
        f"mechanisms at the same kept share) through the SLURM profile. Assumptions: the "
        f"marginal costs above stay linear; Stages 1-2 split evenly over "
        f"{args.cores_per_node} cores per node; the surrogate fit runs on one node at "
        f"{work['3'] / args.cores:.0f} s; 60 s of scheduling and status polling per stage:"
    )
    for nodes in (1, 4, 16):
        parallel = (work["1"] + work["2"]) / (nodes * args.cores_per_node)
        wall = parallel + work["3"] / args.cores + 3 * 60
        print(f"  {nodes:>2} nodes: about {wall / 60:.0f} min")


if __name__ == "__main__":
    main()
