"""Drive catalogue and selection (qsm.embodiment.drives), checked against hand computation."""

import json
from dataclasses import replace
from pathlib import Path

import mujoco
import numpy as np
import pytest

from qsm.embodiment.drives.catalogue import (
    CatalogueError,
    default_catalogue_folder,
    read_catalogue,
)
from qsm.embodiment.drives.report import motor_json, motor_of
from qsm.embodiment.drives.selection import offer, select_drives
from qsm.embodiment.drives.utilization import CHECKS, utilization
from qsm.report.drive_text import shortfall
from qsm.report.readiness import drive_problems

MOTORS = """key,manufacturer,ID,type,V,k_t,R,L,mass,inertia,omega_nl,I_nl,I_nom,max_int_torque,\
max_int_speed,max_cont_speed,max_cont_power,source
CU_A,Custom,A,DC,24,0.1,1.0,0.001,0.5,1e-5,200,,2,,300,,,test
CU_B,Custom,B,BLDC,48,0.2,0.5,0.001,2.0,1e-4,240,,10,1.5,,,,test
"""
GEARBOXES = """key,manufacturer,ID,type,stages,ratio,mass,inertia,efficiency,direction,\
max_int_torque,max_cont_torque
CU_G10,Custom,G10,planetary,1,10,0.2,1e-6,0.8,1,20,10
CU_G50,Custom,G50,planetary,2,50,0.4,2e-6,0.5,1,60,30
"""
COMPAT = "CU_A,CU_G10,CU_G50\nCU_B,CU_G1*\n"  # CU_G1* is a prefix key


def write_catalogue(folder: Path, motors=MOTORS, gearboxes=GEARBOXES, compat=COMPAT, ts=None):
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "test_motors.csv").write_text(motors)
    (folder / "test_gearboxes.csv").write_text(gearboxes)
    (folder / "test_compatibility.csv").write_text(compat)
    if ts is not None:
        (folder / "torque_speed.csv").write_text(ts)
    return folder


@pytest.fixture
def three(tmp_path):
    """Three drives: (A, G10) 0.7 kg, (A, G50) 0.9 kg, (B, G10) 2.2 kg."""
    cat = read_catalogue(write_catalogue(tmp_path / "cat"))
    assert list(zip(cat.drives["motor"], cat.drives["gearbox"], strict=True)) == [
        ("CU_A", "CU_G10"),
        ("CU_A", "CU_G50"),
        ("CU_B", "CU_G10"),
    ]
    return cat


def test_drive_table_mass_and_reflected_inertia(three):
    assert three.drives["mass"].to_numpy() == pytest.approx([0.7, 0.9, 2.2])
    # (J_motor + J_gear,in) N^2
    assert three.drives["reflected_inertia"].to_numpy() == pytest.approx(
        [11e-6 * 100, 12e-6 * 2500, 101e-6 * 100]
    )


def test_envelope_rms_speed_and_gear_by_hand(three):
    # constant 8 N m at +5 rad/s (driving)
    u = utilization(three, np.full(4, 8.0), np.full(4, 5.0), np.ones(4))[0]
    # (A, G10): tau_m = 8 / (10 0.8) = 1 N m, w_m = 50 rad/s; stall = 0.1 24 / 1 = 2.4 N m
    assert u[0] == pytest.approx([1 / 2.4 + 50 / 200, 1.0 / 0.2, 50 / 300, 8 / 20, 8 / 10])
    # (A, G50): tau_m = 8 / 25 = 0.32, w_m = 250 beyond the no-load speed
    assert u[1] == pytest.approx([0.32 / 2.4 + 250 / 200, 0.32 / 0.2, 250 / 300, 8 / 60, 8 / 30])
    # (B, G10): stall = 0.2 48 / 0.5 = 19.2 N m, intermittent 1.5 N m, continuous 0.2 10 = 2 N m
    assert 1 / 19.2 + 50 / 240 < 1 / 1.5
    assert u[2] == pytest.approx([1 / 1.5, 1.0 / 2.0, 0.0, 8 / 20, 8 / 10])


def test_back_driven_samples_and_weighted_rms_by_hand(three):
    # 2 N m at +1 rad/s for 3 s (driving), 6 N m at -1 rad/s for 1 s (back-driven)
    u = utilization(three, [2.0, 6.0], [1.0, -1.0], [3.0, 1.0])[0, 0]
    drive, back = 2 / (10 * 0.8), 6 * 0.8 / 10  # motor torque, N m
    rms = np.sqrt((3 * drive**2 + 1 * back**2) / 4)
    # the back-driven sample brakes: no speed term in its envelope, and it is the peak
    peak = max(drive / 2.4 + 10 / 200, back / 2.4)
    assert peak == back / 2.4
    gear_rms = np.sqrt((3 * 2.0**2 + 6.0**2) / 4)
    assert u == pytest.approx([peak, rms / 0.2, 10 / 300, 6 / 20, gear_rms / 10])
    # (B, G10): the back-driven 0.48 N m against the intermittent 1.5 N m is the peak
    u = utilization(three, [2.0, 6.0], [1.0, -1.0], [3.0, 1.0])[0, 2]
    assert u[0] == pytest.approx(6 * 0.8 / 10 / 1.5)


def test_selection_on_three_drives(three):
    tau, omega, w = np.full(3, 3.0), np.full(3, 0.5), np.ones(3)
    # (A, G10) fails RMS: 3 / 8 / 0.2 = 1.875; (A, G50) rms 0.6; (B, G10) worst check 0.3
    light = select_drives(three, tau, omega, w, rule="lightest")
    assert light.choice.tolist() == [1]
    assert light.violation[0] == pytest.approx(0.3 - 1)
    assert light.report(0).margins["motor_rms"] == pytest.approx(1 - 0.6)
    stiff = select_drives(three, tau, omega, w, rule="smallest_inertia")
    assert stiff.choice.tolist() == [2]
    # many designs at once: 8 N m at 5 rad/s has only (B, G10); 30 N m has none
    both = select_drives(
        three, [[3.0] * 3, [8.0] * 3, [30.0] * 3], [[0.5] * 3, [5.0] * 3, [5.0] * 3], w
    )
    assert both.choice.tolist() == [1, 2, -1]
    assert both.violation[1] == pytest.approx(8 / 10 - 1)


def test_no_drive_reports_failing_limit_and_strongest(three):
    sel = select_drives(three, np.full(3, 30.0), np.zeros(3), np.ones(3))
    rep = sel.report(0)
    assert not rep.has_drive
    # (A, G10) worst check: motor RMS 30 / 8 / 0.2 = 18.75; (A, G50): motor RMS 30 / 25 / 0.2 = 6;
    # best (B, G10): motor peak 30 / 8 / 1.5 = 2.5, motor RMS 30 / 8 / 2 = 1.875, gearbox
    # 30 / 20 = 1.5 and 30 / 10 = 3
    assert rep.drive.motor_key == "CU_B"  # the nearest drive
    assert motor_json(rep)["best_drive"]["motor_key"] == "CU_B" and "drive" not in motor_json(rep)
    assert sel.violation[0] == pytest.approx(3 - 1)
    failing = {"motor_peak": 1.5, "motor_rms": 0.875, "gear_peak": 0.5, "gear_rms": 2.0}
    assert rep.failing == pytest.approx(failing)
    # strongest at standstill: (A, G50) min(2.4 50 0.5, 60) = 60 N m
    assert rep.strongest_offer.peak_torque_Nm == pytest.approx(60.0)
    assert rep.strongest.gearbox_key == "CU_G50"
    written = json.loads(json.dumps(motor_json(rep)))
    assert written["strongest_drive"]["peak_torque_Nm"] == pytest.approx(60.0)
    assert motor_of(written) == rep  # the record reads back as it was


def test_torque_speed_table_envelope(tmp_path):
    ts = "motor,speed_rad_s,torque_Nm\nCU_A,0,0.5\nCU_A,10,0.3\nCU_A,20,0.1\n"
    gb = GEARBOXES + "CU_G5,Custom,G5,planetary,1,5,0.1,0,1.0,1,,\n"
    cat = read_catalogue(write_catalogue(tmp_path, gearboxes=gb, compat="CU_A,CU_G5\n", ts=ts))
    # w_m = 15 rad/s: pull-out 0.2 N m; tau_m = 0.8 / 5 = 0.16 N m; speed limit = last speed 20
    u = utilization(cat, [0.8], [3.0], [1.0])[0, 0]
    assert u[0] == pytest.approx(0.16 / 0.2)
    assert u[2] == pytest.approx(15 / 20)
    # above the table: speed fails; the envelope uses the last torque
    u = utilization(cat, [0.4], [5.0], [1.0])[0, 0]
    assert u[[0, 2]] == pytest.approx([0.08 / 0.1, 25 / 20])
    assert offer(cat)[0]["peak_torque_Nm"] == pytest.approx(0.5 * 5)


@pytest.mark.parametrize(
    ("which", "text", "line", "column"),
    [
        ("gearboxes", GEARBOXES.replace(",ratio,", ",ratios,"), 1, "ratio"),
        ("gearboxes", GEARBOXES.replace(",2,50,", ",2,-50,"), 3, "'ratio'"),
        ("motors", MOTORS.replace(",0.5,1e-5,", ",0.5kg,1e-5,"), 2, "'mass'"),
        ("compatibility", "CU_A,CU_G10,CU_G77\n", 1, "column 3"),
        ("compatibility", "CU_A,CU_G10\nCU_C,CU_G10\n", 2, "column 1"),
    ],
)
def test_catalogue_errors_name_file_line_column(tmp_path, which, text, line, column):
    arg = {"gearboxes": "gearboxes", "motors": "motors", "compatibility": "compat"}[which]
    folder = write_catalogue(tmp_path, **{arg: text})
    with pytest.raises(CatalogueError) as err:
        read_catalogue(folder)
    msg = str(err.value)
    assert f"test_{which}.csv" in msg
    assert f"line {line}" in msg
    assert column in msg


def test_a_stepper_without_a_torque_speed_table_is_named_with_its_file_and_line(tmp_path):
    """The DC model describes DC and BLDC motors only: a stepper needs its pull-out curve."""
    motors = MOTORS.replace("CU_B,Custom,B,BLDC,", "CU_B,Custom,B,stepper,")
    with pytest.raises(CatalogueError) as err:
        read_catalogue(write_catalogue(tmp_path / "cat", motors=motors))
    msg = str(err.value)
    assert "test_motors.csv, line 3, column 'type': motor 'CU_B' is of type 'stepper'" in msg
    assert "torque_speed.csv" in msg
    ts = "motor,speed_rad_s,torque_Nm\nCU_B,0,0.5\nCU_B,10,0.3\n"
    cat = read_catalogue(write_catalogue(tmp_path / "with_table", motors=motors, ts=ts))
    assert offer(cat)[2]["top_speed_rad_s"] == pytest.approx(10 / 10)  # the table's last speed


def test_a_catalogue_path_that_is_a_file_is_named_as_one(tmp_path):
    path = write_catalogue(tmp_path / "cat") / "test_motors.csv"
    with pytest.raises(FileNotFoundError, match=r"test_motors\.csv is a file: give the folder"):
        read_catalogue(path)


def test_a_drive_without_a_stated_speed_limit_offers_an_unknown_top_speed(tmp_path):
    """Neither omega_nl nor max_int_speed given: no finite top speed, so None (JSON null)."""
    motors = MOTORS.replace(
        "CU_A,Custom,A,DC,24,0.1,1.0,0.001,0.5,1e-5,200,,2,,300,",
        "CU_A,Custom,A,DC,24,0.1,1.0,0.001,0.5,1e-5,,,2,,,",
    )
    cat = read_catalogue(write_catalogue(tmp_path / "cat", motors=motors))
    tops = [o["top_speed_rad_s"] for o in offer(cat)]
    assert tops[:2] == [None, None] and tops[2] == pytest.approx(240 / 10)


def test_shipped_catalogue_spans_1_to_300_Nm_and_has_the_papers_drive():
    cat = read_catalogue(default_catalogue_folder())
    assert 10 <= len(cat.drives) <= 30
    offers = offer(cat)
    assert min(o["cont_torque_Nm"] for o in offers) <= 1.0
    assert max(o["peak_torque_Nm"] for o in offers) >= 300.0
    steppers = cat.motors.index[cat.motors["type"] == "stepper"]
    nema = cat.drives[cat.drives["motor"].isin(steppers) & (cat.drives["ratio"] == 50)]
    assert len(nema) == 1 and nema["motor"].iloc[0] in cat.torque_speed
    assert (cat.motors["source"] != "").all() and (cat.gearboxes["source"] != "").all()
    # a duty the paper's drive meets: 2 N m at 1 rad/s
    sel = select_drives(cat, np.full(5, 2.0), np.full(5, 1.0), np.ones(5))
    assert sel.choice[0] >= 0 and set(sel.report(0).margins) == set(CHECKS)


def _hinge_models(n_ratio: float, armature: float, j_rotor: float):
    """A link on a hinge with joint ``armature``; the same link with a rotor body geared to it."""
    link = """<body name="link"><joint name="q" type="hinge" axis="0 0 1" {arm}/>
      <inertial pos="0.3 0.1 0" mass="2.0" diaginertia="0.01 0.02 0.03"/></body>"""
    with_armature = f"""<mujoco><option gravity="0 -9.81 0"/><worldbody>
      {link.format(arm=f'armature="{float(armature)!r}"')}</worldbody></mujoco>"""
    rotor = f"""<mujoco><option gravity="0 -9.81 0"/><worldbody>
      {link.format(arm="")}
      <body name="rotor"><joint name="r" type="hinge" axis="0 0 1"/>
        <inertial pos="0 0 0" mass="0.5" diaginertia="{j_rotor} {j_rotor} {j_rotor}"/></body>
      </worldbody><equality><joint joint1="r" joint2="q" polycoef="0 {n_ratio} 0 0 0"/>
      </equality></mujoco>"""
    return mujoco.MjModel.from_xml_string(with_armature), mujoco.MjModel.from_xml_string(rotor)


def test_armature_equals_a_geared_rotor_body(three):
    # drive (A, G10): rotor and gear input 1e-5 + 1e-6 kg m^2 behind 10:1
    n_ratio, j_rotor = 10.0, 11e-6
    arm, rot = _hinge_models(n_ratio, three.drives["reflected_inertia"].iloc[0], j_rotor)
    rot.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_CONSTRAINT  # open tree, exact coupling
    da, dr = mujoco.MjData(arm), mujoco.MjData(rot)
    rng = np.random.default_rng(7)
    for q, v, a in rng.uniform(-2, 2, (5, 3)):
        da.qpos[:], da.qvel[:], da.qacc[:] = q, v, a
        mujoco.mj_inverse(arm, da)
        # the rotor turns N times the link: q_r = N q, and so do its speed and acceleration
        dr.qpos[:], dr.qvel[:], dr.qacc[:] = [q, n_ratio * q], [v, n_ratio * v], [a, n_ratio * a]
        mujoco.mj_inverse(rot, dr)
        # link torque = G^T qfrc with G = d(q, q_r)/dq = (1, N)
        geared = dr.qfrc_inverse[0] + n_ratio * dr.qfrc_inverse[1]
        assert da.qfrc_inverse[0] == pytest.approx(geared, rel=1e-9)
        # the rotor's share is J N^2 qacc (not zero: the check above can fail)
        assert geared - dr.qfrc_inverse[0] == pytest.approx(j_rotor * n_ratio**2 * a, rel=1e-9)


def test_a_drive_that_meets_the_duty_but_not_the_task_or_the_stiffness_says_which(three):
    # 3 N m at 0.5 rad/s: (A, G10) meets the duty's limits (the test above), so any failure
    # is the task's motion or the stiffness; its words name it with its number
    tau, omega, w = np.full(3, 3.0), np.full(3, 0.5), np.ones(3)
    task = select_drives(three, tau, omega, w, also=np.full(3, 0.25))
    rep = task.report(0)
    assert not rep.has_drive and rep.failing == {"task_motion": pytest.approx(0.25)}
    assert shortfall(motor_json(rep)) == "exceeds its task motion limit by 25 %"
    none = select_drives(three, tau, omega, w, allowed=np.zeros(3, bool)).report(0)
    assert none.stiff_enough is False
    assert "as stiff as the tolerance asks" in shortfall(motor_json(none))
    motors = {"motor1": motor_json(replace(none, label="lower arm"))}
    problems = drive_problems(motors)
    assert len(problems) == 1 and "as stiff as the tolerance asks" in problems[0]


def test_the_simulations_scalar_torque_limit_is_the_envelopes():
    """``OutputEnvelope.limit_at`` (plain floats, the simulation's step) gives what ``limit``
    (arrays) gives, for every shipped drive, driving and back-driven, table or DC line."""
    from qsm.embodiment.drives.envelope import OutputEnvelope

    cat = read_catalogue(default_catalogue_folder())
    rng = np.random.default_rng(3)
    for row in cat.drives.itertuples():
        env = OutputEnvelope.of(cat, row.motor, row.gearbox)
        tau, omega = rng.normal(0, 50, 400), rng.normal(0, 3, 400)
        scalar = [env.limit_at(t, w) for t, w in zip(tau, omega, strict=True)]
        np.testing.assert_allclose(scalar, env.limit(tau, omega), rtol=1e-12, atol=1e-12)
