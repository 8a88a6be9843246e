"""Time one design's topology optimisation (both links), the torque re-evaluation and the payload
test, and the factorisation of its largest stiffness matrix with pyMOTO's default sparse LU
(COLAMD ordering) against ``qsm.realization.topology.fe.SymmetricLU``, interleaved, with residuals.
Run: python benchmarks/bench_topology.py"""

from __future__ import annotations

import json
import time

import numpy as np
import scipy.sparse as sps
from scipy.sparse.linalg import splu

from qsm.physics import cad, duty
from qsm.physics.cad import mass_properties
from qsm.physics.kinematics import as_design
from qsm.realization.motion import payload
from qsm.realization.motion.torques import torques_before_after
from qsm.realization.topology import topology
from qsm.realization.topology.fe import DEFAULT_TOPOLOGY, SymmetricLU, stiffness
from qsm.realization.topology.plate_loads import link_problem, peak_loads
from qsm.report.payload_report import summary

DESIGN = np.array([0.40, 0.12, 0.40, 0.20, 0.48, 0.16])  # m
POINTS = [[-0.62, 0.20], [-0.82, 0.02], [-0.70, 0.02], [-0.82, 0.14], [-0.70, 0.14]]


def factorisations(cs: cad.CadSettings, d: duty.Duty, repeats: int = 5) -> dict[str, float]:
    """Median seconds of factorising and solving the full upper-arm plate's stiffness matrix:
    pyMOTO's default LU and :class:`SymmetricLU`, alternating; relative residuals of each."""
    design = as_design(DESIGN)
    loads = peak_loads(design, cs, 5.0, d, mass_properties(design, cs))
    problem, _ = link_problem(design, cs, "upper_arm", loads["upper_arm"], DEFAULT_TOPOLOGY)
    dom = problem.grid.domain(problem.thickness_m)
    full = (problem.design | problem.solid).astype(float).ravel()
    void = DEFAULT_TOPOLOGY.min_density
    K = sps.csc_matrix(stiffness(dom, problem, DEFAULT_TOPOLOGY)(void + (1 - void) * full))
    f = problem.forces
    times: dict[str, list[float]] = {"default": [], "symmetric": []}
    residual: dict[str, float] = {}
    for _ in range(repeats):
        for name in times:
            start = time.perf_counter()
            u = splu(K).solve(f) if name == "default" else SymmetricLU().update(K).solve(f)
            times[name].append(time.perf_counter() - start)
            residual[name] = float(np.linalg.norm(K @ u - f) / np.linalg.norm(f))
    out = {f"{k}_s": float(np.median(v)) for k, v in times.items()}
    out["ratio"] = out["symmetric_s"] / out["default_s"]
    out["dofs"] = K.shape[0]
    out.update({f"{k}_residual": v for k, v in residual.items()})
    return out


def main() -> None:
    cs, d = cad.CadSettings(), duty.duty_cycle()
    t0 = time.perf_counter()
    res = topology.optimize_links(DESIGN, cs, 5.0, d)
    t1 = time.perf_counter()
    tq = torques_before_after(DESIGN, cs, 5.0, d, res.props)
    t2 = time.perf_counter()
    test = payload.payload_test(DESIGN, POINTS, cs, res.props)
    t3 = time.perf_counter()
    out = {
        "topology_s": t1 - t0,
        "torques_before_after_s": t2 - t1,
        "payload_test_s": t3 - t2,
        "links": {k: v.summary() for k, v in res.links.items()},
        "torques": tq,
        "payload_test": summary(test),
        "factorisation": factorisations(cs, d),
    }
    print(json.dumps(out, indent=1, default=float))


if __name__ == "__main__":
    main()
