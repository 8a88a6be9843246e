"""An elastic model of the realised arm in MuJoCo, for its motion: beams of hinged segments,
gearboxes as springs, the loop closed by an equality.

Each beam of the accuracy budget's frame (:data:`qsm.embodiment.stiffness.frame.BEAMS`: the
lower arm A-B, the crank A-C, the coupler C-D and the upper arm's D-B, B-E' and E'-E) is cut into
:data:`SEGMENTS` elements of length l. A hinge at each element's middle joins rigid pieces and
carries a torsional spring ``k = E I f / l`` (I the drawn section's, f the link's plate factor),
so each beam bends as an Euler-Bernoulli beam does (the midpoint rule of its curvature); axial
and shear compliance are left out. Each piece carries its link's mass in proportion to its
length, as a thin rod; the payload is a point mass at E. Each gearbox is a spring of the drive's
torsional stiffness from the motor's commanded angle to its link at A: a position actuator,
the servo holding the rotor. The loop is closed at D by a ``connect`` equality between sites,
as in :mod:`qsm.physics.mjcf`. Damping is proportional to stiffness, ``beta = 2 zeta / omega``,
which gives the mode of angular frequency ``omega`` the damping ratio ``zeta``.

Planar, all hinges about +z, gravity along -y, lengths in m.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np
from mujoco import rollout
from numpy.typing import ArrayLike, NDArray

from qsm.embodiment.stiffness.error_terms import GRAVITY_M_S2
from qsm.physics.kinematics import as_design, pose
from qsm.physics.mjcf import EQ_SOLIMP, EQ_SOLREF, planar_spec
from qsm.realization.accuracy.accuracy_budget import ArmModel

#: Elements per beam.
SEGMENTS = 4
#: Time step (s) of the elastic model: well under the stiffest piece's period.
TIMESTEP_S = 2e-4
#: Each bend hinge's armature is ``k (ARMATURE_STEPS dt)^2``: alone on it, the spring would ring
#: over 2 pi ARMATURE_STEPS steps, so MuJoCo's explicit springs stay stable at the time step
#: (a hinge's own piece may be far lighter); it adds a rotor's inertia to each hinge, which
#: lowers the first mode by about 1 % (``tests/test_elastic_arm.py`` bounds it).
ARMATURE_STEPS = 2.0
#: The joints whose angles the rigid chain sets (the segments' hinges start straight).
CHAIN_JOINTS = ("theta1", "q_upper", "theta2", "q_coupler")
#: How long (s) the elastic model holds each stop after its move.
HOLD_S = 1.5
#: Newton's steps at most, and the share of the first accelerations they leave, to find a rest.
REST_STEPS = 8
REST_TOLERANCE = 1e-9


@dataclass(frozen=True, eq=False)
class ElasticArm:
    """A compiled elastic model: ``model``, the ``design`` (6,) m it was built for, and the
    damping factor ``beta`` (s) on every spring."""

    model: mujoco.MjModel
    design: NDArray[np.float64]
    beta: float

    def rest_qpos(self, theta: ArrayLike) -> NDArray[np.float64]:
        """The model's joint positions (rad) with the motors at ``theta`` (2,) rad and every
        segment straight: the rigid chain's pose."""
        t1, t2 = (float(a) for a in np.asarray(theta, dtype=float))
        p = pose(self.design, t1, t2)
        psi = float(np.arctan2(*(p.D - p.C)[::-1]))
        q = np.zeros(self.model.nq)
        for name, value in zip(CHAIN_JOINTS, (t1, float(p.phi) - t1, t2, psi - t2), strict=True):
            q[self.model.joint(name).qposadr[0]] = value
        return q


@dataclass
class _Pieces:
    """Each body's pieces while the spec is built: its origin in its link's frame (m) and the
    thin rods it carries, (mass kg, start, end) in that frame."""

    origin: dict[str, NDArray[np.float64]]
    rods: dict[str, list[tuple[float, NDArray, NDArray]]]

    def add(self, body: str, origin: ArrayLike) -> None:
        self.origin[body] = np.asarray(origin, dtype=float)
        self.rods[body] = []


def _beam(
    spec_body: mujoco.MjsBody, pieces: _Pieces, start: ArrayLike, end: ArrayLike,
    ei: float, mass: float, name: str, beta: float,
) -> mujoco.MjsBody:  # fmt: skip
    """The beam from ``start`` to ``end`` (link frame, m) hung on ``spec_body``: its
    :data:`SEGMENTS` hinges with their springs, and its pieces' masses; returns the last piece's
    body (where ``end`` lies)."""
    a, b = np.asarray(start, dtype=float), np.asarray(end, dtype=float)
    el = float(np.linalg.norm(b - a)) / SEGMENTS
    k, share = ei / el, mass / SEGMENTS
    body, last, m = spec_body, a, share / 2
    for i in range(SEGMENTS):
        hinge = a + (b - a) * (i + 0.5) / SEGMENTS
        pieces.rods[body.name].append((m, last, hinge))
        child = body.add_body(name=f"{name}_{i}", pos=[*(hinge - pieces.origin[body.name]), 0.0])
        child.add_joint(name=f"{name}_bend_{i}", type=mujoco.mjtJoint.mjJNT_HINGE,
                        axis=[0.0, 0.0, 1.0], stiffness=k, damping=beta * k,
                        armature=ARMATURE_STEPS**2 * k * TIMESTEP_S**2)  # fmt: skip
        pieces.add(child.name, hinge)
        body, last, m = child, hinge, share
    pieces.rods[body.name].append((share / 2, last, b))
    return body


def _set_inertials(spec: mujoco.MjSpec, pieces: _Pieces) -> None:
    """Each body's inertial from its rods (thin, about z) in its own frame."""
    for name, rods in pieces.rods.items():
        origin = pieces.origin[name]
        mass = sum(m for m, _, _ in rods)
        if mass <= 0:
            continue
        com = sum(m * ((s + e) / 2 - origin) for m, s, e in rods) / mass
        izz = sum(
            m * (np.sum((e - s) ** 2) / 12 + np.sum(((s + e) / 2 - origin - com) ** 2))
            for m, s, e in rods
        )
        body = spec.body(name)
        body.explicitinertial = True
        body.mass, body.ipos = mass, [*com, 0.0]
        body.fullinertia = [izz, izz, izz, 0.0, 0.0, 0.0]


def _root(
    parent: mujoco.MjsBody, pieces: _Pieces, name: str, at: ArrayLike, joint: str
) -> mujoco.MjsBody:
    """A link's first body, at ``at`` in ``parent``'s frame, turning on hinge ``joint``."""
    body = parent.add_body(name=name, pos=[*np.asarray(at, dtype=float), 0.0])
    body.add_joint(name=joint, type=mujoco.mjtJoint.mjJNT_HINGE, axis=[0.0, 0.0, 1.0])
    pieces.add(name, (0.0, 0.0))
    return body


def _ei(arm: ArmModel, link: int) -> float:
    """Bending stiffness (N m^2) of ``link``'s printed section: E w^3 t / 12 times its factor."""
    s = arm.sections
    w, t = float(s.width_m[link]), float(s.thickness_m[link])
    return s.youngs_pa * t * w**3 / 12 * float(arm.factor[link])


def elastic_spec(arm: ArmModel, payload_kg: float, beta: float) -> mujoco.MjSpec:
    """The elastic model's spec (module docs) of the realised ``arm`` carrying ``payload_kg``
    (kg) at E, every spring damped by ``beta`` (s) times its stiffness."""
    l1, l2, l3, l4, ee_x, ee_y = (float(v) for v in as_design(arm.design))
    mass = [float(m) for m in arm.inertials.mass_kg]
    spec = planar_spec("qsm_elastic_arm", TIMESTEP_S, GRAVITY_M_S2)
    pieces = _Pieces({}, {})
    lower = _root(spec.worldbody, pieces, "lower_arm", (0.0, 0.0), "theta1")
    b_end = _beam(lower, pieces, (0, 0), (l1, 0), _ei(arm, 0), mass[0], "lower", beta)
    upper = _root(b_end, pieces, "upper_arm", (l1, 0.0) - pieces.origin[b_end.name], "q_upper")
    span = l4 + ee_x + ee_y  # the upper arm's mass along its three beams
    d_end = _beam(upper, pieces, (0, 0), (-l4, 0), _ei(arm, 3), mass[3] * l4 / span, "ud", beta)
    corner = _beam(upper, pieces, (0, 0), (ee_x, 0), _ei(arm, 3), mass[3] * ee_x / span, "ub", beta)
    tool = _beam(corner, pieces, (ee_x, 0), (ee_x, -ee_y), _ei(arm, 3), mass[3] * ee_y / span,
                 "ue", beta)  # fmt: skip
    crank = _root(spec.worldbody, pieces, "crank", (0.0, 0.0), "theta2")
    c_end = _beam(crank, pieces, (0, 0), (l2, 0), _ei(arm, 1), mass[1], "crank", beta)
    coupler = _root(c_end, pieces, "coupler", (l2, 0.0) - pieces.origin[c_end.name], "q_coupler")
    c_d = _beam(coupler, pieces, (0, 0), (l3, 0), _ei(arm, 2), mass[2], "coupler", beta)
    pieces.rods[tool.name].append((payload_kg, np.array([ee_x, -ee_y]), np.array([ee_x, -ee_y])))
    _set_inertials(spec, pieces)
    _sites(spec, pieces, {"d_upper": (d_end, (-l4, 0)), "d_coupler": (c_d, (l3, 0)),
                          "tool": (tool, (ee_x, -ee_y))})  # fmt: skip
    _drives(spec, arm.drive_stiffness, beta)
    spec.add_sensor(name="tool", type=mujoco.mjtSensor.mjSENS_FRAMEPOS,
                    objtype=mujoco.mjtObj.mjOBJ_SITE, objname="tool")  # fmt: skip
    return spec


def _sites(spec: mujoco.MjSpec, pieces: _Pieces, at: dict) -> None:
    """The sites (name: (body, point in its link's frame)) and the loop's equality at D."""
    for name, (body, point) in at.items():
        body.add_site(name=name, pos=[*(np.asarray(point, float) - pieces.origin[body.name]), 0])
    spec.add_equality(name="loop_D", type=mujoco.mjtEq.mjEQ_CONNECT,
                      objtype=mujoco.mjtObj.mjOBJ_SITE, name1="d_coupler", name2="d_upper",
                      solref=EQ_SOLREF, solimp=EQ_SOLIMP)  # fmt: skip


def _drives(spec: mujoco.MjSpec, stiffness: ArrayLike, beta: float) -> None:
    """Each gearbox as a position actuator of its stiffness (N m/rad) on its joint at A."""
    for motor, joint, k in zip(("motor1", "motor2"), ("theta1", "theta2"), stiffness, strict=True):
        act = spec.add_actuator(name=motor, target=joint, trntype=mujoco.mjtTrn.mjTRN_JOINT)
        act.set_to_position(kp=float(k), kv=beta * float(k))


def elastic_arm(arm: ArmModel, payload_kg: float, beta: float) -> ElasticArm:
    """The compiled elastic model (:func:`elastic_spec`)."""
    return ElasticArm(elastic_spec(arm, payload_kg, beta).compile(), as_design(arm.design), beta)


def rest_states(arm: ElasticArm, thetas: ArrayLike) -> NDArray[np.float64]:
    """The model's full physics states (k, nstate) held still with its motors at each of
    ``thetas`` (k, 2) rad: the statics solved by Newton's method from the rigid pose, each step
    from MuJoCo's finite-difference derivative of the accelerations at rest (damping, which
    does not change a rest, set aside meanwhile, so that the step's matrix is M^-1 K)."""
    m, spec = arm.model, mujoco.mjtState.mjSTATE_FULLPHYSICS
    damping, bias = m.dof_damping.copy(), m.actuator_biasprm.copy()
    m.dof_damping[:], m.actuator_biasprm[:, 2] = 0.0, 0.0
    out = []
    try:
        for theta in np.atleast_2d(np.asarray(thetas, dtype=float)):
            d = mujoco.MjData(m)
            d.qpos[:], d.ctrl[:] = arm.rest_qpos(theta), theta
            _newton_rest(m, d)
            state = np.zeros(mujoco.mj_stateSize(m, spec))
            mujoco.mj_getState(m, d, state, spec)
            out.append(state)
    finally:
        m.dof_damping[:], m.actuator_biasprm[:] = damping, bias
    return np.array(out)


def _newton_rest(m: mujoco.MjModel, d: mujoco.MjData) -> None:
    """``d`` moved to rest in place: Newton's steps on the accelerations at zero speed, until
    they fall below :data:`REST_TOLERANCE` of their start or :data:`REST_STEPS` are taken."""
    nv, a = m.nv, np.zeros((2 * m.nv + m.na, 2 * m.nv + m.na))
    d.qvel[:] = 0.0
    mujoco.mj_forward(m, d)
    first = float(np.linalg.norm(d.qacc)) or 1.0
    for _ in range(REST_STEPS):
        if np.linalg.norm(d.qacc) <= REST_TOLERANCE * first:
            break
        mujoco.mjd_transitionFD(m, d, 1e-7, True, a, None, None, None)
        jac = a[nv : 2 * nv, :nv] / m.opt.timestep  # d(qacc)/d(qpos)
        mujoco.mj_integratePos(m, d.qpos, np.linalg.solve(jac, -d.qacc), 1.0)
        mujoco.mj_forward(m, d)


def data_at(arm: ElasticArm, state: ArrayLike, theta: ArrayLike) -> mujoco.MjData:
    """The model's data at full physics ``state`` with its motors commanded to ``theta``."""
    d = mujoco.MjData(arm.model)
    mujoco.mj_setState(arm.model, d, np.asarray(state, float), mujoco.mjtState.mjSTATE_FULLPHYSICS)
    d.ctrl[:] = np.asarray(theta, dtype=float)
    mujoco.mj_forward(arm.model, d)
    return d


def tool_offset_m(arm: ElasticArm, data: mujoco.MjData, theta: ArrayLike) -> NDArray[np.float64]:
    """The tool's place (2,) m in ``data`` less the rigid arm's at motor angles ``theta``."""
    t1, t2 = (float(a) for a in np.asarray(theta, dtype=float))
    return data.site("tool").xpos[:2] - pose(arm.design, t1, t2).E


def first_mode_hz(arm: ElasticArm, data: mujoco.MjData) -> float:
    """The lowest natural frequency (Hz) about the state ``data`` (at rest), from the
    eigenvalues of the linearised step (MuJoCo's finite-difference transition matrix)."""
    m = arm.model
    a = np.zeros((2 * m.nv + m.na, 2 * m.nv + m.na))
    mujoco.mjd_transitionFD(m, data, 1e-6, True, a, None, None, None)
    s = np.log(np.linalg.eigvals(a).astype(complex)) / m.opt.timestep
    f = np.abs(s.imag) / (2 * np.pi)
    return float(f[f > 1e-3].min())


@dataclass(frozen=True)
class ElasticStop:
    """A stop in the elastic model: the tool's ringing about its rest on arrival (``ringing_mm``,
    mm: the largest over the first period after it), the time (s) after which it stays within
    what the tolerance allows (``settling_s``; None: nothing is allowed)."""

    ringing_mm: float
    settling_s: float | None


def _commands(t: NDArray, q: NDArray, step: float, hold_s: float) -> NDArray[np.float64]:
    """The motor angles (M, 2) rad at every model step of ``step`` s over a move sampled at
    times ``t`` (N,) s with angles ``q`` (N, 2), linearly between samples, then held
    ``hold_s`` s at its end."""
    steps = np.arange(round((t[-1] + hold_s) / step) + 1) * step
    return np.stack([np.interp(steps, t, q[:, j]) for j in range(2)], axis=-1)


def stops(
    arm: ElasticArm, moves: list[tuple[NDArray, NDArray]], omegas: ArrayLike, allowed_m: float
) -> list[ElasticStop]:
    """The stop after each move (times (N,) s, motor angles (N, 2) rad) from rest at its start,
    held :data:`HOLD_S` s at its end: the tool's ringing about its rest there and the time after
    the arrival from which it stays within ``allowed_m`` (m); ``omegas`` (rad/s) each stop's
    first mode (the period the ringing is read over, and its decay past the hold)."""
    m, step, n = arm.model, arm.model.opt.timestep, len(moves)
    ends = np.array([q[0] for _, q in moves] + [q[-1] for _, q in moves])
    rests = rest_states(arm, ends)
    commands = [_commands(t - t[0], q, step, HOLD_S) for t, q in moves]
    longest = max(len(c) for c in commands)
    padded = np.array([np.vstack([c, np.repeat(c[-1:], longest - len(c), 0)]) for c in commands])
    _, tool = rollout.rollout(m, mujoco.MjData(m), rests[:n], padded)
    out = []
    for k, ((t, q), c, w, xy) in enumerate(zip(moves, commands, omegas, tool, strict=True)):
        rest = tool_offset_m(arm, data_at(arm, rests[n + k], q[-1]), q[-1])
        arrive = round((t[-1] - t[0]) / step)
        e = xy[arrive : len(c), :2] - pose(arm.design, c[arrive:, 0], c[arrive:, 1]).E - rest
        out.append(_stop(np.linalg.norm(e, axis=-1), w, arm, allowed_m))
    return out


def _stop(ring: NDArray, omega: float, arm: ElasticArm, allowed_m: float) -> ElasticStop:
    """A stop from its ringing (M,) m after the arrival, one sample per model step: the largest
    over its first period (of the mode of angular frequency ``omega``, rad/s), and when it stays
    within ``allowed_m`` (m). Still past it in the hold's last period, the ringing decays from
    there as that mode does, ``e^(-zeta omega t)`` with ``zeta = beta omega / 2``."""
    step = arm.model.opt.timestep
    period = round(2 * np.pi / omega / step)
    over = np.flatnonzero(ring > allowed_m)
    if allowed_m <= 0:
        settle = None  # the static terms leave nothing
    elif not over.size:
        settle = 0.0
    elif over[-1] < len(ring) - period:
        settle = float((over[-1] + 1) * step)
    else:
        envelope = float(ring[-period:].max())
        settle = len(ring) * step + float(np.log(envelope / allowed_m)) / (arm.beta * omega**2 / 2)
    return ElasticStop(1e3 * float(ring[:period].max()), settle)
