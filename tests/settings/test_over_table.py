"""The command line over the [simulation] table of a file or preset (``over_table``)."""

from __future__ import annotations

from jointplay.io.config import simulation_settings
from jointplay.settings.simulation import over_table

FLORES = simulation_settings(None, "flores-slider-crank")


def test_a_key_given_overrides_that_key_only() -> None:
    values = over_table(FLORES, {"restitution": 0.6, "friction": None})
    assert values == {**FLORES, "restitution": 0.6}


def test_a_law_named_drops_the_tables_law_and_its_parameters() -> None:
    """--method (or --contact) comes with its own parameters: the preset's law, K and e go,
    its friction (not a law's parameter) stays."""
    assert over_table(FLORES, {"method": "ifm-conventional"}) == {
        "friction": 0.0,
        "method": "ifm-conventional",
    }
    assert over_table(FLORES, {"contact": "hertz", "k": None}) == {
        "friction": 0.0,
        "contact": "hertz",
    }


def test_a_stiffness_given_drops_the_tables_other_stiffness() -> None:
    values = over_table(FLORES, {"stiffness_law": "hertz"})
    assert "k" not in values and values["stiffness_law"] == "hertz"
    assert values["contact"] == "lankarani-nikravesh" and values["restitution"] == 0.9
