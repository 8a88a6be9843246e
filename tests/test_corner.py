"""The stress concentration at the upper arm's filleted inside corner: hand-computed beam cases
(qsm.embodiment.strength.stresses.link_peaks)."""

from __future__ import annotations

import numpy as np
import pytest

from qsm.embodiment.strength.beam import Section
from qsm.embodiment.strength.loads import Inertials, JointLoads, LinkMotion
from qsm.embodiment.strength.material import Material, StrengthSettings
from qsm.embodiment.strength.stresses import link_strength

SEC = Section(width_m=0.04, thickness_m=0.02, boss_radius_m=0.025)
BORES = np.full(4, 0.022)
WEIGHTLESS = Inertials(np.zeros(4), np.zeros((4, 2)), np.zeros(4))
#: l4, E_x, E_y = 0.2, 0.5, 0.2 m.
DESIGN = np.array([0.4, 0.2, 0.5, 0.2, 0.5, 0.2])
_Z = np.zeros((1, 4))
#: One sample, every link frame at rest at the origin along the world axes.
AT_REST = LinkMotion(_Z + 1.0, _Z, _Z, _Z, np.zeros((1, 4, 2)), np.zeros((1, 4, 2)))


def _at_e(force: tuple[float, float]) -> JointLoads:
    """Only the force at E on the upper arm (link frame = world frame at rest)."""
    fields = {k: np.zeros((1, 2)) for k in JointLoads._fields}
    fields["e"] = np.array([force], dtype=float)
    fields["tau"] = np.zeros((1, 2))
    return JointLoads(**fields)


def _upper(force: tuple[float, float], k_corner: float) -> tuple[float, str]:
    req = StrengthSettings(corner_stress_concentration=k_corner)
    res = link_strength(DESIGN, SEC, Material(), req, WEIGHTLESS, _at_e(force), AT_REST, BORES)
    upper = res["upper_arm"]
    return float(upper.stress_pa), upper.labels[upper.where]


@pytest.mark.parametrize("k_corner", [1.4, 2.0, 2.7])
def test_corner_governs_under_a_force_along_the_upper_leg(k_corner):
    """E pulled along +x by F: the B-E' leg carries N = F and M = E_y F from B to the corner,
    so the bar at boss B and the bar at the corner have the same beam stress
    F / (w t) + 6 E_y F / (t w^2) (above the net section at B, M R / I_net, and the lugs, unloaded
    here); the corner's is K_t times it and governs. Below the corner (N = 0,
    M = (E_y - w/2) F) it is lower."""
    force, w, t, ey = 300.0, 0.04, 0.02, 0.2
    beam = force / (w * t) + 6 * ey * force / (t * w**2)
    stress, where = _upper((force, 0.0), k_corner)
    assert where == "bar at the corner"
    assert stress == pytest.approx(k_corner * beam, rel=1e-12)


def test_only_the_corner_cuts_are_scaled():
    """E pulled along -y by F: at the boss B edge (x0 from B) M = (E_x - x0) F, at the corner
    cut M = F w / 2, below the corner N = F and M = 0. The boss edge governs, unscaled, unless
    K_t lifts the corner above it."""
    force, w, t, r, ex = 300.0, 0.04, 0.02, 0.025, 0.5
    x0 = np.sqrt(r**2 - (w / 2) ** 2)
    at_boss = 6 * (ex - x0) * force / (t * w**2)
    stress, where = _upper((0.0, -force), 2.0)
    assert where == "bar at boss B, E side"
    assert stress == pytest.approx(at_boss, rel=1e-12)
    corner = 6 * force * (w / 2) / (t * w**2)  # no axial force at the corner cut
    k_big = 1.01 * at_boss / corner
    stress, where = _upper((0.0, -force), k_big)
    assert where == "bar at the corner"
    assert stress == pytest.approx(k_big * corner, rel=1e-12)


def test_corner_factor_below_one_is_rejected():
    with pytest.raises(ValueError, match="stress concentrations"):
        StrengthSettings(corner_stress_concentration=0.9)
