"""Writing mechanism configurations (TOML) back, e.g. a calibrated copy of a preset.

A calibrated configuration is the user's own configuration (or the preset) with the fitted
values put in the places :mod:`jointplay.io.config` reads them from, each with its unit:

==================  =======================================================================
parameter           key
==================  =======================================================================
``crank-speed``     ``[driver] speed`` (rpm)
``<len>-length``    ``[geometry] <len>`` (mm) of a template mechanism
``clearance``       ``clearance`` (mm) of every ``[joints.*]`` table that has one, and
                    ``[simulation] clearance`` when that table sets it
``k``               ``[simulation] k`` (N/m^exponent) and ``contact``
``c_max``           ``[simulation] cmax`` (N*s/m)
``restitution``     ``[simulation] restitution``
``friction``        ``[simulation] friction`` (the Coulomb coefficient)
==================  =======================================================================

Values are written with 10 significant digits. Comments of the source file are not kept;
the header says where the file came from. The result is read by
:func:`jointplay.io.config.load_config` like any other configuration file.
"""

from __future__ import annotations

import json
import math
import tomllib
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from jointplay.errors import ConfigError


def source_config(preset: str | None = None, config: Path | str | None = None) -> dict[str, Any]:
    """The raw TOML data of a configuration file, or of a preset (default ``paper-fourbar``)."""
    from jointplay.io.config import preset_text, read_toml

    if config is not None:
        return read_toml(config)
    return tomllib.loads(preset_text(preset or "paper-fourbar"))


def _number(value: float, digits: int = 10) -> str:
    return f"{value:.{digits}g}"


def calibrated_config(
    data: Mapping[str, Any],
    values: Mapping[str, float],
    *,
    exponent: float = 1.5,
    contact_law: str | None = None,
) -> dict[str, Any]:
    """A copy of ``data`` (raw TOML) with fitted ``values`` (SI, by parameter name) written in.

    Names without a place in a configuration (``phase``, ``crank-speed@LABEL``) are skipped:
    the phase belongs to the measurements, a per-file crank speed to its run.

    Raises:
        ConfigError: a fitted length that the configuration's ``[geometry]`` does not have.
    """
    out: dict[str, Any] = json.loads(json.dumps(data, default=str))  # deep copy, plain types
    simulation = out.get("simulation")
    for name, value in values.items():
        if not math.isfinite(value):
            continue
        if name == "crank-speed":
            out.setdefault("driver", {})["speed"] = f"{_number(value * 30 / math.pi)} rpm"
        elif name.endswith("-length"):
            length = name.removesuffix("-length")
            geometry = out.get("geometry")
            if not isinstance(geometry, dict) or length not in geometry:
                raise ConfigError(
                    f"cannot write {name}: the configuration has no [geometry] {length}"
                )
            geometry[length] = f"{_number(value * 1e3)} mm"
        elif name == "clearance":
            text = f"{_number(value * 1e3)} mm"
            for table in (out.get("joints") or {}).values():
                if isinstance(table, dict) and "clearance" in table:
                    table["clearance"] = text
            if isinstance(simulation, dict) and "clearance" in simulation:
                simulation["clearance"] = text
        elif name in ("k", "c_max", "restitution", "friction"):
            sim = out.setdefault("simulation", {})
            simulation = sim
            if name == "k":
                unit = "N/m" if exponent == 1 else f"N/m^{exponent:g}"
                sim["k"] = f"{_number(value)} {unit}"
                if contact_law is not None:
                    sim["contact"] = contact_law
                if "exponent" in sim or exponent != 1.5:
                    sim["exponent"] = exponent
            elif name == "c_max":
                sim["cmax"] = f"{_number(value)} N*s/m"
                if contact_law is not None:
                    sim.setdefault("contact", contact_law)
            else:
                sim[name] = float(_number(value))
    return out


# --- a small TOML writer (tables, arrays, strings, numbers, booleans) --------------------------


def _key(name: str) -> str:
    bare = name and all(ch.isalnum() or ch in "-_" for ch in name)
    return name if bare else json.dumps(name)


def _value(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    if isinstance(value, str):
        return json.dumps(value, ensure_ascii=False)
    if isinstance(value, list | tuple):
        return "[" + ", ".join(_value(v) for v in value) + "]"
    if isinstance(value, Mapping):
        return "{" + ", ".join(f"{_key(k)} = {_value(v)}" for k, v in value.items()) + "}"
    raise ConfigError(f"cannot write {type(value).__name__} {value!r} as TOML")


def _table(lines: list[str], prefix: str, table: Mapping[str, Any]) -> None:
    scalars = {k: v for k, v in table.items() if not isinstance(v, Mapping)}
    tables = {k: v for k, v in table.items() if isinstance(v, Mapping)}
    if prefix and (scalars or not tables):
        lines += ["", f"[{prefix}]"]
    for key, value in scalars.items():
        lines.append(f"{_key(key)} = {_value(value)}")
    for key, value in tables.items():
        _table(lines, f"{prefix}.{_key(key)}" if prefix else _key(key), value)


def dumps_toml(data: Mapping[str, Any], header: str = "") -> str:
    """``data`` as TOML text, with ``header`` as leading ``#`` comment lines."""
    lines = [f"# {line}".rstrip() for line in header.splitlines()]
    _table(lines, "", data)
    return "\n".join(lines).lstrip("\n") + "\n"


def write_config(path: Path, data: Mapping[str, Any], header: str = "") -> None:
    """Write ``data`` as a TOML configuration file."""
    path.write_text(dumps_toml(data, header), encoding="utf-8")
