"""``qsm evaluate --lengths`` and ``qsm export --lengths``: one design at its own scale."""

import json

import mujoco
import numpy as np
import pytest
import trimesh

from qsm.app.cli import main
from qsm.config.reading import load_config
from qsm.physics.cad import DEFAULT_CAD
from qsm.physics.duty import duty_cycle
from qsm.physics.dynamics import evaluate_mechanism

DESIGN = [0.40, 0.12, 0.40, 0.20, 0.48, 0.16]


def test_evaluate_lengths_gives_the_dynamics_strength_and_drives_of_that_design(capsys):
    assert main(["evaluate", "--lengths", *map(str, DESIGN)]) == 0
    out = json.loads(capsys.readouterr().out)
    direct = evaluate_mechanism(np.array(DESIGN), duty_cycle(), DEFAULT_CAD, 5.0)
    assert out["tau1_Nm"] == pytest.approx(direct["tau1_Nm"], rel=1e-12)
    # one set of keys with --ratios, and every value filled
    assert {"eta", "tau1_Nm", "tau2_Nm", "dynamics_status", "printable"} <= set(out)
    assert not any(k.endswith("_true") or "_true_" in k for k in out)
    assert isinstance(out["printable"], bool)
    assert set(out["strength"]["links"]) == {"lower_arm", "crank", "coupler", "upper_arm"}
    assert isinstance(out["strength"]["holds_loads"], bool)
    assert set(out["drives"]["motors"]) == {"motor1", "motor2"}
    assert out["design_m"]["l1"] == DESIGN[0]


def test_bad_lengths_are_named(capsys):
    assert main(["evaluate", "--lengths", "0.4", "-0.1", "0.4", "0.2", "0.48", "0.16"]) == 2
    assert "--lengths: lengths must be finite and positive (m): l2=-0.1" in capsys.readouterr().err


def test_export_lengths_writes_bored_parts_a_drawing_and_a_closed_home_pose(tmp_path, capsys):
    out = tmp_path / "export"
    code = main(["export", "--lengths", *map(str, DESIGN), "--out", str(out)])
    assert code == 0, capsys.readouterr().err
    record = json.loads((out / "design.json").read_text())
    assert record["source"]["kind"] == "lengths"
    for name, holes in {"lower_arm": 2, "crank": 2, "coupler": 2, "upper_arm": 3}.items():
        mesh = trimesh.load(out / f"stl/{name}.stl")
        assert mesh.is_watertight and (2 - mesh.euler_number) // 2 == holes, name
    assert (out / "drawing.svg").stat().st_size > 0 and (out / "drawing.png").stat().st_size > 0
    model = mujoco.MjModel.from_xml_path(str(out / "model.xml"))
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, model.key("home").id)
    mujoco.mj_forward(model, data)
    assert np.abs(data.efc_pos[: data.ne]).max() < 1e-5  # the loop closes at the home pose (m)
    assert (
        "payload" in (out / "README.md").read_text() and "bore" in (out / "README.md").read_text()
    )
    assert load_config()["task"]["payload_kg"] == record["task"]["payload_kg"]
    budget = record["stiffness"]  # the exported parts' accuracy at the default task, or why not
    assert isinstance(budget["meets_requirements"], bool) and budget["verdict"]
    if "per_point" in budget:
        worst = budget["worst"]["error_budget_mm"]
        assert budget["meets_requirements"] == (worst <= load_config()["task"]["tolerance_mm"])


def test_lengths_in_millimetres_are_refused_naming_the_unit(capsys):
    """297 for l1 is 297 m: refused, saying the lengths are in metres, before any physics."""
    assert main(["evaluate", "--lengths", "297", "112", "350", "175", "261", "106"]) != 0
    err = capsys.readouterr().err
    assert "--lengths" in err and "lengths are in metres" in err and "0.297 m" in err
