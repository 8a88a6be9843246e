"""Accuracy and cost of the workspace slicing against the inverse-kinematics pixel reference.

    python benchmarks/bench_workspace.py [--designs 20] [--pixels 1500]

Prints, for the default resolution and a coarser and a finer one, the median and largest relative
area error over random feasible designs and the time per design (scale search included).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from reference_workspace import pixel_area

from qsm import settings
from qsm.config.reading import load_config
from qsm.mechanisms.scale import FitSettings, fit_design
from qsm.physics.kinematics import design_from_ratios, loop_closes_everywhere
from qsm.physics.workspace import Resolution, slice_workspace


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--designs", type=int, default=20)
    parser.add_argument("--pixels", type=int, default=1500)
    args = parser.parse_args()
    config = load_config()
    fit_settings = settings.fit(
        config["operating_range"], config["task"]["points"], config["scale"], config["workspace"]
    )
    op = fit_settings.op
    rng = np.random.default_rng(0)
    bounds = config["sampling"]["bounds"]
    designs = []
    while len(designs) < args.designs:
        r = np.array([rng.uniform(*bounds[k]) for k in ("l2", "l3", "l4", "ee_x", "ee_y")])
        if r[1] + r[0] < 1 + r[2] and loop_closes_everywhere(r, op.delta_max):
            designs.append(r)
    reference = np.array([pixel_area(design_from_ratios(r), op, args.pixels) for r in designs])
    for res in (Resolution(361, 300), fit_settings.resolution, Resolution(1441, 1200)):
        areas = np.array([slice_workspace(r, op, 0.0, res).area for r in designs])
        err = np.abs(areas / reference - 1)
        start = time.perf_counter()
        for r in designs:
            fit_design(r, FitSettings(op, fit_settings.disk, fit_settings.scale_max, 0.0, res))
        per = (time.perf_counter() - start) / len(designs)
        print(
            f"n_delta={res.n_delta:5d} n_levels={res.n_levels:5d}: area error median "
            f"{np.median(err):.2e}, max {err.max():.2e}; {per * 1e3:.2f} ms per design"
        )


if __name__ == "__main__":
    main()
