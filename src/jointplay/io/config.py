"""Mechanism configuration files (TOML) with units, and the named presets.

A configuration describes one mechanism. Quantities are strings with units (``"270.5 mm"``,
``"200 rpm"``, ``"207 GPa"``) converted to SI once, here. Unknown keys and missing units are
errors that name the table and key. See the files in ``jointplay/data/presets`` (printed by
``jointplay show PRESET``) for annotated examples of the three forms: ``template = "four-bar"``,
``"slider-crank"`` and ``"general"``.

Keys may be written as the command-line options are (``stiffness-law``) or with underscores
(``stiffness_law``), in every table; a table that has both spellings of one key is refused.
An unknown key is refused with the table's allowed keys and the closest one ("did you
mean"). Names that are data, not keys (links, joints, points), are taken as written.
"""

from __future__ import annotations

import math
import os
import stat
import tomllib
from collections.abc import Mapping
from dataclasses import dataclass, replace
from importlib import resources
from pathlib import Path
from typing import TYPE_CHECKING, Any

from jointplay.dynamics.declared import CONTACT_SETTINGS, RUN_SETTINGS
from jointplay.errors import ConfigError, JointplayError
from jointplay.io.keys import option_keys, unknown_keys_message
from jointplay.model.lubricants import parse_grade, split_regime
from jointplay.model.mechanism import (
    GROUND,
    MAX_START_ANGLE,
    REGIMES,
    STEEL,
    Driver,
    Ground,
    JointFit,
    LengthTolerance,
    Link,
    Lubrication,
    Material,
    Mechanism,
    PrismaticJoint,
    RevoluteJoint,
    check_gravity,
)
from jointplay.model.templates import (
    FourBarGeometry,
    LinkBody,
    SliderCrankGeometry,
    four_bar,
    slider_crank,
)
from jointplay.units import parse_quantity

if TYPE_CHECKING:
    from jointplay.tolerance.spec import ToleranceSpec

STANDARD_GRAVITY = 9.80665


#: The largest length a mechanism file may give, m: beyond it the geometry is a typo.
MAX_LENGTH = 1000.0
#: The largest speed a mechanism file may give, rad/s (about 1e6 rev/min).
MAX_SPEED = 1e5


def _plausible(value: float, unit: str, field: str, given: Any) -> float:
    """``value``, unless it is a length beyond :data:`MAX_LENGTH` (blamed on the geometry), a
    speed beyond :data:`MAX_SPEED` or an angle (the driver's start angle, a link's initial
    angle, a prismatic joint's axis) beyond two turns either way
    (:data:`jointplay.model.mechanism.MAX_START_ANGLE`)."""
    if unit == "rad/s" and abs(value) > MAX_SPEED:
        raise ConfigError(
            f"{field} = {given!r} is not a plausible crank speed (at most {MAX_SPEED:g} rad/s, "
            "about 1e6 rpm)"
        )
    if unit == "rad" and not abs(value) <= MAX_START_ANGLE:
        raise ConfigError(
            f"{field} = {given!r} is not a plausible angle: it must lie within ±720° (two "
            "turns; every position is within one); write it within one turn, e.g. '30 deg'"
        )
    if unit == "m" and abs(value) > MAX_LENGTH:
        raise ConfigError(
            f"{field} = {given!r} is not a plausible length for a linkage (at most "
            f"{MAX_LENGTH:g} m); check the geometry"
        )
    return value


class _Table:
    """A TOML table that hands out its keys and reports the ones nobody asked for.

    A key may be written with ``-`` for ``_`` (the option spelling); the parser asks in
    the canonical spelling. Every key asked for (present or not) is an allowed key of the
    table, listed when an unknown key is refused.
    """

    def __init__(self, data: Any, where: str) -> None:
        if not isinstance(data, Mapping):
            raise ConfigError(f"{where} must be a table, got {type(data).__name__}")
        self.data = dict(data)
        self.where = where
        self.used: set[str] = set()
        self.allowed: set[str] = set()

    def _key(self, key: str) -> str | None:
        """The key as written in the file (``key`` or its option spelling), or None."""
        self.allowed.add(key)
        spellings = [k for k in dict.fromkeys((key, key.replace("_", "-"))) if k in self.data]
        if len(spellings) > 1:
            raise ConfigError(
                f"{self.where or 'top level'}: {spellings[0]!r} and {spellings[1]!r} are the "
                "same key; give it once"
            )
        return spellings[0] if spellings else None

    def has(self, key: str) -> bool:
        return self._key(key) is not None

    def raw(self, key: str, default: Any = ...) -> Any:
        written = self._key(key)
        if written is None:
            if default is ...:
                raise ConfigError(f"{self.where}: missing required key {key!r}")
            return default
        self.used.add(written)
        return self.data[written]

    def quantity(self, key: str, unit: str, default: Any = ...) -> Any:
        value = self.raw(key, default)
        if value is default and default is not ...:
            return default
        return _plausible(
            parse_quantity(value, unit, field=f"{self.where}.{key}"),
            unit,
            f"{self.where}.{key}",
            value,
        )

    def number(self, key: str, default: Any = ...) -> Any:
        value = self.raw(key, default)
        if value is default and default is not ...:
            return default
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise ConfigError(f"{self.where}.{key} must be a number, got {value!r}")
        if not math.isfinite(value):
            raise ConfigError(f"{self.where}.{key} must be a finite number, got {value!r}")
        return float(value)

    def text(self, key: str, default: Any = ...) -> Any:
        value = self.raw(key, default)
        if value is default and default is not ...:
            return default
        if not isinstance(value, str):
            raise ConfigError(f"{self.where}.{key} must be a string, got {value!r}")
        return value

    def table(self, key: str) -> _Table:
        return _Table(self.raw(key, {}), f"{self.where}.{key}" if self.where else key)

    def names(self) -> list[str]:
        """The keys of a table of *names* (links, joints, points), taken as written."""
        self.used.update(self.data)
        return list(self.data)

    def name_table(self, name: str) -> _Table:
        """The sub-table of the name ``name`` (one of :meth:`names`), as written."""
        self.used.add(name)
        where = f"{self.where}.{name}" if self.where else name
        return _Table(self.data[name], where)

    def point(self, key: str, value: Any = ...) -> tuple[float, float]:
        value = self.raw(key) if value is ... else value
        if not isinstance(value, list | tuple) or len(value) != 2:
            raise ConfigError(f"{self.where}.{key} must be a pair [x, y] with units, got {value!r}")
        return (
            _plausible(
                parse_quantity(value[0], "m", field=f"{self.where}.{key}[0]"),
                "m",
                f"{self.where}.{key}[0]",
                value[0],
            ),
            _plausible(
                parse_quantity(value[1], "m", field=f"{self.where}.{key}[1]"),
                "m",
                f"{self.where}.{key}[1]",
                value[1],
            ),
        )

    def finish(self) -> None:
        unknown = sorted(set(self.data) - self.used)
        if unknown:
            raise ConfigError(unknown_keys_message(self.where, unknown, self.allowed))


@dataclass(frozen=True)
class Preset:
    """A named mechanism configuration shipped with jointplay.

    Attributes:
        name: the preset's name (its file's, and its ``[mechanism] name``).
        description: ``[mechanism] description``.
        text: the TOML text, comments included.
        source: ``[mechanism] source``: where its numbers come from (a paper, a table).
        reproduces: ``[mechanism] reproduces``: what a run of it shows of that source, and
            what it does not.
    """

    name: str
    description: str
    text: str
    source: str = ""
    reproduces: str = ""


def _preset_files() -> dict[str, Any]:
    folder = resources.files("jointplay") / "data" / "presets"
    return {
        item.name.removesuffix(".toml"): item
        for item in folder.iterdir()
        if item.name.endswith(".toml")
    }


#: Keys of ``[mechanism]`` that every shipped preset gives (:func:`list_presets` refuses a
#: preset without them): where its numbers come from and what a run of it reproduces.
PRESET_KEYS = ("source", "reproduces")


def list_presets() -> list[Preset]:
    """All shipped presets, sorted by name.

    Raises:
        ConfigError: a preset without a ``source`` or ``reproduces`` in ``[mechanism]``
            (every preset states where its numbers come from and what it reproduces).
    """
    presets = []
    for name, item in sorted(_preset_files().items()):
        text = item.read_text(encoding="utf-8")
        head = tomllib.loads(text).get("mechanism", {})
        missing = [key for key in PRESET_KEYS if not str(head.get(key, "")).strip()]
        if missing:
            raise ConfigError(
                f"preset {name!r}: [mechanism] has no {' or '.join(missing)}; a preset states "
                "where its numbers come from (source) and what a run of it shows (reproduces)"
            )
        presets.append(
            Preset(name, head.get("description", ""), text, head["source"], head["reproduces"])
        )
    return presets


def preset_text(name: str) -> str:
    """The TOML text of preset ``name`` (comments included)."""
    files = _preset_files()
    if name not in files:
        raise ConfigError(f"unknown preset {name!r}; available: {', '.join(sorted(files))}")
    return str(files[name].read_text(encoding="utf-8"))


def load_preset(name: str) -> Mechanism:
    """Build the mechanism of preset ``name``."""
    return parse_config(tomllib.loads(preset_text(name)), source=f"preset {name!r}")


#: The largest configuration file read, bytes (a guard against reading a huge file by mistake).
MAX_CONFIG_BYTES = 16 * 2**20
#: The deepest nesting of tables and arrays in a TOML file (a mechanism needs 4:
#: ``[tolerances.lengths.crank]`` holding an array); deeper is a mistake or an attack.
MAX_TOML_DEPTH = 16


def read_text_file(path: Any, what: str = "configuration file") -> str:
    """The UTF-8 text of the regular file ``path``, or a ConfigError saying what is wrong.

    The one reader of user-given text files: refuses what is not a path, a missing file, a
    folder, a FIFO or device (opened without blocking and checked on the open file, so it
    cannot hang), a file over :data:`MAX_CONFIG_BYTES` and text that is not UTF-8.
    """
    if isinstance(path, bool) or not isinstance(path, str | os.PathLike):
        raise ConfigError(f"the {what} must be a file path, got {type(path).__name__}")
    name = os.fspath(path)
    if isinstance(name, bytes) or not name.strip():
        raise ConfigError(f"the {what} must be a file path, got {name!r}")
    shown = repr(name)
    flags = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_NOCTTY", 0)
    try:
        descriptor = os.open(name, flags)
    except FileNotFoundError:
        raise ConfigError(f"{what} {shown} not found") from None
    except OSError as exc:
        raise ConfigError(f"cannot read {what} {shown}: {exc.strerror}") from None
    try:
        info = os.fstat(descriptor)
        if not stat.S_ISREG(info.st_mode):
            kind = "a folder" if stat.S_ISDIR(info.st_mode) else "not a regular file"
            raise ConfigError(f"{what} {shown} is {kind}; give a file")
        if info.st_size > MAX_CONFIG_BYTES:
            raise ConfigError(
                f"{what} {shown} is {info.st_size / 2**20:.0f} MiB; a {what} is at most "
                f"{MAX_CONFIG_BYTES / 2**20:.0f} MiB"
            )
        raw = os.read(descriptor, MAX_CONFIG_BYTES + 1)
    except OSError as exc:
        raise ConfigError(f"cannot read {what} {shown}: {exc.strerror}") from None
    finally:
        os.close(descriptor)
    if len(raw) > MAX_CONFIG_BYTES:  # it grew after the check
        raise ConfigError(f"{what} {shown} is over {MAX_CONFIG_BYTES / 2**20:.0f} MiB")
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise ConfigError(
            f"{what} {shown} is not UTF-8 text (byte 0x{raw[exc.start]:02x} at offset "
            f"{exc.start}); save it as UTF-8"
        ) from None


def read_toml(path: Any, what: str = "configuration file") -> dict[str, Any]:
    """The TOML data of the file ``path`` (:func:`read_text_file`), nested at most
    :data:`MAX_TOML_DEPTH` deep, or a ConfigError saying what is wrong."""
    text = read_text_file(path, what)
    shown = os.fspath(path)
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"{shown}: malformed TOML: {exc}") from None
    except RecursionError:
        data = None
    if data is None or _depth(data) > MAX_TOML_DEPTH:
        raise ConfigError(
            f"{shown}: tables and arrays nested deeper than {MAX_TOML_DEPTH} levels; a "
            f"{what} needs a few"
        )
    return data


def _depth(data: Any) -> int:
    """How deep tables and arrays nest in ``data`` (without recursion)."""
    deepest, stack = 0, [(data, 1)]
    while stack:
        item, level = stack.pop()
        if isinstance(item, dict | list):
            deepest = max(deepest, level)
            if level <= MAX_TOML_DEPTH:
                values = item.values() if isinstance(item, dict) else item
                stack.extend((value, level + 1) for value in values)
    return deepest


def load_config(path: Path | str) -> Mechanism:
    """Read a TOML configuration file and build its mechanism.

    The mechanism is named by the file's ``[mechanism] name``. A file that keeps a preset's
    name (a copy from ``jointplay show``) but describes another mechanism — edited lengths,
    masses, joints, tolerances — is named ``"<preset> (edited: <file name>)"``, so that titles
    and reports never pass an edited mechanism off as the preset; an unedited copy keeps the
    preset's name. Give an edited file its own ``name`` to choose the title.
    """
    data = read_toml(path)
    return _edited_name(parse_config(data, source=os.fspath(path)), path)


def _edited_name(mechanism: Mechanism, path: Path | str) -> Mechanism:
    """``mechanism`` renamed ``"<preset> (edited: <file>)"`` when it bears a preset's name but
    differs from that preset (see :func:`load_config`)."""
    if mechanism.name not in _preset_files():
        return mechanism
    try:
        preset = load_preset(mechanism.name)
    except ConfigError:  # pragma: no cover - a shipped preset always loads
        return mechanism
    if preset == mechanism:
        return mechanism
    return replace(mechanism, name=f"{mechanism.name} (edited: {Path(path).name})")


def tolerance_table(
    preset: str | None = None, config: Path | str | None = None
) -> dict[str, Any] | None:
    """The raw ``[tolerances]`` table of a config file or preset (``None`` without one)."""
    if config is not None:
        data = read_toml(config)
    else:
        data = tomllib.loads(preset_text(preset or "paper-fourbar"))
    table = data.get("tolerances")
    return dict(table) if isinstance(table, Mapping) else None


def load_mechanism(preset: str | None = None, config: Path | str | None = None) -> Mechanism:
    """The mechanism from a config file if given, else from a preset (default ``paper-fourbar``)."""
    if config is not None:
        if preset is not None:
            raise ConfigError("give either a preset or a config file, not both")
        return load_config(config)
    return load_preset(preset or "paper-fourbar")


def load_study_spec(
    preset: str | None = None, config: Path | str | None = None
) -> tuple[Mechanism, ToleranceSpec]:
    """Load a mechanism (preset or TOML file) and its full tolerance specification.

    Args:
        preset: a preset name (default ``paper-fourbar`` when ``config`` is not given).
        config: a configuration file; takes precedence over ``preset``.

    Raises:
        ConfigError: the file cannot be read or its tables are invalid.
    """
    from jointplay.io.tolerances import parse_tolerance_table

    mechanism = load_mechanism(preset, config)
    # parse_config has validated the table already (with the file's name in any message).
    return mechanism, parse_tolerance_table(tolerance_table(preset, config), mechanism)


def parse_config(data: Mapping[str, Any], *, source: str = "configuration") -> Mechanism:
    """Build a mechanism from parsed TOML data (see the module docstring for the format)."""
    try:
        return _parse(_Table(data, ""))
    except ConfigError as exc:
        raise ConfigError(f"{source}: {exc}") from None


def _parse(root: _Table) -> Mechanism:
    head = root.table("mechanism")
    name = head.text("name", "mechanism")
    head.text("description", "")
    for key in PRESET_KEYS:  # what the file reproduces and from where: text, not mechanism
        head.text(key, "")
    template = head.text("template", "four-bar")
    branch_value = head.number("branch", 1)
    if branch_value not in (1.0, -1.0):
        raise ConfigError(f"mechanism.branch must be 1 or -1, got {head.raw('branch', 1)!r}")
    branch = int(branch_value)
    gravity = _gravity(head)
    head.finish()
    material = _material(root.table("material")) if root.has("material") else STEEL
    driver_table = root.table("driver")
    speed = driver_table.quantity("speed", "rad/s")
    direction_text = driver_table.text("direction", "ccw").lower()
    if direction_text not in ("ccw", "cw"):
        raise ConfigError(f"driver.direction must be 'ccw' or 'cw', got {direction_text!r}")
    direction = 1 if direction_text == "ccw" else -1
    start_angle = driver_table.quantity("start_angle", "rad", 0.0)
    raw_tolerances = root.raw("tolerances", None)
    tolerances: tuple[LengthTolerance, ...] = ()
    raw_lubrication = root.raw("lubrication", None)
    root.raw("simulation", None)  # read by simulation_settings(); not part of the mechanism
    for table_name in DESIGN_TABLES:  # read by design_tables(); not part of the mechanism
        root.raw(table_name, None)
    if template in ("four-bar", "slider-crank"):
        mechanism = _parse_template(
            root,
            template,
            name,
            material,
            speed,
            direction,
            start_angle,
            gravity,
            branch,
            tolerances,
        )
        driver_table.finish()
    elif template == "general":
        mechanism = _parse_general(
            root, driver_table, name, material, speed, direction, start_angle, gravity, tolerances
        )
    else:
        raise ConfigError(
            f"mechanism.template must be 'four-bar', 'slider-crank' or 'general', got {template!r}"
        )
    root.finish()
    if raw_tolerances is not None:
        # io.tolerances reads the [tolerances] table (classes, fits, distributions); imported
        # here because it builds on this module (and on NumPy, which the other tables need not).
        from jointplay.io.tolerances import mechanism_tolerances

        if not isinstance(raw_tolerances, Mapping):
            raise ConfigError("tolerances must be a table")
        mechanism = replace(mechanism, tolerances=mechanism_tolerances(raw_tolerances, mechanism))
    if raw_lubrication is not None:
        default, joints = _lubrication(_Table(raw_lubrication, "lubrication"))
        mechanism = replace(mechanism, lubrication=default, joint_lubrication=joints)
    return mechanism


#: Keys of a ``[lubrication]`` table and of its ``[lubrication.joints.<J>]`` tables.
LUBRICATION_KEYS = ("regime", "viscosity", "grade")


def _lubrication(table: _Table) -> tuple[Lubrication | None, dict[str, Lubrication]]:
    """The ``[lubrication]`` table (docs/contact.md, "Lubrication, declared per joint"): its
    ``regime`` and ``viscosity`` (or ISO VG ``grade``), every joint's that declares none, and
    per joint ``[lubrication.joints.<J>]`` (or ``<J> = "dry"``, ``<J> = "oil ISO VG 46"`` in
    ``[lubrication.joints]``)."""
    declares = any(table.has(key) for key in LUBRICATION_KEYS)
    default = _regime(table) if declares else None
    joints: dict[str, Lubrication] = {}
    if table.has("joints"):
        joints_table = table.table("joints")
        for name in joints_table.names():
            value = joints_table.data[name]
            if isinstance(value, str):
                joints[name] = _declared_lubrication(
                    value, None, f"lubrication.joints.{name}", None
                )
            else:
                joints[name] = _regime(joints_table.name_table(name))
        joints_table.finish()
    table.finish()
    return default, joints


def _regime(table: _Table) -> Lubrication:
    """The ``regime`` and ``viscosity`` (or ``grade``) of one lubrication table."""
    viscosity = table.quantity("viscosity", "Pa*s", None)
    grade = table.raw("grade", None)
    return _declared_lubrication(table.text("regime", "oil"), viscosity, table.where, grade)


def _declared_lubrication(
    regime: str, viscosity: float | None, where: str, grade: object
) -> Lubrication:
    """:class:`Lubrication` of ``regime`` (``"oil"``, or with its grade ``"oil ISO VG 46"``),
    ``viscosity`` and ISO VG ``grade`` (text such as ``"ISO VG 46"``), its errors naming
    ``where``."""
    regime, named = split_regime(regime, f"{where}.regime")
    if regime not in REGIMES:
        raise ConfigError(f"{where}: regime must be one of {', '.join(REGIMES)}, got {regime!r}")
    number = None if grade is None else parse_grade(grade, f"{where}.grade")
    if named is not None and number is not None and named != number:
        raise ConfigError(
            f"{where}: the regime names ISO VG {named} and grade ISO VG {number}: give one"
        )
    if number is not None and viscosity is not None:
        raise ConfigError(
            f"{where}: give the lubricant's grade or its viscosity, not both (a grade stands "
            "for its viscosity at 40 °C; a joint at another temperature: its viscosity alone)"
        )
    try:
        return Lubrication(regime, viscosity, named if number is None else number)
    except ConfigError as exc:
        raise ConfigError(f"{where}: {exc}") from None


def _gravity(head: _Table) -> tuple[float, float]:
    value = head.raw("gravity", "off")
    if value in ("off", False, "none"):
        return (0.0, 0.0)
    if value in ("on", True):
        return (0.0, -STANDARD_GRAVITY)
    if isinstance(value, str):
        g = parse_quantity(value, "m/s^2", field="mechanism.gravity")
        return check_gravity((0.0, -abs(g)), "mechanism.gravity", value)
    if isinstance(value, list) and len(value) == 2:
        vector = (
            parse_quantity(value[0], "m/s^2", field="mechanism.gravity[0]"),
            parse_quantity(value[1], "m/s^2", field="mechanism.gravity[1]"),
        )
        return check_gravity(vector, "mechanism.gravity", value)
    raise ConfigError(
        f"mechanism.gravity must be 'off', a magnitude like '9.81 m/s^2' (towards -y) or a "
        f"vector [gx, gy] with units, got {value!r}"
    )


def _material(table: _Table) -> Material:
    material = Material(
        name=table.text("name", "material"),
        density=table.quantity("density", "kg/m^3"),
        youngs_modulus=table.quantity("youngs_modulus", "Pa"),
        poisson_ratio=table.number("poisson_ratio"),
        yield_strength=table.quantity("yield_strength", "Pa", None),
        allowable_contact_pressure=table.quantity("allowable_contact_pressure", "Pa", None),
    )
    table.finish()
    return material


#: How far (m) a joint's ``clearance`` may lie outside its fit's radial clearance range: the
#: round-off of writing the range's ends in µm or mm, far below any fit's micrometres.
FIT_MARGIN = 1e-9


def _fit(table: _Table) -> JointFit:
    fit = JointFit(
        diameter=table.quantity("diameter", "m"),
        fit=table.text("fit", None),
        pin_length=table.quantity("pin_length", "m", None),
        pin_mass=table.quantity("pin_mass", "kg", None),
        clearance=table.quantity("clearance", "m", None),
    )
    table.finish()
    if fit.fit is not None and fit.clearance is not None:
        _check_fit_clearance(fit, table.where)
    return fit


def _check_fit_clearance(joint: JointFit, where: str) -> None:
    """Refuse a ``clearance`` outside the radial clearance of the joint's ``fit`` (a copied
    clearance kept after the fit was changed), naming both: commands that simulate one
    clearance would use it while the tolerance studies use the fit."""
    from jointplay.tolerance import iso286

    assert joint.fit is not None and joint.clearance is not None
    try:
        result = iso286.fit(joint.fit, joint.diameter)
    except JointplayError as exc:
        raise ConfigError(f"{where}: fit {joint.fit!r}: {exc}") from None
    low, high = result.radial_clearance_min, result.radial_clearance_max
    if not low - FIT_MARGIN <= joint.clearance <= high + FIT_MARGIN:
        raise ConfigError(
            f"{where}: clearance = {joint.clearance * 1e6:.4g} µm lies outside the radial "
            f"clearance of its fit {joint.fit} at Ø{joint.diameter * 1e3:g} mm "
            f"({low * 1e6:.4g} … {high * 1e6:.4g} µm); remove the clearance to use the fit's "
            "mean, or give one within the fit's range, or change the fit"
        )


def _parse_template(
    root: _Table,
    template: str,
    name: str,
    material: Material,
    speed: float,
    direction: int,
    start_angle: float,
    gravity: tuple[float, float],
    branch: int,
    tolerances: tuple[LengthTolerance, ...],
) -> Mechanism:
    geometry_table = root.table("geometry")
    if template == "four-bar":
        geometry: FourBarGeometry | SliderCrankGeometry = FourBarGeometry(
            crank=geometry_table.quantity("crank", "m"),
            coupler=geometry_table.quantity("coupler", "m"),
            rocker=geometry_table.quantity("rocker", "m"),
            ground=geometry_table.quantity("ground", "m"),
        )
        link_names = ("crank", "coupler", "rocker")
    else:
        geometry = SliderCrankGeometry(
            crank=geometry_table.quantity("crank", "m"),
            rod=geometry_table.quantity("rod", "m"),
            offset=geometry_table.quantity("offset", "m", 0.0),
        )
        link_names = ("crank", "rod", "slider")
    geometry_table.finish()
    links_table = root.table("links")
    bodies: dict[str, LinkBody] = {}
    coupler_points: dict[str, tuple[float, float]] = {}
    for key in links_table.names():
        if key not in link_names:
            raise ConfigError(f"links: unknown link {key!r}; a {template} has {list(link_names)}")
        entry = links_table.name_table(key)
        bodies[key] = LinkBody(
            mass=entry.quantity("mass", "kg", None),
            width=entry.quantity("width", "m", 0.022),
            thickness=entry.quantity("thickness", "m", 0.010),
            inertia=entry.quantity("inertia", "kg*m^2", None),
        )
        if entry.has("points"):
            if key != link_names[1]:
                raise ConfigError(
                    f"links.{key}.points: extra points are supported on the {link_names[1]}"
                )
            points = entry.table("points")
            for point_name in points.names():
                coupler_points[point_name] = points.point(point_name, points.data[point_name])
            points.finish()
        entry.finish()
    links_table.finish()
    joints_table = root.table("joints")
    fits = {key: _fit(joints_table.name_table(key)) for key in joints_table.names()}
    joints_table.finish()
    builder = four_bar if template == "four-bar" else slider_crank
    return builder(
        geometry,  # type: ignore[arg-type]
        speed=speed,
        bodies=bodies,
        material=material,
        direction=direction,  # type: ignore[arg-type]
        start_angle=start_angle,
        gravity=gravity,
        branch=branch,  # type: ignore[arg-type]
        coupler_points=coupler_points,
        fits=fits,
        tolerances=tolerances,
        name=name,
    )


def _parse_general(
    root: _Table,
    driver_table: _Table,
    name: str,
    material: Material,
    speed: float,
    direction: int,
    start_angle: float,
    gravity: tuple[float, float],
    tolerances: tuple[LengthTolerance, ...],
) -> Mechanism:
    ground_table = root.table("ground")
    ground_points = ground_table.table("points")
    ground = Ground(
        {k: ground_points.point(k, ground_points.data[k]) for k in ground_points.names()}
    )
    ground_points.finish()
    ground_table.finish()
    links_table = root.table("links")
    links = []
    initial_angles = {}
    for key in links_table.names():
        entry = links_table.name_table(key)
        points = entry.table("points")
        link_points = {p: points.point(p, points.data[p]) for p in points.names()}
        points.finish()
        links.append(
            Link(
                name=key,
                points=link_points,
                mass=entry.quantity("mass", "kg"),
                com=entry.point("com"),
                inertia=entry.quantity("inertia", "kg*m^2"),
                material=material.name,
            )
        )
        if entry.has("initial_angle"):
            initial_angles[key] = entry.quantity("initial_angle", "rad")
        entry.finish()
    links_table.finish()
    joint_list = root.raw("joint", [])
    if not isinstance(joint_list, list):
        raise ConfigError("joint must be an array of tables: write each joint as [[joint]]")
    joints: list[RevoluteJoint | PrismaticJoint] = []
    for number, raw in enumerate(joint_list, start=1):
        entry = _Table(raw, f"joint[{number}]")
        joint_name = entry.text("name")
        kind = entry.text("type", "revolute")
        between = entry.raw("between")
        if not (
            isinstance(between, list)
            and len(between) == 2
            and all(isinstance(v, str) for v in between)
        ):
            raise ConfigError(f"joint {joint_name!r}: between must be ['link.point', 'link.point']")
        (link_a, point_a), (link_b, point_b) = (_split_ref(ref, joint_name) for ref in between)
        if kind == "revolute":
            fit = _fit(entry.table("fit")) if entry.has("fit") else None
            joints.append(RevoluteJoint(joint_name, link_a, point_a, link_b, point_b, fit=fit))
        elif kind == "prismatic":
            joints.append(
                PrismaticJoint(
                    joint_name,
                    link_a,
                    point_a,
                    link_b,
                    point_b,
                    axis_angle=entry.quantity("axis_angle", "rad", 0.0),
                    relative_angle=entry.quantity("relative_angle", "rad", 0.0),
                )
            )
        else:
            raise ConfigError(
                f"joint {joint_name!r}: type must be 'revolute' or 'prismatic', got {kind!r}"
            )
        entry.finish()
    driver = Driver(
        link=driver_table.text("link"),
        joint=driver_table.text("joint"),
        speed=speed,
        direction=direction,  # type: ignore[arg-type]
        start_angle=start_angle,
    )
    driver_table.finish()
    return Mechanism(
        name=name,
        ground=ground,
        links=tuple(links),
        joints=tuple(joints),
        driver=driver,
        gravity=gravity,
        materials={material.name: material},
        tolerances=tolerances,
        initial_angles=initial_angles,
    )


def _split_ref(ref: str, joint: str) -> tuple[str, str]:
    if ref.count(".") != 1:
        raise ConfigError(
            f"joint {joint!r}: {ref!r} must read 'link.point' (e.g. 'crank.A' or '{GROUND}.O2')"
        )
    link, point = ref.split(".")
    return link, point


#: Keys of the ``[simulation]`` table (the same names as the ``jointplay simulate`` options):
#: the declared contact and run settings (:mod:`jointplay.dynamics.declared`) and the
#: others of ``simulate``.
SIMULATION_KEYS = (
    *(s.key for s in (*CONTACT_SETTINGS, *RUN_SETTINGS)), "clearance", "joints", "start_angle",
    "sample_deg", "output_step", "format",
)  # fmt: skip


#: Tables of a configuration file that the design and wear studies read (Archard data per
#: joint, the cost–tolerance model).
DESIGN_TABLES = ("wear", "cost")
#: Keys of ``[wear]``, of its ``[wear.joints.<J>]`` tables and of ``[cost]``
#: (:meth:`jointplay.tolerance.cost.CostModel.from_table`; ``it`` and ``iso2768`` are tables
#: of grade and class names).
WEAR_KEYS = ("coefficient", "hardness", "joints")
WEAR_JOINT_KEYS = ("coefficient", "hardness")
COST_KEYS = ("model", "a", "b", "k", "reference", "it", "iso2768")


def design_table_keys(tables: Mapping[str, Any], source: str) -> dict[str, Any]:
    """``[wear]`` and ``[cost]`` tables with their keys in the canonical spelling, checked
    (:func:`option_keys`); joint names, IT grades and class letters are taken as written.

    Args:
        tables: ``{"wear": {...}, "cost": {...}}`` (either may be missing).
        source: where they come from (a file name), for messages.
    """
    out: dict[str, Any] = {}
    for name, table in tables.items():
        where = f"{source}: [{name}]"
        if name == "wear":
            wear = option_keys(table, WEAR_KEYS, where)
            if "joints" in wear:
                joints = wear["joints"]
                if not isinstance(joints, Mapping):
                    raise ConfigError(f"{where} joints must be a table of joint tables")
                wear["joints"] = {
                    joint: option_keys(entry, WEAR_JOINT_KEYS, f"{source}: [wear.joints.{joint}]")
                    for joint, entry in joints.items()
                }
            out[name] = wear
        elif name == "cost":
            out[name] = option_keys(table, COST_KEYS, where)
        else:
            raise ConfigError(
                f"{source}: unknown table [{name}]; expected {', '.join(DESIGN_TABLES)}"
            )
    return out


def design_tables(path: Path | str | None) -> dict[str, Any]:
    """The ``[wear]`` and ``[cost]`` tables of a configuration file (keys checked and in
    their canonical spelling, values raw; empty without)."""
    if path is None:
        return {}
    data = read_toml(path)
    tables = {name: data[name] for name in DESIGN_TABLES if name in data}
    for name, table in tables.items():
        if not isinstance(table, dict):
            raise ConfigError(f"{os.fspath(path)}: [{name}] must be a table, got {table!r}")
    return design_table_keys(tables, os.fspath(path))


def simulation_settings(path: Path | str | None, preset: str | None = None) -> dict[str, Any]:
    """The ``[simulation]`` table of a configuration file, else of the preset (raw values;
    empty without one).

    A preset carries the contact of its source there (``flores-slider-crank``: the published
    dry Lankarani–Nikravesh contact; docs/contact.md, "Presets carry their published
    contact"), which the command line's options override as they override a file's.

    Args:
        path: a configuration file, or ``None``.
        preset: the preset read when ``path`` is ``None`` (default ``paper-fourbar``, as
            :func:`load_mechanism`).
    """
    if path is None:
        name = preset or "paper-fourbar"
        data = tomllib.loads(preset_text(name))
        source = f"preset {name!r}"
    else:
        data = read_toml(path)
        source = os.fspath(path)
    table = _Table(data.get("simulation", {}), f"{source}: [simulation]")
    values = {key: table.raw(key) for key in SIMULATION_KEYS if table.has(key)}
    table.finish()
    for key, value in values.items():
        where = f"{source}: simulation.{key}"
        if key == "settle":
            from jointplay.dynamics.cycles import settle_revolutions  # NumPy: only for one

            settle_revolutions(value, where)
        elif key in _SIMULATION_NUMBERS:
            if isinstance(value, bool) or not isinstance(value, int | float):
                raise ConfigError(f"{where} must be a number, got {value!r}")
            if not math.isfinite(value):
                raise ConfigError(f"{where} must be a finite number, got {value!r}")
        elif key == "joints":
            if not (
                isinstance(value, str)
                or (isinstance(value, list) and all(isinstance(v, str) for v in value))
            ):
                raise ConfigError(
                    f"{where} must be a list of joint names or a string like 'O2,A', got {value!r}"
                )
        elif isinstance(value, bool) or not isinstance(value, str | int | float):
            raise ConfigError(
                f"{where} must be a string (with a unit where it has one), got {value!r}"
            )
    return values


#: Keys of the ``[simulation]`` table that are plain numbers (the others are strings).
_SIMULATION_NUMBERS = tuple(s.key for s in (*CONTACT_SETTINGS, *RUN_SETTINGS) if s.kind is float)
