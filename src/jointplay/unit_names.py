"""Whether a quantity's units are defined, read without importing pint.

``import pint`` takes ~0.35 s and brings NumPy, SciPy's top level and Dask's ``base`` with it;
a mistyped unit (``--rpm "200 rmp"``) should be one error line without that wait. This
module reads the unit names, symbols, aliases and prefixes from pint's own definition files
(``default_en.txt`` and the files it imports, found beside pint's sources without importing
it) and resolves a name as pint does: an optional prefix, a defined name, an optional plural
``s`` (pint's defaults: case-sensitive; no plural of a one-letter name).

It only ever says "not defined": :func:`undefined_unit` returns the first name that no
prefix, name and suffix make, for a text of the plain form ``<number> <units>`` (names
joined by ``*``, ``/``, spaces and powers ``^``/``**`` with numbers, parentheses). Anything
else (``per``, ``square``, ``°``, ``%``, superscripts or any non-ASCII character but a letter,
a missing definition file) returns
``None``, and pint reads the text as before. ``tests/test_unit_names.py`` checks that every
name defined in the files resolves and that pint refuses each name this refuses.
"""

from __future__ import annotations

import functools
import importlib.util
import re
from pathlib import Path

#: Names jointplay adds to pint's registry (:func:`jointplay.units._registry`).
EXTRA_UNITS = ("rev",)
#: Pint's plural suffixes (``UnitRegistry`` default).
SUFFIXES = ("", "s")
#: Words pint's preprocessing turns into operators: a text with them is left to pint.
_PINT_WORDS = frozenset({"per", "square", "sq", "cubic", "squared", "cubed"})
_NUMBER = r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?"
_NAME = r"[^\W\d]\w*"
_LEADING_NUMBER = re.compile(rf"\s*{_NUMBER}")
#: The tokens of the units: a power with its number, a name, ``*``, ``/``, parentheses, spaces.
_TOKEN = re.compile(rf"(?:\*\*|\^)\s*{_NUMBER}|(?P<name>{_NAME})|[*/()]|\s+")


@functools.cache
def _definitions() -> tuple[frozenset[str], frozenset[str]] | None:
    """(unit names, prefixes) of pint's definition files; ``None`` where they are not found."""
    spec = importlib.util.find_spec("pint")
    if spec is None or not spec.submodule_search_locations:
        return None
    folder = Path(next(iter(spec.submodule_search_locations)))
    units: set[str] = set(EXTRA_UNITS)
    prefixes: set[str] = {""}
    pending, seen = ["default_en.txt"], set()
    while pending:
        name = pending.pop()
        if name in seen:
            continue
        seen.add(name)
        try:
            text = (folder / name).read_text(encoding="utf-8")
        except OSError:
            return None
        skipping = False  # inside a @context or @system block: not definitions of units
        for raw in text.splitlines():
            line = raw.split("#", 1)[0].strip()
            if not line:
                continue
            if line.startswith("@"):
                if line.startswith("@import"):
                    pending.append(line.split(None, 1)[1].strip())
                elif line.startswith(("@context", "@system", "@defaults")):
                    skipping = True
                elif line == "@end":
                    skipping = False
                continue
            if skipping or line.startswith("[") or "=" not in line:
                continue
            parts = [part.strip() for part in line.split("=")]
            names = [parts[0], *parts[2:]]
            if parts[0].endswith("-"):
                prefixes.update(n.removesuffix("-") for n in names if n not in ("", "_"))
            else:
                units.update(n for n in names if n not in ("", "_"))
    if len(units) < 100:  # not the files this was written for
        return None
    return frozenset(units), frozenset(prefixes)


def _resolves(name: str, units: frozenset[str], prefixes: frozenset[str]) -> bool:
    for prefix in prefixes:
        if not name.startswith(prefix):
            continue
        for suffix in SUFFIXES:
            if not name.endswith(suffix):
                continue
            stem = name[len(prefix) : len(name) - len(suffix)]
            if suffix and len(stem) == 1:  # pint: no plural of a one-letter name
                continue
            if stem and stem in units:
                return True
    return False


def undefined_unit(text: str) -> str | None:
    """The first unit name of the quantity ``text`` (``"200 rmp"``) that pint's registry does
    not define (``"rmp"``); ``None`` when every name is defined, or when ``text`` is not of
    the plain form this reads (pint then decides)."""
    number = _LEADING_NUMBER.match(text)
    if number is None or not all(c.isascii() or c.isalpha() for c in text):
        return None
    names: list[str] = []
    position = number.end()
    while position < len(text):
        token = _TOKEN.match(text, position)
        if token is None:
            return None  # not the plain form: pint decides
        if token["name"]:
            names.append(token["name"])
        position = token.end()
    definitions = _definitions()
    if definitions is None or not names or any(name in _PINT_WORDS for name in names):
        return None
    units, prefixes = definitions
    return next((name for name in names if not _resolves(name, units, prefixes)), None)
