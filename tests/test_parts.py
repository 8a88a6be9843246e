"""Bored link parts: hole count by the Euler number, exact mass against a hand-computed plate."""

from __future__ import annotations

import math

import numpy as np
import pytest

from qsm.embodiment.parts import bearings, part_mass, part_outlines
from qsm.embodiment.parts import link_parts as parts
from qsm.physics import cad
from qsm.physics.kinematics import LINK_NAMES

DESIGN = np.array([0.5, 0.15, 0.55, 0.22, 0.6, 0.2])


def _index(name: str) -> int:
    table = bearings.load_catalogue()
    return int(np.flatnonzero(table.designation == name)[0])


def test_every_link_has_one_through_hole_per_joint_and_is_watertight() -> None:
    idx = [_index(n) for n in ("6000", "608", "6204", "6206")]
    built = parts.link_parts(DESIGN, idx)
    meshes = parts.part_meshes(built)
    expected = {"lower_arm": 2, "crank": 2, "coupler": 2, "upper_arm": 3}  # upper arm: B, D, E
    for name, mesh in meshes.items():
        assert mesh.is_watertight and mesh.is_winding_consistent and mesh.volume > 0
        genus = (2 - mesh.euler_number) // 2
        assert genus == expected[name] == built[name].holes, name
    no_tool = parts.link_parts(DESIGN, idx, parts.PartSettings(tool_hole_m=0.0))
    assert (2 - parts.part_meshes(no_tool)["upper_arm"].euler_number) // 2 == 2


def test_bores_and_bosses_follow_the_bearings() -> None:
    # 6206 at D: seat 62 mm, boss 31 + 4 = 35 mm; 608 at B: boss stays the configured 25 mm
    idx = [_index(n) for n in ("6000", "608", "6204", "6206")]
    bores = parts.link_bores(DESIGN, idx)
    coupler = {b.joint: b for b in bores["coupler"]}
    assert coupler["D"].kind == "seat" and coupler["D"].diameter_m == pytest.approx(0.062)
    assert coupler["D"].boss_radius_m == pytest.approx(0.035)
    assert coupler["C"].kind == "pin" and coupler["C"].diameter_m == pytest.approx(0.020)
    assert coupler["D"].ligament_m() == pytest.approx(0.004)
    upper = {b.joint: b for b in bores["upper_arm"]}
    assert upper["D"].diameter_m == pytest.approx(0.030) and upper["D"].boss_radius_m == 0.035
    assert upper["B"].diameter_m == pytest.approx(0.008) and upper["B"].boss_radius_m == 0.025
    assert upper["E"].diameter_m == pytest.approx(0.009) and upper["E"].centre_m == (0.6, -0.2)
    lower = {b.joint: b for b in bores["lower_arm"]}
    assert lower["A"].kind == "shaft" and lower["A"].diameter_m == pytest.approx(0.010)
    assert lower["B"].kind == "seat" and lower["B"].diameter_m == pytest.approx(0.022)
    # the polygon's holes: the inscribed circle of each is the nominal bore
    poly = parts.link_parts(DESIGN, idx)["coupler"].polygon
    hole = np.asarray(poly.interiors[1].coords)[:-1] - (0.55, 0.0)
    n = cad.CadSettings().segments_per_circle
    assert np.hypot(*hole.T).min() * math.cos(math.pi / n) == pytest.approx(0.031)


def test_mass_of_bored_plate_matches_hand_computation() -> None:
    """Stadium plate (bosses of half the bar width) minus a 10 mm and a 22 mm disc."""
    L, w, t, rho, n = 0.4, 0.04, 0.01, 1040.0, 4096
    h = w / 2
    section = cad.CadSettings(
        width_m=w,
        thickness_m=t,
        boss_radius_m=h * (1 + 1e-12),
        density_kg_m3=rho,
        segments_per_circle=n,
    )
    settings = parts.PartSettings(cad=section, boss_wall_m=0.004)
    # lower arm: A shaft of 6000 (d 10 mm), B seat of 608 (D 22 mm, boss 11 + 4 < 20 mm)
    idx = [_index("6000"), _index("608"), _index("608"), _index("608")]
    mp = part_mass.bored_mass_properties([L, L, L, L, L, L], idx, settings)["lower_arm"]
    # hand: stadium (rectangle + two half discs) about its centre (L/2, 0)
    a_half = math.pi * h**2 / 2
    a_st = L * w + 2 * a_half
    iy_st = L * w**3 / 12 + math.pi * h**4 / 4  # integral y^2
    ix_st = w * L**3 / 12 + 2 * ((L / 2) ** 2 * a_half + L * (2 * h**3 / 3) + math.pi * h**4 / 8)
    # holes: discs of radius ra at x = 0 and rb at x = L (polygon area n r^2 tan(pi/n))
    ra, rb = 0.005, 0.011
    aa, ab = (n * r * r * math.tan(math.pi / n) for r in (ra, rb))
    area = a_st - aa - ab
    cx = (a_st * L / 2 - ab * L) / area
    ix = ix_st + a_st * (L / 2 - cx) ** 2
    ix -= aa * ra**2 / 4 + aa * cx**2 + ab * rb**2 / 4 + ab * (L - cx) ** 2
    iy = iy_st - aa * ra**2 / 4 - ab * rb**2 / 4
    mass = rho * t * area
    assert mp.mass_kg == pytest.approx(mass, rel=1e-6)
    np.testing.assert_allclose(mp.com_m, [cx, 0.0, 0.0], atol=1e-9)
    hand = np.diag(
        [rho * t * iy + mass * t**2 / 12, rho * t * ix + mass * t**2 / 12, rho * t * (ix + iy)]
    )
    np.testing.assert_allclose(mp.inertia_kg_m2, hand, rtol=1e-5, atol=1e-12)
    # holes make it lighter than qsm.physics.cad's solid bar by the discs
    solid = cad.mass_properties([L, L, L, L, L, L], section)["lower_arm"]
    assert solid.mass_kg - mp.mass_kg == pytest.approx(rho * t * (aa + ab), rel=1e-6)


def test_analytic_mass_properties_match_trimesh() -> None:
    idx = [_index(n) for n in ("6001", "6203", "6005", "6206")]
    built = parts.link_parts(DESIGN, idx)
    analytic = part_mass.part_mass_properties(built)
    for name, mesh in parts.part_meshes(built).items():
        mesh.density = cad.DEFAULT_CAD.density_kg_m3
        a = analytic[name]
        assert mesh.mass == pytest.approx(a.mass_kg, rel=1e-9), name
        np.testing.assert_allclose(mesh.center_mass, a.com_m, atol=1e-9)
        np.testing.assert_allclose(mesh.moment_inertia, a.inertia_kg_m2, rtol=1e-9, atol=1e-12)


def test_outlines_with_the_configured_boss_are_qsm_cad_outlines() -> None:
    s = cad.CadSettings()
    r = s.boss_radius_m
    o = cad.link_outlines(DESIGN, s)
    np.testing.assert_array_equal(part_outlines.bar_outline(0.55, r, r, s), o["coupler"])
    np.testing.assert_array_equal(
        part_outlines.upper_arm_outline(0.22, 0.6, 0.2, r, r, r, s), o["upper_arm"]
    )


def test_stl_export_in_millimetres(tmp_path) -> None:
    import trimesh

    idx = [_index(n) for n in ("6000", "608", "6204", "6206")]
    paths = parts.export_parts_stl(parts.link_parts(DESIGN, idx), tmp_path)
    assert [p.name for p in paths] == [f"{n}.stl" for n in LINK_NAMES]
    mesh = trimesh.load(paths[2])  # coupler: C boss 23.5 + 4 mm (6204), D 31 + 4 mm (6206)
    assert mesh.is_watertight
    np.testing.assert_allclose(mesh.extents, [550 + 27.5 + 35, 70, 20], atol=0.05)


def test_boss_fit_violation_agrees_with_the_outline() -> None:
    idx = [_index("6206")] * 4  # bosses of 35 mm at A-D: overlap sqrt(35^2 - 20^2) = 28.7 mm
    radii = parts.joint_radii(idx)
    x = math.sqrt(0.035**2 - 0.02**2)
    short = np.array([0.5, 2 * x - 0.001, 0.55, 0.22, 0.6, 0.2])
    ok = np.array([0.5, 2 * x + 0.001, 0.55, 0.22, 0.6, 0.2])
    v = parts.boss_fit_violation_m(np.stack([short, ok]), np.stack([radii, radii]))
    assert v[0] == pytest.approx(0.001) and v[1] < 0
    with pytest.raises(cad.CadError):
        parts.link_parts(short, idx)
    parts.link_parts(ok, idx)
