"""jointplay.units: the unit registry's cache and its fallback."""

from __future__ import annotations

import subprocess
import sys
from typing import Any

import numpy as np
import pint
import pytest

from jointplay import units
from jointplay.errors import ConfigError


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
