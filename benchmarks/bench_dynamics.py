"""Per-mechanism cost of the dynamics stage (CAD, loop kinematics, inertials, inverse dynamics,
strength check), its multiple of MuJoCo's own floor, and a projection.

The floor is measured in the same process: one ``mj_inverse`` call on a prebuilt model and a
fixed state, timed over many repeats, times the number of duty samples: what one ``mj_inverse``
call per sample costs at least. The stage makes one call per design on a model of many tree
copies (:mod:`qsm.physics.tiled`), so its inverse dynamics can cost less than that floor.

Run: ``python benchmarks/bench_dynamics.py [--designs 200] [--seed 0]``. Random designs: ratios
l2 in [0.18, 0.6], l3 [0.8, 1.3], l4 [0.3, 0.6], ee_x [1.0, 1.4], ee_y [0.2, 0.7] and scale l1 in
[0.3, 0.8] m, kept when the loop closes over the whole operating range.
"""

from __future__ import annotations

import argparse
import math
import time
from concurrent.futures import ProcessPoolExecutor

import numpy as np
import pandas as pd

from qsm.dataset.evaluation import evaluate_table
from qsm.embodiment.drives.drive_checks import DriveCheck
from qsm.embodiment.strength.link_checks import StrengthCheck
from qsm.physics import cad, duty, dynamics, kinematics, mjcf
from qsm.physics.kinematics import DESIGN_COLUMNS

PAPER_MECHANISMS = 11_080
LOW = np.array([0.18, 0.8, 0.3, 1.0, 0.2])
HIGH = np.array([0.6, 1.3, 0.6, 1.4, 0.7])


def random_designs(n: int, seed: int) -> np.ndarray:
    """``n`` scaled designs (n, 6) in m whose loop closes over the operating range."""
    rng = np.random.default_rng(seed)
    kept: list[np.ndarray] = []
    while sum(len(k) for k in kept) < n:
        ratios = rng.uniform(LOW, HIGH, (4 * n, 5))
        ratios = ratios[kinematics.loop_closes_everywhere(ratios, math.radians(217.5))]
        kept.append(kinematics.design_from_ratios(ratios, rng.uniform(0.3, 0.8, len(ratios))))
    return np.concatenate(kept)[:n]


def stage_times(designs: np.ndarray, d: duty.Duty, payload_kg: float) -> dict[str, float]:
    """Mean ms per mechanism of each step of :func:`qsm.physics.dynamics.evaluate_mechanism`."""
    steps = dict.fromkeys(("cad", "loop_kinematics", "body_inertials", "inverse_dynamics"), 0.0)
    settings = cad.DEFAULT_CAD
    for design in designs:
        t0 = time.perf_counter()
        props = cad.mass_properties(design, settings)
        t1 = time.perf_counter()
        state = dynamics.loop_state(design, d.theta, d.dtheta, d.ddtheta)
        t2 = time.perf_counter()
        bodies = mjcf.body_inertials(design, props, payload_kg)
        t3 = time.perf_counter()
        dynamics.tree_inverse_dynamics(design, bodies, state)
        t4 = time.perf_counter()
        for key, dt in zip(steps, (t1 - t0, t2 - t1, t3 - t2, t4 - t3), strict=True):
            steps[key] += dt
    return {k: 1e3 * v / len(designs) for k, v in steps.items()}


def mujoco_floor_ms(design: np.ndarray, d: duty.Duty, payload_kg: float, repeats: int) -> float:
    """ms for ``len(d.theta)`` calls of ``mj_inverse`` on a prebuilt model of ``design``."""
    import mujoco

    model = mjcf.model_spec(design, cad.DEFAULT_CAD, payload_kg).compile()
    model.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_EQUALITY
    data = mujoco.MjData(model)
    state = dynamics.loop_state(design, d.theta[:1], d.dtheta[:1], d.ddtheta[:1])
    data.qpos[:], data.qvel[:], data.qacc[:] = state.q[0], state.qd[0], state.qdd[0]
    mujoco.mj_inverse(model, data)  # warm up
    t0 = time.perf_counter()
    for _ in range(repeats):
        mujoco.mj_inverse(model, data)
    per_call = (time.perf_counter() - t0) / repeats
    return 1e3 * per_call * len(d.theta)


def _table_chunk(designs: np.ndarray) -> pd.DataFrame:
    df = pd.DataFrame(designs, columns=list(DESIGN_COLUMNS))
    return evaluate_table(df, duty.duty_cycle(), payload_kg=5.0)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--designs", type=int, default=200)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    designs = random_designs(args.designs, args.seed)
    d = duty.duty_cycle()
    print(f"{len(designs)} designs, {len(d.theta)} duty samples ({d.static.sum()} static)")

    _table_chunk(designs[:5])  # warm up
    steps = stage_times(designs, d, 5.0)
    for key, ms in steps.items():
        print(f"  {key:<18s} {ms:7.3f} ms/mechanism")
    print(f"  {'sum of steps':<18s} {sum(steps.values()):7.3f} ms/mechanism")

    t0 = time.perf_counter()
    out = _table_chunk(designs)
    serial = (time.perf_counter() - t0) / len(designs)
    print(f"evaluate_table, 1 process: {1e3 * serial:.3f} ms/mechanism, status counts:")
    print(out["status"].value_counts().to_string())
    print(f"  -> {PAPER_MECHANISMS} mechanisms on 2 cores: {serial * PAPER_MECHANISMS / 2:.1f} s")
    floor = np.median([mujoco_floor_ms(x, d, 5.0, 20_000) for x in designs[:5]])
    print(
        f"MuJoCo floor ({len(d.theta)} x mj_inverse on a prebuilt model): {floor:.3f} ms/mechanism;"
        f" the stage takes {1e3 * serial / floor:.2f} x the floor, inverse dynamics alone "
        f"{steps['inverse_dynamics'] / floor:.2f} x"
    )

    with ProcessPoolExecutor(2) as pool:
        list(pool.map(_table_chunk, [designs[:2], designs[2:4]]))  # start the workers
        t0 = time.perf_counter()
        list(pool.map(_table_chunk, np.array_split(designs, 2)))
        wall = time.perf_counter() - t0
    print(
        f"evaluate_table, 2 processes: {1e3 * wall / len(designs):.3f} ms/mechanism wall -> "
        f"{PAPER_MECHANISMS} mechanisms: {wall / len(designs) * PAPER_MECHANISMS:.1f} s"
    )

    check = StrengthCheck(duty=d)
    check.evaluate(designs[:5])  # warm up
    t0 = time.perf_counter()
    check.evaluate(designs)
    strength = (time.perf_counter() - t0) / len(designs)
    print(
        f"strength check (loads, bearings, stresses; in the stage): {1e3 * strength:.3f} "
        f"ms/mechanism = {1e3 * strength / floor:.2f} x the MuJoCo floor "
        f"({100 * strength / serial:.0f} % of the dynamics)"
    )

    drives = DriveCheck(duty=d)
    torques = drives.torques(designs)
    drives.evaluate(designs[:5], (torques[0][:5], torques[1][:5]))  # warm up
    t0 = time.perf_counter()
    drives.evaluate(designs, torques)
    select = (time.perf_counter() - t0) / len(designs)
    print(
        f"drive selection (both motors, default catalogue, from the torques): "
        f"{1e3 * select:.3f} ms/mechanism (goal 0.2)"
    )

    t0 = time.perf_counter()
    for design in designs[:20]:
        cad.link_meshes(design)
    mesh_ms = 1e3 * (time.perf_counter() - t0) / 20
    print(f"optional trimesh solids (STL path, not in the stage): {mesh_ms:.1f} ms/mechanism")


if __name__ == "__main__":
    main()
