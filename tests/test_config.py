"""Configuration: defaults, and errors that name the offending key or file."""

import copy
from pathlib import Path

import pytest
import yaml

from qsm.config.reading import ConfigError, load_config, schema, validate_config
from qsm.workflow.tables import settings_hash

ROOT = Path(__file__).resolve().parents[1]


def test_defaults_are_the_papers():
    c = load_config()
    assert c["sampling"]["n_samples"] == 200000
    assert c["sampling"]["n_mechanisms"] == 11080
    assert c["sampling"]["bounds"]["l2"] == [0.18, 0.6]
    assert c["operating_range"] == {"theta1_deg": [45.0, 180.0], "theta2_min_deg": -37.5}
    assert c["task"]["payload_kg"] == 5.0
    assert c["scale"]["safety_margin_m"] == 0.0


def test_shipped_configs_are_valid_and_config_yaml_spells_out_the_defaults():
    full = load_config(ROOT / "config" / "config.yaml")
    assert full == load_config()
    test = yaml.safe_load((ROOT / "config" / "test.yaml").read_text())
    validate_config(test)


def _schema_keys(props, prefix=""):
    out = set()
    for name, prop in props.items():
        if prop.get("type") == "object" and "properties" in prop:
            out |= _schema_keys(prop["properties"], f"{prefix}{name}.")
        else:
            out.add(prefix + name)
    return out


def _keys(mapping, prefix=""):
    out = set()
    for name, value in mapping.items():
        out |= _keys(value, f"{prefix}{name}.") if isinstance(value, dict) else {prefix + name}
    return out


def test_config_yaml_names_every_key_of_the_schema():
    """A user finds every key in config/config.yaml, each with a comment on its section."""
    text = (ROOT / "config" / "config.yaml").read_text()
    assert _keys(yaml.safe_load(text)) == _schema_keys(schema()["properties"])
    for line in text.splitlines():  # every section and key line has its comment
        if line.strip() and not line.lstrip().startswith(("#", "- ")):
            assert "#" in line, line


def test_workflow_schema_is_the_package_schema():
    shipped = yaml.safe_load((ROOT / "workflow" / "schemas" / "config.schema.yaml").read_text())
    assert shipped == schema()


@pytest.mark.parametrize(
    ("config", "key"),
    [
        ({"samplng": {}}, "'samplng' is unknown"),
        ({"sampling": {"n_sample": 5}}, "'sampling.n_sample' is unknown"),
        ({"sampling": {"n_samples": "many"}}, "'sampling.n_samples'"),
        ({"sampling": {"n_samples": 0}}, "'sampling.n_samples'"),
        ({"sampling": {"bounds": {"l3": [1.3, 0.8]}}}, "'sampling.bounds.l3'"),
        ({"sampling": {"bounds": {"l3": [0.8]}}}, "'sampling.bounds.l3'"),
        ({"sampling": {"n_samples": 10, "n_mechanisms": 20}}, "'sampling.n_mechanisms'"),
        ({"operating_range": {"theta1_deg": [180, 45]}}, "'operating_range.theta1_deg'"),
        ({"task": {"points": []}}, "'task.points'"),
        ({"task": {"points": [[0.1, 0.2, 0.3]]}}, "'task.points.0'"),
        ({"task": {"payload_kg": -1}}, "'task.payload_kg'"),
        ({"workspace": {"shards": 0}}, "'workspace.shards'"),
        ({"scale": {"safety_margin_m": -0.1}}, "'scale.safety_margin_m'"),
        ({"task": {"points": [[-0.6, 0.1]]}}, "'task.points': the points span a circle"),
        ({"task": {"points": [[-0.6, 0.1], [-0.6, 0.1]]}}, "'task.points': the points span"),
        ({"task": {"points": [[float("nan"), 0.1], [-0.5, 0.1]]}}, "'task.points': every"),
        ({"task": {"points": [[float("inf"), 0.1], [-0.5, 0.1]]}}, "'task.points': every"),
        ({"optimization": {"formulations": ["ratios"]}}, "'optimization.formulation'"),
        ({"cad": {"width_m": 5.0}}, "'cad.boss_radius_m': 0.025 m must exceed half"),
        ({"cad": {"boss_radius_m": 2.0}}, "'cad.boss_radius_m': bosses of radius 2.0 m"),
        ({"cad": {"thickness_m": float("nan")}}, "'cad.thickness_m': nan is not a finite"),
        ({"scale": {"max_m": float("inf")}}, "'scale.max_m': inf is not a finite"),
        ({"kit": {"torque_limit_margin": 1.1}}, "'kit.torque_limit_margin': 1.1 is below 1 +"),
    ],
)
def test_errors_name_the_key(config, key):
    with pytest.raises(ConfigError, match=key.replace(".", r"\.")):
        validate_config(copy.deepcopy(config))


def test_unreadable_file_is_named(tmp_path):
    bad = tmp_path / "broken.yaml"
    bad.write_text("sampling: [unclosed\n")
    with pytest.raises(ConfigError, match=r"broken\.yaml"):
        load_config(bad)
    with pytest.raises(ConfigError, match=r"config file '.*missing\.yaml' does not exist"):
        load_config(tmp_path / "missing.yaml")


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("", "is empty: it must hold a mapping"),
        ("# only a comment\n", "is empty"),
        ("[1, 2]\n", "must hold a mapping of config keys, not a list"),
    ],
)
def test_an_empty_or_non_mapping_file_is_named(tmp_path, text, message):
    bad = tmp_path / "odd.yaml"
    bad.write_text(text)
    with pytest.raises(ConfigError, match=message) as info:
        load_config(bad)
    assert f"config file '{bad}'" in str(info.value)


def test_settings_hash_is_stable_and_sensitive():
    a = {"x": 1, "y": [1, 2]}
    assert settings_hash(a) == settings_hash({"y": [1, 2], "x": 1})
    assert settings_hash(a) != settings_hash({"x": 2, "y": [1, 2]})
