"""The verdict that leads (qsm.report.readiness): one line per failed check, worst first by how
far past its limit, each with its number and the run's own fix; one bold line ahead of them."""

from qsm.physics.kinematics import LINK_NAMES
from qsm.report.readiness import failures, verdict_lines, verdict_sentence

FIX = "a stiffer gearbox on motor 1: 32,000 N m/rad or more"


def _record(error_mm=10.4, utilisation=1.12, drive=False):
    """A design 10.4 mm from a 5 mm tolerance, its coupler at 1.12 of its strength, motor 2
    without a drive."""
    ok = {"holds": True}
    weak = {"holds": False, "stress_peak_MPa": 17.4, "allowable_MPa": 15.5}
    links = dict.fromkeys(LINK_NAMES, ok) | ({"coupler": weak} if utilisation > 1 else {})
    strength = {"links": links, "bearings": {}, "holds_loads": utilisation <= 1,
                "utilisation": utilisation, "weakest_link": "coupler",
                "weakest_check": "stress"}  # fmt: skip
    budget = {"meets_requirements": error_mm <= 5.0, "tolerance_mm": 5.0,
              "worst": {"error_budget_mm": error_mm}, "would_meet": [FIX],
              "verdict": f"NOT STIFF ENOUGH: the error reaches {error_mm:.2f} mm"}  # fmt: skip
    motors = {"motor2": {"has_drive": drive, "drives": "crank", "failing": {"peak": 0.3}}}
    return {"printable": True, "strength": strength, "stiffness": budget,
            "drives": {"motors": motors}}  # fmt: skip


def test_the_failed_checks_come_worst_first_with_their_numbers_and_fixes():
    found = failures(_record(), {"links": {}}, {"passed": True})
    assert [f.ratio for f in found][:2] == [10.4 / 5.0, 1.12]
    assert found[0].text.startswith("NOT STIFF ENOUGH") and found[0].fix == FIX
    assert found[1].text.startswith("the coupler does not hold its loads")
    assert found[2].text.startswith("motor 2 (crank) has no drive") and found[2].ratio is None
    lines = verdict_lines(found)
    assert lines[2] == f"1. {found[0].text} (2.08 times its limit). What would meet it: {FIX}."
    assert lines[3].startswith("2. the coupler") and "(1.12 times its limit)." in lines[3]
    sentence = verdict_sentence(_record(), {"links": {}}, {"passed": True})
    assert sentence.startswith("NOT READY TO BUILD: 3 checks fail; the worst: NOT STIFF ENOUGH")


def test_a_stronger_failure_leads_when_it_is_further_past_its_limit():
    found = failures(_record(error_mm=5.5, utilisation=1.4), {"links": {}}, {"passed": True})
    assert [f.ratio for f in found][:2] == [1.4, 5.5 / 5.0]


def test_a_ready_design_has_one_line_and_no_list():
    record = _record(error_mm=4.0, utilisation=0.8, drive=True)
    assert failures(record, {"links": {}}, {"passed": True}) == []
    assert verdict_lines([]) == []
    sentence = verdict_sentence(record, {"links": {}}, {"passed": True})
    assert sentence.startswith("Ready to build") and "at most 4.0 mm (tolerance 5 mm)" in sentence


def test_a_first_mode_too_low_or_a_saturated_drive_is_not_ranked_below_its_limit():
    """A budget within its tolerance that fails on the first mode is ranked by the required
    mode over the arm's (12 / 8 Hz); a payload test within its tracking tolerance that failed
    on its drives has no ratio, not one below 1."""
    record = _record(error_mm=4.0, utilisation=0.8, drive=True)
    record["stiffness"] |= {"meets_requirements": False, "min_first_mode_hz": 12.0,
                            "worst": {"error_budget_mm": 4.0, "first_mode_hz": 8.0}}  # fmt: skip
    payload = {"passed": False, "max_tracking_error_deg": 0.2, "tracking_tolerance_deg": 0.5,
               "reason": "requested torque exceeds the drives' envelopes"}  # fmt: skip
    found = failures(record, {"links": {}}, payload)
    assert [f.ratio for f in found] == [1.5, None]


def test_a_failed_payload_test_says_why_once_and_what_its_drives_would_need():
    """Its reason names the tracking error once; motor 1 past its top speed for 2 % of the test
    is told to move slower or take a faster drive, motor 2 at 1.00 of its torque a stronger
    one; a drive below its limit gets no advice."""
    record = _record(error_mm=4.0, utilisation=0.8, drive=True)
    reason = "requested torque exceeds the drives' envelopes; tracking error 2.5 deg > 0.5 deg"
    payload = {"passed": False, "max_tracking_error_deg": 2.5, "tracking_tolerance_deg": 0.5,
               "reason": reason, "past_top_speed_fraction": [0.02, 0.0, 0.0],
               "peak_torque_over_available": [None, 1.0, 0.6]}  # fmt: skip
    (found,) = failures(record, {"links": {}}, payload)
    assert found.text.count("2.5 deg") == 1 and found.ratio == 5.0
    assert found.fix.startswith("motor 1's drive runs past its top speed for 2.0 % of the test")
    assert "payload_test.segment_duration_s" in found.fix
    assert "motor 2's drive gives 1.00 of its torque" in found.fix and "motor 3" not in found.fix


def test_a_cycle_that_overheats_says_how_far_and_what_rating_would_carry_it():
    """Motor 1 at 1.30 of its 10 N m continuous rating: ranked at 1.30, and told to take a drive
    rated 13.0 N m or more; motor 2 within its rating gets no advice; the links past their
    strength on the cycle rank by their utilisation; MuJoCo's run, 3 deg from the motors' path
    against 0.5 deg allowed, ranks at 6 and names motor 1's drive at its torque limit."""
    record = _record(error_mm=4.0, utilisation=0.8, drive=True)
    record["cycle"] = {"planned": True, "cycle_time_s": 2.5, "thermal_ok": False,
                       "rms_torque_Nm": [11.0, 4.0], "continuous_torque_Nm": [10.0, 8.0],
                       "thermal_use": [1.3, 0.5], "links_hold": False,
                       "strength_utilisation": 1.05,
                       "simulation": {"passed": False, "reason": "tracking 3 deg",
                                      "max_tracking_error_deg": 3.0,
                                      "tracking_tolerance_deg": 0.5,
                                      "peak_torque_over_available": [1.0, 0.4]}}  # fmt: skip
    found = failures(record, {"links": {}}, {"passed": True})
    assert [f.ratio for f in found] == [6.0, 1.3, 1.05]
    assert found[0].text.startswith("MuJoCo's run of the cycle fails")
    assert found[0].fix == "motor 1's drive gives 1.00 of its torque: a drive with more"
    assert found[1].text.startswith("DRIVES OVERHEAT") and "motor 2" not in found[1].fix
    assert found[1].fix == "a drive for motor 1 rated 13.0 N m continuous or more"
    assert found[2].text.startswith("the links reach 1.05") and found[2].fix is None


def test_every_alternative_is_a_fix_and_the_sizing_note_is_not_one():
    """Each of the budget's alternatives is offered ("or"), the first mode's need besides them
    ("and"); the sizing's note (what it did, not a change to make) is pointed to, not given as
    a fix."""
    note = "more than the sizing may give: it stopped at the crank at 2.00x its section"
    other = "a material of Young's modulus 25.0 GPa or more"
    mode = "for a first mode of 8 Hz: an arm 1.5x as stiff for its mass"
    record = _record(utilisation=0.9, drive=True)
    record["stiffness"] |= {"would_meet": [note, FIX, other, mode], "sizing_note": [note]}
    (found,) = failures(record, {"links": {}}, {"passed": True})
    assert found.fix.startswith(f"{FIX}; or {other}; and {mode} (why the sizing did not reach")
    assert note not in found.fix
