"""Sections sized by strength (qsm.embodiment.strength.sizing): a hand-computed cantilever, the
loads -> sections -> masses iteration, the bounds, a load no section holds, fixed mode unchanged."""

from __future__ import annotations

import copy
import math
from dataclasses import replace

import numpy as np
import pandas as pd
import pytest

from qsm.config.checks import check_config
from qsm.config.errors import ConfigError
from qsm.config.reading import load_config
from qsm.embodiment.strength.link_checks import StrengthCheck
from qsm.embodiment.strength.loads import Inertials, joint_loads, link_motion
from qsm.embodiment.strength.material import DEFAULT_MATERIAL, DEFAULT_STRENGTH
from qsm.embodiment.strength.sizing import (
    TARGET,
    SizedSections,
    SizingSettings,
    size_sections,
    smallest_holding,
    utilization,
)
from qsm.embodiment.strength.stresses import LinkLoads
from qsm.physics.batch_mass import batch_mass_properties
from qsm.physics.cad import DEFAULT_CAD
from qsm.physics.duty import DutySettings, duty_cycle
from qsm.physics.dynamics import evaluate_mechanism, loop_state
from qsm.physics.kinematics import LINK_NAMES

DESIGNS = np.array(
    [
        [0.5, 0.15, 0.5, 0.22, 0.6, 0.2],
        [0.35, 0.1, 0.38, 0.14, 0.42, 0.2],
        [0.8, 0.3, 0.8, 0.4, 1.0, 0.45],
    ]
)
DUTY = duty_cycle(DutySettings(samples_per_segment=8))
SIZING = SizingSettings()


def _cantilever(moment: np.ndarray) -> LinkLoads:
    """One bar cut carrying only the moment ``moment`` (D,) N m: no axial force, no bore, no
    lug force, never compressed."""
    n = len(moment)
    return LinkLoads(
        axial_N=np.zeros((n, 1, 1)),
        moment_Nm=moment[:, None, None],
        cut_bore_m=np.zeros((n, 1, 1)),
        bore_force_N=np.zeros((n, 1)),
        bore_m=np.zeros((n, 1)),
        compression_N=np.zeros(n),
        column_m=np.ones(n),
        labels=("bar",),
    )


def test_cantilever_section_meets_the_allowable_exactly():
    """sigma = 6 M / (t w^2) with w = s w0, t = s t0: the smallest s holding M at TARGET times
    the allowable is s* = (6 M sf / (TARGET yield t0 w0^2))^(1/3)."""
    moment = np.array([20.0, 80.0, 200.0])  # N m
    links = dict.fromkeys(LINK_NAMES, _cantilever(moment))
    y, sf = DEFAULT_MATERIAL.yield_strength_pa, DEFAULT_STRENGTH.safety_factor
    w0, t0 = DEFAULT_CAD.width_m, DEFAULT_CAD.thickness_m
    expected = np.cbrt(6 * moment * sf / (TARGET * y * t0 * w0**2))
    lo, hi = np.full((3, 4), 0.3), np.full((3, 4), 3.0)

    def util(x: np.ndarray) -> np.ndarray:
        return utilization(links, x, DEFAULT_CAD, DEFAULT_MATERIAL, DEFAULT_STRENGTH)

    s = smallest_holding(util, lo, hi)
    np.testing.assert_allclose(s, np.repeat(expected[:, None], 4, 1), rtol=2e-3)
    assert (util(s) <= TARGET * (1 + 1e-12)).all()
    stress = 6 * moment[:, None] / (s * t0 * (s * w0) ** 2)  # the hand formula at the answer
    np.testing.assert_allclose(stress, TARGET * y / sf, rtol=6e-3)


def _loads(designs: np.ndarray, scale: np.ndarray, payload: float = 5.0):
    state = loop_state(designs, DUTY.theta, DUTY.dtheta, DUTY.ddtheta)
    inertials = Inertials(*batch_mass_properties(designs, DEFAULT_CAD, scale))
    return joint_loads(designs, inertials, payload, state, link_motion(designs, state))


def _sized(max_iterations: int) -> SizedSections:
    check = StrengthCheck(duty=DUTY)
    return size_sections(
        DESIGNS, DEFAULT_CAD, check.material, check.strength, 5.0, DUTY,
        check.usable_bearings(), replace(SIZING, max_iterations=max_iterations),
    )  # fmt: skip


def test_iteration_converges_and_the_links_hold():
    scale, iterations = _sized(SIZING.max_iterations)
    assert ((iterations > 1) & (iterations < SIZING.max_iterations)).all()
    n = int(iterations.max())
    previous, _ = _sized(n - 1)  # the sections one round earlier
    tau = np.abs(_loads(DESIGNS, scale).tau).max(-2)
    tau_before = np.abs(_loads(DESIGNS, previous).tau).max(-2)
    assert (np.abs(tau - tau_before) / tau < SIZING.tolerance).all()
    table = StrengthCheck(duty=DUTY, sizing=SIZING).evaluate(DESIGNS)
    assert table["holds_loads"].all()
    # sized tightly: the weakest link sits close to the target, not far below it
    assert (table["strength_utilisation"] > 0.97).all()
    assert (table["section_iterations"] == iterations).all()


def test_bounds_are_respected():
    narrow = SizingSettings(width_m=(0.036, 0.044), thickness_m=(0.018, 0.022))
    table = StrengthCheck(duty=DUTY, sizing=narrow).evaluate(DESIGNS)
    for link in LINK_NAMES:
        w = table[f"section_width_{link}_mm"]
        t = table[f"section_thickness_{link}_mm"]
        assert ((w >= 36 - 1e-9) & (w <= 44 + 1e-9)).all()
        assert ((t >= 18 - 1e-9) & (t <= 22 + 1e-9)).all()
    # the wide bounds shrink the lightly loaded crank to well below the narrow bounds' minimum
    wide = StrengthCheck(duty=DUTY, sizing=SIZING).evaluate(DESIGNS)
    assert (wide["section_width_crank_mm"] < 36).all()


def test_a_load_no_section_holds_takes_the_upper_bound_and_says_so():
    check = StrengthCheck(payload_kg=400.0, duty=DUTY, sizing=SIZING)
    scale = check.section_scales(DESIGNS[:1]).scale
    table = check.evaluate(DESIGNS[:1])
    hi = SIZING.bounds(DEFAULT_CAD)[1]
    weakest = table["weakest_link"].iloc[0]
    assert not table["holds_loads"].iloc[0]
    assert table["strength_utilisation"].iloc[0] > 1
    assert weakest in LINK_NAMES
    k = LINK_NAMES.index(weakest)
    assert scale[0, k] == pytest.approx(hi)
    assert table[f"section_width_{weakest}_mm"].iloc[0] == pytest.approx(1e3 * SIZING.width_m[1])


def test_fixed_mode_is_the_unit_scale():
    """The fixed section gives the torques, masses and strength table of the sized machinery
    with every scale 1. Two arithmetic paths (Python floats through libm, NumPy arrays through
    vectorised ufuncs) whose roundings may differ in the last bits: the table to a relative
    1e-12, 4,500 ulps, room for the roundings of the few dozen operations from section to
    safety factor and far below any engineering difference. The torques are one path (a unit
    scale multiplies exactly), so bit for bit."""
    ones = np.ones((len(DESIGNS), 4))
    fixed, tau, _ = StrengthCheck(duty=DUTY).evaluate_with_torques(DESIGNS)
    unit_sections = SizedSections(ones, np.zeros(len(DESIGNS), dtype=np.intp))
    unit, tau_unit, _ = StrengthCheck(duty=DUTY).evaluate_with_torques(DESIGNS, unit_sections)
    assert np.array_equal(tau, tau_unit, equal_nan=True)
    pd.testing.assert_frame_equal(fixed, unit, check_exact=False, rtol=1e-12, atol=0)
    assert (fixed["section_width_lower_arm_mm"] == 1e3 * DEFAULT_CAD.width_m).all()
    assert (fixed["section_iterations"] == 0).all()
    for d in DESIGNS:
        a = evaluate_mechanism(d, DUTY)
        b = evaluate_mechanism(d, DUTY, scale=np.ones(4))
        assert a == b
    assert StrengthCheck(duty=DUTY).section_scales(DESIGNS) is None


def test_sized_torques_follow_the_lighter_links():
    """MuJoCo on the sized links gives the strength check's Newton-Euler torques (one path)."""
    check = StrengthCheck(duty=DUTY, sizing=SIZING)
    sized = check.section_scales(DESIGNS[:1])
    scale = sized.scale
    table, tau, _ = check.evaluate_with_torques(DESIGNS[:1], sized)
    assert (table["section_iterations"] == sized.iterations).all()
    assert sized.iterations[0] > 0
    dyn = evaluate_mechanism(DESIGNS[0], DUTY, scale=scale[0])
    assert dyn["tau1_Nm"] == pytest.approx(np.abs(tau[0, :, 0]).max(), rel=1e-6)
    assert dyn["tau2_Nm"] == pytest.approx(np.abs(tau[0, :, 1]).max(), rel=1e-6)
    fixed = evaluate_mechanism(DESIGNS[0], DUTY)
    assert dyn["mass_crank_kg"] < fixed["mass_crank_kg"]


def test_config_checks_the_sizing_bounds():
    config = load_config()
    bad = copy.deepcopy(config)
    bad["cad"]["sized"]["thickness_m"] = [0.01, 0.5]
    with pytest.raises(ConfigError, match=r"cad\.sized\.thickness_m"):
        check_config(bad)
    bad = copy.deepcopy(config)
    bad["cad"]["section"] = "sized"
    bad["cad"]["sized"]["width_m"] = [0.01, 0.02]
    bad["cad"]["sized"]["thickness_m"] = [0.03, 0.04]
    with pytest.raises(ConfigError, match=r"cad\.sized"):
        check_config(bad)
    assert math.isfinite(SIZING.bounds(DEFAULT_CAD)[0])


def test_the_loop_sizes_within_its_allowance():
    """The optimisation's g13 multiplies the utilisation by 1 + LOOP_ALLOWANCE (coarser duty):
    its sized check sizes the links that much lower, so a sized link passes g13."""
    from qsm.config.settings.optimization import front_of
    from qsm.optimization.constraint_set import LOOP_ALLOWANCE

    config = load_config()
    config["cad"]["section"] = "sized"
    config["task"]["payload_kg"] = 5.0
    check = front_of(config, "paper").extra.strength
    assert check.sizing.target == pytest.approx(TARGET / (1 + LOOP_ALLOWANCE))
    table = check.evaluate(DESIGNS)
    y, sf = check.material.yield_strength_pa, check.strength.safety_factor
    for link in LINK_NAMES:
        links = table[f"stress_peak_{link}_MPa"] * 1e6 * sf / y
        assert (links * (1 + LOOP_ALLOWANCE) <= 1).all()


def test_a_bearing_seat_the_section_cannot_take_fails_the_link_without_an_error():
    """Short links under a heavy payload: the section's upper bound (the bosses must leave a
    bar) is below what the joint's bearing seat needs; the check reports it, no exception."""
    small = DESIGNS * 0.2
    check = StrengthCheck(payload_kg=60.0, duty=DUTY, sizing=SIZING)
    table = check.evaluate(small)
    good = table["strength_utilisation"].notna()
    assert good.any()
    failing = good & ~table["holds_loads"]
    assert table.loc[failing, "weakest_check"].eq("bearing seat").any()
