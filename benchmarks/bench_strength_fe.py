"""Beam model against plane-stress FE of the solid arm plates (qsm.realization.fe_check): prints
the table of docs/strength.md. Usage: python benchmarks/bench_strength_fe.py [cell_mm ...]
(default 4 2; 1 mm takes about 30-45 s a design, 0.5 mm about 5 min)."""

from __future__ import annotations

import sys
import time

from qsm.realization.fe_check import compare_design

DESIGNS = {
    "T1": [0.5, 0.15, 0.5, 0.22, 0.6, 0.2],
    "T2": [0.35, 0.1, 0.38, 0.14, 0.42, 0.2],
    "T3": [0.8, 0.3, 0.8, 0.4, 1.0, 0.45],
    "D": [0.40, 0.12, 0.40, 0.20, 0.48, 0.16],
}


def main(cells_mm: list[float]) -> None:
    for h in cells_mm:
        print(f"\n## {h:g} mm cells\n")
        print(
            "| design | link | sample | beam MPa | FE MPa | FE/beam"
            " | mid/legs FE/beam | corner FE/beam |"
        )
        print("|---|---|---|---|---|---|---|---|")
        for name, d in DESIGNS.items():
            t = time.perf_counter()
            for r in compare_design(d, cell_size_m=h / 1000):
                away = [
                    s.fe_pa / s.beam_pa
                    for s in r.sections
                    if "mid-span" in s.label or "the corner" in s.label
                ]
                corner = [s.fe_pa / s.beam_pa for s in r.sections if s.label == "inside corner E'"]
                print(
                    f"| {name} | {r.link} | {r.case} | {r.beam_pa / 1e6:.2f} | {r.fe_pa / 1e6:.2f}"
                    f" | {r.ratio:.3f} | {min(away):.3f}-{max(away):.3f} | "
                    + (f"{corner[0]:.2f}" if corner else "-")
                    + " |"
                )
            print(f"<!-- {name}: {time.perf_counter() - t:.1f} s -->")


if __name__ == "__main__":
    main([float(a) for a in sys.argv[1:]] or [4.0, 2.0])
