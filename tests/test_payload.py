"""Payload test: passes with the paper's motors, fails when a limit is below the requirement."""

from __future__ import annotations

import numpy as np
import pytest

from qsm import payload

DESIGN = np.array([0.40, 0.12, 0.40, 0.20, 0.48, 0.16])
POINTS = [[-0.62, 0.20], [-0.82, 0.02], [-0.70, 0.14]]
FAST = {"segment_duration_s": 0.6, "dwell_s": 0.1}


def test_passes_with_generous_limits(tmp_path) -> None:
    exact = payload.PayloadSettings(plant_mass_error=0.0, **FAST)
    res = payload.payload_test(DESIGN, POINTS, settings=exact)
    print(payload.summary(res))
    assert res["passed"] and not res["saturated"]
    # the plant is the model: only the integrator and the constraint softness remain
    assert res["max_tracking_error_deg"] < 0.1
    assert max(res["point_error_mm"]) < 1.0
    assert np.all(np.asarray(res["peak_torque_Nm"]) < res["limit_Nm"])
    assert res["payload_kg"] == 5.0
    n = len(res["t_s"])
    assert res["theta_deg"].shape == res["torque_requested_Nm"].shape == (n, 2)
    assert payload.plot_payload_test(res, tmp_path / "p.png").stat().st_size > 0


def test_model_error_shows_in_tracking_and_soft_gains_fail() -> None:
    errors = [
        payload.payload_test(
            DESIGN, POINTS, settings=payload.PayloadSettings(plant_mass_error=e, **FAST)
        )["max_tracking_error_deg"]
        for e in (0.0, 0.15, 0.3)
    ]
    assert errors[0] < errors[1] < errors[2]  # a heavier plant sags further below the reference
    soft = payload.PayloadSettings(
        plant_mass_error=0.3, kp_Nm_rad=(100.0, 50.0), kd_Nms_rad=(5.0, 2.5), **FAST
    )
    res = payload.payload_test(DESIGN, POINTS, settings=soft)
    assert not res["passed"] and not res["saturated"]
    assert "tracking error" in res["reason"]


def test_fails_when_the_limit_is_below_the_required_torque() -> None:
    ok = payload.payload_test(DESIGN, POINTS, settings=payload.PayloadSettings(**FAST))
    need = ok["peak_feedforward_Nm"][0]
    low = payload.PayloadSettings(torque_limits_Nm=(0.8 * need, 100.0), **FAST)
    res = payload.payload_test(DESIGN, POINTS, settings=low)
    assert not res["passed"] and res["saturated"]
    assert res["peak_torque_Nm"][0] > res["limit_Nm"][0]
    assert np.abs(res["torque_applied_Nm"][:, 0]).max() <= 0.8 * need + 1e-9
    assert "exceeds the limit" in res["reason"]
    req = np.abs(res["torque_requested_Nm"])
    assert res["saturated"] == bool((req > res["limit_Nm"]).any())
    assert res["peak_torque_Nm"] == pytest.approx(req.max(axis=0).tolist())


def test_unreachable_task_point_is_an_error() -> None:
    with pytest.raises(ValueError, match="point"):
        payload.payload_test(DESIGN, [[-0.62, 0.20], [2.0, 2.0]])
