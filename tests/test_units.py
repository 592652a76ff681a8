"""jointplay.units: the unit registry's cache and its fallback."""

from __future__ import annotations

import math
import subprocess
import sys
from typing import Any

import numpy as np
import pint
import pytest

from jointplay import units
from jointplay.errors import ConfigError, QuantityError


@pytest.fixture
def fresh_registry() -> Any:
    units._registry.cache_clear()
    yield
    units._registry.cache_clear()


def test_a_cached_registry_reads_what_a_plain_one_reads(fresh_registry: None) -> None:
    plain = pint.UnitRegistry()
    plain.define("rev = revolution")
    for text, unit in (
        ("200 rev/min", "rad/s"),
        ("2.07e5 N/mm^2", "Pa"),
        ("1e4 N/mm^1.5", "N/m^1.5"),
    ):
        expected = float(plain.Quantity(text).to(unit).magnitude)
        assert units.parse_quantity(text, unit, field="x") == expected


def test_an_unusable_cache_falls_back_to_parsing_the_definitions(
    fresh_registry: None, monkeypatch: pytest.MonkeyPatch
) -> None:
    real = pint.UnitRegistry

    def no_cache(*args: Any, **kwargs: Any) -> Any:
        if kwargs.get("cache_folder"):
            raise PermissionError("read-only cache folder")
        return real(*args, **kwargs)

    monkeypatch.setattr(pint, "UnitRegistry", no_cache)
    assert units.parse_quantity("3 rev/s", "rad/s", field="x") == pytest.approx(
        6 * 3.141592653589793
    )


@pytest.mark.parametrize("unit", sorted(units._SIMPLE_UNITS))
def test_quantities_read_without_pint_are_what_pint_reads(unit: str) -> None:
    registry = pint.UnitRegistry()
    rng = np.random.default_rng(7)
    numbers = ["0", "1", "+3", "-2.5", ".5", "270.5", "1e4", "2.1E-5", "7801", "0.021"]
    numbers += [repr(float(v)) for v in rng.uniform(-1e3, 1e3, 200)]
    for written in units._SIMPLE_UNITS[unit]:
        for number in numbers:
            text = f"{number} {written}"
            expected = float(registry.Quantity(text).to(unit).magnitude)
            assert units.parse_quantity(text, unit, field="x") == expected, text
    with pytest.raises(ConfigError, match="cannot be converted"):
        units.parse_quantity("3 N", unit, field="x")  # pint still judges everything else


def test_loading_a_preset_does_not_import_pint() -> None:
    code = (
        "import sys; from jointplay.io.config import list_presets, load_preset; "
        "[load_preset(p.name) for p in list_presets()]; print('pint' in sys.modules)"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.strip() == "False"


def test_a_bad_quantity_names_its_field_and_its_detail_apart() -> None:
    """parse_quantity's error carries the field and the bare message, so callers that name
    the field their own way (a setting, an option) take the detail without string editing."""
    import pickle

    from jointplay.dynamics.setup import contact_from_strings
    from jointplay.errors import ConfigError, QuantityError, SettingError
    from jointplay.units import parse_quantity

    with pytest.raises(QuantityError) as caught:
        parse_quantity("0.1 kg", "m", field="depth: of the bearing")
    error = caught.value
    assert isinstance(error, ConfigError)
    assert error.field == "depth: of the bearing" and error.detail.startswith("'0.1 kg' has units")
    assert str(error) == f"depth: of the bearing: {error.detail}"
    assert pickle.loads(pickle.dumps(error)).detail == error.detail
    with pytest.raises(SettingError) as setting:
        contact_from_strings({"contact": "impact", "depth": "0.1 kg"})
    assert str(setting.value).startswith("depth: '0.1 kg' has units")
    assert str(setting.value.named({"depth": "--depth"})).startswith("--depth: '0.1 kg' has")


# --- one strict grammar: nothing dropped, nothing multiplied in silently --------------------------


@pytest.mark.parametrize(
    ("text", "unit", "message"),
    [
        ("200,5 rpm", "rad/s", r"',' at character 4: decimal comma\? write '200\.5 rpm'"),
        ("9,81 m/s^2", "m/s^2", r"decimal comma\? write '9\.81 m/s\^2'"),
        ("200 rpm > 5", "rad/s", r"'>' \(character 9\) is not part of a quantity"),
        ("200 rpm;", "rad/s", r"';' \(character 8\)"),
        ("200 rpm # 5", "rad/s", r"'#' \(character 9\)"),
        ("1_000 rpm", "rad/s", r"'_' \(character 2\)"),
        ("200 [rpm]", "rad/s", r"'\[' \(character 5\)"),
        ("2 00 rpm", "rad/s", r"a second number '00' \(character 3\)"),
        ("200 rpm 5", "rad/s", r"a second number '5' \(character 9\)"),
        ("200 rpm-5", "rad/s", r"'-' \(character 8\) is not part of a quantity: a sign"),
        ("0.05 Pa*s, 1 mm", "Pa*s", r"',' \(character 10\)"),
    ],
)
def test_a_quantity_with_anything_beyond_the_grammar_is_refused(
    text: str, unit: str, message: str
) -> None:
    """pint's tokenizer drops such characters and multiplies what is left: "200,5 rpm" was
    2005 rpm, "9,81 m/s^2" 981 m/s², "200 rpm > 5" 1000 rpm, "2 00 rpm" 0."""
    with pytest.raises(QuantityError, match=message):
        units.parse_quantity(text, unit, field="x")


@pytest.mark.parametrize(
    ("text", "unit", "expected"),
    [
        ("270.5 mm", "m", 0.2705),
        ("+20 um", "m", 20e-6),
        ("21 µm", "m", 21e-6),
        ("-2.5 mm", "m", -2.5e-3),
        (".5 mm", "m", 0.5e-3),
        ("600 h", "s", 2.16e6),
        ("60 min", "s", 3600.0),
        ("10 %", "", 0.1),
        ("0.01 percent", "", 1e-4),
        ("1e-6", "", 1e-6),
        ("0.05 Pa*s", "Pa*s", 0.05),
        ("50 mPa*s", "Pa*s", 0.05),
        ("9.81 m/s^2", "m/s^2", 9.81),
        ("1e4 N/mm^1.5", "N/m^1.5", 1e4 * 1000**1.5),
        ("2.07e5 N/mm^2", "Pa", 2.07e11),
        ("10 N*s/mm", "N*s/m", 1e4),
        ("0.1 kN*s/m", "N*s/m", 100.0),
        ("200 rev/min", "rad/s", 200 * 2 * math.pi / 60),
        ("3 rev/s", "rad/s", 6 * math.pi),
        ("5 1/s", "1/s", 5.0),
        ("2 m^-1", "1/m", 2.0),
        ("2 m**-1", "1/m", 2.0),
        ("3 kg·m²", "kg*m^2", 3.0),
        ("4 N.m", "N*m", 4.0),
        ("90 °", "rad", math.pi / 2),
        ("200rpm", "rad/s", 200 * 2 * math.pi / 60),
    ],
)
def test_every_quantity_the_docs_write_still_reads(text: str, unit: str, expected: float) -> None:
    assert units.parse_quantity(text, unit, field="x") == pytest.approx(expected, rel=1e-12)
