"""Parts at each link's own section (``cad.section: sized``): the bored parts, their meshes,
masses, BOM and drawing, the FE problem, the realisation's scales and the export, against hand
computation."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
import trimesh

from qsm.embodiment.parts import bearings, bom, part_mass, printing
from qsm.embodiment.parts import link_parts as parts
from qsm.embodiment.parts.printing import link_printability, printability_violation_mm
from qsm.physics.cad import CadSettings
from qsm.physics.kinematics import LINK_NAMES
from qsm.realization.topology.plate_loads import LinkLoads, link_problem
from qsm.report.drawing import draw_links

DESIGN = np.array([0.5, 0.15, 0.55, 0.22, 0.6, 0.2])
#: lower arm, crank, coupler, upper arm: the configured 40 x 20 mm section (boss R25) times these
SCALE = (1.0, 0.8, 1.6, 1.1)


def _index(name: str) -> int:
    table = bearings.load_catalogue()
    return int(np.flatnonzero(table.designation == name)[0])


IDX = [_index(n) for n in ("6000", "608", "6204", "6206")]  # at A, B, C, D


def _sized() -> dict[str, parts.LinkPart]:
    return parts.link_parts(DESIGN, IDX, parts.PartSettings(scale=SCALE))


def test_each_part_takes_its_own_section() -> None:
    """By hand (R = 25 s mm, boss max(R, D / 2 + 4 mm)): the coupler (s 1.6) has bosses of
    R 40 at C (6204: 27.5) and D (6206: 35), so it spans 550 + 2 x 40 by 80 mm, 32 thick; the
    crank (s 0.8, R 20) has 20 at A (6000: 17) and 27.5 at C: 150 + 20 + 27.5 by 55 mm, 16 thick."""
    built = _sized()
    for name, f in zip(LINK_NAMES, SCALE, strict=True):
        assert built[name].section.width_m == pytest.approx(0.040 * f)
        assert built[name].section.thickness_m == pytest.approx(0.020 * f)
    coupler = {b.joint: b.boss_radius_m for b in built["coupler"].bores}
    crank = {b.joint: b.boss_radius_m for b in built["crank"].bores}
    assert coupler == pytest.approx({"C": 0.040, "D": 0.040})
    assert crank == pytest.approx({"A": 0.020, "C": 0.0275})
    meshes = parts.part_meshes(built)
    extents = {name: sorted(1e3 * m.extents) for name, m in meshes.items()}
    assert extents["coupler"] == pytest.approx(sorted([630.0, 80.0, 32.0]), abs=0.05)
    assert extents["crank"] == pytest.approx(sorted([197.5, 55.0, 16.0]), abs=0.05)
    masses = part_mass.part_mass_properties(built)
    for name, f in zip(LINK_NAMES, SCALE, strict=True):
        assert meshes[name].is_watertight
        assert 1e3 * meshes[name].extents[2] == pytest.approx(20.0 * f)
        # density x own thickness x the shapely area of the bored outline
        area = shapely.area(built[name].polygon)
        assert masses[name].mass_kg == pytest.approx(1040.0 * 0.020 * f * area, rel=1e-9)


def test_one_scale_for_every_link_is_the_configured_section() -> None:
    fixed = parts.link_parts(DESIGN, IDX)
    ones = parts.link_parts(DESIGN, IDX, parts.PartSettings(scale=(1.0,) * 4))
    for name in LINK_NAMES:
        assert fixed[name].polygon.equals_exact(ones[name].polygon, 0.0)
        assert fixed[name].section == ones[name].section == CadSettings()
    with pytest.raises(ValueError, match="one positive factor per link"):
        parts.PartSettings(scale=(1.0, 1.0, 1.0))


def test_the_bom_and_the_drawing_give_each_links_section(tmp_path) -> None:
    """Pins through the two plates of their joint: B lower arm 20 + upper arm 22 = 42 mm, C crank
    16 + coupler 32 = 48 mm, D coupler 32 + upper arm 22 = 54 mm."""
    built = _sized()
    frame = bom.bill_of_materials(built, part_mass.part_mass_properties(built), IDX)
    printed = frame[frame.category == "printed part"].set_index("item")
    assert printed["bbox_z_mm"].tolist() == pytest.approx([20.0, 16.0, 32.0, 22.0])
    assert printed.loc["coupler", ["bbox_x_mm", "bbox_y_mm"]].tolist() == pytest.approx(
        [630.0, 80.0], abs=0.05
    )
    pins = frame[frame.category == "pin"].set_index("where")["designation"].tolist()
    assert pins == ["dowel pin 8 x 42 mm", "dowel pin 20 x 48 mm", "dowel pin 30 x 54 mm"]
    svg, _ = draw_links(DESIGN, built, tmp_path / "links")
    text = svg.read_text()
    assert "coupler: section width 64.0 x thickness 32.0 mm" in text
    assert "crank: section width 32.0 x thickness 16.0 mm" in text


def test_the_fe_problem_is_the_links_own_plate() -> None:
    """The upper arm at s 1.1: plate 22 mm thick, its outline reaches R 27.5 mm above B."""
    cases = [LinkLoads("case", "B", {"D": np.array([0.0, 10.0]), "E": np.array([0.0, -5.0])})]
    problem, outline = link_problem(DESIGN, CadSettings(), "upper_arm", cases, scale=SCALE)
    assert problem.thickness_m == pytest.approx(0.022)
    assert outline.bounds[3] == pytest.approx(0.0275, rel=1e-6)
    fixed, _ = link_problem(DESIGN, CadSettings(), "upper_arm", cases)
    assert fixed.thickness_m == 0.020
    assert problem.solid.sum() > fixed.solid.sum()  # bosses of R 27.5, not 25 mm


def test_the_exports_printability_is_each_links_own() -> None:
    """With one section: the numbers of qsm.embodiment.parts.printing and g12; sized: the coupler's
    CAD outline is 550 + 2 x 40 by 80 mm, 32 thick, and the upper arm's the longest."""
    cad, volume = CadSettings(), (600.0, 350.0, 350.0)
    fixed = link_printability(DESIGN, cad, None, volume)
    assert fixed["links"] == printing.fits_build_volume(DESIGN, cad, volume)
    assert (
        fixed["needed_volume_mm"] == printing.needed_volume_mm(DESIGN[None], None, cad)[0].tolist()
    )
    assert fixed["print_excess_mm"] == printability_violation_mm(DESIGN[None], cad, volume)[0]
    sized = link_printability(DESIGN, cad, SCALE, volume)
    assert sized["links"]["coupler"]["dims_mm"] == pytest.approx((630.0, 80.0, 32.0), abs=0.05)
    assert not sized["links"]["coupler"]["fits"]  # 630 mm > 600 mm
    # the upper arm (R 27.5): 220 + 27.5 + 600 + 27.5 by 27.5 + 200 + 27.5; the coupler 32 thick
    assert sized["needed_volume_mm"] == pytest.approx([875.0, 255.0, 32.0])
    assert sized["print_excess_mm"] == pytest.approx(875.0 - 600.0)


def test_a_sized_export_builds_each_link_at_its_checked_section(tmp_path) -> None:
    """``qsm export`` under ``cad.section: sized``: each STL as thick as its link's checked
    section, the box in ``design.json`` too, and the MJCF's link masses those of the solid links
    at these sections."""
    import mujoco

    from qsm.app.export import export_design
    from qsm.config.reading import load_config
    from qsm.physics.cad import mass_properties

    config = load_config()
    config["cad"]["section"] = "sized"
    design = np.array([0.3987, 0.0825, 0.4323, 0.1373, 0.3928, 0.1178])
    record = export_design(design, config, tmp_path)
    links = record["strength"]["links"]
    scale = [links[k]["width_mm"] / 40.0 for k in LINK_NAMES]
    assert not np.allclose(scale, 1.0)
    for name in LINK_NAMES:
        t = links[name]["thickness_mm"]
        assert trimesh.load(tmp_path / "stl" / f"{name}.stl").extents[2] == pytest.approx(t)
        assert record["printability"]["links"][name]["box_mm"][2] == pytest.approx(t)
    model = mujoco.MjModel.from_xml_path(str(tmp_path / "model.xml"))
    masses = mass_properties(design, CadSettings(), scale)
    for name in ("crank", "coupler", "lower_arm"):  # the upper arm carries the payload
        assert model.body(name).mass[0] == pytest.approx(masses[name].mass_kg, rel=1e-5)


def test_a_printed_part_too_large_for_the_printer_is_not_ready() -> None:
    """``printable`` is decided on the configured section; a part drawn larger (sized) that
    does not fit is named once, with its box."""
    from qsm.report.readiness import build_verdict

    links = {key: {"holds": True} for key in LINK_NAMES}
    strength = {"links": links, "bearings": {}, "holds_loads": True}
    whole = {"fits": True, "watertight": True}
    printer = {key: {"box_mm": [20.0, 50.0, 300.0]} | whole for key in LINK_NAMES}
    printer["coupler"] = {"box_mm": [32.0, 80.0, 630.0], "fits": False, "watertight": True}
    topology = {"links": {}, "parts": {"printer": printer}}
    ok = {"links": {}, "parts": {"printer": {"coupler": {"box_mm": [1, 2, 3]} | whole}}}
    assert build_verdict({"printable": True, "strength": strength}, ok, {"passed": True})[0]
    ready, problems = build_verdict(
        {"printable": True, "strength": strength}, topology, {"passed": True}
    )
    assert not ready
    assert problems == ["the printed coupler (32.0 x 80.0 x 630.0 mm) does not fit the printer"]
    boxes = {key: [20.0, 50.0, 300.0] for key in LINK_NAMES} | {"coupler": [32.0, 80.0, 630.0]}
    unprintable = {
        "printable": False,
        "printer_box_mm": boxes,
        "printer_volume_mm": [600, 350, 350],
    }
    _, problems = build_verdict(unprintable | {"strength": strength}, topology, {"passed": True})
    assert problems[0] == (
        "not printable: the coupler (32 x 80 x 630 mm) does not fit the printer's 600 x 350 x "
        "350 mm build volume"
    )


def test_a_mesh_with_a_hole_is_mended_and_one_that_stays_open_is_not_ready() -> None:
    """A box with one face removed is open; trimesh's repairs close it. A printed part whose
    mesh stays open makes the run NOT READY, naming the part."""
    from qsm.realization.selection.outputs import watertight
    from qsm.report.readiness import build_verdict

    box = trimesh.creation.box((1.0, 2.0, 3.0))
    box.update_faces(np.arange(1, len(box.faces)))
    assert not box.is_watertight
    assert watertight(box) and box.volume == pytest.approx(6.0)
    links = {key: {"holds": True} for key in LINK_NAMES}
    strength = {"links": links, "bearings": {}, "holds_loads": True}
    printer = {"crank": {"box_mm": [1, 2, 3], "fits": True, "watertight": False}}
    _, problems = build_verdict(
        {"printable": True, "strength": strength},
        {"links": {}, "parts": {"printer": printer}},
        {"passed": True},
    )
    assert problems == [
        "the crank's STL is not watertight after trimesh's repairs: a slicer may not print it "
        "as drawn"
    ]
