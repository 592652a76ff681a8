"""jointplay.units: the unit registry's cache and its fallback."""

from __future__ import annotations

from typing import Any

import pint
import pytest

from jointplay import units


@pytest.fixture
def fresh_registry() -> Any:
    units._registry.cache_clear()
    yield
    units._registry.cache_clear()


def test_a_cached_registry_reads_what_a_plain_one_reads(fresh_registry: None) -> None:
    plain = pint.UnitRegistry()
    plain.define("rev = revolution")
    for text, unit in (("200 rpm", "rad/s"), ("207 GPa", "Pa"), ("1e4 N/mm^1.5", "N/m^1.5")):
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
