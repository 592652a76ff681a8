"""Quantities with units at the edges of jointplay (config files, CLI options, reports).

Inside jointplay every number is SI (m, kg, s, rad, N, Pa). Strings such as ``"270.5 mm"``,
``"200 rpm"``, ``"207 GPa"`` or ``"1e4 N/mm^1.5"`` are converted here, once, with
`pint <https://pint.readthedocs.io>`_.
"""

from __future__ import annotations

import functools
import math
import re
from typing import Any

from jointplay.errors import QuantityError
from jointplay.unit_names import undefined_unit

#: SI target unit of each physical kind that a configuration may contain.
SI_UNITS: dict[str, str] = {
    "length": "m",
    "mass": "kg",
    "angle": "rad",
    "angular_velocity": "rad/s",
    "angular_acceleration": "rad/s^2",
    "time": "s",
    "velocity": "m/s",
    "force": "N",
    "pressure": "Pa",
    "density": "kg/m^3",
    "inertia": "kg*m^2",
    "acceleration": "m/s^2",
    "damping": "N*s/m",
    "torque": "N*m",
}


#: Quantities written as ``"<number> <unit>"`` with one of these units are read without pint,
#: whose import takes ~0.35 s (most of ``jointplay fit``'s start-up, and all that loading a
#: preset needed it for): SI unit asked for → {unit as written: factor}. The factors are
#: pint's own, applied as pint applies them (magnitude × factor), so the result is the same
#: float (``tests/test_units.py`` checks every entry against pint). Everything else goes
#: through pint.
_SIMPLE_UNITS: dict[str, dict[str, float]] = {
    "m": {"m": 1.0, "cm": 1e-2, "mm": 1e-3, "um": 1e-6, "µm": 1e-6, "μm": 1e-6},
    "kg": {"kg": 1.0, "g": 1e-3},
    "s": {"s": 1.0, "ms": 1e-3},
    "rad": {"rad": 1.0, "deg": math.pi / 180.0},
    "rad/s": {"rad/s": 1.0, "rpm": 2.0 * math.pi / 60.0},
    "Pa": {"Pa": 1.0, "kPa": 1e3, "MPa": 1e6, "GPa": 1e9},
    "kg/m^3": {"kg/m^3": 1.0},
    "m/s^2": {"m/s^2": 1.0},
    "kg*m^2": {"kg*m^2": 1.0},
}
_SIMPLE_QUANTITY = re.compile(r"\s*([+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)\s*(\S+)\s*")


#: A number raised to a power ("10**10**10", "2^64"): pint would evaluate it exactly, which
#: can take for ever. Units may carry powers ("N/mm^1.5"); numbers are written out ("1e10").
_NUMBER_POWER = re.compile(r"[\d.)]\s*(\*\*|\^)")
_MAX_QUANTITY_CHARS = 200

#: The tokens of a quantity (:func:`check_quantity_text`): blanks, a number, a unit name
#: (letters and underscores: ``mm``, ``µm``, ``um``, ``rev``, ``percent``; or ``%``, ``°``),
#: a superscript exponent (``m²``), an operator (``**``, ``* / ^ ( ) . · + -``).
_TOKEN = re.compile(
    r"(?P<blank>\s+)"
    r"|(?P<number>(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)"
    r"|(?P<name>[^\W\d_][^\W\d]*|%|°)"
    r"|(?P<superscript>⁻?[⁰¹²³⁴⁵⁶⁷⁸⁹]+)"
    r"|(?P<op>\*\*|[*/^().·+-])"
)
_DECIMAL_COMMA = re.compile(r"(\d),(\d)")


def check_quantity_text(text: str) -> str:
    """Why ``text`` is not a quantity of jointplay's grammar, or ``""``.

    The grammar: an optional number (``270.5``, ``+20``, ``-2.5``, ``.5``, ``1e-6``) and an
    optional unit expression made of unit names, ``* / ^ ** ( ) . ·`` and blanks, where
    digits (and a sign) appear only in exponents (``N/mm^1.5``, ``m^-1``, ``m²``) or as the
    ``1`` of ``1/s``. Anything else, which pint would drop or multiply in silently
    (``"200,5 rpm"`` is 2005 rpm to it, ``"200 rpm > 5"`` 1000 rpm, ``"2 00 rpm"`` 0), is
    refused, the message naming the first offending character.
    """
    if comma := _DECIMAL_COMMA.search(text):
        fixed = _DECIMAL_COMMA.sub(r"\1.\2", text)
        return (
            f"',' at character {comma.start(0) + 2}: decimal comma? write {fixed!r} "
            f"(a point, and no thousands separators)"
        )
    tokens: list[tuple[str, str, int]] = []  # (kind, text, 1-based character)
    position = 0
    while position < len(text):
        match = _TOKEN.match(text, position)
        if match is None:
            character = text[position]
            return (
                f"{character!r} (character {position + 1}) is not part of a quantity; write a "
                f"number and a unit of letters, * / ^ ( ), e.g. '200.5 rpm' or '0.05 Pa*s'"
            )
        kind = match.lastgroup or ""
        if kind != "blank":
            tokens.append((kind, match[0], position + 1))
        position = match.end()
    for index, (kind, token, at) in enumerate(tokens):
        before = tokens[index - 1][1] if index else ""
        after = tokens[index + 1][1] if index + 1 < len(tokens) else ""
        exponent = before in ("^", "**") or (
            before in ("+", "-") and index >= 2 and tokens[index - 2][1] in ("^", "**")
        )
        if kind == "number":
            first = index == 0 or (index == 1 and before in ("+", "-"))
            if not (first or exponent or (token == "1" and after == "/")):
                return (
                    f"a second number {token!r} (character {at}): write one number, then "
                    f"the unit; digits go in exponents only (e.g. 'N/mm^1.5')"
                )
        elif kind == "op" and token in ("+", "-"):
            if not (index == 0 or before in ("^", "**")):
                return (
                    f"{token!r} (character {at}) is not part of a quantity: a sign goes "
                    f"before the number or an exponent only (e.g. '-2.5 mm', 'm^-1')"
                )
        elif kind == "superscript" and not (
            index and (tokens[index - 1][0] == "name" or before == ")")
        ):
            return f"{token!r} (character {at}) is an exponent without a unit before it"
    return ""


@functools.cache
def _registry() -> Any:
    import pint

    try:  # pint's cache of its parsed definitions (~/.cache/pint): 0.05 s instead of 0.23 s
        registry: Any = pint.UnitRegistry(cache_folder=":auto:")
    except Exception:  # an unwritable or damaged cache only costs the parsing
        registry = pint.UnitRegistry()
    registry.define("rev = revolution")
    return registry


def parse_quantity(
    value: Any, unit: str, *, field: str, allow_bare: bool = False, example: str | None = None
) -> float:
    """Convert ``value`` to a float in the SI unit ``unit``.

    Args:
        value: a string with a unit (``"270.5 mm"``), a number (only with ``allow_bare``,
            then taken to be in ``unit`` already), or a pint quantity.
        unit: the SI unit to convert to, e.g. ``"m"``, ``"rad/s"``, ``"N/m^1.5"``.
        field: the name of the field, used in error messages.
        allow_bare: accept plain numbers as already being in ``unit``.
        example: the unit a message about a bare number suggests (default: a usual one for
            ``unit``, e.g. ``"rpm"`` for ``"rad/s"``).

    Raises:
        QuantityError: (a ConfigError, its ``field`` and ``detail`` apart) the value has no
            unit, an unknown unit or the wrong dimension.
    """
    if isinstance(value, bool):
        raise QuantityError(field, f"expected a quantity in {unit}, got {value!r}")
    if isinstance(value, int | float):
        if allow_bare or unit in ("", "1", "dimensionless"):
            return _finite(float(value), field)
        raise QuantityError(
            field,
            f'{value!r} has no unit; write it with one, e.g. "{value} {example or _example(unit)}"',
        )
    if isinstance(value, str) and unit in _SIMPLE_UNITS:
        simple = _SIMPLE_QUANTITY.fullmatch(value)
        factor = _SIMPLE_UNITS[unit].get(simple[2]) if simple else None
        if simple and factor is not None:
            return _finite(float(simple[1]) * factor, field, value)
    if isinstance(value, str):
        text = value.strip()
        if not text:
            raise QuantityError(field, f"empty value; expected a quantity in {unit}")
        if len(text) > _MAX_QUANTITY_CHARS:
            raise QuantityError(
                field,
                f"{text[:40]!r}... is too long for a quantity (at most "
                f"{_MAX_QUANTITY_CHARS} characters); expected e.g. '1.5 {_example(unit)}'",
            )
        if why := check_quantity_text(text):
            raise QuantityError(field, f"cannot read {value!r} as a quantity: {why}")
        if _NUMBER_POWER.search(text):
            raise QuantityError(
                field,
                f"cannot read {value!r}: write numbers out (e.g. '1e10'), powers go "
                f"on units only (e.g. 'N/mm^1.5')",
            )
        unknown = undefined_unit(text)  # before pint's import (0.35 s), as pint says it
        if unknown is not None:
            raise QuantityError(
                field,
                f"cannot read {value!r} as a quantity ('{unknown}' is not defined in the unit "
                "registry)",
            )
        try:
            quantity = _registry().Quantity(text)
        except Exception as exc:  # pint raises several unrelated types
            raise QuantityError(field, f"cannot read {value!r} as a quantity ({exc})") from None
    else:
        quantity = value
    if not hasattr(quantity, "to"):
        raise QuantityError(field, f"expected a quantity in {unit}, got {value!r}")
    if quantity.unitless and unit not in ("", "1", "dimensionless") and not allow_bare:
        raise QuantityError(
            field,
            f"{value!r} has no unit; write it with one, e.g. "
            f'"{quantity.magnitude} {example or _example(unit)}"',
        )
    try:
        magnitude = float(quantity.to(unit).magnitude)
    except Exception:
        raise QuantityError(
            field, f"{value!r} has units of {quantity.units:~}, which cannot be converted to {unit}"
        ) from None
    return _finite(magnitude, field, value)


def _finite(value: float, field: str, given: Any = None) -> float:
    if not math.isfinite(value):
        shown = f"{given!r} is {value} in SI" if given is not None else f"got {value}"
        raise QuantityError(field, f"value must be finite, {shown}")
    return value


def _example(unit: str) -> str:
    return {"m": "mm", "rad/s": "rpm", "Pa": "GPa", "rad": "deg", "s": "s"}.get(unit, unit)


def format_quantity(value_si: float, unit: str, *, digits: int = 6) -> str:
    """Format an SI value in ``unit`` as a string that :func:`parse_quantity` reads back."""
    registry = _registry()
    magnitude = registry.Quantity(value_si, _si_of(unit)).to(unit).magnitude
    return f"{float(magnitude):.{digits}g} {unit}"


def _si_of(unit: str) -> Any:
    return _registry().Quantity(1, unit).to_base_units().units


def to_unit(value_si: float, unit: str) -> float:
    """Convert an SI value to ``unit`` (e.g. metres to ``"mm"``, rad/s to ``"rpm"``)."""
    registry = _registry()
    return float(registry.Quantity(value_si, _si_of(unit)).to(unit).magnitude)
