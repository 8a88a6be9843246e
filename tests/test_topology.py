"""SIMP topology optimisation (pyMOTO): textbook cantilever, solids, link optimisation."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sps
import shapely
from scipy.sparse.linalg import spsolve

from qsm.physics import cad, duty
from qsm.realization.motion import torques
from qsm.realization.topology import fe, geometry, simp, topology
from qsm.report import topology_figure

SETTINGS = fe.TopologySettings(volume_fraction=0.5, max_iterations=60, cell_size_m=0.01)
DESIGN = np.array([0.40, 0.12, 0.40, 0.20, 0.48, 0.16])


def cantilever(nx: int = 60, ny: int = 20, h: float = 0.01) -> fe.FeProblem:
    """Left edge clamped, downward tip load at mid-height of the right edge."""
    grid = fe.Grid((0.0, 0.0), h, nx, ny)
    nodes = grid.node_positions()
    left = np.flatnonzero(nodes[:, 0] <= 1e-12)
    fixed = np.concatenate([2 * left, 2 * left + 1])
    f = fe.nodal_forces(grid, [((nx * h, ny * h / 2), (0.0, -100.0))], 0.5 * h)
    design = np.ones((ny, nx), bool)
    return fe.FeProblem(grid, fixed, f[:, None], design, ~design, 0.02)


def test_cantilever_compliance_volume_and_layout() -> None:
    problem = cantilever()
    res = simp.simp(problem, SETTINGS)
    uniform = fe.analyse(problem, np.full((20, 60), 0.5), SETTINGS).compliance_J
    assert res.history_J[0] == pytest.approx(uniform, rel=1e-6)  # starts from the uniform design
    print(f"cantilever: compliance {uniform:.4g} -> {res.history_J[-1]:.4g} J, {res.iterations} it")
    assert res.history_J[-1] < 0.4 * uniform
    assert res.history_J[-1] <= 1.02 * res.history_J.min()  # no late blow-up
    assert np.all(np.diff(res.history_J[:10]) < 0)  # decreasing from the start
    assert res.volume_fraction == pytest.approx(0.5, abs=2e-3)
    rho = res.density
    # bending near the clamp: material in the top and bottom fibres, little at the neutral axis
    near_clamp = rho[:, :10]
    fibres = np.r_[near_clamp[:3].mean(), near_clamp[-3:].mean()]
    assert fibres.min() > 0.8 and near_clamp[8:12].mean() < 0.5
    assert ((rho < 0.1) | (rho > 0.9)).mean() > 0.55  # mostly black and white


def test_symmetric_lu_solves_the_stiffness_system_like_scipy() -> None:
    """The faster factorisation gives scipy's direct solution, and ``analyse`` its compliance."""
    problem = cantilever()
    dom = problem.grid.domain(problem.thickness_m)
    scale = SETTINGS.min_density + (1 - SETTINGS.min_density) * 0.5**SETTINGS.penal
    K = sps.csc_matrix(fe.stiffness(dom, problem, SETTINGS)(np.full(60 * 20, scale)))
    reference = spsolve(K, problem.forces[:, 0])
    u = fe.SymmetricLU().update(K).solve(problem.forces)[:, 0]
    assert np.abs(u - reference).max() < 1e-10 * np.abs(reference).max()
    compliance = fe.analyse(problem, np.full((20, 60), 0.5), SETTINGS).compliance_J
    assert compliance == pytest.approx(problem.forces[:, 0] @ reference, rel=1e-10)


def test_extruded_cells_are_watertight_with_the_cell_mass() -> None:
    grid = fe.Grid((-0.1, 0.05), 0.004, 40, 12)
    rng = np.random.default_rng(3)
    mask = rng.random((12, 40)) > 0.45  # random cells: holes, islands and diagonal touches
    geom = geometry.cells_to_geometry(grid, mask)
    assert geom.area == pytest.approx(mask.sum() * grid.h**2, rel=1e-9)
    mesh = geometry.extrude(geom, 0.02)
    assert mesh.is_watertight and mesh.is_volume
    props = geometry.mesh_mass_properties(mesh, 1040.0)
    cell_mass = mask.sum() * grid.h**2 * 0.02 * 1040.0
    # the 10 um dilation that makes the rings manifold adds perimeter x 10 um of area
    assert props.mass_kg == pytest.approx(cell_mass, rel=0.02)
    assert props.mass_kg >= cell_mass


def test_mesh_mass_properties_match_the_exact_polygon_moments() -> None:
    outline = cad.link_outlines(DESIGN)["upper_arm"]
    exact = cad.polygon_mass_properties(outline, 0.02, 1040.0)
    mesh = geometry.extrude(shapely.Polygon(outline), 0.02, dilate_m=0.0)
    props = geometry.mesh_mass_properties(mesh, 1040.0)
    assert props.mass_kg == pytest.approx(exact.mass_kg, rel=1e-9)
    np.testing.assert_allclose(props.com_m, exact.com_m, atol=1e-9)
    np.testing.assert_allclose(props.inertia_kg_m2, exact.inertia_kg_m2, atol=1e-9)


def test_link_optimization_lightens_links_and_lowers_torques(tmp_path) -> None:
    coarse = fe.TopologySettings(  # no stiffness floor: the plates as SIMP cuts them
        volume_fraction=0.6, cell_size_m=0.005, max_iterations=40, min_stiffness_factor=0.05
    )
    cs = cad.CadSettings()
    d = duty.duty_cycle(
        duty.DutySettings(
            raster_lines=3, samples_per_segment=8, static_theta1_count=3, static_theta2_count=3
        )
    )
    res = topology.optimize_links(DESIGN, cs, 5.0, d, coarse)
    assert set(res.links) == {"lower_arm", "upper_arm"}
    for link in res.links.values():
        s = link.summary()
        print(s)
        assert link.mesh.is_watertight
        assert s["mass_after_kg"] < 0.85 * s["mass_before_kg"]
        assert s["compliance_after_J"] > s["compliance_before_J"]  # less material, less stiff
        assert s["compliance_after_J"] < 5 * s["compliance_before_J"]  # but still connected
        assert np.isfinite(s["max_von_mises_after_MPa"])
    # the loads are in equilibrium with the motor: moment of the pin force about A ~ tau1
    fb = res.links["lower_arm"].loads[0].forces["B"]
    tq = torques.torques_before_after(DESIGN, cs, 5.0, d, res.props)
    assert abs(DESIGN[0] * fb[1]) == pytest.approx(tq["before"]["tau1_Nm"], rel=0.1)
    assert tq["after"]["tau1_Nm"] < tq["before"]["tau1_Nm"]
    assert tq["after"]["tau2_Nm"] < tq["before"]["tau2_Nm"]
    assert topology_figure.plot_links(res, tmp_path / "links.png").stat().st_size > 0


def test_a_plate_over_the_stress_limit_is_not_kept(tmp_path) -> None:
    """At 30 % material and a 6 kg payload the compliance optimum of the lower arm exceeds the
    allowable stress, which the solid plate meets: the plate gets more material until its
    printed form holds, or the solid link is kept; the result never exceeds the limit unless the
    solid plate itself does."""
    lean = fe.TopologySettings(volume_fraction=0.3, cell_size_m=0.005, max_iterations=40)
    d = duty.duty_cycle(
        duty.DutySettings(
            raster_lines=3, samples_per_segment=8, static_theta1_count=3, static_theta2_count=3
        )
    )
    res = topology.optimize_links(DESIGN, cad.CadSettings(), 6.0, d, lean, links=("lower_arm",))
    link = res.links["lower_arm"]
    allow = lean.allowable_stress_pa / 1e6
    first = link.attempts[0]
    assert first["volume_fraction"] == 0.3 and first["max_von_mises_MPa"] > allow
    assert link.max_von_mises_before_pa <= lean.allowable_stress_pa  # the solid plate holds
    assert link.carries_loads
    if link.kept_solid:
        assert link.props_after == link.props_before
    else:
        assert link.attempts[-1]["max_von_mises_MPa"] <= allow
        assert link.attempts[-1]["volume_fraction"] > 0.3


def test_a_plate_keeps_the_stiffness_the_realisation_sized_for() -> None:
    """At 50 % material and a 1 kg payload the lower arm's printed plate holds its stress but is far
    less stiff than the solid one. With
    ``min_stiffness_factor`` 0.8 it gets more material until it keeps 0.8 of the solid plate's
    stiffness (the solid compliance over the printed one, which the accuracy budget applies), or
    the solid link is kept; with a floor of 0.05 the first plate is kept."""
    d = duty.duty_cycle(
        duty.DutySettings(
            raster_lines=3, samples_per_segment=8, static_theta1_count=3, static_theta2_count=3
        )
    )

    def lower_arm(floor: float) -> topology.LinkResult:
        lean = fe.TopologySettings(
            volume_fraction=0.5, cell_size_m=0.005, max_iterations=40, min_stiffness_factor=floor
        )
        res = topology.optimize_links(DESIGN, cad.CadSettings(), 1.0, d, lean, links=("lower_arm",))
        return res.links["lower_arm"]

    loose = lower_arm(0.05)
    first = loose.attempts[0]
    assert len(loose.attempts) == 1 and not loose.kept_solid
    assert first["stiffness_factor"] == pytest.approx(
        loose.compliance_before_J / loose.compliance_after_J, rel=1e-12
    )
    assert first["stiffness_factor"] < 0.8  # the lean plate is too soft for the floor below
    stiff = lower_arm(0.8)
    assert stiff.attempts[0]["stiffness_factor"] == pytest.approx(first["stiffness_factor"])
    if stiff.kept_solid:
        assert stiff.props_after == stiff.props_before
    else:
        assert stiff.compliance_before_J / stiff.compliance_after_J >= 0.8
        assert stiff.attempts[-1]["volume_fraction"] > 0.5


def test_the_stiffness_floor_is_a_share_of_the_solid_plate() -> None:
    with pytest.raises(ValueError, match="min_stiffness_factor"):
        fe.TopologySettings(min_stiffness_factor=1.2)
