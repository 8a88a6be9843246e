"""The realised machine is realised once: ``machine.json`` rebuilds the realisation that
wrote it (qsm.realization.selection.machine), and ``qsm export`` gives the workflow's record."""

import json
import re
import subprocess
import sys
from dataclasses import fields, replace
from pathlib import Path

import numpy as np
import pytest
from workflow_helpers import assert_one_machine, copy_workflow, snakemake

from qsm import load_config
from qsm.config.settings.realization import realization_of
from qsm.embodiment.drives.report import drive_of
from qsm.embodiment.strength.record import BearingLoad, strength_json, strength_of
from qsm.physics.kinematics import end_effector
from qsm.realization.accuracy.accuracy_budget import AccuracySettings
from qsm.realization.selection.machine import machine_record, realization_from_record
from qsm.realization.selection.pipeline import budget_of, realize
from qsm.workflow.json_files import dumps

DESIGN = np.array([0.5, 0.15, 0.55, 0.22, 0.6, 0.2])
ANGLES = np.radians([[95.0, 20.0], [120.0, 30.0], [140.0, 60.0]])
POINTS = end_effector(DESIGN, ANGLES[:, 0], ANGLES[:, 1])


def _settings(tolerance_mm: float):
    points = tuple(map(tuple, POINTS.tolist()))
    accuracy = AccuracySettings(tolerance_mm, points_m=points, max_section_scale=2.0)
    return replace(realization_of(load_config()), accuracy=accuracy)


@pytest.mark.parametrize("tolerance_mm", [1.0, 1e3])  # grown for the tolerance, and not
def test_the_record_rebuilds_the_realisation_it_was_written_from(tolerance_mm):
    settings = _settings(tolerance_mm)
    done = realize(DESIGN, settings)
    again = realization_from_record(json.loads(dumps(machine_record(done))), settings)
    # the default's fixed section, grown for a tight tolerance: not "sized by strength"
    assert done.strength.section == ("fixed" if done.scale is None else "grown")
    assert np.array_equal(again.design, done.design)
    assert again.scale == done.scale
    assert again.strength_check == done.strength_check
    assert again.bearing_rows == done.bearing_rows
    assert again.accuracy.record() == done.accuracy.record()
    assert again.part_settings == done.part_settings
    assert again.tool_flange == done.tool_flange and again.fixed_point == done.fixed_point
    assert again.strength == done.strength  # the typed records, every field
    assert again.drives == done.drives
    for name, part in done.parts.items():
        assert again.parts[name].polygon.equals_exact(part.polygon, 0.0)
    if done.sections is None:
        assert again.sections is None
    else:
        assert np.array_equal(again.sections.scale, done.sections.scale)
    # what later rules compute from it: the same numbers, to the bit
    assert dumps(budget_of(again, settings, POINTS)) == dumps(budget_of(done, settings, POINTS))


def test_a_tight_tolerance_records_the_floor_it_grew_the_sections_to():
    settings = _settings(1.0)
    done = realize(DESIGN, settings)
    record = machine_record(done)
    assert record["sizing"]["floor"] is not None  # else the case shows nothing
    assert record["tolerance_choice"]["section_scale"] == record["sizing"]["floor"]


def test_a_joint_without_a_bearing_is_written_without_the_catalogue_s_figures():
    """A joint none of the bearing table fits is written with its load alone, and read back
    as it was; a fitted one keeps every figure, a missing static safety as null."""
    done = realize(DESIGN, _settings(1e3))
    bare = BearingLoad("", 250.0, (30.0, 40.0))
    record = replace(done.strength, bearings={**done.strength.bearings, "C": bare})
    data = json.loads(dumps(strength_json(record)))
    assert data["bearings"]["C"] == {
        "designation": "",
        "peak_force_N": 250.0,
        "at_theta_deg": [30.0, 40.0],
    }
    assert set(data["bearings"]["B"]) == {f.name for f in fields(BearingLoad)}
    assert strength_of(data) == record


@pytest.mark.parametrize(("tolerance_mm", "section"), [(1e3, "sized"), (1.0, "sized and grown")])
def test_sections_sized_by_strength_say_when_the_tolerance_grew_them(tolerance_mm, section):
    config = load_config()
    config["cad"]["section"] = "sized"
    points = tuple(map(tuple, POINTS.tolist()))
    accuracy = AccuracySettings(tolerance_mm, points_m=points, max_section_scale=2.0)
    done = realize(DESIGN, replace(realization_of(config), accuracy=accuracy))
    assert done.strength.section == section


def test_a_record_of_another_version_is_refused():
    settings = _settings(1e3)
    record = machine_record(realize(DESIGN, settings)) | {"version": 0}
    with pytest.raises(ValueError, match="rerun the rule select_design"):
        realization_from_record(record, settings)


def test_the_drive_rule_marks_the_nearest_drive():
    chosen = {"has_drive": True, "drive": {"motor": "m"}}
    nearest = {"has_drive": False, "best_drive": {"motor": "n"}}
    assert drive_of(chosen) == {"motor": "m", "chosen": True}
    assert drive_of(nearest) == {"motor": "n", "chosen": False}
    assert drive_of({}) == {}


def test_only_the_selection_and_the_export_realise():
    """The rules after select_design rebuild the realisation from machine.json."""
    root = Path(__file__).resolve().parents[1]
    callers = {
        p.relative_to(root).as_posix()
        for p in [*root.glob("src/qsm/**/*.py"), *root.glob("workflow/scripts/*.py")]
        if re.search(r"\brealize\(", p.read_text()) and p.name != "pipeline.py"
    }
    assert callers == {"src/qsm/realization/selection/chosen_machine.py", "src/qsm/app/export.py"}


def test_the_workflow_and_the_export_give_one_record(run, tmp_path):
    real = run / "results" / "realization"
    machine = json.loads((real / "machine.json").read_text())
    selected = json.loads((real / "selected.json").read_text())
    assert selected["drives"] == machine["drives"]
    assert selected["strength"] == machine["strength"]
    lengths = [repr(v) for v in machine["design_m"]]
    out = tmp_path / "export"
    cmd = [sys.executable, "-m", "qsm", "export", "--lengths", *lengths, "--out", str(out)]
    cmd += ["--config", "config/test.yaml"]
    done = subprocess.run(cmd, cwd=run, capture_output=True, text=True, check=False)
    assert done.returncode == 0, done.stderr
    assert json.loads((out / "machine.json").read_text()) == machine


def test_the_test_run_describes_one_machine(run):
    assert_one_machine(run)


LIGHT = """\
task:
  points: [[-0.36, 0.12], [-0.46, 0.05], [-0.42, 0.2]]
  payload_kg: 1.5
  tolerance_mm: 3
printing: {build_volume_mm: [250, 210, 210]}
"""


@pytest.mark.workflow
def test_a_light_task_on_a_small_printer_describes_one_machine(tmp_path):
    """1.5 kg, three points 0.36-0.46 m out, 3 mm, a 250 x 210 x 210 mm printer: the plates are
    cut, and every output still describes the machine the verdict judges."""
    work = copy_workflow(tmp_path / "light")
    light = tmp_path / "light.yaml"
    light.write_text(LIGHT)
    snakemake(work, configs=(str(light),))
    assert_one_machine(work)
    # no design prints on it: the advice's printer is that of the plates as realised
    selected = json.loads((work / "results/realization/selected.json").read_text())
    assert selected["printable"] is False
    advice = selected["printing_advice"]
    plates = max(box[2] for box in selected["printer_box_mm"].values())
    assert min(advice["needed_volume_mm"]) == pytest.approx(plates, rel=1e-9)
    other = advice["smallest_over_designs"]
    # realised too: its plates sized up from the configured 20 mm, as this design's are
    assert other["holds_loads"] is True and min(other["exact_volume_mm"]) > 20.0
