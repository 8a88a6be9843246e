"""A stage's share of the config (:mod:`qsm.config.sections`): the rules' one param builds the
same settings as the whole config, and changes exactly when a key those settings read changes."""

import copy
import csv
import dataclasses
import pickle
from pathlib import Path

import pytest

from qsm.config.reading import load_config
from qsm.config.sections import (
    cycles_section,
    dataset_provenance,
    dataset_section,
    drives_section,
    mechanisms_section,
    optimization_section,
    realization_section,
    surrogate_section,
)
from qsm.config.settings import physics, surrogate
from qsm.config.settings.dataset import dataset_of
from qsm.config.settings.optimization import front_of
from qsm.config.settings.realization import realization_of
from qsm.config.settings.simulation import cycles_of

ROOT = Path(__file__).resolve().parents[1]
CONFIG = load_config(ROOT / "config" / "config.yaml")


def _settings(config):
    return pickle.dumps(realization_of(config))


@pytest.mark.parametrize("name", ["config.yaml", "test.yaml"])
def test_the_realisations_share_builds_what_the_whole_config_builds(name):
    """``qsm export`` builds the realisation's settings from the whole config, the Stage 6 rules
    from their share of it: the two are the same object, field for field."""
    config = load_config(ROOT / "config" / "config.yaml", ROOT / "config" / name)
    assert _settings(realization_section(config)) == _settings(config)


@pytest.mark.parametrize("name", ["config.yaml", "test.yaml"])
def test_the_datasets_share_builds_what_the_whole_config_builds(name):
    """``qsm evaluate --lengths`` builds Stage 2's checks from the whole config, the rule
    ``dynamics`` from its share: the same object; a drive or sag key changes the share."""
    config = load_config(ROOT / "config" / "config.yaml", ROOT / "config" / name)
    share = dataset_section(config)
    assert pickle.dumps(dataset_of(share)) == pickle.dumps(dataset_of(config))
    assert dataset_section(_changed("optimization.generations", 3)) == dataset_section(CONFIG)
    assert dataset_section(_changed("task.payload_kg", 4.0)) != dataset_section(CONFIG)


@pytest.mark.parametrize("name", ["config.yaml", "test.yaml"])
@pytest.mark.parametrize("formulation", ["paper", "ratios"])
def test_a_fronts_share_builds_what_the_whole_config_builds(name, formulation):
    """The rules ``optimize`` and ``verify_pareto`` build a front's settings from their share,
    a notebook or benchmark from the whole config: the same object; so do ``front_cycles``'s."""
    config = load_config(ROOT / "config" / "config.yaml", ROOT / "config" / name)
    share = optimization_section(config, formulation)
    assert pickle.dumps(front_of(share, formulation)) == pickle.dumps(front_of(config, formulation))
    assert pickle.dumps(cycles_of(cycles_section(config))) == pickle.dumps(cycles_of(config))


def test_the_constraints_apply_to_their_formulation():
    """g11 only in the paper formulation; its tolerance wherever the task is contained (g11, or
    the ratios formulation's scale-up): a formulation's share changes with the tolerance
    exactly when its front uses it."""
    paper, ratios = front_of(CONFIG, "paper").extra, front_of(CONFIG, "ratios").extra
    tolerance = CONFIG["optimization"]["constraints"]["containment_tolerance_m"]
    assert paper.containment and not ratios.containment
    assert paper.tolerance_m == ratios.tolerance_m == tolerance
    wider = _changed("optimization.constraints.containment_tolerance_m", 2 * tolerance)
    assert optimization_section(wider, "ratios") != optimization_section(CONFIG, "ratios")
    off = _changed("optimization.constraints.containment", False)
    assert not front_of(off, "paper").extra.containment
    assert front_of(off, "paper").extra.tolerance_m == 0.0
    wider["optimization"]["constraints"]["containment"] = False
    assert optimization_section(wider, "paper") == optimization_section(off, "paper")
    assert optimization_section(wider, "ratios") != optimization_section(off, "ratios")


@pytest.mark.parametrize(
    ("path", "changes"),
    [
        ("optimization.generations", True),
        ("surrogate.infill.rounds", True),
        ("task.tolerance_mm", True),
        ("sampling.bounds.l2", True),
        ("optimization.formulation", False),  # which front the later stages take
        ("task.repeatability_mm", False),
        ("payload_test.dwell_s", False),
    ],
)
def test_a_fronts_share_changes_with_the_keys_it_reads(path, changes):
    """A key the front's settings read changes its share (so the rules rerun); another does
    not."""
    value = {
        "optimization.generations": 3,
        "surrogate.infill.rounds": 0,
        "task.tolerance_mm": 3.0,
        "sampling.bounds.l2": [0.3, 0.9],
        "optimization.formulation": "ratios",
        "task.repeatability_mm": 0.5,
        "payload_test.dwell_s": 0.8,
    }[path]
    changed = _changed(path, value)
    assert (optimization_section(changed, "paper") != optimization_section(CONFIG, "paper")) is (
        changes
    )


def _changed(path, value):
    config = copy.deepcopy(CONFIG)
    *parents, key = path.split(".")
    section = config
    for name in parents:
        section = section[name]
    section[key] = value
    return config


@pytest.mark.parametrize(
    ("path", "value"),
    [
        ("task.tolerance_mm", 3.0),
        ("task.payload_kg", 4.0),
        ("payload_test.dwell_s", 0.8),
        ("printed_material.creep.service_time_h", 100.0),
        ("topology.min_stiffness_factor", 0.5),
        ("kit.tool_offset_m", 0.08),
        ("printing.build_volume_mm", [300.0, 300.0, 300.0]),
    ],
)
def test_a_key_the_realisation_reads_changes_its_share(path, value):
    """The share changes with every key whose change changes the settings (so the rules rerun)."""
    changed = _changed(path, value)
    assert _settings(changed) != _settings(CONFIG)
    assert realization_section(changed) != realization_section(CONFIG)


@pytest.mark.parametrize(
    ("path", "value"),
    [
        ("payload_test.kp_Nm_rad", [900.0, 900.0]),  # the simulations' gains
        ("optimization.generations", 3),
        ("task.repeatability_mm", 0.5),
        ("printing.selection_rule", "min_tau1"),
    ],
)
def test_a_key_it_does_not_read_leaves_its_share_alone(path, value):
    """Keys the realisation does not read leave its share as it was (so no Stage 6 rule reruns
    for them through this param)."""
    changed = _changed(path, value)
    assert _settings(changed) == _settings(CONFIG)
    assert realization_section(changed) == realization_section(CONFIG)


def test_the_catalogue_hash_follows_its_files(tmp_path):
    """Editing a value of a catalogue file changes ``drives.catalogue_sha256``; the same values
    give the same hash wherever the folder is, and however the file is saved (a byte-order mark,
    CRLF line ends, a comment, blank lines, spaces around the cells, in the interface file too);
    a CSV file that is no table of the catalogue does not count."""
    from qsm.embodiment.drives.catalogue import catalogue_folder
    from qsm.embodiment.kit.interfaces import read_interfaces

    for folder in (tmp_path / "a", tmp_path / "b"):
        folder.mkdir()
        for path in sorted(catalogue_folder(None).rglob("*.csv")):
            target = folder / path.relative_to(catalogue_folder(None))
            target.parent.mkdir(parents=True, exist_ok=True)
            target.write_bytes(path.read_bytes())
    sha = [drives_section(_changed("drives.catalogue", str(tmp_path / f)))["catalogue_sha256"]
           for f in ("a", "b")]  # fmt: skip
    assert sha[0] == sha[1] == drives_section(CONFIG)["catalogue_sha256"]
    motors = next((tmp_path / "b").rglob("*motor*.csv"))
    with motors.open(newline="", encoding="utf-8") as f:
        rows = list(csv.reader(f))
    with motors.open("w", newline="", encoding="utf-8-sig") as f:  # a byte-order mark, CRLF
        f.write("# saved again\r\n\r\n")
        csv.writer(f).writerows([[f" {c} " for c in row] for row in rows])
    interfaces = tmp_path / "b" / "interfaces.csv"
    with interfaces.open(newline="", encoding="utf-8") as f:
        cells = list(csv.reader(f))
    with interfaces.open("w", newline="", encoding="utf-8") as f:
        csv.writer(f).writerows([[f"{c} " for c in row] for row in cells])
    (tmp_path / "b" / "notes.csv").write_bytes("Geh\u00e4use\n".encode("latin-1"))  # no table
    again = drives_section(_changed("drives.catalogue", str(tmp_path / "b")))
    assert again["catalogue_sha256"] == sha[0]  # the same values, saved another way
    assert read_interfaces(tmp_path / "b") == read_interfaces(tmp_path / "a")  # read the same
    header = next(k for k, row in enumerate(rows) if row and not row[0].startswith("#"))
    column = rows[header].index("mass")
    rows[header + 1][column] = repr(float(rows[header + 1][column]) + 0.01)
    with motors.open("w", newline="", encoding="utf-8") as f:
        csv.writer(f).writerows(rows)
    edited = drives_section(_changed("drives.catalogue", str(tmp_path / "b")))
    assert edited["catalogue_sha256"] != sha[0]


def test_a_share_does_not_change_with_the_order_the_configs_were_merged_in():
    """An override file puts its keys first in the merged config; the rules compare their
    params by their repr, so every share sorts its keys (no rerun for a value unchanged)."""
    moved = copy.deepcopy(CONFIG)
    section = moved["optimization"]
    moved["optimization"] = {"constraints": section.pop("constraints"), **section}
    moved["task"] = dict(reversed(moved["task"].items()))
    for share in (
        lambda c: optimization_section(c, "paper"),
        realization_section,
        dataset_section,
        cycles_section,
    ):
        assert repr(share(moved)) == repr(share(CONFIG))


@pytest.mark.parametrize("name", ["config.yaml", "test.yaml"])
def test_stage_1s_share_scales_up_as_the_whole_config_without_its_filters(name):
    """The rules ``fit_task`` and ``select_mechanisms`` build the scale-up from Stage 1's share:
    the whole config's, but for the transmission-angle filter, which ``filter_kinematics`` has
    applied to the candidates already."""
    config = load_config(ROOT / "config" / "config.yaml", ROOT / "config" / name)
    config["filters"]["min_transmission_angle_deg"] = 20.0
    whole = physics.fit_of(config)
    assert whole.min_transmission_angle_deg == 20.0
    expected = dataclasses.replace(whole, min_transmission_angle_deg=0.0)
    assert pickle.dumps(physics.scale_up(mechanisms_section(config))) == pickle.dumps(expected)


def test_stage_1s_share_designs_a_task_beyond_the_base_mirrored():
    """The share holds the points every stage designs for: a task at x > 0 through x = 0."""
    mirrored = _changed("task.points", [[-x, y] for x, y in CONFIG["task"]["points"]])
    assert mechanisms_section(mirrored)["task_points"] == mechanisms_section(CONFIG)["task_points"]
    assert mechanisms_section(mirrored) == mechanisms_section(CONFIG)


@pytest.mark.parametrize(
    ("path", "value", "stage1", "dataset", "stage3"),
    [
        ("workspace.n_scan", 7, True, True, False),
        ("workspace.shards", 5, False, False, False),
        ("filters.min_transmission_angle_deg", 20.0, True, True, False),
        ("task.payload_kg", 4.0, False, True, False),
        ("strength.safety_factor", 3.0, False, True, False),
        ("surrogate.alpha", 0.01, False, False, True),
        ("surrogate.infill.rounds", 0, False, False, False),
        ("optimization.generations", 3, False, False, False),
    ],
)
def test_stage_1_2_and_3_shares_change_with_the_keys_they_read(
    path, value, stage1, dataset, stage3
):
    """Stage 1's share, what the dataset records it depends on and Stage 3's share change with
    a key they read (so their rules rerun), and not with the shard counts or another stage's."""
    changed = _changed(path, value)
    drives = drives_section(CONFIG)
    assert (mechanisms_section(changed) != mechanisms_section(CONFIG)) is stage1
    assert (dataset_provenance(changed, drives) != dataset_provenance(CONFIG, drives)) is dataset
    assert (surrogate_section(changed) != surrogate_section(CONFIG)) is stage3
    assert surrogate.surrogate(surrogate_section(CONFIG)) == surrogate.surrogate(
        CONFIG["surrogate"]
    )
