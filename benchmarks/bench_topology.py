"""Time one design's topology optimisation (both links), the torque re-evaluation and the payload
test.  Run: python benchmarks/bench_topology.py"""

from __future__ import annotations

import json
import time

import numpy as np

from qsm.physics import cad, duty
from qsm.realisation import payload, topology

DESIGN = np.array([0.40, 0.12, 0.40, 0.20, 0.48, 0.16])  # m
POINTS = [[-0.62, 0.20], [-0.82, 0.02], [-0.70, 0.02], [-0.82, 0.14], [-0.70, 0.14]]


def main() -> None:
    cs, d = cad.CadSettings(), duty.duty_cycle()
    t0 = time.perf_counter()
    res = topology.optimise_links(DESIGN, cs, 5.0, d)
    t1 = time.perf_counter()
    torques = topology.torques_before_after(DESIGN, cs, 5.0, d, res.props)
    t2 = time.perf_counter()
    test = payload.payload_test(DESIGN, POINTS, cs, res.props)
    t3 = time.perf_counter()
    out = {
        "topology_s": t1 - t0,
        "torques_before_after_s": t2 - t1,
        "payload_test_s": t3 - t2,
        "links": {k: v.summary() for k, v in res.links.items()},
        "torques": torques,
        "payload_test": payload.summary(test),
    }
    print(json.dumps(out, indent=1, default=float))


if __name__ == "__main__":
    main()
