"""The utilisation of every motor-gearbox pair of the catalogue over a joint's duty, all at once.

The duty of one joint is a set of samples: output torque tau (N m), output speed omega (rad/s)
and the time each sample stands for, w (s). Conventions (magnitudes; the gearbox ``direction``
does not matter):

- motor speed w_m = ratio |omega| (rad/s);
- driving samples (tau omega >= 0: power flows from the motor to the load, standstill included):
  motor torque tau_m = |tau| / (ratio eta); back-driven samples (tau omega < 0: the load drives
  the motor through the gear): tau_m = |tau| eta / ratio;
- DC motor (type DC or BLDC, no torque-speed table): stall torque T_s = k_t V / R; a driving
  sample uses u = tau_m / T_s + w_m / omega_nl, the datasheet's straight torque-speed line at V
  (u = 1 on it); a back-driven (braking) sample uses u = tau_m / T_s (the supply then allows at
  least the stall current);
- a motor with a torque-speed table (a stepper's pull-out curve): u = tau_m / T(w_m), T
  interpolated linearly; its speed limit is the table's last speed;
- friction and no-load current are not modelled (the omega_nl line already contains them).

Each drive gets five utilisations (required over allowed, <= 1 meets the limit), in CHECKS order:
motor_peak = max over samples of max(u, tau_m / max_int_torque); motor_rms = rms(tau_m) /
(k_t I_nom), the thermal (continuous) rating, rms weighted by w; motor_speed = max(max w_m /
max_int_speed, rms(w_m) / max_cont_speed); gear_peak = max |tau| / max_int_torque of the
gearbox; gear_rms = rms(tau) / max_cont_torque of the gearbox. A value a check needs that the
catalogue lacks (nan) makes the utilisation infinite.

How: each drive c is checked against its own output torque x = tau + J_c accel (J_c its reflected
inertia; 0 without ``accel``). With s = sign(omega), sigma = s x is >= 0 exactly on driving
samples, so per design and drive one pass over the samples gives the largest driving |x|
(max sigma), the largest back-driven |x| (-min sigma), the driving envelope and the driving and
total mean squares; every check follows from these. Samples at standstill without acceleration
(x = tau, driving, for every drive) reduce to one peak and one mean square per design. A
standstill sample with acceleration (driving whatever its sign) enters twice, with s = +1 and -1:
the copy with sigma >= 0 adds its driving square, the s = +1 copy alone its total square, and the
other copy, back-driven at standstill, gives eta |x| where the driving one gives |x| / eta, so it
changes no maximum as long as eta <= 1 (which the catalogue enforces). A DC motor needs a finite,
positive stall torque and no-load speed, else its envelope is infinite.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from qsm.embodiment.drives.catalogue import Catalogue

CHECKS = ("motor_peak", "motor_rms", "motor_speed", "gear_peak", "gear_rms")
_BLOCK = 1 << 17  # elements of a (designs, drives, samples) block held at once


@dataclass(frozen=True)
class DriveArrays:
    """Per-drive values (C,) in SI units, motor side unless named gear_; ``mass`` (kg) and
    ``reflected_inertia`` (kg m^2 at the output) are the catalogue's drive columns."""

    ratio: np.ndarray
    efficiency: np.ndarray
    stall_torque: np.ndarray  # k_t V / R, N m
    no_load_speed: np.ndarray  # rad/s
    int_torque: np.ndarray  # N m
    cont_torque: np.ndarray  # k_t I_nom, N m
    int_speed: np.ndarray  # rad/s
    cont_speed: np.ndarray  # rad/s
    gear_int_torque: np.ndarray  # N m at the output
    gear_cont_torque: np.ndarray  # N m at the output
    mass: np.ndarray  # kg
    reflected_inertia: np.ndarray  # kg m^2
    tables: dict[int, tuple[np.ndarray, np.ndarray]]  # drive index -> (speed, torque)

    @classmethod
    def of(cls, cat: Catalogue) -> DriveArrays:
        m = cat.motors.loc[cat.drives["motor"]]
        g = cat.gearboxes.loc[cat.drives["gearbox"]]
        col = lambda frame, name: frame[name].to_numpy(dtype=float)  # noqa: E731
        tables = {
            i: cat.torque_speed[k]
            for i, k in enumerate(cat.drives["motor"])
            if k in cat.torque_speed
        }
        int_speed = col(m, "max_int_speed").copy()
        for i, (speed, _) in tables.items():
            int_speed[i] = min(int_speed[i], speed[-1])
        with np.errstate(divide="ignore", invalid="ignore"):
            stall = col(m, "k_t") * col(m, "V") / col(m, "R")
        return cls(
            ratio=col(cat.drives, "ratio"),
            efficiency=col(cat.drives, "efficiency"),
            stall_torque=stall,
            no_load_speed=col(m, "omega_nl"),
            int_torque=col(m, "max_int_torque"),
            cont_torque=col(m, "k_t") * col(m, "I_nom"),
            int_speed=int_speed,
            cont_speed=col(m, "max_cont_speed"),
            gear_int_torque=col(g, "max_int_torque"),
            gear_cont_torque=col(g, "max_cont_torque"),
            mass=col(cat.drives, "mass"),
            reflected_inertia=col(cat.drives, "reflected_inertia"),
            tables=tables,
        )

    def take(self, idx: np.ndarray) -> DriveArrays:
        """The values of drives ``idx`` (indices into the catalogue's drives), in that order."""
        idx = np.asarray(idx, dtype=int)
        where = {int(i): k for k, i in enumerate(idx)}
        fields = {
            name: getattr(self, name)[idx] for name in self.__dataclass_fields__ if name != "tables"
        }
        tables = {where[i]: t for i, t in self.tables.items() if i in where}
        return DriveArrays(**fields, tables=tables)


def utilization(
    cat: Catalogue | DriveArrays,
    tau: np.ndarray,
    omega: np.ndarray,
    weights: np.ndarray,
    accel: np.ndarray | None = None,
) -> np.ndarray:
    """Utilisation (D, C, len(CHECKS)) of every drive for duties (D, N) (or (N,): D = 1).

    tau in N m, omega in rad/s at the joint, weights in s (positive sum per design). ``accel``
    (rad/s^2, shaped as tau), when given, loads drive c with tau + J_c accel, J_c its reflected
    inertia; a drive of unknown (non-finite) J_c then gets infinite utilisations.
    """
    arr = cat if isinstance(cat, DriveArrays) else DriveArrays.of(cat)
    tau, omega, w = duty_arrays(tau, omega, weights)
    acc = None if accel is None else np.broadcast_to(np.asarray(accel, float), tau.shape)
    out = np.empty((tau.shape[0], arr.ratio.size, len(CHECKS)))
    if tau.shape[0] == 0:
        return out
    rows = [x for x in (omega, w, acc) if x is not None]
    one = all((x == x[:1]).all() for x in rows)  # one duty for all designs
    for g in [slice(None)] if one else [slice(d, d + 1) for d in range(tau.shape[0])]:
        out[g] = _one_duty(arr, tau[g], omega[g][0], w[g][0], None if acc is None else acc[g][0])
    return out


def duty_arrays(tau, omega, weights) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``tau`` (N m), ``omega`` (rad/s) and ``weights`` (s) as (D, N) arrays of one shape;
    raises ``ValueError`` when they differ."""
    tau, omega = np.atleast_2d(np.asarray(tau, float)), np.atleast_2d(np.asarray(omega, float))
    w = np.broadcast_to(np.atleast_2d(np.asarray(weights, float)), tau.shape)
    if tau.shape != omega.shape:
        raise ValueError(f"tau {tau.shape} and omega {omega.shape} differ in shape")
    if np.any(w < 0) or np.any(w.sum(axis=1) <= 0):
        raise ValueError("time weights must be >= 0 with a positive sum per design")
    return tau, omega, w


def _one_duty(
    arr: DriveArrays, tau: np.ndarray, omega: np.ndarray, w: np.ndarray, acc: np.ndarray | None
) -> np.ndarray:
    """:func:`utilisation` (D, C, checks) of torques tau (D, N) on one duty: omega, w and acc
    (N,) shared by the designs (see the module's "How")."""
    n_ratio, eta = arr.ratio, arr.efficiency
    wn = w / w.sum()
    inertia = np.zeros(1) if acc is None else arr.reflected_inertia
    unknown = ~np.isfinite(inertia) if acc is not None else np.zeros(n_ratio.size, bool)
    acc = np.zeros_like(omega) if acc is None else acc
    rest = (omega == 0) & (acc == 0)
    move = np.flatnonzero(~rest)
    turn = np.flatnonzero(~rest & (omega == 0))
    cols = np.concatenate([move, turn])
    sign = np.concatenate([np.where(omega[move] < 0, -1.0, 1.0), -np.ones(turn.size)])
    w_all = np.concatenate([wn[move], np.zeros(turn.size)])
    speed = np.abs(omega[cols])
    js = inertia[:, None] * (acc[cols] * sign) + 0.0  # (C or 1, M), no -0.0
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        # the DC envelope of a driving sample is c0 (sigma + slope speed), of a back-driven c1 |x|
        c0 = 1 / (eta * n_ratio * arr.stall_torque)
        c1 = eta / (n_ratio * arr.stall_torque)
        slope = n_ratio / arr.no_load_speed / c0
        dc = np.isfinite(c1) & np.isfinite(slope) & (c0 > 0)
        slope = np.where(dc, slope, 0.0)
        a0 = np.abs(tau[:, rest])
        peak0, ms0 = a0.max(axis=1, initial=0.0)[:, None], _row_sums(a0 * a0 * wn[rest])[:, None]
        pull = {i: np.interp(speed * n_ratio[i], *t) for i, t in arr.tables.items()}
        hi, lo, env, s_all, s_drv, table = _moving(
            arr, tau[:, cols] * sign, js, slope[:, None] * speed, w_all, wn[cols], pull
        )
        drv_peak = np.maximum(hi, peak0)
        ms_drv = s_drv + ms0
        ms_back = np.maximum(s_all + ms0 - ms_drv, 0.0)
        env = np.maximum(c0 * np.maximum(env, drv_peak), lo * c1)
        env[:, ~dc] = np.inf
        for i, (sp, tq) in arr.tables.items():
            tau_m = peak0[:, 0] / eta[i] / n_ratio[i]
            env[:, i] = np.maximum(table[i], np.where(tau_m > 0, tau_m / np.interp(0, sp, tq), 0))
        motor_speed = np.maximum(
            speed.max(initial=0.0) * n_ratio / arr.int_speed,
            np.sqrt(wn @ omega**2) * n_ratio / arr.cont_speed,
        )
        u = np.stack(
            [
                np.maximum(env, np.maximum(drv_peak / eta, lo * eta) / n_ratio / arr.int_torque),
                np.sqrt(ms_drv / eta**2 + ms_back * eta**2) / n_ratio / arr.cont_torque,
                np.broadcast_to(motor_speed, env.shape),
                np.maximum(drv_peak, lo) / arr.gear_int_torque,
                np.broadcast_to(np.sqrt(s_all + ms0) / arr.gear_cont_torque, env.shape),
            ],
            axis=-1,
        )
    u[:, unknown] = np.inf
    return np.where(np.isnan(u), np.inf, u)


def _row_sums(x: np.ndarray) -> np.ndarray:
    """Sums over the last axis of ``x`` (D, ...), design by design: numpy's order of summation
    depends on the array's shape, so one call per design keeps each design's sums the same to
    the bit whatever designs share its block or shard (the determinism of the dataset)."""
    out = np.empty(x.shape[:-1])
    for d in range(x.shape[0]):
        out[d] = x[d].sum(axis=-1)
    return out


def _moving(
    arr: DriveArrays,
    ts: np.ndarray,
    js: np.ndarray,
    spk: np.ndarray,
    w_all: np.ndarray,
    w_drv: np.ndarray,
    pull: dict[int, np.ndarray],
) -> tuple[np.ndarray, ...]:
    """Over the moving samples, sigma = ts (D, M) + js (J, M) with J = C drives or 1: per design
    and J, the largest driving |x| (hi), back-driven |x| (lo) and the driving and total mean
    squares; per design and drive, the largest sigma + spk (C, M) over driving samples (env); per
    table drive i (pull-out torques ``pull[i]`` (M,)), its envelope utilisation (D,). Designs in
    blocks, into buffers reused."""
    n_d, m = ts.shape
    n_j, n_c = js.shape[0], spk.shape[0]
    hi, lo, s_all, s_drv = (np.empty((n_d, n_j)) for _ in range(4))
    env = np.empty((n_d, n_c))
    table = {i: np.empty(n_d) for i in pull}
    step = max(1, _BLOCK // max(1, n_c * m))
    sig, sq, driving = (np.empty((step, n_j, m)) for _ in range(3))
    e = np.empty((step, n_c, m))
    eta, n_ratio = arr.efficiency, arr.ratio
    for start in range(0, n_d, step):  # no masked copies: branches on the sign are slow
        b = slice(start, min(n_d, start + step))
        k = b.stop - b.start
        s, q, dr, ee = sig[:k], sq[:k], driving[:k], e[:k]
        np.add(ts[b, None, :], js, out=s)
        s.max(axis=2, initial=0.0, out=hi[b])
        s.min(axis=2, initial=0.0, out=lo[b])
        np.multiply(s, s, out=q)
        np.multiply(q, w_all, out=q)
        s_all[b] = _row_sums(q)
        np.maximum(s, 0.0, out=q)
        np.multiply(q, q, out=q)
        np.multiply(q, w_drv, out=q)
        s_drv[b] = _row_sums(q)
        np.greater_equal(s, 0.0, out=dr)  # 1.0 on driving samples, else 0.0
        np.add(s, spk, out=ee)
        np.multiply(ee, dr, out=ee)
        ee.max(axis=2, initial=0.0, out=env[b])
        for i, p in pull.items():
            x = s[:, i if n_j > 1 else 0]
            tau_m = np.where(x >= 0, x / eta[i], -x * eta[i]) / n_ratio[i]
            table[i][b] = np.where(tau_m > 0, tau_m / p, 0.0).max(axis=1, initial=0.0)
    return hi, -lo, env, s_all, s_drv, table
