"""The unit-name check read without pint (:mod:`jointplay.unit_names`) agrees with pint:
every name it reads from pint's definition files is one pint defines, and every name it
calls undefined pint refuses too, so a mistyped unit is refused before pint is imported."""

from __future__ import annotations

import random
import string

import pint
import pytest

from jointplay.unit_names import _definitions, undefined_unit
from jointplay.units import _registry

TYPOS = [
    "200 rmp", "3 mmm", "5 Nmm", "1 metrs", "2 secnd", "7 GPA", "1e4 N/mm^1.5x", "1e4 Nn/mm^1.5",
    "0.1 mm/sss", "10 kgg*m^2", "50 msek", "3 degs2", "9.81 m/s^2 x", "1 (m/zz)^2", "4 Mpa",
]  # fmt: skip
DEFINED = [
    "200 rpm", "20.9 rad/s", "1e4 N/mm^1.5", "0.05 Pa*s", "207 GPa", "9.81 m/s^2", "5 deg",
    "5 degrees", "3 meters", "2 µm", "2 μm", "2 um", "1 rev", "0.1 (N*s)/m", "1 kg*m**2",
    "3 revolutions / minute", "10 N*s/mm", "1 h", "600 hours", "2e-3m",
]  # fmt: skip


@pytest.mark.parametrize("text", DEFINED)
def test_defined_units_are_left_to_pint(text: str) -> None:
    assert undefined_unit(text) is None
    _registry().Quantity(text)  # pint reads them


@pytest.mark.parametrize("text", TYPOS)
def test_a_name_called_undefined_is_refused_by_pint(text: str) -> None:
    name = undefined_unit(text)
    assert name is not None
    with pytest.raises(pint.UndefinedUnitError) as refused:
        _registry().Quantity(text)
    assert refused.value.unit_names in (name, (name,), [name])


def test_random_names_agree_with_pint() -> None:
    """Names of 2-5 letters: whenever the check calls one undefined, pint refuses it; the
    names it resolves (prefix, name, plural s) pint reads."""
    generator = random.Random(41)
    registry = _registry()
    refused = 0
    for _ in range(400):
        name = "".join(generator.choices(string.ascii_letters, k=generator.randint(2, 5)))
        text = f"1 {name}"
        try:
            registry.parse_units(name)
            pint_defines = True
        except pint.UndefinedUnitError:
            pint_defines = False
        said = undefined_unit(text)
        assert (said is None) is pint_defines, (text, said)
        refused += said is not None
    assert refused > 100  # the check did refuse names, it is not always silent


def test_every_name_read_from_the_files_is_defined() -> None:
    definitions = _definitions()
    assert definitions is not None
    units, prefixes = definitions
    registry = _registry()
    for name in sorted(units):
        if name.isidentifier():
            registry.parse_units(name)  # raises UndefinedUnitError for a name pint lacks
    for prefix in sorted(prefixes - {""}):
        if prefix.isidentifier():
            registry.parse_units(f"{prefix}m")


@pytest.mark.parametrize("text", ["1 square meter", "5 °C", "3 m²", "10 %", "inf m", "m", ""])
def test_other_forms_are_left_to_pint(text: str) -> None:
    assert undefined_unit(text) is None
