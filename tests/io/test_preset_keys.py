"""The presets' own keys: ``[mechanism] source`` and ``reproduces`` (read as text, required of
a shipped preset) and a preset's ``[simulation]`` table (read by ``simulation_settings``)."""

from __future__ import annotations

import tomllib

import pytest

from jointplay.errors import ConfigError
from jointplay.io import config
from jointplay.io.config import parse_config, preset_text, simulation_settings


@pytest.mark.parametrize("key", ["source", "reproduces"])
def test_source_and_reproduces_are_text(key: str) -> None:
    data = tomllib.loads(preset_text("paper-fourbar"))
    data["mechanism"][key] = 3
    with pytest.raises(ConfigError, match=rf"mechanism\.{key} must be a string"):
        parse_config(data)
    data["mechanism"][key] = "a paper"
    assert parse_config(data).name == "paper-fourbar"  # text: not part of the mechanism


def test_a_preset_without_its_source_is_refused(monkeypatch, tmp_path) -> None:
    """A shipped preset states where its numbers come from: list_presets refuses one
    without, naming it and the missing key."""
    text = preset_text("general-fourbar")
    stripped = "\n".join(line for line in text.splitlines() if not line.startswith("source ="))
    path = tmp_path / "bare.toml"
    path.write_text(stripped, encoding="utf-8")
    monkeypatch.setattr(config, "_preset_files", lambda: {"bare": path})
    with pytest.raises(ConfigError, match=r"preset 'bare': \[mechanism\] has no source"):
        config.list_presets()


def test_a_presets_simulation_table_is_read() -> None:
    """Without a file, the [simulation] table is the preset's (the default preset's without
    one named); a file's own table wins over the preset's."""
    assert simulation_settings(None, "flores-slider-crank") == {
        "contact": "lankarani-nikravesh",
        "k": "6.6e10 N/m^1.5",
        "restitution": 0.9,
        "friction": 0.0,
    }
    assert simulation_settings(None) == {}
    assert simulation_settings(None, "paper-fourbar") == {}


def test_a_copied_preset_keeps_its_contact(tmp_path) -> None:
    """`jointplay show flores-slider-crank > my.toml` runs the same contact from the file."""
    path = tmp_path / "my.toml"
    path.write_text(preset_text("flores-slider-crank"), encoding="utf-8")
    assert simulation_settings(path) == simulation_settings(None, "flores-slider-crank")


def test_the_flores_stiffness_is_hertz_of_its_pin() -> None:
    """The preset's K = 6.6e10 N/m^1.5 is Hertz's K of its own pin and bearing (computed
    6.61e10), so the recalled value and the geometry agree."""
    from jointplay.contact.stiffness import HertzStiffness
    from jointplay.io.config import load_preset
    from jointplay.units import parse_quantity

    mechanism = load_preset("flores-slider-crank")
    joint = mechanism.joint("B")
    pin = joint.fit.diameter / 2
    steel = mechanism.material_of("rod")
    hertz = HertzStiffness.from_materials(
        bearing_radius=pin + joint.fit.clearance,
        pin_radius=pin,
        length=joint.fit.pin_length,
        bearing=steel,
        pin=steel,
    ).stiffness
    k = simulation_settings(None, "flores-slider-crank")["k"]
    given = parse_quantity(k, "N/m^1.5", field="k")
    assert given == pytest.approx(hertz, rel=0.01)
