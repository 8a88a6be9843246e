"""The vectorised strength arithmetic against plain references: a batch of designs gives each
design's own numbers (shared duty states or one per design), and the cut forces equal the
coefficients times the link-frame samples built sample by sample with rotation matrices."""

from __future__ import annotations

import numpy as np
import pytest

from qsm.embodiment.strength.beam import LOADS, Section, link_cuts
from qsm.embodiment.strength.link_checks import StrengthCheck
from qsm.embodiment.strength.loads import GRAVITY, Inertials, joint_loads, link_motion
from qsm.embodiment.strength.stresses import _SPINE, cut_coefficients, cut_forces
from qsm.physics import duty as duty_mod
from qsm.physics.batch_mass import batch_mass_properties
from qsm.physics.cad import DEFAULT_CAD
from qsm.physics.dynamics import loop_state
from qsm.physics.kinematics import LINK_NAMES

DESIGNS = np.array(
    [
        [0.5, 0.15, 0.5, 0.22, 0.6, 0.2],
        [0.35, 0.1, 0.38, 0.14, 0.42, 0.2],
        [0.8, 0.3, 0.8, 0.4, 1.0, 0.45],
    ]
)
PAYLOAD_KG = 5.0


@pytest.fixture(scope="module")
def duty() -> duty_mod.Duty:
    return duty_mod.duty_cycle()


def _close(batch: np.ndarray, single: np.ndarray) -> None:
    np.testing.assert_allclose(batch, single, rtol=1e-13, atol=1e-13 * np.nanmax(np.abs(single)))


@pytest.mark.parametrize("per_design", [False, True])
def test_a_batch_gives_each_designs_own_state_motion_and_loads(duty, per_design):
    """Loop state, link motion and joint loads of three designs at once equal those of each
    design alone, with the duty shared or a duty of its own per design (motor angles offset)."""
    offset = np.array([0.0, 0.02, -0.03])[:, None, None] if per_design else np.zeros((3, 1, 1))
    theta = duty.theta + offset
    inertials = Inertials(*batch_mass_properties(DESIGNS, DEFAULT_CAD))
    states = theta if per_design else duty.theta
    state = loop_state(DESIGNS, states, duty.dtheta, duty.ddtheta)
    motion = link_motion(DESIGNS, state)
    loads = joint_loads(DESIGNS, inertials, PAYLOAD_KG, state, motion)
    for i, design in enumerate(DESIGNS):
        one = loop_state(design, theta[i], duty.dtheta, duty.ddtheta)
        own = Inertials(*(v[i] for v in inertials))
        for batch, single in (
            (state, one),
            (motion, link_motion(design, one)),
            (loads, joint_loads(design, own, PAYLOAD_KG, one)),
        ):
            for name, value in single._asdict().items():
                _close(getattr(batch, name)[i], value)


def test_the_table_does_not_depend_on_the_batch(duty):
    """Every strength column of designs checked together equals the one of each alone."""
    check = StrengthCheck(payload_kg=PAYLOAD_KG, duty=duty)
    together = check.evaluate(DESIGNS)
    for i, design in enumerate(DESIGNS):
        alone = check.evaluate(design[None])
        for column in together.columns:
            a, b = together[column].iloc[i], alone[column].iloc[0]
            assert a == (pytest.approx(b, rel=1e-13) if isinstance(b, float) else b), column


@pytest.mark.parametrize("link", LINK_NAMES)
def test_cut_forces_equal_the_coefficients_times_each_samples_vector(duty, link):
    """At every duty sample the link-frame vector ``[s F_1, ..., g - a_0, alpha, omega^2]`` is
    built with the link's rotation matrix, and N, M are its dot products with the
    coefficients of :func:`cut_coefficients`."""
    design = DESIGNS[0]
    sec = Section.of(DEFAULT_CAD)
    inertials = Inertials(*batch_mass_properties(design[None], DEFAULT_CAD))
    inertials = Inertials(*(v[0] for v in inertials))
    state = loop_state(design, duty.theta, duty.dtheta, duty.ddtheta)
    motion = link_motion(design, state)
    loads = joint_loads(design, inertials, PAYLOAD_KG, state, motion)
    k = LINK_NAMES.index(link)
    cuts = link_cuts(design, sec)[link]
    mu = inertials.mass_kg[k] / _SPINE[link](design)
    cn, cm = cut_coefficients(cuts, len(LOADS[link]), mu)
    axial, moment = cut_forces(design, sec, inertials, loads, motion, link, cuts)
    forces = loads._asdict()
    for n in range(0, len(duty.theta), 7):
        c, s = motion.cos[n, k], motion.sin[n, k]
        to_link = np.array([[c, s], [-s, c]])  # world -> link frame
        parts = [sign * to_link @ forces[name][n] for name, sign in LOADS[link]]
        g_rel = to_link @ (GRAVITY - motion.origin_acc[n, k])
        vector = np.concatenate([*parts, g_rel, [motion.alpha[n, k], motion.omega[n, k] ** 2]])
        scale = np.abs(cn @ vector).max() + np.abs(cm @ vector).max()
        np.testing.assert_allclose(axial[n], cn @ vector, rtol=0, atol=1e-12 * scale)
        np.testing.assert_allclose(moment[n], cm @ vector, rtol=0, atol=1e-12 * scale)
