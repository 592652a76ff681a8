"""The ``[tolerances]`` table of a configuration file: the one reader of its keys.

:func:`parse_tolerance_table` turns the parsed TOML table into a
:class:`~jointplay.tolerance.spec.ToleranceSpec` (lengths with explicit deviations or ISO
2768-1 classes, joint clearances from ISO 286 fits or explicit limits, distributions, shifts
and Cpk); :func:`mechanism_tolerances` is what :func:`jointplay.io.config.parse_config` keeps
of it on the mechanism; :func:`jointplay.io.config.load_study_spec` reads a preset or file
and returns both.
The specification objects, their distributions and validation live in
:mod:`jointplay.tolerance.spec`.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import replace
from functools import partial
from typing import Any, TypeVar

from jointplay.errors import ConfigError, JointplayError
from jointplay.io.keys import option_keys
from jointplay.model.mechanism import LengthTolerance, Mechanism, RevoluteJoint
from jointplay.tolerance.spec import (
    DEFAULT_DISTRIBUTION,
    DISTRIBUTIONS,
    Distribution,
    InputTolerance,
    JointTolerance,
    LinkTolerance,
    ToleranceSpec,
    in_template_order,
    template_lengths,
)
from jointplay.units import parse_quantity

__all__ = ["mechanism_tolerances", "parse_tolerance_table"]

_T = TypeVar("_T")

_TOP_KEYS = ("general", "distribution", "fits", "lengths", "joints")
_SHARED_KEYS = ("distribution", "shift", "cpk", "source")
_LENGTH_KEYS = ("lower", "upper", "class", *_SHARED_KEYS)
_JOINT_KEYS = ("fit", "diameter", "clearance_min", "clearance_max", *_SHARED_KEYS)


def parse_tolerance_table(table: Mapping[str, Any] | None, mechanism: Mechanism) -> ToleranceSpec:
    """Build the specification from a configuration's parsed ``[tolerances]`` table.

    Keys (quantities are strings with units, as everywhere in configuration files; a key
    may also be written with ``-`` for ``_``, e.g. ``clearance-min``)::

        [tolerances]
        general = "c"              # ISO 2768-1 class for every length without its own entry
        distribution = "normal"    # default of every quantity: uniform | normal | triangular
        fits = true                # joints with an ISO 286 fit in [joints.<name>] get a
                                   # clearance input (default true)

        [tolerances.lengths.crank] # either explicit deviations ...
        lower = "-0.8 mm"
        upper = "0.8 mm"
        source = "ISO 2768-1 c"    # free text, recorded
        distribution = "normal"    # optional, per quantity
        shift = "0.1 mm"           # optional process mean shift
        cpk = 1.33                 # optional (normal only)

        [tolerances.lengths.coupler]
        class = "m"                # ... or an ISO 2768-1 class

        [tolerances.joints.A]      # clearance: a fit (diameter defaults to [joints.A]) ...
        fit = "H7/g6"
        diameter = "10 mm"
        [tolerances.joints.B]      # ... or explicit radial clearance limits
        clearance_min = "5 um"
        clearance_max = "30 um"

    A joint table with neither a fit nor limits only sets the distribution of the clearance
    that ``[joints.<name>]``'s fit gives.

    Args:
        table: the parsed TOML table (``None``: no ``[tolerances]`` table).
        mechanism: the mechanism it belongs to (nominal lengths, joint fits and diameters).

    Raises:
        ConfigError: unknown keys, missing units, contradictory entries; the message names
            the table and key.
    """
    raw = option_keys(table or {}, _TOP_KEYS, "tolerances")
    default = _distribution(raw.get("distribution", DEFAULT_DISTRIBUTION), "tolerances")
    general = raw.get("general")
    if general is not None and not isinstance(general, str):
        raise ConfigError(f"tolerances.general must be an ISO 2768-1 class letter, got {general!r}")
    use_fits = raw.get("fits", True)
    if not isinstance(use_fits, bool):
        raise ConfigError(f"tolerances.fits must be true or false, got {use_fits!r}")
    nominal = template_lengths(mechanism)
    inputs: list[InputTolerance] = []
    length_tables = _mapping(raw.get("lengths", {}), "tolerances.lengths")
    for name, entry_raw in length_tables.items():
        where = f"tolerances.lengths.{name}"
        if name not in nominal:
            raise ConfigError(
                f"{where}: unknown length {name!r}; the mechanism's template lengths are "
                f"{sorted(nominal) or 'none (not a template mechanism)'}"
            )
        inputs.append(
            _length_entry(_mapping(entry_raw, where), where, name, nominal[name], default)
        )
    if general is not None:
        for name, value in nominal.items():
            if name not in length_tables and abs(value) >= 0.5e-3:
                inputs.append(
                    _with_context(
                        partial(LinkTolerance.general, name, value, general, distribution=default),
                        "tolerances.general",
                    )
                )
    inputs = in_template_order(inputs, nominal)
    joint_tables = _mapping(raw.get("joints", {}), "tolerances.joints")
    revolute = {j.name: j for j in mechanism.revolute_joints}
    for name in joint_tables:
        if name not in revolute:
            raise ConfigError(
                f"tolerances.joints.{name}: unknown revolute joint {name!r}; revolute joints: "
                f"{sorted(revolute)}"
            )
    for name, joint in revolute.items():
        if name in joint_tables:
            where = f"tolerances.joints.{name}"
            inputs.append(_joint_entry(_mapping(joint_tables[name], where), where, joint, default))
        elif use_fits and joint.fit is not None and joint.fit.fit:
            fit, diameter = joint.fit.fit, joint.fit.diameter
            inputs.append(
                _with_context(
                    partial(JointTolerance.from_fit, name, fit, diameter, distribution=default),
                    f"joints.{name}",
                )
            )
    return ToleranceSpec(tuple(inputs))


def _length_entry(
    entry: Mapping[str, Any], where: str, name: str, nominal: float, default: Distribution
) -> LinkTolerance:
    entry = option_keys(entry, _LENGTH_KEYS, where)
    distribution, shift, cpk, source = _shared(entry, where, default)
    if "class" in entry:
        if "lower" in entry or "upper" in entry:
            raise ConfigError(f"{where}: give either class or lower/upper, not both")
        return _with_context(
            lambda: LinkTolerance.general(
                name,
                nominal,
                str(entry["class"]),
                distribution=distribution,
                shift=shift,
                cpk=cpk,
            ),
            where,
        )
    if "lower" not in entry or "upper" not in entry:
        raise ConfigError(
            f'{where}: give lower and upper deviations (e.g. lower = "-0.8 mm") or an '
            'ISO 2768-1 class (class = "c")'
        )
    lower = parse_quantity(entry["lower"], "m", field=f"{where}.lower")
    upper = parse_quantity(entry["upper"], "m", field=f"{where}.upper")
    return _with_context(
        lambda: LinkTolerance.from_deviations(
            name,
            nominal,
            lower,
            upper,
            distribution=distribution,
            shift=shift,
            cpk=cpk,
            source=source or "explicit",
        ),
        where,
    )


def _joint_entry(
    entry: Mapping[str, Any], where: str, joint: RevoluteJoint, default: Distribution
) -> JointTolerance:
    entry = option_keys(entry, _JOINT_KEYS, where)
    distribution, shift, cpk, source = _shared(entry, where, default)
    fit_data = joint.fit
    diameter = (
        parse_quantity(entry["diameter"], "m", field=f"{where}.diameter")
        if "diameter" in entry
        else (fit_data.diameter if fit_data is not None else None)
    )
    has_limits = "clearance_min" in entry or "clearance_max" in entry
    if has_limits:
        if "fit" in entry:
            raise ConfigError(f"{where}: give either a fit or clearance_min/max, not both")
        if "clearance_min" not in entry or "clearance_max" not in entry:
            raise ConfigError(f"{where}: give both clearance_min and clearance_max (radial)")
        if diameter is None:
            raise ConfigError(
                f"{where}: the pin diameter is needed for the dynamics; give diameter here or "
                f"in [joints.{joint.name}]"
            )
        lower = parse_quantity(entry["clearance_min"], "m", field=f"{where}.clearance_min")
        upper = parse_quantity(entry["clearance_max"], "m", field=f"{where}.clearance_max")
        if not lower > 0:
            raise ConfigError(
                f"{where}.clearance_min = {entry['clearance_min']!r}: the clearance joint model "
                "needs a radial clearance > 0 (at 0 the pin has no room to move and its "
                "penetration ratio is undefined); give clearance_min > 0, e.g. '1 um'"
            )
        return _with_context(
            lambda: JointTolerance.from_limits(
                joint.name,
                lower,
                upper,
                journal_radius=diameter / 2.0,
                distribution=distribution,
                shift=shift,
                cpk=cpk,
                source=source or "explicit",
            ),
            where,
        )
    fit = entry.get("fit", fit_data.fit if fit_data is not None else None)
    if not isinstance(fit, str) or diameter is None:
        raise ConfigError(
            f"{where}: needs an ISO 286 fit and a diameter (here or in [joints.{joint.name}]) "
            "or clearance_min and clearance_max"
        )
    result = _with_context(
        lambda: JointTolerance.from_fit(
            joint.name, fit, diameter, distribution=distribution, shift=shift, cpk=cpk
        ),
        where,
    )
    return replace(result, source=source) if source else result


def _shared(
    entry: Mapping[str, Any], where: str, default: Distribution
) -> tuple[Distribution, float, float | None, str]:
    distribution = _distribution(entry.get("distribution", default), where)
    shift = parse_quantity(entry["shift"], "m", field=f"{where}.shift") if "shift" in entry else 0.0
    cpk = entry.get("cpk")
    if cpk is not None and (isinstance(cpk, bool) or not isinstance(cpk, int | float)):
        raise ConfigError(f"{where}.cpk must be a number, got {cpk!r}")
    source = entry.get("source", "")
    if not isinstance(source, str):
        raise ConfigError(f"{where}.source must be a string, got {source!r}")
    return distribution, shift, None if cpk is None else float(cpk), source


def _distribution(value: Any, where: str) -> Distribution:
    if value not in DISTRIBUTIONS:
        raise ConfigError(
            f"{where}.distribution must be one of {', '.join(DISTRIBUTIONS)}, got {value!r}"
        )
    return value


def _mapping(value: Any, where: str) -> Mapping[str, Any]:
    if not isinstance(value, Mapping):
        raise ConfigError(f"{where} must be a table, got {type(value).__name__}")
    return value


def _with_context(build: Callable[[], _T], where: str) -> _T:
    """Call ``build()``; prefix any jointplay error with the table it came from."""
    try:
        return build()
    except JointplayError as exc:
        raise type(exc)(f"{where}: {exc}") from None


def mechanism_tolerances(
    table: Mapping[str, Any], mechanism: Mechanism
) -> tuple[LengthTolerance, ...]:
    """Validate a whole ``[tolerances]`` table and return the mechanism's length tolerances.

    Called by :func:`jointplay.io.config.parse_config`, so every command checks the extended
    keys (classes, distributions, joints) the same way; class entries become explicit limits.
    """
    spec = parse_tolerance_table(table, mechanism)
    return tuple(
        LengthTolerance(
            item.length,
            item.tolerance.lower - item.nominal,
            item.tolerance.upper - item.nominal,
            item.source,
        )
        for item in spec.inputs
        if isinstance(item, LinkTolerance)
    )
