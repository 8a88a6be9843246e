"""Payload test: passes with the paper's motors, fails when a limit is below the requirement."""

from __future__ import annotations

import numpy as np
import pytest

from qsm import payload

DESIGN = np.array([0.40, 0.12, 0.40, 0.20, 0.48, 0.16])
POINTS = [[-0.62, 0.20], [-0.82, 0.02], [-0.70, 0.14]]
FAST = {"segment_duration_s": 0.6, "dwell_s": 0.1}


def test_passes_with_generous_limits(tmp_path) -> None:
    res = payload.payload_test(DESIGN, POINTS, settings=payload.PayloadSettings(**FAST))
    print(payload.summary(res))
    assert res["passed"] and not res["saturated"]
    assert res["max_tracking_error_deg"] < 0.1
    assert max(res["point_error_mm"]) < 1.0
    assert np.all(np.asarray(res["peak_torque_Nm"]) < res["limit_Nm"])
    assert res["payload_kg"] == 5.0
    n = len(res["t_s"])
    assert res["theta_deg"].shape == res["torque_requested_Nm"].shape == (n, 2)
    assert payload.plot_payload_test(res, tmp_path / "p.png").stat().st_size > 0


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
