"""The TOML writer: presets round-trip, fitted values land where the config reader looks."""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

import pytest

from jointplay.errors import ConfigError
from jointplay.io.config import list_presets, load_config, simulation_settings
from jointplay.io.config_writer import calibrated_config, dumps_toml, source_config


@pytest.mark.parametrize("name", [p.name for p in list_presets()])
def test_every_preset_round_trips(name: str) -> None:
    data = source_config(name)
    assert tomllib.loads(dumps_toml(data, "a header\nof two lines")) == data


def test_fitted_values_are_read_back(tmp_path: Path) -> None:
    values = {
        "crank-speed": 230 * math.pi / 30,
        "phase": 0.1,  # not a mechanism property: skipped
        "coupler-length": 0.2713,
        "clearance": 1.5e-5,
        "k": 2e9,
        "c_max": 3e4,
        "friction": 0.02,
    }
    data = calibrated_config(source_config("paper-fourbar"), values, contact_law="impact")
    path = tmp_path / "calibrated.toml"
    path.write_text(dumps_toml(data, "calibrated"), encoding="utf-8")
    mechanism = load_config(path)
    assert mechanism.driver.speed == pytest.approx(values["crank-speed"], rel=1e-9)
    assert mechanism.template.geometry.coupler == pytest.approx(0.2713, rel=1e-12)  # type: ignore[attr-defined]
    clearances = [j.fit.clearance for j in mechanism.revolute_joints if j.fit]
    assert clearances == pytest.approx([1.5e-5] * 4, rel=1e-12)
    table = simulation_settings(path)
    assert table == {
        "k": "2000000000 N/m^1.5",
        "contact": "impact",
        "cmax": "30000 N*s/m",
        "friction": 0.02,
    }


def test_a_length_the_config_lacks_is_an_error() -> None:
    with pytest.raises(ConfigError, match="no \\[geometry\\] crank"):
        calibrated_config({"mechanism": {}}, {"crank-length": 0.1})
