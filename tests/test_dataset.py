"""Stage 2 wiring: gathering shards, settings from the config, the command line."""

import json
import subprocess
import sys

import mujoco
import numpy as np
import pandas as pd
import pytest

from qsm.config.reading import load_config
from qsm.config.settings import physics
from qsm.dataset.columns import (
    DATASET_COLUMNS,
    DRIVE_COLUMNS,
    DYNAMICS_COLUMNS,
    STIFFNESS_COLUMNS,
    STRENGTH_COLUMNS,
)
from qsm.dataset.gathering import DatasetError, check_coverage, gather, gathered_batches
from qsm.mechanisms.scale import MECHANISM_COLUMNS
from qsm.physics.duty import duty_cycle
from qsm.physics.dynamics import joint_torques, loop_state
from qsm.physics.kinematics import DESIGN_NAMES, pose
from qsm.workflow.tables import read_table, table_schema, write_batches, write_table


def mechanisms(ids):
    table = pd.DataFrame({c: np.linspace(0.1, 0.2, len(ids)) for c in MECHANISM_COLUMNS})
    table["mechanism_id"] = ids
    return table


def shard(ids, status="ok"):
    return pd.DataFrame({"mechanism_id": ids, "tau1_Nm": 1.0, "tau2_Nm": 2.0, "status": status})


def test_gather_keeps_the_mechanism_order_and_every_status():
    table = mechanisms([5, 3, 9, 1])
    parts = [shard([9, 1]), shard([5], status="singular"), shard([3])]
    columns = ["mechanism_id", *DYNAMICS_COLUMNS, *STRENGTH_COLUMNS, *DRIVE_COLUMNS]
    columns += list(STIFFNESS_COLUMNS)
    full = [p.reindex(columns=columns) for p in parts]
    for p, src in zip(full, parts, strict=True):
        p["status"] = src["status"].to_numpy()
    out = gather(table, full)
    assert list(out["mechanism_id"]) == [5, 3, 9, 1]
    assert list(out["status"]) == ["singular", "ok", "ok", "ok"]


def test_a_dataset_written_shard_by_shard_is_the_gathered_one(tmp_path):
    """Shards in the mechanisms' order, the first with no failure (its reasons all null), joined
    and written one at a time with the schema of all the files, read back as the whole join."""
    columns = ["mechanism_id", *DYNAMICS_COLUMNS, *STRENGTH_COLUMNS, *DRIVE_COLUMNS]
    columns += list(STIFFNESS_COLUMNS)
    table = mechanisms([5, 3, 9, 1])
    parts = [shard([5, 3]), shard([9, 1], status="singular")]
    full = [p.reindex(columns=columns) for p in parts]
    for p, src in zip(full, parts, strict=True):
        p["status"] = src["status"].to_numpy()
    full[1]["status_reason"] = "theta1=1.2: the coupler and rocker align"
    paths = [tmp_path / "mechanisms.parquet", tmp_path / "a.parquet", tmp_path / "b.parquet"]
    for frame, path in zip([table, *full], paths, strict=True):
        write_table(frame, path)
    assert check_coverage(table["mechanism_id"], [p["mechanism_id"] for p in full])
    assert not check_coverage(table["mechanism_id"], [[9, 1], [5, 3]])  # covered, not in order
    schema = table_schema(paths, DATASET_COLUMNS)
    shards = (read_table(path) for path in paths[1:])
    write_batches(gathered_batches(table, shards), tmp_path / "dataset.parquet", None, schema)
    expected = gather(table, full)
    got = read_table(tmp_path / "dataset.parquet")
    assert list(got["status_reason"].isna()) == [True, True, False, False]
    pd.testing.assert_frame_equal(got, read_table(_written(expected, tmp_path)))


def _written(frame, tmp_path):
    """``frame`` written whole and its path."""
    write_table(frame, tmp_path / "whole.parquet")
    return tmp_path / "whole.parquet"


@pytest.mark.parametrize(
    ("parts", "message"),
    [
        ([[5, 3], [9]], r"missing 1 \(1\)"),
        ([[5, 3], [9, 1], [3]], r"repeated 1 \(3\)"),
        ([[5, 3], [9, 1, 7]], r"unknown 1 \(7\)"),
    ],
)
def test_gather_fails_loudly_unless_every_id_appears_once(parts, message):
    with pytest.raises(DatasetError, match=message):
        gather(mechanisms([5, 3, 9, 1]), [shard(p) for p in parts])


def test_settings_come_from_the_config():
    config = load_config()
    cad = physics.cad(config["cad"], config["material"])
    assert cad.density_kg_m3 == 1040.0 and cad.width_m == config["cad"]["width_m"]
    duty = physics.duty(config["dynamics"]["duty"], config["operating_range"])
    assert (duty.theta1_min_deg, duty.theta1_max_deg, duty.theta2_min_deg) == (45.0, 180.0, -37.5)


def run_cli(*args, cwd=None):
    cmd = [sys.executable, "-m", "qsm", *args]
    return subprocess.run(cmd, capture_output=True, text=True, check=False, cwd=cwd)


def test_evaluate_reports_torques_equal_to_the_library():
    out = run_cli("evaluate", "--ratios", "0.3", "1.0", "0.5", "1.2", "0.4")
    result = json.loads(out.stdout)
    assert result["dynamics_status"] == "ok"
    design = [result["design_m"][n] for n in DESIGN_NAMES]
    config = load_config()
    duty = duty_cycle(physics.duty(config["dynamics"]["duty"], config["operating_range"]))
    # every duty sample, through the public API: the peak is the CLI's figure
    tau = joint_torques(design, duty.theta, duty.dtheta, duty.ddtheta, payload_kg=5.0)
    assert result["tau1_Nm"] == pytest.approx(np.abs(tau[:, 0]).max(), rel=1e-12)
    assert result["tau2_Nm"] == pytest.approx(np.abs(tau[:, 1]).max(), rel=1e-12)
    # and the static holding poses alone give a lower bound
    static = np.abs(tau[duty.static]).max(axis=0)
    assert np.all(static <= [result["tau1_Nm"], result["tau2_Nm"]])


def test_the_exported_mjcf_holds_its_loop(tmp_path):
    """``qsm export --lengths``: the MJCF, driven by the static torques, holds the pose and keeps
    its loop closed."""
    design = np.array([0.4, 0.12, 0.4, 0.2, 0.48, 0.16])
    out = run_cli("export", "--lengths", *map(str, design), "--out", str(tmp_path / "m"))
    assert out.returncode == 0, out.stderr
    assert len(list((tmp_path / "m/stl").glob("*.stl"))) == 4
    paths = {"mjcf": str(tmp_path / "m/model.xml")}
    model = mujoco.MjModel.from_xml_path(paths["mjcf"])
    data = mujoco.MjData(model)
    theta = np.radians([[110.0, 30.0]])
    state = loop_state(design, theta, np.zeros((1, 2)), np.zeros((1, 2)))
    data.qpos[:] = state.q[0]
    flange = json.loads((tmp_path / "m/design.json").read_text())["tool_flange_kg"]
    carried = 5.0 + flange  # the payload and the tool flange at E, as the MJCF has them
    hold = joint_torques(design, theta, np.zeros((1, 2)), np.zeros((1, 2)), payload_kg=carried)[0]
    gap = 0.0
    for _ in range(1000):  # 0.5 s holding the pose with the static torques
        data.ctrl[:] = hold
        mujoco.mj_step(model, data)
        gap = max(gap, np.linalg.norm(data.site("d_upper").xpos - data.site("d_coupler").xpos))
    assert gap < 1e-4  # the loop stays closed (m)
    assert np.degrees(np.abs(data.qpos[[0, 2]] - theta[0])).max() < 0.1  # and the pose holds
    e = pose(design, *theta[0]).E
    np.testing.assert_allclose(data.site("payload").xpos[:2], e, atol=1e-3)
