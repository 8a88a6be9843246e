"""The elastic MuJoCo model (qsm.realization.final.elastic_arm) against independent references:
one hinged beam against the cantilever's closed forms, the whole arm against the frame model's
static sag and first mode, and its ringing after a move against the single-mode oscillator."""

import math

import mujoco
import numpy as np
import pytest

from qsm.embodiment.stiffness.error_terms import GRAVITY_M_S2, tool_acceleration
from qsm.embodiment.stiffness.frame import FrameSections, tool_compliance
from qsm.embodiment.stiffness.modes import loaded_first_mode_hz
from qsm.embodiment.strength.loads import Inertials
from qsm.physics.mjcf import planar_spec
from qsm.realization.accuracy.accuracy_budget import ArmModel
from qsm.realization.final import elastic_arm as ea
from qsm.realization.final.settling import amplitude_m, mode_at, response

DESIGN = np.array([0.55, 0.22, 0.5, 0.16, 0.42, 0.12])  # m
SECTIONS = FrameSections(
    np.array([0.07, 0.06, 0.05, 0.06]), np.array([0.035, 0.03, 0.025, 0.03]), 2.2e9, 0.35
)
MASSES = np.array([0.9, 0.3, 0.6, 1.2])  # kg
DRIVES = np.array([2.5e4, 1.5e4])  # N m/rad
POSES = np.radians([[60.0, 150.0], [100.0, 190.0], [140.0, 230.0]])
PAYLOAD = 5.0  # kg
ZETA = 0.02


def _arm(masses=MASSES) -> ArmModel:
    return ArmModel(DESIGN, SECTIONS, np.ones(4), Inertials(masses, np.zeros((4, 2)), np.zeros(4)),
                    DRIVES, np.zeros(2), np.zeros(2), np.zeros(2))  # fmt: skip


def _omega(theta) -> float:
    """The frame's first mode (rad/s) at ``theta``, the rotors held (no reflected inertia)."""
    f = loaded_first_mode_hz(DESIGN, *theta, SECTIONS, MASSES, PAYLOAD, DRIVES, np.zeros(2))
    return 2 * math.pi * float(f)


def _cantilever(length, ei, tip_kg, beam_kg):
    """One beam of the model's segments, clamped at the world, a point mass at its tip."""
    spec = planar_spec("cantilever", ea.TIMESTEP_S, GRAVITY_M_S2)
    pieces = ea._Pieces({"root": np.zeros(2)}, {"root": []})
    root = spec.worldbody.add_body(name="root")
    tip = ea._beam(root, pieces, (0, 0), (length, 0), ei, beam_kg, "beam", 0.0)
    pieces.rods[tip.name].append((tip_kg, np.array([length, 0.0]), np.array([length, 0.0])))
    pieces.rods["root"] = []
    ea._set_inertials(spec, pieces)
    tip.add_site(name="tip", pos=[length - pieces.origin[tip.name][0], 0.0, 0.0])
    return spec.compile()


def test_one_beam_is_the_cantilevers_closed_forms():
    """Tip sag P L^3 / 3EI + w L^4 / 8EI under its weights, and first mode
    sqrt(3 EI / ((M + 0.2357 m) L^3)) (Rayleigh, a tip mass M on a beam of mass m), both
    within 2 %: four hinges at the elements' middles integrate the curvature by the midpoint
    rule."""
    length, ei, tip_kg, beam_kg = 0.5, 2200.0, 5.0, 0.5
    m = _cantilever(length, ei, tip_kg, beam_kg)
    d = mujoco.MjData(m)
    m.dof_damping[:] = 0.05 * m.jnt_stiffness  # settle, then measure
    for _ in range(round(1.0 / m.opt.timestep)):
        mujoco.mj_step(m, d)
    sag = -d.site("tip").xpos[1]
    w = beam_kg * GRAVITY_M_S2 / length
    expected = tip_kg * GRAVITY_M_S2 * length**3 / (3 * ei) + w * length**4 / (8 * ei)
    assert sag == pytest.approx(expected, rel=0.02)
    m.dof_damping[:] = 0.0
    d.qvel[:] = 0.0
    mujoco.mj_forward(m, d)
    a = np.zeros((2 * m.nv, 2 * m.nv))
    mujoco.mjd_transitionFD(m, d, 1e-6, True, a, None, None, None)
    s = np.log(np.linalg.eigvals(a).astype(complex)) / m.opt.timestep
    f = float(np.min(np.abs(s.imag)[np.abs(s.imag) > 1e-3])) / (2 * math.pi)
    rayleigh = math.sqrt(3 * ei / ((tip_kg + 0.2357 * beam_kg) * length**3)) / (2 * math.pi)
    assert f == pytest.approx(rayleigh, rel=0.02)


@pytest.mark.parametrize("pose", range(len(POSES)))
def test_the_arm_sags_and_rings_as_the_frame_model(pose):
    """The payload's share of the tool's rest offset against the frame's compliance times its
    weight, and the first mode against the frame's with the rotors held: both within 10 %."""
    theta = POSES[pose]
    w = _omega(theta)
    offsets = []
    for payload in (0.0, PAYLOAD):
        arm = ea.elastic_arm(_arm(), payload, 2 * ZETA / w)
        data = ea.data_at(arm, ea.rest_states(arm, theta)[0], theta)
        offsets.append(ea.tool_offset_m(arm, data, theta))
    frame = tool_compliance(DESIGN, *theta, SECTIONS, DRIVES) @ [0.0, -PAYLOAD * GRAVITY_M_S2]
    sag = offsets[1] - offsets[0]
    assert np.linalg.norm(sag - frame) <= 0.1 * np.linalg.norm(frame)
    assert ea.first_mode_hz(arm, data) == pytest.approx(w / (2 * math.pi), rel=0.1)


def _quintic(a, b, duration, n=61):
    t = np.linspace(0.0, duration, n)
    u = t / duration
    s, sd = 10 * u**3 - 15 * u**4 + 6 * u**5, (30 * u**2 - 60 * u**3 + 30 * u**4) / duration
    sdd = (60 * u - 180 * u**2 + 120 * u**3) / duration**2
    return t, a + np.outer(s, b - a), np.outer(sd, b - a), np.outer(sdd, b - a)


def test_the_ringing_after_a_move_is_the_single_modes_and_grows_with_its_speed():
    """After a quintic move the tool rings about its rest as the single-mode oscillator driven
    by the payload's inertia does, within 25 % (the links' own inertia drives the elastic model
    too), and the faster move rings more; the ringing stays within what it allows only after
    its settling time."""
    a, b = POSES[0], POSES[1]
    arm = _arm()
    rings = []
    for duration in (1.0, 1.5):
        t, q, qd, qdd = _quintic(a, b, duration)
        mode = mode_at(arm, q[-1], PAYLOAD)
        force = -PAYLOAD * tool_acceleration(DESIGN, q, qd, qdd) @ np.asarray(mode.direction)
        x, v = response(force, mode, ZETA, t[1] - t[0])
        single = 1e3 * amplitude_m(float(x[-1]), float(v[-1]), mode, ZETA)
        elastic = ea.elastic_arm(arm, PAYLOAD, 2 * ZETA / mode.omega)
        stop = ea.stops(elastic, [(t, q)], [mode.omega], 0.5e-3)[0]
        assert stop.ringing_mm == pytest.approx(single, rel=0.25)
        decay = math.log(stop.ringing_mm / 0.5) / (ZETA * mode.omega)
        assert stop.settling_s == pytest.approx(decay, rel=0.35)
        rings.append(stop.ringing_mm)
    assert rings[0] > 2 * rings[1]


def test_a_rest_stays_still_on_a_light_arm_with_soft_drives():
    """The rest Newton's method finds is one: held there, a light arm on soft drives (1.2 kg,
    2.4 kN m/rad, as the AK80-6's, a first mode near 4 Hz that damping barely reaches) moves
    its tool less than 1 um in 0.2 s; a damped settle from the rigid pose had missed it by
    0.8 mm."""
    light = _arm(np.array([0.58, 0.45, 0.3, 0.34]))._replace(drive_stiffness=np.full(2, 2400.0))
    theta = POSES[1]
    arm = ea.elastic_arm(light, 1.2, 0.002)
    data = ea.data_at(arm, ea.rest_states(arm, theta)[0], theta)
    start = ea.tool_offset_m(arm, data, theta)
    assert np.linalg.norm(start) > 1e-3  # it sags: the test shows something
    for _ in range(round(0.2 / arm.model.opt.timestep)):
        mujoco.mj_step(arm.model, data)
    assert np.linalg.norm(ea.tool_offset_m(arm, data, theta) - start) < 1e-6
