"""Payload test: passes with the paper's motors, fails when a limit is below the requirement."""

from __future__ import annotations

import numpy as np
import pytest

from qsm.realization.motion import payload
from qsm.report.payload_report import plot_payload_test, summary

DESIGN = np.array([0.40, 0.12, 0.40, 0.20, 0.48, 0.16])
POINTS = [[-0.62, 0.20], [-0.82, 0.02], [-0.70, 0.14]]
FAST = {"segment_duration_s": 0.6, "dwell_s": 0.1}
PAPER = {"torque_limits_Nm": (150.0, 100.0)}  # the paper's motors, as an explicit override


def test_passes_with_generous_limits(tmp_path) -> None:
    exact = payload.PayloadSettings(plant_mass_error=0.0, **FAST, **PAPER)
    res = payload.payload_test(DESIGN, POINTS, settings=exact)
    print(summary(res))
    assert res["passed"] and not res["saturated"]
    # the plant is the model: only the integrator and the constraint softness remain
    assert res["max_tracking_error_deg"] < 0.1
    assert max(res["point_error_mm"]) < 1.0
    assert np.all(np.asarray(res["peak_torque_Nm"]) < res["limit_Nm"])
    assert res["payload_kg"] == 5.0
    n = len(res["t_s"])
    assert res["theta_deg"].shape == res["torque_requested_Nm"].shape == (n, 2)
    assert plot_payload_test(res, tmp_path / "p.png").stat().st_size > 0


def test_model_error_shows_in_tracking_and_soft_gains_fail() -> None:
    errors = [
        payload.payload_test(
            DESIGN, POINTS, settings=payload.PayloadSettings(plant_mass_error=e, **FAST, **PAPER)
        )["max_tracking_error_deg"]
        for e in (0.0, 0.15, 0.3)
    ]
    assert errors[0] < errors[1] < errors[2]  # a heavier plant sags further below the reference
    soft = payload.PayloadSettings(
        plant_mass_error=0.3,
        kp_Nm_rad=(100.0, 50.0),
        ki_Nm_rad_s=(0.0, 0.0),
        kd_Nms_rad=(5.0, 2.5),
        **FAST,
        **PAPER,
    )
    res = payload.payload_test(DESIGN, POINTS, settings=soft)
    assert not res["passed"] and not res["saturated"]
    assert "tracking error" in res["reason"]


def test_integral_action_removes_the_steady_error_at_the_points() -> None:
    """Under PD alone a 15 % heavier plant holds each point short by about 0.15 tau_g / kp (the
    gravity torque the model misses over the stiffness); the integral action removes that
    steady error within the dwell, and 0 gains give PD back."""
    kwargs = {**FAST, "plant_mass_error": 0.15, "dwell_s": 1.0, **PAPER}
    pd = payload.PayloadSettings(ki_Nm_rad_s=(0.0, 0.0), **kwargs)
    pid = payload.PayloadSettings(**kwargs)
    errors = [
        np.asarray(payload.payload_test(DESIGN, POINTS, settings=s)["point_error_mm"])
        for s in (pd, pid)
    ]
    assert errors[0].max() > 0.5  # the PD's steady error, about a millimetre at the tool
    assert errors[1].max() < 0.1 * errors[0].max()


def test_fails_when_the_limit_is_below_the_required_torque() -> None:
    ok = payload.payload_test(DESIGN, POINTS, settings=payload.PayloadSettings(**FAST, **PAPER))
    need = ok["peak_feedforward_Nm"][0]
    low = payload.PayloadSettings(torque_limits_Nm=(0.8 * need, 100.0), **FAST)
    res = payload.payload_test(DESIGN, POINTS, settings=low)
    assert not res["passed"] and res["saturated"]
    assert res["peak_torque_Nm"][0] > res["limit_Nm"][0]
    assert np.abs(res["torque_applied_Nm"][:, 0]).max() <= 0.8 * need + 1e-9
    assert "exceeds the fixed limits" in res["reason"] and "[" not in res["reason"]
    assert "motor 1: " in res["reason"] and " N m at standstill" in res["reason"]
    req = np.abs(res["torque_requested_Nm"])
    assert res["saturated"] == bool((req > res["limit_Nm"]).any())
    assert res["peak_torque_Nm"] == pytest.approx(req.max(axis=0).tolist())


def test_unreachable_task_point_is_an_error() -> None:
    with pytest.raises(ValueError, match="point"):
        payload.payload_test(
            DESIGN, [[-0.62, 0.20], [2.0, 2.0]], settings=payload.PayloadSettings(**PAPER)
        )


def test_motor_inertia_gives_the_kinetic_energy_mujoco_computes() -> None:
    """0.5 v^T M v equals MuJoCo's own kinetic energy of the loop-consistent motion."""
    import mujoco

    from qsm.physics.dynamics import loop_state
    from qsm.physics.mjcf import model_spec

    model = model_spec(DESIGN, payload_kg=5.0).compile()
    model.opt.enableflags |= mujoco.mjtEnableBit.mjENBL_ENERGY
    theta = np.radians([100.0, 20.0])
    inertia = payload.motor_inertia(model, DESIGN, theta)
    np.testing.assert_allclose(inertia, inertia.T, rtol=1e-6)
    data = mujoco.MjData(model)
    for v in ([1.0, 0.0], [0.0, 1.0], [0.7, -1.3]):
        state = loop_state(DESIGN, theta[None], np.array([v]), np.zeros((1, 2)))
        data.qpos[:], data.qvel[:] = state.q[0], state.qd[0]
        mujoco.mj_forward(model, data)
        assert data.energy[1] == pytest.approx(0.5 * np.dot(v, inertia @ v), rel=1e-6)


def test_a_small_light_arm_passes_with_the_paper_motors() -> None:
    """The crank of a 0.2 m arm carrying 1 kg has so little inertia that the default gains,
    stepped at the model's time step, diverged (837 N m requested); the step is cut instead."""
    small = np.array([0.2149, 0.0700, 0.2485, 0.1111, 0.1744, 0.0720])
    res = payload.payload_test(
        small,
        [[-0.38, 0.05], [-0.30, 0.05]],
        settings=payload.PayloadSettings(payload_kg=1.0, **PAPER),
    )
    assert res["passed"], res["reason"]
    assert res["substeps"] > 1 and max(res["peak_torque_Nm"]) < 10.0
    big = payload.payload_test(DESIGN, POINTS, settings=payload.PayloadSettings(**FAST, **PAPER))
    assert big["substeps"] == 1  # the default design keeps the model's step


MOTOR = """key,manufacturer,ID,type,V,k_t,R,L,mass,inertia,omega_nl,I_nl,I_nom,max_int_torque,\
max_int_speed,max_cont_speed,max_cont_power
"""
GEAR = """key,manufacturer,ID,type,stages,ratio,mass,inertia,efficiency,direction,\
max_int_torque,max_cont_torque
"""


def _catalogue(folder, stalls):
    """One 10:1 gearbox (efficiency 0.8) and a DC motor per stall torque (N m): V = 10 V,
    R = 1 ohm, k_t = stall / 10, no-load speed 1e4 rad/s (a flat line over the test's speeds),
    rotor inertia 1e-6 kg m^2 (1e-4 kg m^2 at the joint)."""
    from qsm.embodiment.drives.catalogue import read_catalogue

    folder.mkdir()
    rows = [
        f"M{i},Test,M{i},DC,10,{t / 10},1,0,1,1e-6,1e4,,100,,,,\n" for i, t in enumerate(stalls)
    ]
    (folder / "motors.csv").write_text(MOTOR + "".join(rows))
    (folder / "gearboxes.csv").write_text(GEAR + "G10,Test,G10,planetary,1,10,0.1,0,0.8,1,,\n")
    (folder / "compatibility.csv").write_text("".join(f"M{i},G10\n" for i in range(len(stalls))))
    return read_catalogue(folder)


def test_output_envelope_by_hand(tmp_path) -> None:
    from qsm.embodiment.drives.envelope import OutputEnvelope

    cat = _catalogue(tmp_path / "c", [2.0])
    env = OutputEnvelope.of(cat, "M0", "G10")
    # driving at 100 rad/s at the joint: motor at 1000 rad/s, line 2 (1 - 1000 / 1e4) = 1.8 N m,
    # at the joint 0.8 x 10 x 1.8 = 14.4 N m; back-driven: 10 x 2 / 0.8 = 25 N m
    assert float(env.limit(5.0, 100.0)) == pytest.approx(14.4)
    assert float(env.limit(-5.0, 100.0)) == pytest.approx(25.0)
    assert float(env.limit(1.0, 0.0)) == pytest.approx(16.0)
    assert env.reflected_inertia == pytest.approx(1e-6 * 100)


def test_payload_test_fails_with_a_drive_just_too_weak_and_passes_with_the_next(tmp_path):
    from qsm.embodiment.drives.envelope import OutputEnvelope

    # what the arm needs, with generous fixed limits (the plant 15 % heavier than the model)
    need = payload.payload_test(DESIGN, POINTS, settings=payload.PayloadSettings(**FAST, **PAPER))
    peak1 = need["peak_torque_Nm"][0]
    # motor 1's drives give 0.9 and 1.25 x that at standstill (0.8 x 10 x stall), motor 2's
    # plenty
    stalls = [0.9 * peak1 / 8, 1.25 * peak1 / 8, 100.0]
    cat = _catalogue(tmp_path / "c", stalls)
    strong2 = OutputEnvelope.of(cat, "M2", "G10")
    settings = payload.PayloadSettings(**FAST)
    weak = payload.payload_test(
        DESIGN, POINTS, settings=settings, drives=[OutputEnvelope.of(cat, "M0", "G10"), strong2]
    )
    assert not weak["passed"] and weak["saturated"]
    assert "envelopes" in weak["reason"]
    assert weak["limit_Nm"][0] == pytest.approx(0.9 * peak1)
    # saturated on the envelope: never more than available (back-driven allows 1 / 0.8^2 more)
    applied, available = np.abs(weak["torque_applied_Nm"]), weak["torque_available_Nm"]
    assert np.all(applied <= available + 1e-9)
    assert available[:, 0].max() <= 0.9 * peak1 / 0.8**2 + 1e-9
    good = payload.payload_test(
        DESIGN, POINTS, settings=settings, drives=[OutputEnvelope.of(cat, "M1", "G10"), strong2]
    )
    assert good["passed"], good["reason"]
    assert good["reflected_inertia_kgm2"] == pytest.approx([1e-4, 1e-4])
    assert good["limits_from"] == "drives" and good["drives"][0] == "Test M1 + Test G10"


def test_many_task_points_visit_a_bounded_subset() -> None:
    """2,000 points in the task region: the test visits the points visited_points picks (at
    most 8), so it lasts as long as with those points given alone."""
    from qsm.physics.task_points import MAX_VISITED_POINTS, visited_points

    rng = np.random.default_rng(3)
    centre, radius = np.array([-0.70, 0.10]), 0.06
    angle, r = rng.uniform(0, 2 * np.pi, 2000), radius * np.sqrt(rng.uniform(0, 1, 2000))
    many = centre + np.column_stack([r * np.cos(angle), r * np.sin(angle)])
    settings = payload.PayloadSettings(**FAST, **PAPER)
    subset = many[visited_points(many)]
    assert len(subset) <= MAX_VISITED_POINTS
    full = payload.payload_test(DESIGN, many, settings=settings)
    alone = payload.payload_test(DESIGN, subset, settings=settings)
    assert full["duration_s"] == pytest.approx(alone["duration_s"])
    assert len(full["point_error_mm"]) == len(alone["point_error_mm"])
