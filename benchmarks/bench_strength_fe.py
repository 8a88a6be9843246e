"""Beam model against plane-stress FE of the solid arm plates (tests/reference_fe.py): prints
the tables of docs/strength.md. Usage: python benchmarks/bench_strength_fe.py [--upper-arm]
[--fillet RATIO] [cell_mm ...] (default 4 2 mm cells, both arms, cad.corner_fillet_ratio 0.25;
on an idle machine 1 mm takes about 1 min a design, 0.5 mm about 5 min)."""

from __future__ import annotations

import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from reference_fe import FE_LINKS, compare_design

from qsm.physics.cad import CadSettings

DESIGNS = {
    "T1": [0.5, 0.15, 0.5, 0.22, 0.6, 0.2],
    "T2": [0.35, 0.1, 0.38, 0.14, 0.42, 0.2],
    "T3": [0.8, 0.3, 0.8, 0.4, 1.0, 0.45],
    "D": [0.40, 0.12, 0.40, 0.20, 0.48, 0.16],
}


def main(cells_mm: list[float], links: tuple[str, ...], fillet: float) -> None:
    cad = CadSettings(corner_fillet_ratio=fillet)
    for h in cells_mm:
        print(f"\n## {h:g} mm cells, corner fillet {cad.corner_fillet_m * 1e3:g} mm\n")
        print(
            "| design | link | sample | beam MPa | FE MPa | FE/beam | mid/legs FE/beam"
            " | corner FE MPa | corner FE / corner cuts | corner FE / fillet sections |"
        )
        print("|---|---|---|---|---|---|---|---|---|---|")
        for name, d in DESIGNS.items():
            t = time.perf_counter()
            for r in compare_design(d, cad, cell_size_m=h / 1000, links=links):
                s = {x.label: x for x in r.sections}
                away = [
                    x.fe_pa / x.beam_pa
                    for x in r.sections
                    if "mid-span" in x.label or "the corner" in x.label
                ]
                corner = ["-"] * 3
                if "inside corner E'" in s:
                    k = s["inside corner E'"]
                    fillet_beam = max(
                        s[f"leg {leg} at the fillet"].beam_pa for leg in ("B-E'", "E'-E")
                    )
                    corner = [
                        f"{k.fe_pa / 1e6:.2f}",
                        f"{k.fe_pa / k.beam_pa:.2f}",
                        f"{k.fe_pa / fillet_beam:.2f}",
                    ]
                print(
                    f"| {name} | {r.link} | {r.case} | {r.beam_pa / 1e6:.2f} | {r.fe_pa / 1e6:.2f}"
                    f" | {r.ratio:.3f} | {min(away):.3f}-{max(away):.3f} | "
                    + " | ".join(corner)
                    + " |"
                )
            print(f"<!-- {name}: {time.perf_counter() - t:.1f} s -->", flush=True)


if __name__ == "__main__":
    args = sys.argv[1:]
    links = ("upper_arm",) if "--upper-arm" in args else FE_LINKS
    fillet = 0.25
    if "--fillet" in args:
        i = args.index("--fillet")
        fillet = float(args.pop(i + 1))
    cells = [float(a) for a in args if not a.startswith("--")]
    main(cells or [4.0, 2.0], links, fillet)
