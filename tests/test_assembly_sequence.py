"""The kit's assembly sequence (qsm.realization.kit.kit_sequence, kit_assembly, kit_solids): the
sort and its cycles, prisms that touch or pass through holes, tightening torques against a
published table, the hub screws' interface by hand, the spacers that lift a layer clear of a
pin's head, and the default-like arm's sequence checked again by sampling points."""

from __future__ import annotations

import copy
import itertools
import math

import numpy as np
import pytest
import reference_step as ref
import shapely

from qsm import load_config
from qsm.config.settings.realization import realization_of
from qsm.embodiment.kit import fasteners as fs
from qsm.embodiment.kit import joints as jt
from qsm.embodiment.strength.record import BearingLoad
from qsm.realization.kit.builders_kit import KitSettings, builders_kit, with_hub_holes
from qsm.realization.kit.kit_assembly import kit_sequence
from qsm.realization.kit.kit_sequence import Precedence, Step, Tool, order
from qsm.realization.kit.kit_solids import Prism, blockers, disc
from qsm.realization.selection.pipeline import realize

DESIGN = np.array([0.5, 0.15, 0.55, 0.22, 0.6, 0.2])
HAND = Tool("hand", "by hand")


def _step(key: str) -> Step:
    return Step(key, key, (key,), (), (0.0, 0.0, 1.0), HAND)


def test_the_sort_keeps_every_relation_and_names_a_cycle():
    steps = [_step(k) for k in "abcd"]
    relations = [Precedence("c", "a", "x"), Precedence("a", "b", "y"), Precedence("d", "b", "z")]
    done, cycle = order(steps, relations)
    at = {s.key: i for i, s in enumerate(done)}
    assert not cycle and len(done) == 4
    assert all(at[r.first] < at[r.then] for r in relations)
    done, cycle = order(steps, [*relations, Precedence("b", "c", "w")])
    assert len(done) < 4
    assert set(cycle) == {
        "'c' must come before 'a' (x)",
        "'a' must come before 'b' (y)",
        "'b' must come before 'c' (w)",
    }


def test_prisms_that_touch_do_not_meet_and_a_key_passes_a_hole():
    plate = Prism("z", shapely.box(0, 0, 100, 50).difference(disc(20, 20, 10)), 0.0, 10.0)
    assert not plate.meets(Prism("z", shapely.box(0, 0, 100, 50), 10.0, 20.0))  # stacked
    assert not plate.meets(Prism("z", shapely.box(100, 0, 150, 50), 0.0, 10.0))  # side by side
    assert plate.meets(Prism("z", shapely.box(90, 0, 150, 50), 5.0, 15.0))
    assert not plate.meets(Prism("z", disc(20, 20, 8), -50.0, 50.0))  # through the hole
    assert plate.meets(Prism("z", disc(20, 20, 12), -50.0, 50.0))
    swept = Prism("z", disc(50, 25, 8), 20.0, 30.0).swept((0.0, 0.0, 1.0), 15.0)
    assert swept.meets(plate)  # it came down through the plate


def test_a_key_turned_short_arm_in_reaches_a_head_its_long_arm_cannot():
    """A socket 40 mm above a cheek's face (z = 0), a 5 mm key (long arm 85, short 28): long
    arm first it passes through the cheek; short arm first it ends 12 mm above the face, and
    its handle (5 / 0.866 + 1 mm thick) turns in the plane clear of the cheek, but not of a
    plate beside the head on the handle's side."""
    from qsm.realization.kit.kit_sequence import key_path, short_key_path

    key = fs.HexKey(5.0, 85.0, 28.0)
    cheek = {"cheek": (Prism("z", shapely.box(-100, -100, 100, 100), -30.0, 0.0),)}
    assert blockers(key_path(0.0, 0.0, 40.0, -1.0, key), cheek) == ["cheek"]
    for turn in range(4):
        assert blockers(short_key_path(0.0, 0.0, 40.0, -1.0, key, turn * math.pi / 2), cheek) == []
    beside = {"plate": (Prism("z", shapely.box(20, -10, 60, 10), 0.0, 10.0),)}
    assert blockers(short_key_path(0.0, 0.0, 40.0, -1.0, key, 0.0), beside) == ["plate"]
    assert blockers(short_key_path(0.0, 0.0, 40.0, -1.0, key, math.pi), beside) == []


@pytest.mark.parametrize(
    ("thread", "published_Nm"), [("M3", 1.27), ("M5", 5.9), ("M8", 24.6), ("M12", 84.0)]
)
def test_tightening_torques_agree_with_a_published_table(thread, published_Nm):
    """A maker's table for class 8.8 at 90 % of Rp0.2 and a friction of 0.12 (hexagon head
    screws; a socket head bears on a slightly larger circle): within 8 %."""
    torque, _ = fs.tightening_torque_Nm(thread, fs.clearance_hole_mm(thread))
    assert torque == pytest.approx(published_Nm, rel=0.08)


def test_a_printed_plate_limits_the_preload_and_so_the_torque():
    full, preload = fs.tightening_torque_Nm("M5", 5.5)
    limited, limit = fs.tightening_torque_Nm("M5", 5.5, 500.0)
    assert limit == 500.0 < preload
    assert limited == pytest.approx(full * 500.0 / preload, rel=1e-12)  # linear in the preload


def test_link_side_hub_screws_by_hand():
    plate = jt.Plate("lower_arm", 37.5, 15.5, 46.85)
    s = jt.hub_screws_through_link(plate, 17.0, 83.2, 8.0)
    d, hole = float(s["thread"][1:]), fs.clearance_hole_mm(s["thread"])
    r = plate.boss_mm - jt.EDGE_DISTANCE * hole
    assert s["pcd_mm"] == pytest.approx(2 * r)
    assert s["bearing_MPa"] == pytest.approx(83.2e3 / (6 * r * d * 37.5))
    assert fs.TAPPED_ENGAGEMENT * d <= jt.FLANGE_MM
    screw = s["screw"]
    grip = 37.5 + fs.washer_mm(s["thread"])[2]
    assert grip + fs.TAPPED_ENGAGEMENT * d <= screw.length_mm <= grip + jt.FLANGE_MM + 8.0
    assert s["holds"] and s["side"] == "link"


@pytest.fixture(scope="module")
def kit():
    settings = realization_of(load_config())
    done = realize(DESIGN, settings)
    return done, builders_kit(done, done.parts, KitSettings())


def _sequence(done, record):
    parts = with_hub_holes(done.parts, record["hubs"])
    s = KitSettings()
    allow = {
        k: s.printed.across_layers_MPa(v.allowable_MPa) for k, v in done.strength.links.items()
    }
    bearings = done.strength.bearings
    return kit_sequence(record, done.design, parts, *s.operating_range.degrees, allow, bearings)


def test_the_kit_has_a_sequence_with_a_tool_for_every_screw(kit):
    _, made = kit
    record = made.record
    assert record["checks"]["assembly sequence"] and record["assembly_sequence"]["exists"]
    steps = record["assembly_sequence"]["steps"]
    placed = {p for s in steps for p in s["places"]}
    assert set(record["layout"]["plates"]) | set(record["layout"]["turned"]) <= placed
    for s in steps:
        if "Bolt" in s["text"] or "ISO 7379" in s["text"]:
            assert s["tool"].startswith("ISO 2936") and s["torque_Nm"] > 0
    assert len(record["assembly_steps"]) == len(steps)
    assert record["step_of"]["hub_1"] < record["step_of"]["lower_arm"]


def _inside(point: np.ndarray, prisms) -> bool:
    """Whether a point (x, y, z) mm lies inside any of ``prisms`` (by containment)."""
    for p in prisms:
        along, across = (point[2], point[:2]) if p.axis == "z" else (point[1], point[[0, 2]])
        if p.lo + 0.1 < along < p.hi - 0.1 and p.shape.contains(shapely.Point(*across)):
            return True
    return False


def test_every_key_path_is_free_of_the_parts_placed_before_its_step(kit):
    """An independent check by points: along each screw step's key paths at its chosen pose,
    sampled every 2 mm on the key's axis, no point is inside a part placed before the step
    (all reach alternatives of the step's pose are tried; one must be free)."""
    from qsm.realization.kit.kit_assembly import placed_solids, poses

    done, made = kit
    record = made.record
    found = _sequence(done, record)
    parts = with_hub_holes(done.parts, record["hubs"])
    s = KitSettings()
    angles = poses(done.design, record["layout"]["pose_deg"], *s.operating_range.degrees)
    placed = [placed_solids(record, done.design, parts, a) for a in angles]
    before: list[str] = []
    checked = 0
    for step in found.steps:
        pose = found.poses[step.key]
        solids = {n: placed[pose][n] for n in before if n in placed[pose]}
        if step.group:
            solids = {n: v for n, v in solids.items() if n in ("cheek_2", "drive_2")}
        free = []
        for p_, prisms in step.reach:
            if p_ != pose or step.tool.kind != "hexagon key":
                continue
            points = [
                np.array([*pr.shape.centroid.coords[0], z])
                if pr.axis == "z"
                else np.array([pr.shape.centroid.x, z, pr.shape.centroid.y])
                for pr in prisms[::2] if pr.axis in ("z", "y")
                for z in np.arange(pr.lo, pr.hi, 2.0)
            ]  # fmt: skip
            free.append(not any(_inside(pt, [q for v in solids.values() for q in v])
                                for pt in points))  # fmt: skip
        if free:
            checked += 1
            assert any(free), step.key
        before += list(step.places)
    assert checked >= 8


def test_hub_screws_from_the_hub_side_leave_no_order(kit):
    """Hub 1 bolted to its drive's flange with its link's screws from the hub's side (as the
    kit had them): the keys reach them only through the cheek and the drive, which the hub
    needs first, and the sequence names that cycle."""
    done, made = kit
    record = copy.deepcopy(made.record)
    if record["drives"][0]["output"] != "flange":
        pytest.skip("motor 1's drive has a shaft here")
    record["hubs"][0]["link_screws"] |= {"side": "hub", "thread": "M4",
                                         "screw": "ISO 4762 M4 x 16"}  # fmt: skip
    found = _sequence(done, record)
    assert not found.exists
    text = " ".join(found.blocked)
    assert "'hub 1 screws' must come before" in text
    assert any(part in text for part in ("cheek_1", "drive_1", "hub_1"))


def test_a_head_the_next_layer_cannot_clear_gets_spacers():
    """Pin B's head stands 5.5 mm out of the upper arm; where the coupler passes over it, the
    joint between the upper arm and the coupler (D) takes enough 1.6 mm washers to lift the
    coupler past the head and 1 mm, and pin D's grip and bending arm grow by them."""
    bearing = BearingLoad("", 400.0, (0.0, 0.0), d_mm=6.0, B_mm=6.0)
    seat, other = jt.Plate("coupler", 37.5, 15.5, 40.0), jt.Plate("upper_arm", 32.5, 15.5, 40.0)
    one = jt.pin("D", bearing, seat, other, 2.0)
    washer = fs.washer_mm(one["spacer"].split()[-1])[2]
    n = math.ceil((fs.shoulder_head_mm(8.0)[1] + 1.0) / washer)
    more = jt.pin("D", bearing, seat, other, 2.0, n)
    assert more["spacers_mm"] == pytest.approx(n * washer)
    assert more["grip_mm"] - one["grip_mm"] == pytest.approx((n - 1) * washer)
    assert more["bending_arm_mm"] - one["bending_arm_mm"] == pytest.approx((n - 1) * washer)


def test_shims_close_a_pin_s_axial_float():
    """The shoulder's length is the grip, the fill washers, the shims and what float is left,
    and that is below the shims' 0.1 mm step."""
    bearing = BearingLoad("", 400.0, (0.0, 0.0), d_mm=6.0, B_mm=6.0)
    seat, other = jt.Plate("crank", 37.5, 15.5, 40.0), jt.Plate("coupler", 37.5, 15.5, 40.0)
    pin = jt.pin("C", bearing, seat, other, 2.0)
    washer = fs.washer_mm(pin["spacer"].split()[-1])[2]
    length = float(pin["screw"].split(" x ")[1].split()[0])
    parts = pin["grip_mm"] + pin["fill_spacers"] * washer + pin["shims_mm"]
    assert length == pytest.approx(parts + pin["axial_float_mm"])
    assert 0.0 <= pin["axial_float_mm"] < jt.SHIM_MM


def test_the_nut_ends_facing_the_cheeks_clear_them_and_each_solid_names_its_frame(kit):
    """B's nut end on the lower arm and C's on the crank (the spacers filling the shoulder, the
    shims, then the farther of the nut on its washer and the thread's end) stand in the gap to
    the cheeks with 1 mm to spare; every solid of the layout names the link that carries it."""
    _, made = kit
    record = made.record
    gap = record["stack_mm"]["gap"]
    for j in ("B", "C"):
        pin = record["pins"][j]
        thread = pin["nut"].split()[-1]
        washer = fs.washer_mm(pin["spacer"].split()[-1])[2]
        nut = fs.washer_mm(thread)[2] + fs.nut_height_mm(thread)
        end = max(nut, fs.shoulder_thread_mm(pin["shoulder_d_mm"])) if pin["screw"] else nut
        beyond = pin["fill_spacers"] * washer + pin["shims_mm"] + pin["axial_float_mm"]
        assert gap >= (beyond if pin["screw"] else 0.0) + end + 1.0 - 1e-9
    layout = record["layout"]
    assert set(layout["moves_with"]) == {*layout["plates"], *layout["turned"], *layout["hardware"]}
    assert layout["moves_with"]["hub_1"] == "lower_arm"
    assert layout["moves_with"]["cheek_2"] == "base"


def test_a_set_screw_past_the_shaft_s_end_is_found_by_hand():
    """Motor 2's drive face on a 30 mm cheek whose inner face is at z = 200, so at 230; hub 2's
    flange ends at 150 + 8 = 158 and its M4 set screw sits at (158 + 200) / 2 = 179. A 24 mm
    shaft ends at 206, 29 mm short of the screw's far edge (177); a 60 mm one at 170, 7 mm
    past it."""
    from types import SimpleNamespace

    from qsm.realization.kit.builders_kit import set_screw_reach_mm

    hub = {"motor": 2, "set_screw": "ISO 4029 M4 x 4"}
    stack = {"cheek_2": 200.0, "crank_end": 150.0, "lower_arm": 18.0}
    cheeks = [{"pocket": {"web_mm": 10.0}}, {"pocket": {"web_mm": 30.0}}]
    short = {"interface": SimpleNamespace(shaft_length_mm=24.0)}
    assert set_screw_reach_mm(hub, short, stack, cheeks) == pytest.approx(-29.0)
    long = {"interface": SimpleNamespace(shaft_length_mm=60.0)}
    assert set_screw_reach_mm(hub, long, stack, cheeks) == pytest.approx(7.0)
    cheeks[1]["pocket"]["web_mm"] = 6.0  # a 24 mm pocket: the face at 206, the shaft's end at 182
    assert set_screw_reach_mm(hub, short, stack, cheeks) == pytest.approx(-5.0)


def test_a_pocket_brings_a_short_shaft_past_its_set_screw():
    """A 12 x 24 mm shaft, a 30 mm cheek 20 mm from its link: the screw sits (20 - 8) / 2 = 6
    mm in from the cheek, so the shaft must run 30 + 6 + d / 2 + 1 mm from the outer face; the
    pocket takes the rest, to 0.5 mm, and the shaft then ends 1 to 1.5 mm past the screw's far
    edge. A 6 mm cheek needs none; a 60 mm gap would leave less than the least web."""
    from types import SimpleNamespace

    from qsm.embodiment.kit import base as bs
    from qsm.realization.kit.builders_kit import _pocket, set_screw_reach_mm

    iface = SimpleNamespace(output="shaft", shaft_d_mm=12.0, shaft_length_mm=24.0, body_d_mm=48.0)
    d = float(jt.set_screw().split()[2][1:])
    pocket = _pocket(iface, 30.0, 20.0)
    assert pocket.depth_mm == pytest.approx(math.ceil(2 * (30 + 6 + d / 2 + 1 - 24)) / 2)
    assert pocket.d_mm == pytest.approx(48 * math.sqrt(2) + 1, abs=0.05)
    stack = {"cheek_2": 200.0, "crank_end": 180.0}
    cheeks = [{}, {"pocket": {"web_mm": 30.0 - pocket.depth_mm}}]
    hub = {"motor": 2, "set_screw": jt.set_screw()}
    reach = set_screw_reach_mm(hub, {"interface": iface}, stack, cheeks)
    assert 1.0 <= reach <= 1.5
    assert _pocket(iface, 6.0, 20.0).depth_mm == 0
    assert _pocket(iface, 30.0, 60.0).depth_mm == 30.0 - bs.MIN_WEB_MM


def test_the_kit_names_its_fits_and_checks_each_bearing_seat(kit):
    """Every joint bearing's seat (P7 on an ISO 492 Normal ring: always an interference), its
    shoulder (f9: always a clearance) and each hub's spigot are in ``kit.json`` with their
    classes, and each seat is a check of the kit. A thin boss's hoop stress tends to delta E /
    D (about 3.5 MPa here); over an allowable of 2 MPa the seat fails, and the kit's words say
    so with the numbers."""
    from qsm.embodiment.kit import fits as ft
    from qsm.realization.kit.builders_kit import _seat_problems

    done, record = kit[0], kit[1].record
    fits = record["fits"]
    seats = [f for f in fits if f["hole"] == "P7"]
    assert len(seats) == 3 and all(f["kind"] == "interference" for f in seats)
    assert all(record["checks"][f"bearing {j}'s seat"] for j in "BCD")
    shoulders = [f for f in fits if f["shaft"] == "f9"]
    assert len(shoulders) == 6 and all(f["min_clearance_um"] > 0 for f in shoulders)
    assert sum("spigot" in f["what"] for f in fits) == 2
    bearing = done.strength.bearings["B"]
    thin = ft.joint_fits("B", bearing, ("lower_arm", 1.02 * bearing.D_mm, 2.0), 2200.0, 0.35)
    delta_e_over_d = -thin[0]["min_clearance_um"] * 1e-3 * 2200.0 / bearing.D_mm
    assert thin[0]["hoop_stress_MPa"] == pytest.approx(delta_e_over_d, rel=0.02)
    assert not thin[0]["holds"]
    (words,) = _seat_problems([thin[0]])
    assert f"{thin[0]['hoop_stress_MPa']:.1f} MPa (2.0 MPa allowed)" in words


def test_the_gap_to_a_link_s_true_outline_agrees_with_the_placed_plates(kit):
    """The least distance from a joint to a neighbouring link's outline over the operating
    range, against the layout's own placing of the plate (its frames, one pose at a time) on
    every 6th pose of the grid, which can only find a larger least distance."""
    from shapely import affinity

    from qsm.physics.kinematics import pose
    from qsm.realization.kit.builders_kit import outline_gap_mm
    from qsm.realization.kit.kit_layout import link_frames

    done, s = kit[0], KitSettings()
    t1s = np.radians(np.linspace(*s.operating_range.theta1_deg, 61))[::6]
    for joint, link in (("B", "coupler"), ("C", "upper_arm"), ("A", "upper_arm")):
        outline = shapely.Polygon(done.parts[link].polygon.exterior.coords)
        brute = np.inf
        for t1 in t1s:
            for frac in np.linspace(0.0, 1.0, 61)[::6]:
                t2 = np.radians(s.operating_range.theta2_min_deg) + frac * (
                    t1 - np.radians(s.operating_range.theta2_min_deg)
                )
                p = pose(done.design, t1, t2)
                if not bool(p.closes):
                    continue
                (x0, y0), a = link_frames(done.design, t1, t2)[link]
                c, sn = np.cos(a), np.sin(a)
                placed = affinity.affine_transform(outline, [c, -sn, sn, c, x0, y0])
                at = np.zeros(2) if joint == "A" else np.asarray(getattr(p, joint))
                brute = min(brute, 1e3 * placed.distance(shapely.Point(*at)))
        gap = outline_gap_mm(done, done.parts, s, link, joint)
        assert gap <= brute + 1e-9
        assert gap == pytest.approx(brute, abs=0.15 * brute + 2.0)


@pytest.fixture(scope="module")
def read_back(kit, tmp_path_factory):
    """``assembly.step`` of the kit read back with build123d: each solid by its name."""
    from qsm.realization.kit.kit_files import write_step

    layout = kit[1].record["layout"]
    path = write_step(layout, tmp_path_factory.mktemp("step"))["assembly"]
    return ref.named(ref.read_assembly(path), layout["moves_with"])


def test_the_assembly_step_read_back_has_no_overlap_at_six_poses(kit, read_back):
    """``assembly.step`` read back with build123d (not the writer's code), each solid moved with
    the link ``moves_with`` names: at six poses over the operating range (the corners and the
    middle of theta1, near the two ends of theta2's span) no two solids, parts and hardware,
    share more than 1 mm^3 (solids that move together are checked once, at the layout's pose,
    where only the drives' mounting screws enter another solid: the drives' envelopes, at
    their tapped faces). Hub 1 moved 5 mm into the lower arm's layer overlaps, so the check can
    see one."""
    from OCP.gp import gp_Trsf, gp_Vec
    from OCP.TopLoc import TopLoc_Location

    from qsm.physics.kinematics import pose
    from qsm.realization.kit.kit_layout import link_frames

    done, record = kit[0], kit[1].record
    layout, s, solids = record["layout"], KitSettings(), dict(read_back)
    assert set(solids) == set(layout["moves_with"])
    assert any(n.startswith("ISO 4762 ") and n.endswith(", 1 of 6") for n in solids)
    start = link_frames(done.design, *np.radians(layout["pose_deg"]))
    moves = layout["moves_with"]
    moving = {(a, b) for a, b in itertools.combinations(sorted(solids), 2) if moves[a] != moves[b]}
    tapped = {  # the drives' mounting and output screws in their tapped faces (envelopes)
        (f"drive_{k}", n) for k in (1, 2) for n in solids for into in (f"drive {k} to cheek {k}",
                                                                        f"hub {k} to drive {k}")
        if n.startswith("ISO 4762 ") and f", {into}, " in n
    }  # fmt: skip
    assert set(ref.overlaps(solids, moves, (start, start))) == tapped
    moving -= {(b, a) for a, b in tapped}  # the output screws turn with the flange inside
    poses = 0
    for t1 in np.radians(np.linspace(*s.operating_range.theta1_deg, 3)):
        for frac in (0.15, 0.85):
            t2 = np.radians(s.operating_range.theta2_min_deg) + frac * (
                t1 - np.radians(s.operating_range.theta2_min_deg)
            )
            if bool(pose(done.design, t1, t2).closes):
                poses += 1
                frames = (start, link_frames(done.design, t1, t2))
                assert not ref.overlaps(solids, moves, frames, moving), (t1, t2)
    assert poses == 6
    up = gp_Trsf()
    up.SetTranslation(gp_Vec(0.0, 0.0, 5.0))
    solids["hub_1"] = solids["hub_1"].Moved(TopLoc_Location(up))
    assert ("lower_arm", "hub_1") in ref.overlaps(
        solids, moves, (start, start), {("lower_arm", "hub_1")}
    )


def test_every_screw_in_the_step_file_is_reached_by_its_key_in_the_sequence_s_order(kit, read_back):
    """An independent check of ``assembly.step`` and the sequence in ``kit.json``: each screw
    (ISO 4762, 7379, 4029), found by the axis of its widest cylinder, is reached along that
    axis by the ISO 2936 key of its size (its arms' lengths from the ISO 2936 table; a shoulder
    screw may take the short arm and turn the long one as a handle), the key sharing no more
    than 1 mm^3 with any solid in place at its step, moved to that step's pose. A key run
    through the parts is seen."""
    from qsm.realization.kit.kit_assembly import poses
    from qsm.realization.kit.kit_layout import link_frames

    done, record = kit[0], kit[1].record
    layout, steps, s = record["layout"], record["assembly_sequence"]["steps"], KitSettings()
    start = link_frames(done.design, *np.radians(layout["pose_deg"]))
    angles = poses(done.design, layout["pose_deg"], *s.operating_range.degrees)
    blocked, checked = ref.blocked_screws(
        read_back,
        layout["moves_with"],
        steps,
        lambda step: (start, link_frames(done.design, *angles[step["pose"]])),
    )
    assert checked >= 40 and not blocked
    hub_screw = next(p for p in read_back if p.startswith("ISO 4762") and "hub 1 to lower" in p)
    socket, out = ref.socket_of(read_back[hub_screw])
    through = ref.keys(hub_screw, socket, -out, ref.key_arms())[0][0]  # into the link instead
    assert ref.shared_mm3(through, read_back["lower_arm"]) > 1.0


def test_a_shaft_hub_s_set_screw_inserts_and_keyway_in_the_step_file(kit, tmp_path):
    """Motor 2 on an assumed keyed shaft: hub 2 has its DIN 6885-1 keyway and its set screw's
    tapped hole, the screws come from the hub into heat-set inserts in the crank. Read back,
    none of hub 2's solids shares more than 1 mm^3 with another at the layout's pose (but the
    drive's mounting screws in its envelope); the set screw stands on the shaft's round (its
    end on the bore) and its key reaches it from outside the boss."""
    from build123d import Compound, Vector

    from qsm.embodiment.kit.interfaces import assumed_interface
    from qsm.realization.kit import builders_kit as bk
    from qsm.realization.kit.kit_files import write_step

    done = kit[0]
    with pytest.MonkeyPatch.context() as patch:
        real = bk.interface_of
        patch.setattr(bk, "interface_of", lambda key, limit, folder=None: (
            assumed_interface(key, limit) if limit < done.torque_limits_Nm[0] else
            real(key, limit, folder)))  # fmt: skip
        record = builders_kit(done, done.parts, KitSettings()).record
    layout, iface = record["layout"], record["drives"][1]
    assert iface["output"] == "shaft" and record["hubs"][1]["link_screws"]["side"] == "hub"
    read = ref.read_assembly(write_step(layout, tmp_path)["assembly"])
    solids = ref.named(read, layout["moves_with"])
    near = [n for n in solids if "hub 2" in n or n in ("hub_2", "crank", "cheek_2", "drive_2")]
    assert sum("heat-set insert" in n for n in near) == jt.HUB_SCREWS
    moves = layout["moves_with"]
    frames = (_link_frames_at(done, layout),) * 2
    pairs = {(a, b) for a in near for b in solids if a != b}
    hits = {tuple(sorted(p)) for p in ref.overlaps(solids, moves, frames, pairs)}
    assert all("drive 2 to cheek 2" in a + b and "drive_2" in a + b for a, b in hits), hits
    screw = next(n for n in solids if n.startswith("ISO 4029"))
    socket, out = ref.socket_of(solids[screw])
    r = iface["shaft_d_mm"] / 2
    assert np.hypot(*socket[:2]) == pytest.approx(record["hubs"][1]["boss_d_mm"] / 2, abs=1e-6)
    assert np.hypot(*(socket - out * float(screw.split(" x ")[1].split(",")[0]))[:2]) == (
        pytest.approx(r, abs=1e-6))  # fmt: skip
    key = ref.keys(screw, socket, out, ref.key_arms())[0][0]
    assert all(ref.shared_mm3(key, solids[n]) <= 1.0 for n in ("hub_2", "crank", "cheek_2"))
    hub = Compound(solids["hub_2"])
    turn = math.radians(layout["pose_deg"][1]) + math.pi  # the keyway's side
    inside = r + 0.5 * fs.key_hub_depth_mm(iface["key_w_mm"], iface["key_h_mm"])
    z = layout["turned"]["hub_2"]["z0_mm"] + 1.0
    assert not hub.is_inside(Vector(inside * math.cos(turn), inside * math.sin(turn), z))
    assert hub.is_inside(Vector(-inside * math.cos(turn), -inside * math.sin(turn), z))


def _link_frames_at(done, layout):
    from qsm.realization.kit.kit_layout import link_frames

    return link_frames(done.design, *np.radians(layout["pose_deg"]))


def test_a_link_facing_a_cheek_stands_off_the_drive_s_mounting_heads_by_hand():
    """An M12 mounting screw on a 110 mm circle: its ISO 7089 washer (24 x 2.5 mm) covers radii
    43-67 mm, its ISO 4762 head (18 x 12 mm) 46-64 mm, 14.5 mm out of the cheek. A nut end 13
    mm out of its link that sweeps radii 40-52 mm needs 13 + 14.5 + 1 mm; one within 10-30 mm
    only 14 mm. A hub's 8 mm flange of 47 mm radius passes 1 mm past the heads (23.5 mm); one of
    40.9 mm radius (M5 washers on a 71.7 mm circle) keeps the flange and 10 mm (18 mm)."""
    from types import SimpleNamespace

    from qsm.realization.kit.builders_kit import _hub_gap, _mount_heads, _past_heads

    iface = SimpleNamespace(mount_thread="M12", mount_pcd_mm=110.0)
    heads = _mount_heads([{"interface": iface}])[0]
    assert heads == ((43.0, 67.0, 2.5), (46.0, 64.0, 14.5))
    assert _past_heads(13.0, (40.0, 52.0), heads) == pytest.approx(28.5)
    assert _past_heads(13.0, (10.0, 30.0), heads) == pytest.approx(14.0)
    link_side = {"thread": "M5", "pcd_mm": 71.7, "side": "link"}
    assert _hub_gap(link_side, heads) == pytest.approx(18.0)
    assert _hub_gap(link_side | {"pcd_mm": 84.0}, heads) == pytest.approx(8 + 14.5 + 1)


def test_hardware_in_place_stands_in_the_way_and_a_pressed_part_with_its_carrier():
    """A key path through a screw's head orders the key's step before the screw's; through a
    bearing pressed into a link on the bench, before the link's (the bearing is there once
    the link is); a step's own parts' hardware is skipped."""
    from qsm.realization.kit.kit_sequence import precedences

    head = Prism("z", disc(0.0, 0.0, 10.0), 0.0, 5.0)
    bearing = Prism("z", disc(50.0, 0.0, 22.0), 0.0, 7.0)
    placed = [{"link": (Prism("z", shapely.box(40, -20, 200, 20).difference(disc(50, 0, 22)),
                              0.0, 7.0),), "screw": (head,), "bearing": (bearing,)}]  # fmt: skip
    key = Prism("z", disc(0.0, 0.0, 3.0), -20.0, 20.0)
    press = Tool("press", "arbor press")
    steps = [
        Step("bearing", "press", (), (), (0.0, 0.0, 0.0), press),
        Step("link", "link", ("link",), (), (0.0, 0.0, 1.0), HAND),
        Step("screw", "screw", (), (), (0.0, 0.0, 1.0), HAND),
        Step("key", "key", (), (), (0.0, 0.0, 1.0), HAND, ((0, (key,)),)),
        Step("tool", "tool", (), (), (0.0, 0.0, 1.0), HAND,
             ((0, (Prism("z", disc(50.0, 0.0, 3.0), -20.0, 20.0),)),)),
    ]  # fmt: skip
    hardware = {"screw": ("screw", "link"), "bearing": ("bearing", "link")}
    found = {(r.first, r.then) for r in precedences(steps, placed, hardware)[0]}
    assert ("key", "screw") in found and ("tool", "link") in found
    assert ("tool", "bearing") not in found
    own = [*steps[:4], Step("tool", "tool", ("link",), (), (0.0, 0.0, 1.0), HAND, steps[4].reach)]
    assert ("tool", "link") not in {
        (r.first, r.then) for r in precedences(own, placed, hardware)[0]
    }


def test_the_kit_holds_its_holes_to_the_plates_allowable_across_their_layers(kit):
    """kit.json's allowables: along the layers the links' own, across them times the factor;
    each pin's printed bearing length is its force over the other plate's across-layer
    allowable times the shoulder's diameter."""
    done, made = kit
    record = made.record["printed_material"]
    factor = KitSettings().printed.across_layers_strength_factor
    assert factor < 1.0  # else the test shows nothing
    for link, along in record["allowable_along_layers_MPa"].items():
        assert along == done.strength.links[link].allowable_MPa
        assert record["allowable_across_layers_MPa"][link] == pytest.approx(factor * along)
    for pin in made.record["pins"].values():
        across = record["allowable_across_layers_MPa"][pin["plates"][1]]
        expected = pin["peak_force_N"] / (across * pin["shoulder_d_mm"])
        assert pin["printed_bearing_length_mm"] == pytest.approx(expected)
