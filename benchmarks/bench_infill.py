"""The surrogate's premise, measured on a finished run: the one-shot front, the infilled front
and NSGA-II on the true physics (no surrogate) given as many true evaluations as the dataset and
the infill used, each with its true hypervolume (the verification's: the dataset's ranges,
reference point 1.1, the same for all three) and its cost.

    python benchmarks/bench_infill.py RUN_DIRECTORY [--formulation paper] [--configfile ...]
        [--factor 3]   # the true-physics run at 3x the evaluations (about the same time)

The one-shot front is the infill's round 0 (what ``surrogate.infill.rounds: 0`` gives); its cost
is the dataset's, the training's and the optimisation's up to that round (the rule's log
times); the infilled front costs the whole optimisation. The true-physics run evaluates each
design as the verification does (Stage 1's workspace at the design's scale for eta, the MuJoCo
dynamics for the peak torques; a loop that does not close gets labels far outside the band of
g5..g10, so it is infeasible) under the same constraints, and its front is verified like the
others. Prints one Markdown row; this machine's 2 cores.
"""

from __future__ import annotations

import argparse
import json
import time
from datetime import datetime
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import yaml

from qsm.config.reading import load_config
from qsm.config.settings.optimization import front_of
from qsm.dataset.columns import DATASET_COLUMNS
from qsm.dataset.gathering import ok_rows
from qsm.mechanisms.filters import kinematic_checks
from qsm.optimization.comparison import true_hypervolume
from qsm.optimization.nsga import optimize
from qsm.physics.dynamics import evaluate_mechanism
from qsm.physics.workspace import slice_workspace
from qsm.surrogate.model import load
from qsm.workflow.tables import read_table

STAGES_BEFORE = ("mechanisms", "fit_task", "dynamics", "gather", "train_surrogate")


class TrueModel:
    """The true physics in the surrogate's place: (eta, tau1, tau2) of designs (N, 6) m."""

    def __init__(self, surrogate: Any, fit: Any, check: Any) -> None:
        self.label_mean, self.label_std = surrogate.label_mean, surrogate.label_std
        self.fit, self.check, self.calls = fit, check, 0
        self.far = surrogate.label_mean + 100 * surrogate.label_std  # outside g5..g10's band

    def predict(self, x: np.ndarray) -> np.ndarray:
        x = np.atleast_2d(x)
        self.calls += len(x)
        return np.array([self._one(d) for d in x])

    def _one(self, d: np.ndarray) -> np.ndarray:
        fit, check = self.fit, self.check
        ratios = d[1:] / d[0]
        if not kinematic_checks(ratios, fit.op, fit.min_transmission_angle_deg)["loop_closes"][0]:
            return self.far
        area = slice_workspace(ratios, fit.op, fit.disk.angle, fit.resolution).area * d[0] ** 2
        dyn = evaluate_mechanism(d, check.duty, check.cad, check.payload_kg)
        if dyn["status"] != "ok" or area <= 0:
            return self.far
        return np.array([fit.disk.area / area, dyn["tau1_Nm"], dyn["tau2_Nm"]])


def _job_seconds(results: Path, names: tuple[str, ...]) -> float:
    """The summed run time (s) of the benchmark files of the named rules."""
    total = 0.0
    for name in names:
        for tsv in results.glob(f"benchmarks/{name}*.tsv"):
            total += float(pd.read_csv(tsv, sep="\t")["s"].iloc[-1])
        for tsv in results.glob(f"benchmarks/{name}/*.tsv"):
            total += float(pd.read_csv(tsv, sep="\t")["s"].iloc[-1])
    return total


def _log_times(log: Path) -> tuple[float, float]:
    """Seconds from the optimisation's first log line to its infill round 0, and to its end."""
    stamps = []
    for line in log.read_text().splitlines():
        stamp = datetime.strptime(line[:23], "%Y-%m-%d %H:%M:%S,%f")
        stamps.append((stamp, "infill round 0" in line))
    start = stamps[0][0]
    first = next(s for s, is_round in stamps if is_round)
    return (first - start).total_seconds(), (stamps[-1][0] - start).total_seconds()


def measure(
    run: Path, formulation: str, configfiles: list[Path], factor: float = 1.0
) -> dict[str, Any]:
    """The three fronts' true hypervolumes and costs of a finished run; the true-physics run
    gets ``factor`` times the surrogate's true evaluations."""
    config = load_config(*configfiles)
    res = run / "results"
    dataset = ok_rows(read_table(res / "dataset.parquet", DATASET_COLUMNS))
    rounds = json.loads((res / f"optimization/{formulation}/infill.json").read_text())["rounds"]
    model = load(res / "surrogate/model.json")
    front = front_of(config, formulation)
    fit, check = front.fit, front.strength
    before = _job_seconds(res, STAGES_BEFORE)
    to_round0, whole = _log_times(res / f"logs/optimize/{formulation}.log")
    evaluated = len(read_table(res / "dataset.parquet"))  # every mechanism's dynamics ran
    budget = factor * (evaluated + rounds[-1]["true_evaluations"])
    section = dict(config["optimization"])
    section["generations"] = max(1, int(budget // section["pop_size"]) - 1)
    truth = TrueModel(model, fit, check)
    start = time.perf_counter()
    tables = optimize(formulation, truth, dataset, section, fit, front.ratio_bounds, front.extra)
    direct_s = time.perf_counter() - start
    verified = front.verify(tables.pareto)
    return {
        "one_shot": {"hypervolume": rounds[0]["hypervolume"], "cost_s": before + to_round0,
                     "true_evaluations": evaluated},
        "infilled": {"hypervolume": rounds[-1]["hypervolume"], "cost_s": before + whole,
                     "true_evaluations": evaluated + rounds[-1]["true_evaluations"],
                     "rounds": len(rounds) - 1},
        "true_physics": {"hypervolume": true_hypervolume(verified, dataset),
                         "cost_s": direct_s, "true_evaluations": truth.calls},
    }  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run", type=Path)
    parser.add_argument("--formulation", default="paper")
    parser.add_argument("--configfile", type=Path, nargs="+")
    parser.add_argument("--factor", type=float, default=1.0, help="true-physics budget factor")
    args = parser.parse_args()
    files = args.configfile or [args.run / "config/config.yaml"]
    row = measure(args.run, args.formulation, files, args.factor)
    print(yaml.safe_dump(row, sort_keys=False))
    cells = " | ".join(
        f"{v['hypervolume']:.4f}, {v['true_evaluations']:,} evaluations, {v['cost_s']:.0f} s"
        for v in row.values()
    )
    print(f"| {args.run.name} | {cells} |")


if __name__ == "__main__":
    main()
