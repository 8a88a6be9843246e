"""The one-pass utilisation and selection (qsm.embodiment.drives) against a sample-by-sample
reference written from the conventions of :mod:`qsm.embodiment.drives.utilization`, one drive
at a time, on random duties with every kind of sample."""

from __future__ import annotations

import numpy as np
import pytest
from test_drives import GEARBOXES, MOTORS, write_catalogue

from qsm.embodiment.drives.catalogue import Catalogue, default_catalogue_folder, read_catalogue
from qsm.embodiment.drives.selection import RULES, select_drives
from qsm.embodiment.drives.utilization import utilization

TABLE = "motor,speed_rad_s,torque_Nm\nCU_A,0,0.5\nCU_A,10,0.3\nCU_A,20,0.1\n"


def reference(cat: Catalogue, tau, omega, w, accel=None) -> np.ndarray:
    """Utilisation (D, C, 5), drive by drive and design by design, straight from the datasheet
    values: x = tau + J accel, driving where x omega >= 0."""
    out = np.empty((tau.shape[0], len(cat.drives), 5))
    for c, row in enumerate(cat.drives.itertuples()):
        m, g = cat.motors.loc[row.motor], cat.gearboxes.loc[row.gearbox]
        n, eta = row.ratio, row.efficiency
        stall = m["k_t"] * m["V"] / m["R"]
        table = cat.torque_speed.get(row.motor)
        top = m["max_int_speed"] if table is None else min(m["max_int_speed"], table[0][-1])
        for d in range(tau.shape[0]):
            x = tau[d] if accel is None else tau[d] + row.reflected_inertia * accel[d]
            om, wn = omega[d], w / w.sum()
            a, driving = np.abs(x), x * om >= 0
            tau_m = np.where(driving, a / (n * eta), a * eta / n)
            w_m = n * np.abs(om)
            if table is None:
                env = np.where(driving, tau_m / stall + w_m / m["omega_nl"], tau_m / stall)
            else:
                env = np.where(tau_m > 0, tau_m / np.interp(w_m, *table), 0.0)
            out[d, c] = [
                max(env.max(), tau_m.max() / m["max_int_torque"]),
                np.sqrt(wn @ tau_m**2) / (m["k_t"] * m["I_nom"]),
                max(w_m.max() / top, np.sqrt(wn @ w_m**2) / m["max_cont_speed"]),
                a.max() / g["max_int_torque"],
                np.sqrt(wn @ a**2) / g["max_cont_torque"],
            ]
            if accel is not None and not np.isfinite(row.reflected_inertia):
                out[d, c] = np.inf
    return np.where(np.isnan(out), np.inf, out)


def random_duty(rng, n: int, d: int, scale: float):
    """Samples at rest, moving, and at standstill with acceleration; some of zero weight."""
    kind = rng.integers(0, 3, n)  # 0 rest, 1 moving, 2 standstill with acceleration
    omega = np.where(kind == 1, rng.normal(0, 3, n), 0.0)
    accel = np.where(kind == 0, 0.0, rng.normal(0, 40 / scale, n))
    w = rng.random(n) * (rng.random(n) < 0.8)
    w[0] += 0.1
    tau = rng.normal(0, 2 * scale, (d, n)) * rng.uniform(0.1, 3, (d, 1))
    return tau, np.broadcast_to(omega, tau.shape), w, np.broadcast_to(accel, tau.shape)


@pytest.fixture(params=["table", "unknown_inertia", "shipped"])
def catalogue(request, tmp_path):
    if request.param == "shipped":
        return read_catalogue(default_catalogue_folder()), 60.0
    gb = GEARBOXES + "CU_G5,Custom,G5,planetary,1,5,0.1,0,1.0,1,,\n"
    motors = MOTORS if request.param == "table" else MOTORS.replace(",1e-5,200,", ",,200,")
    compat = "CU_A,CU_G5,CU_G10\nCU_B,CU_G10,CU_G50\n"
    folder = write_catalogue(tmp_path, motors=motors, gearboxes=gb, compat=compat, ts=TABLE)
    return read_catalogue(folder), 1.0


def test_utilization_equals_the_sample_by_sample_reference(catalogue):
    cat, scale = catalogue
    rng = np.random.default_rng(3)
    for _ in range(6):
        tau, omega, w, accel = random_duty(rng, int(rng.integers(2, 30)), 12, scale)
        for acc in (None, accel):
            np.testing.assert_allclose(
                utilization(cat, tau, omega, w, acc), reference(cat, tau, omega, w, acc), 1e-12
            )
    # a speed per design (no shared duty)
    omega = rng.normal(0, 3, tau.shape)
    np.testing.assert_allclose(
        utilization(cat, tau, omega, w, accel), reference(cat, tau, omega, w, accel), 1e-12
    )


@pytest.mark.parametrize("rule", sorted(RULES))
def test_selection_equals_the_reference_choice(catalogue, rule):
    cat, scale = catalogue
    rng = np.random.default_rng(5)
    tau, omega, w, accel = random_duty(rng, 25, 80, scale)
    tau[3, 2] = np.nan  # no drive, infinite violation
    sel = select_drives(cat, tau, omega, w, rule, accel)
    u = np.full((len(tau), len(cat.drives), 5), np.inf)
    fin = np.isfinite(tau).all(axis=1)
    u[fin] = reference(cat, tau[fin], omega[fin], w, accel[fin])
    v = u.max(axis=2) - 1
    key = cat.drives[RULES[rule]].to_numpy(float)
    other = cat.drives[({*RULES.values()} - {RULES[rule]}).pop()].to_numpy(float)
    order = np.lexsort([np.nan_to_num(other, nan=np.inf), np.nan_to_num(key, nan=np.inf)])
    for d in range(len(tau)):
        meets = [c for c in order if v[d, c] <= 0]
        assert sel.choice[d] == (meets[0] if meets else -1)
        assert sel.violation[d] == pytest.approx(v[d].min(), rel=1e-12)
        best = meets[0] if meets else int(np.argmin(v[d]))
        assert sel.best[d] == best
        np.testing.assert_allclose(sel.utilization[d], u[d, best], 1e-12)
    assert 0 < (sel.choice >= 0).mean() < 1


def test_each_designs_numbers_do_not_depend_on_the_designs_beside_it():
    """Determinism whatever the shard count: a design's utilisations are the same to the bit
    alone, in a small batch or in a large one (blocks of several sizes)."""
    cat = read_catalogue(default_catalogue_folder())
    rng = np.random.default_rng(7)
    tau, omega, w, accel = random_duty(rng, 377, 300, 60.0)
    whole = utilization(cat, tau, omega, w, accel)
    for rows in (slice(0, 1), slice(5, 8), slice(17, 150)):
        part = utilization(cat, tau[rows], omega[rows], w, accel[rows])
        np.testing.assert_array_equal(part, whole[rows])
