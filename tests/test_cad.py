"""Link solids: mass properties by hand and from the mesh, STL export."""

from __future__ import annotations

import math

import numpy as np
import pytest

from qsm.physics import cad, kinematics

DESIGN = np.array([0.5, 0.15, 0.55, 0.22, 0.6, 0.2])


def test_bar_with_end_half_discs_matches_hand_computation() -> None:
    """Bosses of radius width/2 turn a bar into a stadium: rectangle plus two half discs."""
    L, w, t, rho = 0.4, 0.03, 0.01, 1040.0
    h = w / 2
    s = cad.CadSettings(
        width_m=w,
        thickness_m=t,
        boss_radius_m=h * (1 + 1e-12),
        density_kg_m3=rho,
        segments_per_circle=4096,
    )
    mp = cad.polygon_mass_properties(cad.link_outlines([L, L, L, L, L, L], s)["crank"], t, rho)
    a_half = math.pi * h**2 / 2
    area = L * w + 2 * a_half
    mass = rho * t * area
    # area moments about the bar centre (L/2, 0)
    int_y2 = L * w**3 / 12 + math.pi * h**4 / 4
    half_x2 = (L / 2) ** 2 * a_half + L * (2 * h**3 / 3) + math.pi * h**4 / 8
    int_x2 = w * L**3 / 12 + 2 * half_x2
    hand = np.diag(
        [
            rho * t * int_y2 + mass * t**2 / 12,
            rho * t * int_x2 + mass * t**2 / 12,
            rho * t * (int_x2 + int_y2),
        ]
    )
    assert mp.mass_kg == pytest.approx(mass, rel=1e-6)
    np.testing.assert_allclose(mp.com_m, [L / 2, 0.0, 0.0], atol=1e-12)
    np.testing.assert_allclose(mp.inertia_kg_m2, hand, rtol=1e-6, atol=1e-12 * hand.max())


def test_bar_with_bosses_area_matches_hand_computation() -> None:
    """Area of rectangle plus two boss discs minus the parts of the discs inside the bar."""
    s = cad.CadSettings(segments_per_circle=8192)
    L, r, h = 0.3, s.boss_radius_m, s.width_m / 2
    x0, beta = math.sqrt(r * r - h * h), math.asin(h / r)
    area = L * 2 * h + 2 * (math.pi * r * r - (h * x0 + r * r * beta))
    mp = cad.mass_properties([L, 0.2, 0.5, 0.2, 0.6, 0.2], s)["lower_arm"]
    assert mp.mass_kg == pytest.approx(s.density_kg_m3 * s.thickness_m * area, rel=1e-6)
    np.testing.assert_allclose(mp.com_m, [L / 2, 0.0, 0.0], atol=1e-12)


def test_analytic_mass_properties_match_trimesh() -> None:
    s = cad.CadSettings()
    analytic = cad.mass_properties(DESIGN, s)
    meshes = cad.link_meshes(DESIGN, s)
    for name in kinematics.LINK_NAMES:
        mesh = meshes[name]
        mesh.density = s.density_kg_m3
        a = analytic[name]
        assert mesh.is_watertight and mesh.is_winding_consistent and mesh.volume > 0
        assert mesh.mass == pytest.approx(a.mass_kg, rel=1e-9), name
        np.testing.assert_allclose(mesh.center_mass, a.com_m, atol=1e-9)
        np.testing.assert_allclose(mesh.moment_inertia, a.inertia_kg_m2, rtol=1e-9, atol=1e-12)
    upper = analytic["upper_arm"]
    assert abs(upper.inertia_kg_m2[0, 1]) > 1e-6  # the L-shape has a product of inertia


def test_link_meshes_are_watertight_with_the_outline_extents() -> None:
    s = cad.CadSettings()
    meshes = cad.link_meshes(DESIGN, s)
    l1, l2, l3, l4, ee_x, ee_y = DESIGN
    r = s.boss_radius_m
    expected = {
        "lower_arm": (l1 + 2 * r, 2 * r),
        "crank": (l2 + 2 * r, 2 * r),
        "coupler": (l3 + 2 * r, 2 * r),
        "upper_arm": (l4 + ee_x + 2 * r, ee_y + 2 * r),
    }
    assert list(meshes) == list(kinematics.LINK_NAMES)
    for name, mesh in meshes.items():
        assert mesh.is_watertight, name
        np.testing.assert_allclose(mesh.extents, [*expected[name], s.thickness_m], rtol=1e-3)


def test_section_that_does_not_fit_raises_cad_error() -> None:
    with pytest.raises(cad.CadError):
        cad.mass_properties([0.1, 0.02, 0.1, 0.04, 0.12, 0.05])
    with pytest.raises(ValueError, match="boss_radius_m"):
        cad.CadSettings(width_m=0.05, boss_radius_m=0.02)


def test_corner_fillet_adds_the_hand_computed_spandrel() -> None:
    """The fillet fills the square r_f x r_f at the inside corner less a quarter disc: area
    (1 - pi/4) r_f^2, centroid 2 r_f / (3 (4 - pi)) from the disc centre along each axis."""
    fine = cad.CadSettings(segments_per_circle=8192)
    sharp = cad.CadSettings(segments_per_circle=8192, corner_fillet_ratio=0.0)
    rf = 0.25 * fine.width_m
    sigma = fine.density_kg_m3 * fine.thickness_m
    a = cad.mass_properties(DESIGN, fine)["upper_arm"]
    b = cad.mass_properties(DESIGN, sharp)["upper_arm"]
    added = sigma * (1 - math.pi / 4) * rf**2
    assert a.mass_kg - b.mass_kg == pytest.approx(added, rel=1e-6)
    h, ee_x = fine.width_m / 2, DESIGN[4]
    centre = np.array([ee_x - h - rf, -h - rf])
    spandrel = centre + 2 * rf / (3 * (4 - math.pi))
    first = a.mass_kg * a.com_m[:2] - b.mass_kg * b.com_m[:2]
    np.testing.assert_allclose(first, added * spandrel, rtol=1e-6)


def test_corner_fillet_is_tangent_to_both_legs_and_needs_room() -> None:
    s = cad.CadSettings()
    h, rf = s.width_m / 2, s.corner_fillet_m
    arc = cad.inside_corner(0.6, s)
    np.testing.assert_allclose(arc[0], [0.6 - h - rf, -h], atol=1e-15)  # on the B-E' edge
    np.testing.assert_allclose(arc[-1], [0.6 - h, -h - rf], atol=1e-15)  # on the E'-E edge
    np.testing.assert_allclose(np.hypot(*(arc - (0.6 - h - rf, -h - rf)).T), rf, rtol=1e-12)
    np.testing.assert_array_equal(
        cad.inside_corner(0.6, cad.CadSettings(corner_fillet_ratio=0)), [[0.6 - h, -h]]
    )
    # legs just long enough without the fillet are too short with it
    short = [0.5, 0.15, 0.55, 0.22, 0.6, s.boss_overlap_m + h + rf / 2]
    cad.mass_properties(short, cad.CadSettings(corner_fillet_ratio=0))
    with pytest.raises(cad.CadError, match="fillet"):
        cad.mass_properties(short, s)


@pytest.mark.parametrize("ratio", [0.0, 0.25, 0.5])
def test_batch_mass_properties_equal_the_outline_ones_with_any_fillet(ratio) -> None:
    """The closed form of qsm.physics.batch_mass against the polygon moments of the outlines,
    sharp and filleted corners, scaled sections."""
    from qsm.physics.batch_mass import batch_mass_properties

    s = cad.CadSettings(corner_fillet_ratio=ratio)
    designs = np.array([DESIGN, [0.35, 0.1, 0.38, 0.14, 0.42, 0.2]])
    scale = np.array([[1.0, 0.8, 1.2, 1.3], [0.9, 1.0, 1.1, 0.7]])
    mass, com, izz = batch_mass_properties(designs, s, scale)
    for k, design in enumerate(designs):
        props = cad.mass_properties(design, s, scale[k])
        for j, link in enumerate(kinematics.LINK_NAMES):
            assert mass[k, j] == pytest.approx(props[link].mass_kg, rel=1e-12)
            np.testing.assert_allclose(com[k, j], props[link].com_m[:2], atol=1e-14)
            assert izz[k, j] == pytest.approx(props[link].inertia_kg_m2[2, 2], rel=1e-12)


def test_an_arc_is_its_circle_point_for_point_and_its_cached_angles_stay_fixed() -> None:
    """Arcs of one angle range share their cos and sin (a fixed section's every design): each
    point is still (cx + r cos a, cy + r sin a) at n evenly spaced angles, and the shared
    arrays cannot be written through."""
    a0, a1, seg = 0.3, 2 * math.pi - 0.3, 48
    n = math.ceil((a1 - a0) / (2 * math.pi) * seg) + 1
    angles = np.linspace(a0, a1, n)
    for cx, cy, r in ((0.0, 0.0, 0.02), (0.41, -0.1, 0.035)):
        points = cad.arc(cx, cy, r, a0, a1, seg)
        expected = np.column_stack([cx + r * np.cos(angles), cy + r * np.sin(angles)])
        np.testing.assert_array_equal(points, expected)
        points[:] = 0.0  # the caller's copy
    cos, _ = cad._unit_arc(a0, a1, seg)
    with pytest.raises(ValueError, match="read-only"):
        cos[0] = 2.0
    np.testing.assert_array_equal(cad.arc(0.0, 0.0, 1.0, a0, a1, seg)[:, 0], np.cos(angles))
