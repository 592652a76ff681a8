"""The settings of ``jointplay explore``: what the page may ask for, read from its query.

The page's state lives in its URL query (a shared link reproduces the view). Every parameter
is one of :data:`PARAMETERS` or, for the explored mechanism's joints and lengths,
``c.<joint>`` (clearance), ``contact.<joint>`` and ``mu.<joint>`` (the joint's own contact and
friction) and ``L.<length>``; anything else is refused. A valid query becomes a *configuration file* — the explored
mechanism's own TOML data with the chosen lengths, crank speed and clearances written in, and a
``[simulation]`` table with the contact, friction and start — which the engine reads exactly as
``jointplay simulate --config`` does (:mod:`jointplay.explore.engine`), and which the download
hands out as ``settings.toml``.

Units at the edge: the query carries µm, mm and rev/min, as the controls show them; the
configuration carries quantities with units, read by :mod:`jointplay.io.config` into SI.
"""

from __future__ import annotations

import copy
import dataclasses
import math
import tomllib
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from jointplay.errors import ConfigError, JointplayError

#: Contact choices: the physical default (docs/contact.md) and the paper's six methods.
PHYSICAL = "physical"
#: Start modes of ``--start``.
STARTS = ("steady", "rest", "impulsive", "ramp")
#: Which clearance of an ISO 286 fit a joint takes.
FIT_PICKS = ("min", "mean", "max")
#: Parameters that are not per joint or per length.
PARAMETERS = ("rpm", "contact", "mu", "start", "settle")
#: The most start-up revolutions the page asks for (each costs a revolution's run time).
MAX_SETTLE = 10
#: Longest value of a parameter, characters (a control never writes more).
MAX_VALUE = 40
#: Clearance range of the page's µm field, µm (beyond it: a typo).
CLEARANCE_RANGE_UM = (0.1, 1000.0)
#: Crank speed range, rev/min.
RPM_RANGE = (1.0, 10000.0)


@dataclass(frozen=True)
class JointControl:
    """A joint that may get clearance: its fit data as the configuration gives it (SI)."""

    name: str
    diameter: float
    fit: str | None
    clearance: float | None
    fit_range: tuple[float, float] | None  # the fit's radial clearance min, max, m

    def default(self) -> str:
        """The query value of the configuration's own clearance."""
        if self.clearance is not None:
            return _number(self.clearance * 1e6)
        if self.fit is not None:
            return f"{self.fit}:mean"
        return "off"


@dataclass(frozen=True)
class LengthControl:
    """A template length and its ISO 2768 (or the configuration's own) tolerance, m."""

    name: str
    nominal: float
    lower: float
    upper: float
    tolerance: str  # in words, e.g. "ISO 2768-c"


@dataclass(frozen=True)
class Base:
    """The mechanism ``jointplay explore`` was started on: its raw TOML data and controls."""

    data: dict[str, Any]
    source: str
    name: str
    rpm: float
    joints: tuple[JointControl, ...]
    lengths: tuple[LengthControl, ...]

    def defaults(self) -> dict[str, str]:
        """The query of the configuration as it is (the physical default contact)."""
        query = {"rpm": _number(self.rpm), "contact": PHYSICAL, "start": "steady", "settle": "2"}
        query.update({f"c.{j.name}": j.default() for j in self.joints})
        query.update({f"L.{length.name}": _number(length.nominal * 1e3) for length in self.lengths})
        return query

    def spec(self) -> dict[str, Any]:
        """What the page needs to draw its controls (units of the controls)."""
        from jointplay.study.methods import METHODS

        return {
            "name": self.name,
            "source": self.source,
            "defaults": self.defaults(),
            "contacts": [PHYSICAL, *METHODS],
            "starts": list(STARTS),
            "max_settle": MAX_SETTLE,
            "rpm_range": list(RPM_RANGE),
            "clearance_range_um": list(CLEARANCE_RANGE_UM),
            "joints": [
                {
                    "name": j.name,
                    "diameter_mm": j.diameter * 1e3,
                    "fit": j.fit,
                    "slider_max_um": max(
                        100.0, 2e6 * max(j.clearance or 0.0, (j.fit_range or (0.0, 0.0))[1])
                    ),
                    "fit_range_um": None
                    if j.fit_range is None
                    else [j.fit_range[0] * 1e6, j.fit_range[1] * 1e6],
                }
                for j in self.joints
            ],
            "lengths": [
                {
                    "name": length.name,
                    "nominal_mm": length.nominal * 1e3,
                    "min_mm": (length.nominal + length.lower) * 1e3,
                    "max_mm": (length.nominal + length.upper) * 1e3,
                    "tolerance": length.tolerance,
                }
                for length in self.lengths
            ],
        }


def _number(value: float) -> str:
    return f"{value:.10g}"


def load_base(preset: str | None = None, config: Path | str | None = None) -> Base:
    """The explored mechanism of ``--preset`` or ``--config`` (default ``paper-fourbar``),
    checked by loading it as every command does."""
    from jointplay.io.config import load_mechanism, preset_text, read_toml

    if preset is not None and config is not None:
        raise ConfigError("give --preset or --config, not both")
    if config is not None:
        data = read_toml(config)
        source = f"configuration {str(config)!r}"
    else:
        preset = preset or "paper-fourbar"
        data = tomllib.loads(preset_text(preset))
        source = f"preset {preset!r}"
    mechanism = load_mechanism(preset, config)
    joints = []
    for name, table in _joint_tables(data).items():
        joint = mechanism.joint(name)
        fit = getattr(joint, "fit", None)
        if fit is None:
            continue
        fit_range = None
        if fit.fit is not None:
            from jointplay.tolerance.iso286 import fit as iso_fit

            limits = iso_fit(fit.fit, fit.diameter)
            fit_range = (limits.radial_clearance_min, limits.radial_clearance_max)
        given = table.get("clearance")
        joints.append(
            JointControl(
                name, fit.diameter, fit.fit, None if given is None else fit.clearance, fit_range
            )
        )
    return Base(
        data=data,
        source=source,
        name=mechanism.name,
        rpm=mechanism.driver.speed * 30 / math.pi,
        joints=tuple(joints),
        lengths=tuple(_lengths(data)),
    )


def _joint_tables(data: Mapping[str, Any]) -> dict[str, dict[str, Any]]:
    """The joints' tables of raw TOML ``data`` that hold fit data (``[joints.<J>]``)."""
    tables = data.get("joints")
    if not isinstance(tables, dict):
        return {}
    return {
        name: table
        for name, table in tables.items()
        if isinstance(table, dict) and "diameter" in table
    }


def _lengths(data: Mapping[str, Any]) -> list[LengthControl]:
    """The ``[geometry]`` lengths and their tolerance: a ``[tolerances.lengths.<L>]`` entry,
    else the ``[tolerances] general`` ISO 2768-1 class."""
    from jointplay.tolerance.iso2768 import general_tolerance
    from jointplay.units import parse_quantity

    geometry = data.get("geometry")
    if not isinstance(geometry, dict):
        return []
    tolerances = data.get("tolerances") if isinstance(data.get("tolerances"), dict) else {}
    assert isinstance(tolerances, dict)
    general = tolerances.get("general")
    own = tolerances.get("lengths") if isinstance(tolerances.get("lengths"), dict) else {}
    assert isinstance(own, dict)
    out = []
    for name, text in geometry.items():
        if not isinstance(text, str):
            continue
        try:
            nominal = parse_quantity(text, "m", field=f"geometry.{name}")
        except JointplayError:
            continue  # not a length (e.g. an offset of zero written as a number)
        if not nominal > 0:
            continue
        entry = own.get(name)
        if isinstance(entry, dict) and "lower" in entry and "upper" in entry:
            lower = parse_quantity(entry["lower"], "m", field=f"tolerances.lengths.{name}.lower")
            upper = parse_quantity(entry["upper"], "m", field=f"tolerances.lengths.{name}.upper")
            words = "the configuration's tolerance"
        elif isinstance(general, str):
            deviation = general_tolerance(general, nominal)
            lower, upper = -deviation, deviation
            words = f"ISO 2768-{general}"
        else:
            continue  # no tolerance: the length stays as it is
        out.append(LengthControl(name, nominal, lower, upper, words))
    return out


@dataclass(frozen=True)
class Clearance:
    """One joint's choice: ``micrometres`` given, or the ``pick`` of the joint's ``fit``, or
    ``off`` (an ideal joint)."""

    off: bool = False
    micrometres: float | None = None
    fit: str | None = None
    pick: str | None = None


@dataclass(frozen=True)
class Settings:
    """A valid query of the page (units of the controls)."""

    rpm: float
    contact: str
    friction: float | None
    start: str
    settle: int
    clearances: Mapping[str, Clearance]
    lengths_mm: Mapping[str, float]
    #: A joint's own contact and friction, where it has one (else the common ``contact``
    #: and ``friction`` above).
    joint_contact: Mapping[str, str] = dataclasses.field(default_factory=dict)
    joint_friction: Mapping[str, float] = dataclasses.field(default_factory=dict)

    def contact_of(self, joint: str) -> tuple[str, float | None]:
        """The contact and friction (``None``: the law's default) of ``joint``."""
        return (
            self.joint_contact.get(joint, self.contact),
            self.joint_friction.get(joint, self.friction),
        )

    def uniform(self) -> tuple[str, float | None] | None:
        """The one contact and friction of every clearance joint, or ``None`` when they
        differ (the command line takes one contact for all joints)."""
        pairs = {self.contact_of(name) for name, c in self.clearances.items() if not c.off}
        if len(pairs) > 1:
            return None
        return pairs.pop() if pairs else (self.contact, self.friction)

    def query(self) -> dict[str, str]:
        """The canonical query of these settings (what the page writes into its URL)."""
        out = {"rpm": _number(self.rpm), "contact": self.contact}
        if self.friction is not None:
            out["mu"] = _number(self.friction)
        out.update({"start": self.start, "settle": str(self.settle)})
        for name, choice in self.clearances.items():
            if choice.off:
                out[f"c.{name}"] = "off"
            elif choice.fit is not None:
                out[f"c.{name}"] = f"{choice.fit}:{choice.pick}"
            else:
                assert choice.micrometres is not None
                out[f"c.{name}"] = _number(choice.micrometres)
            if name in self.joint_contact:
                out[f"contact.{name}"] = self.joint_contact[name]
            if name in self.joint_friction:
                out[f"mu.{name}"] = _number(self.joint_friction[name])
        out.update({f"L.{name}": _number(value) for name, value in self.lengths_mm.items()})
        return out


def _finite(text: str, what: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise ConfigError(f"{what} must be a number, got {text!r}") from None
    if not math.isfinite(value):
        raise ConfigError(f"{what} must be a finite number, got {text!r}")
    return value


def parse_query(base: Base, query: Mapping[str, str] | Any) -> Settings:
    """The :class:`Settings` of a page query (a mapping, or Starlette's multi-dict), over the
    ``base`` defaults; a :class:`ConfigError` names the first bad or unknown parameter."""
    items = list(query.multi_items()) if hasattr(query, "multi_items") else list(query.items())
    given: dict[str, str] = {}
    allowed = set(PARAMETERS)
    allowed |= {f"{key}.{j.name}" for j in base.joints for key in ("c", "contact", "mu")}
    allowed |= {f"L.{length.name}" for length in base.lengths}
    for key, value in items:
        if key not in allowed:
            raise ConfigError(
                f"unknown parameter {key[:MAX_VALUE]!r}; this page takes "
                + ", ".join(sorted(allowed))
            )
        if key in given:
            raise ConfigError(f"parameter {key!r} given twice")
        if not isinstance(value, str) or len(value) > MAX_VALUE:
            raise ConfigError(f"parameter {key!r} is longer than {MAX_VALUE} characters")
        given[key] = value.strip()
    values = {**base.defaults(), **given}

    rpm = _finite(values["rpm"], "the crank speed (rev/min)")
    if not RPM_RANGE[0] <= rpm <= RPM_RANGE[1]:
        raise ConfigError(
            f"the crank speed must lie within {RPM_RANGE[0]:g}–{RPM_RANGE[1]:g} rev/min, got {rpm:g}"
        )
    contact = _contact(values["contact"], "contact")
    friction = _friction(values.get("mu", ""), "the friction coefficient")
    joint_contact: dict[str, str] = {}
    joint_friction: dict[str, float] = {}
    for joint in base.joints:
        own = values.get(f"contact.{joint.name}", "")
        if own != "":
            joint_contact[joint.name] = _contact(own, f"contact of joint {joint.name}")
        value = _friction(
            values.get(f"mu.{joint.name}", ""), f"the friction coefficient of joint {joint.name}"
        )
        if value is not None:
            joint_friction[joint.name] = value
    start = values["start"]
    if start not in STARTS:
        raise ConfigError(f"the start must be one of {', '.join(STARTS)}, got {start!r}")
    try:
        settle = int(values["settle"])
    except ValueError:
        raise ConfigError(
            f"the start-up revolutions must be a whole number, got {values['settle']!r}"
        ) from None
    if not 0 <= settle <= MAX_SETTLE:
        raise ConfigError(f"the start-up revolutions must lie within 0–{MAX_SETTLE}, got {settle}")

    clearances = {j.name: _clearance(j, values[f"c.{j.name}"]) for j in base.joints}
    if clearances and all(c.off for c in clearances.values()):
        raise ConfigError("every joint is ideal: give at least one joint a clearance")
    lengths = {}
    for length in base.lengths:
        key = f"L.{length.name}"
        value = _finite(values[key], f"the {length.name} length (mm)")
        low, high = (length.nominal + length.lower) * 1e3, (length.nominal + length.upper) * 1e3
        if not low - 1e-9 <= value <= high + 1e-9:
            raise ConfigError(
                f"the {length.name} length must lie within its {length.tolerance} tolerance, "
                f"{low:.4g}–{high:.4g} mm, got {value:g}"
            )
        lengths[length.name] = value
    return Settings(
        rpm, contact, friction, start, settle, clearances, lengths, joint_contact, joint_friction
    )


def _contact(text: str, what: str) -> str:
    """A contact choice: :data:`PHYSICAL` or one of the paper's methods."""
    from jointplay.study.methods import METHODS

    if text != PHYSICAL and text not in METHODS:
        raise ConfigError(
            f"unknown {what} {text!r}; choose {PHYSICAL} or one of the paper's methods: "
            + ", ".join(METHODS)
        )
    return text


def _friction(text: str, what: str) -> float | None:
    """A friction coefficient within 0–1, or ``None`` for a blank (the law's default)."""
    if text == "":
        return None
    value = _finite(text, what)
    if not 0 <= value <= 1:
        raise ConfigError(f"{what} must lie within 0–1, got {value:g}")
    return value


def _clearance(joint: JointControl, text: str) -> Clearance:
    what = f"the clearance of joint {joint.name}"
    if text == "off":
        return Clearance(off=True)
    if ":" in text:
        fit, _, pick = text.partition(":")
        if pick not in FIT_PICKS:
            raise ConfigError(
                f"{what}: a fit's clearance is its min, mean or max, got {pick!r} (e.g. H8/g7:max)"
            )
        from jointplay.tolerance.iso286 import fit as iso_fit

        try:
            limits = iso_fit(fit, joint.diameter)
        except JointplayError as exc:
            raise ConfigError(f"{what}: {exc}") from None
        low_um, high_um = limits.radial_clearance_min * 1e6, limits.radial_clearance_max * 1e6
        value = {"min": low_um, "mean": (low_um + high_um) / 2, "max": high_um}[pick]
        if value < CLEARANCE_RANGE_UM[0]:
            kind = "an interference fit" if high_um <= 0 else "a transition fit"
            raise ConfigError(
                f"{what}: {fit} is {kind} at Ø{joint.diameter * 1e3:g} mm (radial clearance "
                f"{low_um:g} to {high_um:g} µm), so its {pick} leaves no clearance "
                f"({value:g} µm); choose a clearance fit such as H7/g6, or a clearance in µm"
            )
        return Clearance(fit=fit, pick=pick)
    value = _finite(text, f"{what} (µm)")
    low, high = CLEARANCE_RANGE_UM
    if not low <= value <= high:
        raise ConfigError(f"{what} must lie within {low:g}–{high:g} µm, got {value:g}")
    return Clearance(micrometres=value)


def config_data(base: Base, settings: Settings) -> dict[str, Any]:
    """The configuration (raw TOML data) of ``settings``: ``jointplay simulate --config`` on
    it simulates what the page shows."""
    from jointplay.tolerance.iso286 import fit as iso_fit

    data = copy.deepcopy(base.data)
    data.setdefault("driver", {})["speed"] = f"{_number(settings.rpm)} rpm"
    geometry = data.get("geometry", {})
    for name, value in settings.lengths_mm.items():
        geometry[name] = f"{_number(value)} mm"
    tables = _joint_tables(data)
    joints = []
    for joint in base.joints:
        choice = settings.clearances[joint.name]
        table = tables[joint.name]
        if choice.off:
            continue
        joints.append(joint.name)
        if choice.fit is not None:
            limits = iso_fit(choice.fit, joint.diameter)
            low, high = limits.radial_clearance_min, limits.radial_clearance_max
            value = {"min": low, "mean": (low + high) / 2, "max": high}[str(choice.pick)]
            table["fit"] = choice.fit
        else:
            assert choice.micrometres is not None
            value = choice.micrometres * 1e-6
            table.pop("fit", None)  # a clearance of its own, not the fit's
        table["clearance"] = f"{_number(value * 1e3)} mm"
    simulation: dict[str, Any] = {}
    # one contact for every joint, as the command line takes it: the joints' common one (the
    # engine gives joints of their own their own; the download refuses them)
    contact, friction = settings.uniform() or (settings.contact, settings.friction)
    if contact != PHYSICAL:
        simulation["method"] = contact
    if friction is not None:
        simulation["friction"] = friction
    if base.joints:  # else simulate's default: every joint with a clearance in its fit data
        simulation["joints"] = joints
    simulation.update({"start": settings.start, "settle": settings.settle, "revolutions": 1})
    data["simulation"] = simulation
    return data
