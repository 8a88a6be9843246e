"""A stage's share of the config (:mod:`qsm.config.sections`): the rules' one param builds the
same settings as the whole config, and changes exactly when a key those settings read changes."""

import copy
import pickle
from pathlib import Path

import pytest

from qsm.config.reading import load_config
from qsm.config.sections import dataset_section, drives_section, realization_section
from qsm.config.settings.dataset import dataset_of
from qsm.config.settings.realization import realization_of

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
    """Editing a catalogue file changes ``drives.catalogue_sha256``; the same files give the same
    hash wherever the folder is."""
    from qsm.embodiment.drives.catalogue import catalogue_folder

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
    motors.write_text(motors.read_text() + "\n")
    edited = drives_section(_changed("drives.catalogue", str(tmp_path / "b")))
    assert edited["catalogue_sha256"] != sha[0]
