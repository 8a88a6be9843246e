"""config/test.yaml locally and through profiles/slurm on a real SLURM, interleaved, same machine.

Each round runs, in a fresh copy of the workflow each time: the local run (``--cores 2``), then
every SLURM variant. Variants:

- ``profile``: profiles/slurm as committed (one SLURM job per shard);
- ``arrays``: the same, but the shard rules as job arrays (``slurm-array-jobs``);
- ``shard-groups``: the same, but the shard rules as group jobs of ``--group-size`` shards;
- ``no-groups``: the same, without any groups (one SLURM job per cluster rule);
- ``before``: the workflow and profile of ``--before`` (default cf17537, before issue 12), with
  the account and partition written into its profile and ``--cores 2`` added (without it the
  dynamics group asks for 3 CPUs and never starts on a 2-CPU node).

It prints each run's wall time, its SLURM job count (from ``sacct``) and whether
results/dataset.parquet equals the first local run's byte for byte, then the medians and their
ratio to the local median. SLURM must be up (``scripts/slurm_local.sh start``); the account and
partition come from SBATCH_ACCOUNT / SBATCH_PARTITION (default qsm / debug, as the script sets).

With ``--config default`` the runs use config/config.yaml alone (the paper's scale); with
``--prepare TARGET`` one local run builds TARGET first and every run starts from a copy of it;
``--target`` limits the runs to one target. The shard stages at the paper's scale:

    python benchmarks/bench_slurm.py --config default --prepare select_mechanisms \
        --target gather_dataset

    python benchmarks/bench_slurm.py [--rounds 2] [--variants profile arrays] [--before REV]

``--project STEP_SECONDS`` runs nothing: it projects the paper's run and a 10x run through the
profile on N nodes from the growth table of docs/performance.md and this cost of one cluster
step (see ``project``).
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parents[1]
SHARD_RULES = ("fit_task", "dynamics", "eta_derivatives_shard")
# benchmarks/LOG.md, 2026-11-22, growth with the number of mechanisms (2 cores, the default config):
# marginal wall seconds per mechanism from the growth table (bench_scaling.py, 5,000-20,000
# mechanisms) for Stages 1-3; the eta derivatives, 2 shards of 15.5 s for 11,080 mechanisms; the
# jobs whose cost does not grow with the mechanisms, in seconds.
MARGINAL_WALL_S = {"stage 1": 0.48e-3, "stage 2": 0.57e-3, "surrogate": 0.08e-3}
DERIVATIVES_CPU_S = 2 * 15.5 / 11_080
FIXED_S = {"surrogate": 4.7, "optimize": 6.3 + 11.6, "verify": 2 * 2.1, "realise": 12.3 + 2.1}
CLUSTER_STEPS = 5  # prepare, fit_task, dynamics, fronts, realise: the critical path's SLURM jobs


def copy_tree(source: Path, dest: Path) -> None:
    """What a run needs (Snakefile, workflow, config, profiles, src) from a checkout."""
    dest.mkdir(parents=True)
    shutil.copy2(source / "Snakefile", dest / "Snakefile")
    for name in ("workflow", "config", ".test", "profiles", "src"):
        shutil.copytree(source / name, dest / name, symlinks=True)


def edit_profile(work: Path, variant: str, group_size: int) -> None:
    """Rewrite the copy's profiles/slurm/config.yaml for ``variant``."""
    path = work / "profiles/slurm/config.yaml"
    profile = yaml.safe_load(path.read_text())
    if variant == "arrays":
        profile["slurm-array-jobs"] = ",".join(SHARD_RULES)
    if variant == "shard-groups":
        profile.setdefault("groups", {}).update({rule: f"{rule}_shards" for rule in SHARD_RULES})
        profile["group-components"] = {f"{rule}_shards": group_size for rule in SHARD_RULES}
    if variant == "no-groups":
        profile.pop("groups", None)
        profile.pop("group-components", None)
    if variant == "before":
        resources = profile["default-resources"]
        resources["slurm_account"] = os.environ["SBATCH_ACCOUNT"]
        resources["slurm_partition"] = os.environ["SBATCH_PARTITION"]
    path.write_text(yaml.safe_dump(profile, sort_keys=False))


def slurm_jobs(log: str) -> int:
    """SLURM jobs (array tasks counted one by one) that sacct lists for the run in ``log``."""
    found = re.search(r"SLURM run ID: (\S+)", log)
    if not found:
        return 0
    out = subprocess.run(
        ["sacct", "-X", "-n", "-P", "--name", found.group(1), "-o", "JobID", "-S", "now-1days"],
        capture_output=True,
        text=True,
        check=True,
    )
    return len(out.stdout.split())


def run(variant: str, source: Path, work: Path, args: argparse.Namespace) -> dict:
    """One timed run of ``variant`` in ``work``, a fresh copy of ``source``."""
    shutil.copytree(source, work, symlinks=True)
    cmd = [sys.executable, "-m", "snakemake", *args.target]
    if variant == "local":
        cmd += ["--cores", "2"]
    else:
        edit_profile(work, variant, args.group_size)
        cmd += ["--profile", "profiles/slurm"] + (["--cores", "2"] if variant == "before" else [])
    if args.config == "test":
        cmd += ["--configfile", "config/test.yaml"]
    start = time.perf_counter()
    out = subprocess.run(cmd, cwd=work, capture_output=True, text=True, check=False)
    wall = time.perf_counter() - start
    if out.returncode != 0:
        raise SystemExit(f"{variant} failed:\n{out.stdout[-3000:]}\n{out.stderr[-3000:]}")
    return {
        "variant": variant,
        "wall": wall,
        "jobs": slurm_jobs(out.stdout + out.stderr) if variant != "local" else 0,
        "dataset": (work / "results/dataset.parquet").read_bytes(),
    }


def project(step_s: float, cpus_per_node: int = 32) -> None:
    """Wall time of the paper's run and of 10x through the profile, on 1, 4 and 16 nodes.

    Assumptions: the marginal costs stay linear in the mechanisms; a sharded stage's CPU time is
    twice its wall time on 2 cores and splits evenly over one shard per CPU (Stage 1's sampling
    and filters included, though they run as one job); the eta derivatives run beside Stage 2
    and the fronts, off the critical path; the fronts group runs its five jobs one after another
    (the surrogate grows with the rows); the local rules' seconds count in neither column; every
    cluster step on the critical path costs ``step_s`` beyond its work (Snakemake start-ups,
    queue, status checks). The local column is the same model on 2 cores.
    """
    print(f"\nProjection ({cpus_per_node} CPUs per node, {step_s:.1f} s per cluster step):")
    print(
        "| run | mechanisms | 2 cores, local (min) | "
        + " | ".join(f"{n} node{'s' if n > 1 else ''} (min)" for n in (1, 4, 16))
        + " |"
    )
    print("| --- | --- | --- |" + " --- |" * 3)
    for name, mechanisms in (("paper", 11_080), ("10x", 110_800)):
        cpu = {s: 2 * MARGINAL_WALL_S[s] * mechanisms for s in ("stage 1", "stage 2")}
        derivatives = DERIVATIVES_CPU_S * mechanisms
        surrogate = FIXED_S["surrogate"] + MARGINAL_WALL_S["surrogate"] * mechanisms
        tail = surrogate + FIXED_S["optimize"] + FIXED_S["verify"] + FIXED_S["realise"]
        local = (cpu["stage 1"] + cpu["stage 2"] + derivatives) / 2 + tail
        cells = []
        for nodes in (1, 4, 16):
            cpus = nodes * cpus_per_node
            wall = CLUSTER_STEPS * step_s + (cpu["stage 1"] + cpu["stage 2"]) / cpus + tail
            cells.append(f"{wall / 60:.1f}")
        print(f"| {name} | {mechanisms:,} | {local / 60:.1f} | " + " | ".join(cells) + " |")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=2)
    parser.add_argument(
        "--variants",
        nargs="+",
        default=["profile", "arrays", "shard-groups"],
        choices=["profile", "arrays", "shard-groups", "no-groups", "before"],
    )
    parser.add_argument("--before", default="cf17537", help="commit of the 'before' variant")
    parser.add_argument("--group-size", type=int, default=2, help="shards per group job")
    parser.add_argument("--config", choices=["test", "default"], default="test")
    parser.add_argument("--prepare", help="a target built locally once, before the runs")
    parser.add_argument("--target", nargs="*", default=[], help="the runs' targets")
    parser.add_argument("--project", type=float, metavar="STEP_SECONDS", help="projection only")
    args = parser.parse_args()
    if args.project is not None:
        project(args.project)
        return
    os.environ.setdefault("SBATCH_ACCOUNT", "qsm")
    os.environ.setdefault("SBATCH_PARTITION", "debug")
    rows = []
    with tempfile.TemporaryDirectory(prefix="bench_slurm_") as tmp_name:
        tmp = Path(tmp_name)
        sources = {"now": tmp / "source-now", "before": tmp / "source-before"}
        copy_tree(ROOT, sources["now"])
        if "before" in args.variants:
            archive = subprocess.run(
                ["git", "archive", args.before], cwd=ROOT, capture_output=True, check=True
            )
            sources["before"].mkdir()
            subprocess.run(["tar", "-x", "-C", sources["before"]], input=archive.stdout, check=True)
        for source in sources.values():
            if args.prepare and source.exists():
                cmd = [sys.executable, "-m", "snakemake", args.prepare, "--cores", "2"]
                if args.config == "test":
                    cmd += ["--configfile", "config/test.yaml"]
                subprocess.run(cmd, cwd=source, capture_output=True, check=True)
        for index in range(args.rounds):
            for variant in ["local", *args.variants]:
                source = sources["before" if variant == "before" else "now"]
                row = run(variant, source, tmp / f"{variant}-{index}", args)
                row["same"] = row["dataset"] == (rows[0]["dataset"] if rows else row["dataset"])
                rows.append(row)
                print(
                    f"round {index + 1} {variant:>12}: {row['wall']:6.1f} s, "
                    f"{row['jobs']:>2} SLURM jobs, dataset identical: {row['same']}",
                    flush=True,
                )
    local = statistics.median(r["wall"] for r in rows if r["variant"] == "local")
    print("\n| run | wall (s), median | SLURM jobs | / local | dataset identical |")
    print("| --- | --- | --- | --- | --- |")
    for variant in ["local", *args.variants]:
        mine = [r for r in rows if r["variant"] == variant]
        wall = statistics.median(r["wall"] for r in mine)
        same = all(r["same"] for r in mine)
        print(f"| {variant} | {wall:.1f} | {mine[0]['jobs']} | {wall / local:.2f} | {same} |")
    print(f"\nmedians of {args.rounds} interleaved rounds, this machine ({os.cpu_count()} CPUs)")


if __name__ == "__main__":
    main()
