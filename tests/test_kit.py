"""The builder's kit (qsm.embodiment.kit, qsm.realization.kit.builders_kit,
qsm.realization.kit.kit_files):
fasteners from the standards' tables, the pins, hubs and tool flange against hand calculations,
the base's cheek against a cantilever of the frame model, the drives' interfaces and their
assumptions, the BOM's quantities, and STEP and DXF files read back by their kernels."""

from __future__ import annotations

import json
import math
from dataclasses import replace

import ezdxf
import numpy as np
import pytest
from build123d import import_step

from qsm.embodiment.kit import base as bs
from qsm.embodiment.kit import fasteners as fs
from qsm.embodiment.kit import joints as jt
from qsm.embodiment.kit.interfaces import interface_of, read_interfaces
from qsm.embodiment.stiffness.frame import beam_stiffness
from qsm.embodiment.strength.record import BearingLoad
from qsm.realization.kit import kit_layout as kl
from qsm.realization.kit.kit_bom import fastener_rows, screw_lines
from qsm.realization.kit.kit_files import write_dxf, write_step


def test_screw_lengths_are_the_shortest_preferred_that_span_grip_and_tail():
    # tapped: 20 mm grip + 1.5 x 6 mm engagement = 29 -> the next preferred length, 30
    assert fs.cap_screw("M6", 20.0, True, "").length_mm == 30
    # through: 20 + washer 1.6 + nut 6.0 + 1 mm of thread beyond = 28.6 -> 30
    assert fs.cap_screw("M6", 20.0, False, "").length_mm == 30
    # 25.1 + 9 = 34.1 -> 35
    assert fs.cap_screw("M6", 25.1, True, "").length_mm == 35
    # beyond the series: a threaded rod with a nut at each end, in 5 mm steps
    rod = fs.cap_screw("M4", 60.0, False, "")
    assert rod.standard == "DIN 976-1" and rod.length_mm % 5 == 0
    assert rod.length_mm >= 60.0 + 2 * (fs.washer_mm("M4")[2] + fs.nut_height_mm("M4") + 1)


def test_a_pin_is_checked_as_a_cantilever_from_its_printed_bore():
    bearing = BearingLoad("", 400.0, (0.0, 0.0), d_mm=6.0, B_mm=6.0)
    seat = jt.Plate("lower_arm", 20.0, 15.5, 20.0)
    other = jt.Plate("upper_arm", 20.0, 15.5, 20.0)
    pin = jt.pin("B", bearing, seat, other, 2.0)
    # by hand: the printed bore carries 400 N over 400 / (15.5 x 6) = 4.30 mm; the arm is
    # 3 mm (half the bearing) + 1.6 mm (the M6 washer) + 2.15 mm = 6.75 mm
    arm = 3.0 + 1.6 + 400 / (15.5 * 6) / 2
    assert pin["bending_arm_mm"] == pytest.approx(arm)
    bending = 32 * 400 * arm / (math.pi * 6**3)  # 127 MPa
    shear = 4 * 400 / (math.pi * 6**2)  # 14 MPa
    assert pin["safety_factor"] == pytest.approx(1100 / math.hypot(bending, math.sqrt(3) * shear))
    assert pin["screw"] == "ISO 7379 6 x 45 - M5"  # 20 + 1.6 + 20 = 41.6 -> 45
    assert pin["fill_spacers"] == 2  # 3.4 mm of shoulder left: two 1.6 mm spacers
    assert pin["holds"]
    weak = jt.pin("B", replace(bearing, peak_force_N=4000.0), seat, other, 2.0)
    assert not weak["holds"]  # 43 mm of printed bore needed, and 10x the moment


def test_the_tool_flange_is_the_smallest_pattern_that_carries_the_load():
    light = jt.tool_flange(50.0, 0.05, 40.0, 20.0, 2.0)
    assert light.pattern == "ISO 9409-1-31.5-4-M5"
    # the most loaded of 4 bolts on r = 15.75 mm: 2 F e / (n r) + F / n
    assert light.bolt_force_N == pytest.approx(2 * 50 * 50 / (4 * 15.75) + 50 / 4)
    # 60 kN at 0.2 m is too much for the 31.5 pattern's M5 bolts (14.2 mm^2 x 640 MPa / 2)
    heavy = jt.tool_flange(2000.0, 0.2, 60.0, 20.0, 2.0)
    assert heavy.pattern != light.pattern and heavy.holds
    bare = jt.tool_flange(2000.0, 0.2, 15.0, 20.0, 2.0)  # no face fits the boss
    assert not bare.holds and bare.record()["tried"] == list(bare.tried)
    for flange in (light, bare):  # the record reads back as the flange
        assert jt.ToolFlange.of(json.loads(json.dumps(flange.record()))) == flange


def _cantilever_top(load: bs.CheekLoad, h: float, b: float, t: float) -> tuple[float, float]:
    """The cheek's top under the force F (along x) and the torque T turning it the same way
    (clockwise, the worst case the check takes), by the frame model's Timoshenko beam without
    shear: solve the 3 free dofs of the tip."""
    e = bs.ALUMINIUM["E_MPa"]
    k = beam_stiffness(np.array([0.0, 0.0]), np.array([0.0, h]), e * b * t, e * t * b**3 / 12, 0.0)
    tip = np.linalg.solve(k[3:, 3:], np.array([load.force_N, 0.0, -load.torque_Nm * 1e3]))
    return tip[0], -tip[2]


def test_the_cheek_s_deflection_and_turn_agree_with_the_frame_model():
    load = bs.CheekLoad(400.0, 30.0, 3.0, 40.0, 30.0)
    deflection, turn = bs.top_motion(load, 300.0, 150.0, 10.0)
    frame = _cantilever_top(load, 300.0, 150.0, 10.0)
    assert deflection == pytest.approx(frame[0], rel=1e-9)
    assert turn == pytest.approx(frame[1], rel=1e-9)


def test_the_cheek_s_root_stress_by_hand_and_its_width_for_the_tolerance():
    load = bs.CheekLoad(400.0, 30.0, 3.0, 40.0, 30.0)
    h, b, t = 300.0, 150.0, 10.0
    by_hand = (
        6 * (400 * 300 + 30e3) / (t * b**2)
        + 6 * (400 * (30 + t / 2) + 3 * 9.81 * (40 + t / 2)) / (b * t**2)
        + (400 + 3 * 9.81) / (b * t)
    )
    assert bs.root_stress_MPa(load, h, b, t) == pytest.approx(by_hand)
    part = bs.cheek(load, h, b, 2.0, (800.0, 0.0), t, (0.05, 1.0))
    assert part["tool_error_mm"] <= 0.05 + 1e-9 and part["width_mm"] > b
    narrower = bs.cheek(load, h, part["width_mm"] - 5, 2.0, (800.0, 0.0), t, (1e3, 1.0))
    assert narrower["tool_error_mm"] > 0.05


def test_the_cheek_s_tilt_across_its_thickness_agrees_with_the_frame_model():
    """The moment F e + m g c at the top of the cheek, bent across its thickness: the frame
    model's beam with I = b t^3 / 12 gives the top's turn and move along the axis; the tool moves
    by the move, plus the turn times its reach and its distance along the axis."""
    load = bs.CheekLoad(400.0, 30.0, 3.0, 40.0, 30.0)
    h, b, t = 300.0, 150.0, 10.0
    e = bs.ALUMINIUM["E_MPa"]
    k = beam_stiffness(np.array([0.0, 0.0]), np.array([0.0, h]), e * b * t, e * b * t**3 / 12, 0.0)
    moment = 400.0 * (30.0 + t / 2) + 3.0 * 9.81 * (40.0 + t / 2)
    tip = np.linalg.solve(k[3:, 3:], np.array([0.0, 0.0, moment]))
    angle, along = bs.tilt(load, h, b, t)
    assert angle == pytest.approx(tip[2], rel=1e-9)
    assert along == pytest.approx(abs(tip[0]), rel=1e-9)
    part = bs.cheek(load, h, b, 2.0, (800.0, 60.0), t, (1e3, 1.0))
    assert part["tilt_error_mm"] == pytest.approx(along + angle * 860.0, rel=1e-12)
    assert part["tilt_error_mm"] > part["allowed_tilt_error_mm"]  # 10 mm is too thin here


def test_a_pocketed_cheek_s_tilt_and_stress_agree_with_two_beams_and_two_strips():
    """A 60 mm pocket: the frame model's two beams (the full section from the root to D / 2
    below A, the strips beside the pocket, I = (b - D) t^3 / 12, over the last D / 2) give the
    top's turn and move along the axis; at the pocket's lowest edge the in-plane moment F D / 2
    + T bends the two 20 mm strips (parallel axes), the out-of-plane one bends them across."""
    load = bs.CheekLoad(1000.0, 10.0, 1.0, 30.0, 20.0)
    h, b, t, d = 150.0, 100.0, 20.0, 60.0
    e = bs.ALUMINIUM["E_MPa"]
    k = np.zeros((9, 9))
    for (y0, y1), width, at in (((0, h - d / 2), b, 0), ((h - d / 2, h), b - d, 3)):
        ends = np.array([0.0, y0]), np.array([0.0, y1])
        k[at : at + 6, at : at + 6] += beam_stiffness(
            *ends, e * width * t, e * width * t**3 / 12, 0.0
        )
    moment = 1000.0 * (20.0 + t / 2) + 1.0 * 9.81 * (30.0 + t / 2)
    tip = np.linalg.solve(k[3:, 3:], np.array([0.0, 0.0, 0.0, 0.0, 0.0, moment]))
    angle, along = bs.tilt(load, h, b, t, bs.Pocket(d, 12.0))
    assert angle == pytest.approx(tip[5], rel=1e-9)
    assert along == pytest.approx(abs(tip[3]), rel=1e-9)
    w = (b - d) / 2
    strips = 2 * (t * w**3 / 12 + t * w * (d / 2 + w / 2) ** 2)
    by_hand = (
        (1000.0 * d / 2 + 10e3) * (b / 2) / strips
        + moment * (t / 2) / ((b - d) * t**3 / 12)
        + (1000.0 + 9.81) / ((b - d) * t)
    )
    assert bs.pocket_stress_MPa(load, b, t, bs.Pocket(d, 12.0)) == pytest.approx(by_hand)
    assert bs.pocket_stress_MPa(load, b, t, bs.Pocket()) == 0.0
    part = bs.cheek(load, h, 70.0, 2.0, (800.0, 0.0), t, (1e3, 1e3), bs.Pocket(d, 12.0))
    assert part["width_mm"] == d + 20 and part["pocket"]["web_mm"] == t - 12.0


def test_interfaces_from_the_catalogue_and_what_is_assumed_named(tmp_path):
    rows = read_interfaces()
    assert rows["TM_AK80-6_GB"].output == "flange" and rows["TM_AK80-6_GB"].flange_bolts == 6
    ak = interface_of("TM_AK80-6_GB", 10.0)
    assert ak.assumed == ""  # every value in the row
    hd = interface_of("HD_CSF-32-100-2UH", 60.0)
    assert "output flange" in hd.assumed and hd.body_d_mm == 138.0
    none = interface_of("no such gearbox", 60.0)
    assert none.status == "assumed" and "shaft" in none.assumed
    # the shaft grows with the torque: 16 T / (pi d^3) <= 60 MPa
    assert interface_of("x", 600.0).shaft_d_mm > none.shaft_d_mm
    d = interface_of("x", 600.0).shaft_d_mm
    assert 16 * 600e3 / (math.pi * d**3) <= 60.0


def test_fastener_quantities_add_up_across_the_assembly():
    lines = [("ISO 4762 M6 x 30", 4, "a"), ("ISO 7089 M6", 4, "a"), ("ISO 4762 M6 x 30", 3, "b")]
    rows = {r["item"]: r for r in fastener_rows(lines)}
    assert rows["ISO 4762 M6 x 30"]["quantity"] == 7
    assert rows["ISO 4762 M6 x 30"]["where"] == "a (4); b (3)"
    assert sum(r["quantity"] for r in rows.values()) == sum(q for _, q, _ in lines)


def _layout() -> dict:
    plate = {
        "outline": [[0, 0], [100, 0], [100, 40], [0, 40]],
        "holes": [kl.circle(20, 20, 8), kl.circle(80, 20, 8)],
        "thickness_mm": 6.0,
        "origin": [0, 0, 0],
        "x_dir": [1, 0, 0],
        "normal": [0, 0, 1],
        "kind": "cut",
    }
    other = plate | {"origin": [0, 0, 10], "x_dir": [0, 1, 0]}
    turned = {"hub_1": kl.turned([(30, -8, 0), (20, 0, 10)], 10)}
    return {"plates": {"one": plate, "two": other}, "turned": turned, "pose_deg": [90, 0]}


def test_step_files_reopen_as_closed_solids_and_dxf_reads_back(tmp_path):
    layout = _layout()
    paths = write_step(layout, tmp_path / "step")
    for name in ("one", "two", "hub_1"):
        shape = import_step(paths[name])
        assert len(shape.solids()) == 1 and shape.is_valid, name
    plate = import_step(paths["one"])
    hole = _area(kl.circle(0, 0, 8))
    assert plate.volume == pytest.approx(100 * 40 * 6 - 2 * 6 * hole, rel=1e-6)
    assembly = import_step(paths["assembly"])
    assert len(assembly.solids()) == 3
    dxf = write_dxf(layout, tmp_path / "dxf")
    doc = ezdxf.readfile(dxf["one"])
    layers = [e.dxf.layer for e in doc.modelspace().query("LWPOLYLINE")]
    assert layers.count("OUTLINE") == 1 and layers.count("HOLES") == 2


def test_a_hub_s_keyway_and_set_screw_hole_and_a_cheek_s_tapped_edge_by_hand(tmp_path):
    """A 20 mm hub on a 12 mm bore, 30 mm long, less a 4 mm keyway 7.8 mm from the axis (DIN
    6885-1's 1.8 mm past the bore) at 0 rad, and a 4 mm hole across the wall at z = 15, at pi
    rad: the keyway takes 30 (4 x 7.8 - the bore's segment) mm^3 and the hole the integral of
    its chords between r = 6 and 10. A 40 x 50 x 10 mm plate less a 5 mm hole 20 mm up from its
    bottom edge at mid-thickness. Each read back from its STEP file and probed where the cuts
    are."""
    from build123d import Vector
    from scipy.integrate import quad

    hub = kl.turned([(20.0, 0.0, 30.0)], 12.0) | {
        "keyways": [[0.0, 4.0, 7.8, 0.0, 30.0]],
        "cross_holes": [[math.pi, 15.0, 4.0]],
    }
    plate = {"outline": [[-20, -50], [20, -50], [20, 0], [-20, 0]], "holes": [],
             "thickness_mm": 10.0, "origin": [0, 0, 0], "x_dir": [1, 0, 0], "normal": [0, 0, 1],
             "edge_holes": [[0.0, 5.0, -50.0, -30.0]]}  # fmt: skip
    paths = write_step({"plates": {"cheek": plate}, "turned": {"hub": hub}}, tmp_path)
    segment = 2 * (2 * math.sqrt(32) / 2 + 18 * math.asin(2 / 6))  # the bore's, |y| < 2

    def chord(w: float) -> float:  # the hole's width at w times the wall's depth there
        return 2 * math.sqrt(4 - w * w) * (math.sqrt(100 - w * w) - math.sqrt(36 - w * w))

    chords = quad(chord, -2, 2)[0]
    solid = import_step(paths["hub"])
    ring = math.pi / 4 * (20**2 - 12**2) * 30
    assert solid.volume == pytest.approx(ring - 30 * (4 * 7.8 - segment) - chords, rel=2e-3)
    assert not solid.is_inside(Vector(7.0, 0.0, 3.0))  # in the keyway
    assert solid.is_inside(Vector(-7.0, 0.0, 3.0))
    assert not solid.is_inside(Vector(-8.0, 0.0, 15.0))  # in the set screw's hole
    assert solid.is_inside(Vector(-8.0, 0.0, 20.0))
    cheek = import_step(paths["cheek"])
    assert cheek.volume == pytest.approx(40 * 50 * 10 - math.pi / 4 * 25 * 20, rel=1e-6)
    assert not cheek.is_inside(Vector(0.0, -40.0, 5.0)) and cheek.is_inside(Vector(0, -25, 5))


def _area(ring: list) -> float:
    x, y = np.asarray(ring).T
    return 0.5 * abs(np.dot(x, np.roll(y, 1)) - np.dot(y, np.roll(x, 1)))


def test_a_threaded_rod_brings_the_nut_for_its_second_end():
    rod = screw_lines("DIN 976-1 M4 x 60", 6, "hub 1 to the lower arm")
    assert rod == [
        ("DIN 976-1 M4 x 60", 6, "hub 1 to the lower arm"),
        ("ISO 10511 M4", 6, "hub 1 to the lower arm: rod ends"),
    ]
    assert screw_lines("ISO 4762 M6 x 30", 4, "x") == [("ISO 4762 M6 x 30", 4, "x")]


def test_a_hub_s_key_bears_over_its_engaged_length_less_its_width():
    plate = jt.Plate("crank", 30.0, 15.5, 40.0)
    drive = interface_of("no such gearbox", 12.0)  # an assumed 12 mm keyed shaft, 24 mm long
    screws = jt.hub_screws(plate, 17.0, 12.0)
    hub = jt.hub(2, drive, plate, 17.0, 12.0, 2.0, 30.0, screws)
    engaged = min(drive.shaft_length_mm, 30.0 + jt.FLANGE_MM)
    by_hand = 2 * 12e3 / (drive.shaft_d_mm * 0.4 * drive.key_h_mm * (engaged - drive.key_w_mm))
    assert hub["key"]["pressure_MPa"] == pytest.approx(by_hand)
    # the inserts' holes keep two diameters from the boss's edge and bear T / (6 r D L)
    length, hole, _ = fs.insert(screws["thread"])
    assert screws["pcd_mm"] / 2 == pytest.approx(40.0 - 2 * hole)
    r = screws["pcd_mm"] / 2
    assert screws["bearing_MPa"] == pytest.approx(12e3 / (6 * r * hole * length))
    # the screw engages its insert and ends short of the plate's far face
    screw_length = float(screws["screw"].designation.split()[-1])
    grip = jt.FLANGE_MM + fs.washer_mm(screws["thread"])[2]
    assert grip + 1.5 * float(screws["thread"][1:]) <= screw_length <= grip + 30.0 - 1.0
