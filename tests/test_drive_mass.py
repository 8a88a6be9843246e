"""The drive-mass objective (optimization.objectives: drive_mass): the objective on a
three-drive catalogue by hand, NSGA-II with it, and how fronts optimised on it are ranked and
compared."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pandas as pd
import pytest
from test_drive_checks import _duty
from test_drives import write_catalogue

from qsm.config.reading import load_config
from qsm.config.settings import actuation, links, physics
from qsm.embodiment.drives.catalogue import read_catalogue
from qsm.embodiment.drives.drive_checks import DriveCheck
from qsm.embodiment.strength.link_checks import StrengthCheck
from qsm.optimization.comparison import compare, true_hypervolume
from qsm.optimization.constraint_set import ExtraConstraints, loop_duty
from qsm.optimization.nsga import optimize
from qsm.optimization.ranking import (
    DRIVE_MASS,
    OBJECTIVE_SETS,
    front_ranks,
    objectives_of,
    rule_scores,
)
from qsm.physics.cad import DEFAULT_CAD
from qsm.surrogate.model import INPUTS, SurrogateSettings, train


def test_objective_on_three_drives_by_hand(tmp_path):
    """Drives (test_drives): (A, G10) 0.7 kg, (A, G50) 0.9 kg, (B, G10) 2.2 kg; every sample at
    5 rad/s, no acceleration."""
    check = DriveCheck(
        catalogue=read_catalogue(write_catalogue(tmp_path / "cat")), duty=_duty(3, 5.0, 0.0)
    )
    # per design, (motor 1, motor 2) torque in N m, constant over the duty
    loads = np.array([[1.0, 1.0], [1.0, 8.0], [25.0, 1.0], [1.0, 1.0]])
    tau = np.repeat(loads[:, None, :], 3, axis=1)
    good = np.array([True, True, True, False])  # the last design's loop does not close
    table = check.evaluate(np.zeros((4, 6)), (tau, good))
    mass = check.mass_objective(table)
    # 1 N m: (A, G10), the lightest, meets it: envelope 1 / (10 x 0.8) / 2.4 + 50 / 200 = 0.30,
    # RMS 0.125 / 0.2 = 0.63, speed 50 / 300, gearbox 1 / 20 and 1 / 10
    # 8 N m: only (B, G10) (test_drive_checks): 2.2 kg
    # 25 N m: no drive; the nearest, (B, G10), exceeds its gearbox's RMS rating 25 / 10 = 2.5 by
    # 1.5 (its envelope 0.37, motor peak 3.125 / 1.5 = 2.08, RMS 3.125 / 2 = 1.56, gear peak
    # 1.25; (A, G50) exceeds its motor's RMS rating 1 / 0.2 by 4, (A, G10) by 14.6): the penalty
    # twice the heaviest drive, 4.4 kg, plus 1.5; the undefined design 4.4 + 10
    np.testing.assert_allclose(mass, [1.4, 2.9, 4.4 + 1.5, 4.4 + 10.0], rtol=1e-12)
    assert table["has_drives"].tolist() == [True, True, False, False]


@pytest.fixture(scope="module")
def model():
    rng = np.random.default_rng(0)
    x = rng.uniform([0.3, 0.06, 0.25, 0.1, 0.35, 0.07], [0.5, 0.3, 0.6, 0.3, 0.7, 0.35], (400, 6))
    y = np.column_stack([0.05 + 0.1 * x[:, 0], 40 + 30 * x[:, 4], 10 + 20 * x[:, 3]])
    return train(x, y, SurrogateSettings(max_epochs=100)).model, x, y


def test_nsga_with_drive_mass_on_the_test_config(model):
    """NSGA-II on (eta', drive mass) with g11..g14 of the test config: the front's drive-mass
    column is the drive check's objective of its designs, recomputed."""
    surrogate, x, y = model
    config = load_config("config/config.yaml", "config/test.yaml")
    fit = physics.fit(
        config["operating_range"], config["task"]["points"], config["scale"], config["workspace"]
    )
    coarse = loop_duty(physics.duty(config["dynamics"]["duty"], config["operating_range"]))
    case = links.load_case_of(config).with_duty(coarse)
    drives = actuation.drive_check(config["drives"], case)
    extra = ExtraConstraints(
        containment=True,
        printable=False,
        fit=fit,
        cad=DEFAULT_CAD,
        volume_mm=(600.0, 350.0, 350.0),
        strength=StrengthCheck(drives.cad, payload_kg=drives.payload_kg, duty=drives.duty),
        drives=drives,
    )
    dataset = pd.DataFrame(x, columns=list(INPUTS))
    dataset[["eta", "tau1_Nm", "tau2_Nm"]] = y
    dataset["drive_mass_kg"] = np.linspace(0.5, 6.0, len(x))
    section = {**config["optimization"], "objectives": "drive_mass", "pop_size": 12}
    section["generations"] = 3
    tables = optimize("paper", surrogate, dataset, section, fit, {}, extra)
    pareto = tables.pareto
    assert objectives_of(pareto)[1] == DRIVE_MASS
    designs = pareto[list(INPUTS)].to_numpy()
    expected = drives.mass_objective(drives.evaluate(designs))
    np.testing.assert_allclose(pareto[DRIVE_MASS.predicted], expected, rtol=1e-9)
    np.testing.assert_allclose(pareto["eta_pred"], surrogate.predict(designs)[:, 0], rtol=1e-9)
    assert np.isfinite(tables.hypervolume["hypervolume"]).all()
    torques = optimize(
        "paper", surrogate, dataset, {**section, "objectives": "torques"}, fit, {}, extra
    )
    assert DRIVE_MASS.predicted not in torques.pareto


def _verified(**columns) -> pd.DataFrame:
    n = len(next(iter(columns.values())))
    base = {
        "feasible": [True] * n,
        "dynamics_status": ["ok"] * n,
        "printable": [True] * n,
        "task_contained": [True] * n,
        "tau2_true_Nm": [1.0] * n,
    }
    return pd.DataFrame({**base, **columns})


def test_knee_uses_the_drive_mass_of_a_front_optimized_on_it():
    # eta (0.1, 0.2, 0.3), tau1 (30, 20, 10), drive mass (3, 1, 2) kg: normalised to [0, 1],
    # the torque knee distances are (1, 0.71, 1) with tau2 constant; drive mass
    # (eta, mass): (0, 1) -> 1, (0.5, 0) -> 0.5, (1, 0.5) -> 1.12
    table = _verified(
        eta_true=[0.1, 0.2, 0.3],
        tau1_true_Nm=[30.0, 20.0, 10.0],
        drive_mass_kg=[3.0, 1.0, 2.0],
    )
    np.testing.assert_allclose(rule_scores(table, "knee"), [1.0, np.sqrt(0.5), 1.0])
    table[DRIVE_MASS.predicted] = table["drive_mass_kg"]
    np.testing.assert_allclose(rule_scores(table, "knee"), [1.0, 0.5, np.sqrt(1.25)])
    assert front_ranks(table).tolist() == [2, 1, 3]


def test_comparison_gives_drive_share_mass_and_hypervolume():
    n = 4
    table = _verified(
        crank_rocker=[True] * n,
        loop_closes=[True] * n,
        transmission_ok=[True] * n,
        in_table1=[True] * n,
        holds_loads=[True] * n,
        has_drives=[True, True, False, True],
        eta_pred=[0.1] * n,
        tau1_pred_Nm=[10.0] * n,
        tau2_pred_Nm=[1.0] * n,
        eta_true=[0.1, 0.2, 0.05, 0.3],
        tau1_true_Nm=[10.0] * n,
        drive_mass_kg=[2.0, 1.0, 0.5, 4.0],
    )
    dataset = pd.DataFrame(
        {"eta": [0.0, 0.4], "tau1_Nm": [0.0, 20.0], "tau2_Nm": [0.0, 2.0], "drive_mass_kg": [0, 4]}
    )
    e = compare({"paper": table}, dataset, "paper")["fronts"]["paper"]
    assert e["has_drives_share"] == 0.75
    assert e["median_drive_mass_kg"] == 2.0  # of 2, 1 and 4 kg (the third has no drives)
    assert e["objectives"] == ["eta", "tau1", "tau2"]
    # (eta, mass) normalised: (0.25, 0.5), (0.5, 0.25), (0.75, 1); the third (0.125, 0.125)
    # has no drives. Dominated area below 1.1: 0.85 x 0.6 + 0.6 x 0.25 = 0.66
    assert e["true_hypervolume_drive_mass"] == pytest.approx(0.85 * 0.6 + 0.6 * 0.25)


def test_a_constant_dataset_column_still_gives_a_hypervolume():
    """One drive fits every design (a light task): the drive mass column of the dataset is
    constant; it normalises with span 1, so the point (eta 0.5, mass 0) dominates 0.6 x 1.1."""
    n = 1
    table = _verified(
        crank_rocker=[True],
        loop_closes=[True],
        transmission_ok=[True],
        has_drives=[True] * n,
        eta_true=[0.2],
        tau1_true_Nm=[10.0],
        drive_mass_kg=[0.96],
    )
    dataset = pd.DataFrame({"eta": [0.0, 0.4], "drive_mass_kg": [0.96, 0.96]})
    assert true_hypervolume(table, dataset, OBJECTIVE_SETS["drive_mass"]) == pytest.approx(
        0.6 * 1.1
    )


def test_the_front_is_checked_on_the_full_duty(model):
    """The loop's g13 on a coarser duty lets through designs that the full check fails (here the
    full check carries 1.5 times the payload, so that some do): the front keeps only the
    designs that pass the full check, and its constraint label says how many were removed."""
    surrogate, x, y = model
    config = load_config("config/config.yaml", "config/test.yaml")
    fit = physics.fit(
        config["operating_range"], config["task"]["points"], config["scale"], config["workspace"]
    )
    full = physics.duty(config["dynamics"]["duty"], config["operating_range"])
    kg = config["task"]["payload_kg"]

    def check(duty, payload_kg):
        case = replace(links.load_case_of(config), duty=duty, payload_kg=payload_kg)
        return links.strength_check(case, config["strength"])

    extra = ExtraConstraints(
        containment=True,
        printable=False,
        fit=fit,
        cad=DEFAULT_CAD,
        volume_mm=(600.0, 350.0, 350.0),
        strength=check(loop_duty(full), kg),
        full_strength=check(full, 1.5 * kg),
    )
    dataset = pd.DataFrame(x, columns=list(INPUTS))
    dataset[["eta", "tau1_Nm", "tau2_Nm"]] = y
    section = {**config["optimization"], "pop_size": 30, "generations": 8}
    loop_only = optimize(
        "paper", surrogate, dataset, section, fit, {}, replace(extra, full_strength=None)
    )
    fails = extra.full_strength.violation(loop_only.pareto[list(INPUTS)].to_numpy()) > 0
    assert 0 < fails.sum() < len(fails)  # the case this test is about
    tables = optimize("paper", surrogate, dataset, section, fit, {}, extra)
    assert len(tables.pareto) == len(fails) - fails.sum()
    assert (extra.full_strength.violation(tables.pareto[list(INPUTS)].to_numpy()) <= 0).all()
    assert f"{fails.sum()} of the front's {len(fails)} designs removed" in tables.constraints
