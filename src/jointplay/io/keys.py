"""The keys of configuration tables: their canonical spelling and the check of allowed keys.

Keys may be written as command-line options are (``stiffness-law``) or with underscores
(``stiffness_law``); a table that has both spellings of one key, or a key it does not take,
is refused with the allowed keys and the closest one ("did you mean"). Used by every
reader of a table (:mod:`jointplay.io.config`, :mod:`jointplay.io.tolerances`).
"""

from __future__ import annotations

import difflib
from collections.abc import Iterable, Mapping
from typing import Any

from jointplay.errors import ConfigError

__all__ = ["option_key", "option_keys", "unknown_keys_message"]


def option_key(key: str) -> str:
    """A configuration key in its canonical spelling: ``stiffness-law`` → ``stiffness_law``."""
    return key.replace("-", "_")


def unknown_keys_message(where: str, unknown: Iterable[str], allowed: Iterable[str]) -> str:
    """One line naming the unknown keys of table ``where``, the closest allowed key of each
    ("did you mean"), and every allowed key."""
    choices = sorted(set(allowed))
    named = []
    for key in unknown:
        close = difflib.get_close_matches(option_key(key), choices, n=1, cutoff=0.6)
        named.append(f"{key!r}" + (f" (did you mean {close[0]!r}?)" if close else ""))
    allowed_text = ", ".join(choices) if choices else "none"
    return (
        f"{where or 'top level'}: unknown key{'s' if len(named) > 1 else ''} "
        f"{', '.join(named)}; allowed keys: {allowed_text} (each also with '-' for '_')"
    )


def option_keys(table: Mapping[str, Any], allowed: Iterable[str], where: str) -> dict[str, Any]:
    """``table`` with its keys in the canonical spelling (:func:`option_key`), checked.

    For tables whose keys are settings (``[simulation]``, ``[wear]``, ``[cost]``, the
    entries of ``[tolerances]``), not names.

    Raises:
        ConfigError: a key given in both spellings, or a key that is not ``allowed`` (the
            message lists the allowed keys and suggests the closest).
    """
    if not isinstance(table, Mapping):
        raise ConfigError(f"{where} must be a table, got {type(table).__name__}")
    permitted = {option_key(k) for k in allowed}
    out: dict[str, Any] = {}
    written: dict[str, str] = {}
    for key, value in table.items():
        canonical = option_key(str(key))
        if canonical in out:
            raise ConfigError(
                f"{where}: {written[canonical]!r} and {key!r} are the same key; give it once"
            )
        out[canonical], written[canonical] = value, str(key)
    unknown = [written[k] for k in out if k not in permitted]
    if unknown:
        raise ConfigError(unknown_keys_message(where, unknown, permitted))
    return out
