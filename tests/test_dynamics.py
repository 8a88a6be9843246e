"""Closed-chain inverse dynamics: virtual work, forward simulation, duty, failure reporting."""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pandas as pd
import pytest

from qsm.dataset.evaluation import evaluate_table
from qsm.physics import duty, dynamics, kinematics, mjcf
from qsm.physics.kinematics import DESIGN_COLUMNS
from qsm.physics.results import DYNAMICS_COLUMNS

G = mjcf.GRAVITY_M_S2
# (l1, l2, l3, l4, ee_x, ee_y) in m; the loop closes over the whole operating range
DESIGNS = np.array(
    [
        [0.5, 0.15, 0.5, 0.22, 0.6, 0.2],
        [0.35, 0.1, 0.38, 0.14, 0.42, 0.2],
        [0.8, 0.3, 0.8, 0.4, 1.0, 0.45],
    ]
)


def random_poses(rng: np.random.Generator, n: int) -> np.ndarray:
    """Motor angles (n, 2) rad spread over the operating range."""
    t1 = rng.uniform(math.radians(45), math.pi, n)
    return np.column_stack([t1, rng.uniform(math.radians(-37.5), t1)])


def ee_derivatives(design: np.ndarray, th: np.ndarray, dth: np.ndarray, ddth: np.ndarray):
    """J_E (n, 2, 2) and E'' (n, 2) from kinematics.pose by central differences."""
    h = 1e-6
    jac = np.empty((len(th), 2, 2))
    for j in range(2):
        e = np.zeros(2)
        e[j] = h
        plus = kinematics.end_effector(design, *(th + e).T)
        minus = kinematics.end_effector(design, *(th - e).T)
        jac[:, :, j] = (plus - minus) / (2 * h)
    s = 1e-3  # E(theta(s)) along the second-order Taylor path of the motion

    def at(s_: float) -> np.ndarray:
        return kinematics.end_effector(design, *(th + dth * s_ + ddth * s_**2 / 2).T)

    return jac, (at(s) - 2 * at(0.0) + at(-s)) / s**2


@pytest.mark.parametrize("design", DESIGNS)
def test_payload_only_static_torques_equal_virtual_work(design: np.ndarray) -> None:
    rng = np.random.default_rng(1)
    th = random_poses(rng, 60)
    zero = np.zeros_like(th)
    mass = 5.0
    tau = dynamics.joint_torques(design, th, zero, zero, payload_kg=mass, link_density=1e-6)
    jac, _ = ee_derivatives(design, th, zero, zero)
    expected = np.einsum("nij,i->nj", jac, [0.0, mass * G])  # tau = J_E^T (0, m g)
    err = np.abs(tau - expected).max()
    peak = np.abs(expected).max()
    print(f"virtual work: max |tau - J^T (0, m g)| = {err:.2e} N m (peak {peak:.1f} N m)")
    assert err <= 1e-4 * peak


def test_payload_only_dynamic_torques_include_velocity_terms() -> None:
    """Massless links: tau = J_E^T m (E'' + g y), E'' = J theta'' + Jdot theta'."""
    rng = np.random.default_rng(2)
    design, mass = DESIGNS[0], 5.0
    th = random_poses(rng, 50)
    dth, ddth = rng.normal(0, 2.0, th.shape), rng.normal(0, 10.0, th.shape)
    tau = dynamics.joint_torques(design, th, dth, ddth, payload_kg=mass, link_density=1e-6)
    jac, acc = ee_derivatives(design, th, dth, ddth)
    expected = np.einsum("nij,ni->nj", jac, mass * (acc + np.array([0.0, G])))
    assert np.abs(tau - expected).max() <= 1e-4 * np.abs(expected).max()


def test_forward_simulation_tracks_reference() -> None:
    """Torques from the inverse dynamics drive the closed-chain forward model along the duty."""
    design, payload = DESIGNS[0], 5.0
    model = mjcf.build_model(design, payload_kg=payload)
    data = mujoco.MjData(model)
    dt, duration = model.opt.timestep, 0.5
    assert dt == 0.0005 and model.opt.integrator == mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    n = round(duration / dt)
    t = np.arange(n + 1) * dt
    th, dth, ddth = duty.minimum_jerk(np.radians([90, 10]), np.radians([130, 60]), duration, t)
    tau = dynamics.joint_torques(design, th, dth, ddth, payload_kg=payload)
    state = dynamics.loop_state(design, th, dth, ddth)
    data.qpos[:], data.qvel[:] = state.q[0], state.qd[0]
    err = 0.0
    for k in range(n):
        data.ctrl[:] = tau[k]
        mujoco.mj_step(model, data)
        err = max(err, np.abs(data.qpos[[0, 2]] - th[k + 1]).max())
    print(f"forward simulation: max tracking error {math.degrees(err):.4f} deg over {duration} s")
    assert math.degrees(err) < 0.1
    # without the torques the mechanism falls away
    data.qpos[:], data.qvel[:], data.ctrl[:] = state.q[0], state.qd[0], 0.0
    for _ in range(100):
        mujoco.mj_step(model, data)
    assert math.degrees(np.abs(data.qpos[[0, 2]] - th[100]).max()) > 1.0


def test_coupler_force_matches_mujoco_constraint_force() -> None:
    """Static hold: MuJoCo's (soft, so within 1 %) connect force is the computed coupler force."""
    design, payload = DESIGNS[0], 5.0
    th = np.radians([[120.0, 30.0]])
    zero = np.zeros_like(th)
    state = dynamics.loop_state(design, th, zero, zero)
    model = mjcf.build_model(design, payload_kg=payload)
    lam = dynamics.inverse_dynamics(model, design, state)
    data = mujoco.MjData(model)
    data.qpos[:] = state.q[0]
    data.ctrl[:] = lam.tau[0]
    mujoco.mj_forward(model, data)
    np.testing.assert_allclose(data.efc_force[:2], lam.coupler_force[0], rtol=1e-2)


def test_xml_loads_standalone_and_gives_the_same_torques() -> None:
    design = DESIGNS[1]
    model = mujoco.MjModel.from_xml_string(mjcf.mjcf_xml(design, payload_kg=5.0))
    assert (model.nv, model.neq, model.nu) == (4, 1, 2)
    assert np.all(model.geom_contype == 0) and np.all(model.geom_conaffinity == 0)
    d = duty.duty_cycle()
    state = dynamics.loop_state(design, d.theta, d.dtheta, d.ddtheta)
    from_xml = dynamics.inverse_dynamics(model, design, state).tau
    direct = dynamics.joint_torques(design, d.theta, d.dtheta, d.ddtheta, payload_kg=5.0)
    np.testing.assert_allclose(from_xml, direct, atol=1e-4 * np.abs(direct).max())


def test_duty_covers_operating_range() -> None:
    s = duty.DutySettings()
    d = duty.duty_cycle(s)
    n = len(d.theta)
    assert 300 <= n <= 600 and d.static.sum() == s.static_theta1_count * s.static_theta2_count
    deg = np.degrees(d.theta)
    assert deg[:, 0].min() == pytest.approx(45) and deg[:, 0].max() == pytest.approx(180)
    assert deg[:, 1].min() == pytest.approx(-37.5)
    assert np.all(deg[:, 1] <= deg[:, 0] + 1e-9) and np.all(deg[:, 0] >= 45 - 1e-9)
    assert np.abs(np.degrees(d.dtheta)).max() == pytest.approx(s.peak_speed_deg_s)
    assert np.all(d.dtheta[d.static] == 0) and np.all(d.ddtheta[d.static] == 0)
    assert d.weight_s.sum() == pytest.approx(np.nanmax(d.time_s))
    # velocities and accelerations are the time derivatives of the positions
    t = np.linspace(0.0, 2.0, 2001)
    q, dq, ddq = duty.minimum_jerk([0.1, 0.2], [1.0, -0.5], 2.0, t)
    np.testing.assert_allclose(np.gradient(q, t, axis=0)[1:-1], dq[1:-1], atol=1e-5)
    np.testing.assert_allclose(np.gradient(dq, t, axis=0)[1:-1], ddq[1:-1], atol=1e-4)


def test_failures_are_reported_not_lost() -> None:
    rows = [
        DESIGNS[0],
        kinematics.design_from_ratios([0.6, 0.8, 0.3, 1.2, 0.4], 0.5),  # |l3-l4| > 1-l2: opens
        [0.1, 0.02, 0.1, 0.04, 0.12, 0.05],  # too small for the bosses
        [0.8, 0.35, 0.85, 0.4, 1.0, 0.45],  # |l3 - l4| = l1 - l2: coupler and rocker align
        DESIGNS[2],
    ]
    df = pd.DataFrame(rows, columns=list(DESIGN_COLUMNS))
    df.insert(0, "mechanism_id", [10, 11, 12, 13, 14])
    out = evaluate_table(df, duty.duty_cycle(), payload_kg=5.0)
    assert list(out["mechanism_id"]) == [10, 11, 12, 13, 14]
    assert list(out["status"]) == ["ok", "loop_open", "cad_invalid", "singular", "ok"]
    assert "theta1=" in out.loc[1, "status_reason"] and np.isnan(out.loc[1, "tau1_Nm"])
    assert out.loc[1, "mass_crank_kg"] > 0  # the CAD part of a loop_open mechanism is kept
    ok = out[out["status"] == "ok"]
    assert np.all(ok[["tau1_Nm", "tau2_Nm", "coupler_force_peak_N"]] > 0)
    assert np.all(ok["tau1_Nm"] >= ok["tau1_rms_Nm"])
    assert list(out.columns) == ["mechanism_id", *DYNAMICS_COLUMNS]


@pytest.mark.parametrize("design", DESIGNS)
def test_tiled_tree_gives_the_designs_own_model_numbers(design: np.ndarray) -> None:
    """One mj_inverse call on the tiled model (in chunks beyond its size, with rows where the
    loop does not close) equals one call per state on the design's compiled model."""
    from qsm.physics.cad import mass_properties
    from qsm.physics.tiled import TILE_STATES

    rng = np.random.default_rng(7)
    n = 2 * TILE_STATES + 37
    th = random_poses(rng, n)
    state = dynamics.loop_state(design, th, rng.normal(0, 2, (n, 2)), rng.normal(0, 20, (n, 2)))
    state = state._replace(closes=np.arange(n) % 50 != 0)  # rows marked open are skipped
    props = mass_properties(design)
    own = dynamics.inverse_dynamics(
        mjcf.model_spec(design, payload_kg=3.0, props=props).compile(), design, state
    )
    tiled = dynamics.tree_inverse_dynamics(design, mjcf.body_inertials(design, props, 3.0), state)
    scale = np.nanmax(np.abs(own.tau))
    np.testing.assert_allclose(tiled.tau, own.tau, rtol=0, atol=1e-12 * scale)
    np.testing.assert_allclose(
        tiled.coupler_force,
        own.coupler_force,
        rtol=0,
        atol=1e-12 * np.nanmax(np.abs(own.coupler_force)),
    )
    assert np.array_equal(np.isnan(tiled.tau[:, 0]), ~state.closes)


def test_a_shard_evaluated_in_chunks_gives_the_same_table() -> None:
    """The rows of a shard evaluated 2 at a time (a failing row among them, a chunk of one at
    the end) give the table evaluated whole: each row's numbers are its own (to 1e-12, as
    numpy's vectorised and scalar loops may round a last bit apart on another CPU)."""
    from qsm.config.reading import load_config
    from qsm.config.settings.dataset import dataset_of
    from qsm.dataset.evaluation import evaluate_shard

    settings = dataset_of(load_config())
    rows = [*DESIGNS, [0.1, 0.02, 0.1, 0.04, 0.12, 0.05], DESIGNS[1]]  # the 4th: too small
    df = pd.DataFrame(rows, columns=list(DESIGN_COLUMNS))
    df.insert(0, "mechanism_id", range(len(rows)))
    whole = evaluate_shard(df, settings, chunk_rows=len(rows))
    assert list(whole["status"]) == ["ok", "ok", "ok", "cad_invalid", "ok"]
    chunked = evaluate_shard(df, settings, chunk_rows=2)
    pd.testing.assert_frame_equal(chunked, whole, check_exact=False, rtol=1e-12)


def test_loop_states_solved_in_batches_are_each_designs_own() -> None:
    """The loop states of designs solved :data:`LOOP_BATCH` at a time (more designs than one
    batch, some whose loop opens at some poses) are each design's own call, field by field
    (to 1e-12: numpy's vectorised and scalar loops may round a last bit apart on another CPU)."""
    rng = np.random.default_rng(3)
    ratios = rng.uniform([0.1, 0.5, 0.1, 0.3, 0.05], [0.6, 1.5, 0.6, 1.5, 0.8], (70, 5))
    designs = np.array([kinematics.design_from_ratios(r, rng.uniform(0.3, 0.9)) for r in ratios])
    designs[[5, 66]] = kinematics.design_from_ratios([0.6, 0.8, 0.3, 1.2, 0.4], 0.5)  # opens
    cycle = duty.duty_cycle()
    batched = list(dynamics.loop_states(designs, cycle))
    assert len(batched) == len(designs) > dynamics.LOOP_BATCH
    for design, state in zip(designs, batched, strict=True):
        own = dynamics.loop_state(design, cycle.theta, cycle.dtheta, cycle.ddtheta)
        np.testing.assert_array_equal(state.closes, own.closes)
        for got, expected in zip(state, own, strict=True):
            np.testing.assert_allclose(got, expected, rtol=1e-12, atol=0, equal_nan=True)
    assert not batched[5].closes.all() and batched[0].q.shape == (len(cycle.theta), 4)
