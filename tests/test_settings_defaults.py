"""The settings dataclasses' defaults are the config schema's, the defaults a run uses.

Notebook calls take the dataclass defaults (read from the schema by :mod:`qsm.schema.defaults`), the
workflow the validated config's: each field must read its own key.
"""

import dataclasses

import pytest

from qsm.config.reading import load_config
from qsm.embodiment.strength.material import Material, StrengthSettings
from qsm.physics.cad import CadSettings
from qsm.physics.duty import DutySettings
from qsm.physics.workspace import OperatingRange, Resolution
from qsm.realization.motion.payload import PayloadSettings
from qsm.realization.topology.fe import TopologySettings
from qsm.surrogate.model import SurrogateSettings

CONFIG = load_config()


def _plain(value):
    return list(value) if isinstance(value, tuple) else value


@pytest.mark.parametrize(
    ("cls", "section"),
    [
        (CadSettings, CONFIG["cad"]),
        (Material, CONFIG["material"]),
        (StrengthSettings, CONFIG["strength"]),
        (DutySettings, CONFIG["dynamics"]["duty"]),
        (Resolution, CONFIG["workspace"]),
        (TopologySettings, CONFIG["topology"]),
        (PayloadSettings, {**CONFIG["payload_test"], "payload_kg": CONFIG["task"]["payload_kg"]}),
        (SurrogateSettings, CONFIG["surrogate"]),
    ],
    ids=lambda v: getattr(v, "__name__", ""),
)
def test_dataclass_defaults_equal_the_schema(cls, section):
    shared = [f for f in dataclasses.fields(cls) if f.name in section]
    assert len(shared) >= 2, cls
    for f in shared:
        assert _plain(f.default) == _plain(section[f.name]), f"{cls.__name__}.{f.name}"


def test_operating_range_defaults_equal_the_schema():
    lo, hi = CONFIG["operating_range"]["theta1_deg"]
    theta2 = CONFIG["operating_range"]["theta2_min_deg"]
    duty = DutySettings()
    assert (duty.theta1_min_deg, duty.theta1_max_deg, duty.theta2_min_deg) == (lo, hi, theta2)
    payload = PayloadSettings()
    assert payload.operating_range.degrees == ((lo, hi), theta2)


def test_the_settings_layer_gives_the_default_dataclasses_on_the_default_config():
    from qsm.config.settings import links, physics, plates, simulation, surrogate

    c = CONFIG
    assert physics.cad(c["cad"], c["material"]) == CadSettings()
    assert links.material(c["material"]) == Material()
    assert links.strength(c["strength"]) == StrengthSettings()
    assert physics.duty(c["dynamics"]["duty"], c["operating_range"]) == DutySettings()
    assert plates.topology(c["topology"], c["material"], c["strength"]) == TopologySettings()
    assert surrogate.surrogate(c["surrogate"]) == SurrogateSettings()
    op = physics.operating_range(c["operating_range"])
    assert op == OperatingRange()
    assert (
        simulation.payload_test(c["payload_test"], c["task"]["payload_kg"], op) == PayloadSettings()
    )
    fit = physics.fit(c["operating_range"], c["task"]["points"], c["scale"], c["workspace"])
    assert fit.resolution == Resolution() and fit.op == physics.operating_range(
        c["operating_range"]
    )


def test_a_default_names_a_key_the_schema_lacks():
    from qsm.schema.defaults import default

    assert default("cad.width_m") == CONFIG["cad"]["width_m"]
    assert default("operating_range.theta1_deg") == tuple(CONFIG["operating_range"]["theta1_deg"])
    with pytest.raises(KeyError, match=r"'cad\.no_such_key'"):
        default("cad.no_such_key")
