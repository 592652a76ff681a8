"""The simulation's settings of the command line's options and of the ``[simulation]`` table
(the same keys): :func:`contact_model` turns the contact options into the
:class:`~jointplay.dynamics.setup.ContactModel` the layers below take;
:func:`solver_tolerances` reads the integrator's tolerances; :func:`finite_number`,
:func:`joint_list` and :func:`check_revolutions` read and check the run's values. Read by
the simulating commands and by ``jointplay explore`` alike."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any, TypedDict

from jointplay.dynamics.declared import CONTACT_SETTINGS, RUN_SETTINGS, Setting
from jointplay.errors import ConfigError

if TYPE_CHECKING:  # the dynamics import Numba: loaded when a simulation runs
    from jointplay.dynamics.setup import ContactModel

#: Options that set the contact law (refused together with --method): the declared contact
#: settings (:data:`~jointplay.dynamics.declared.CONTACT_SETTINGS`) a method sets itself.
CONTACT_KEYS = tuple(s.key for s in CONTACT_SETTINGS if s.offered and not s.allowed_with_method)
#: Every contact option, by its key in ``values`` (and in ``[simulation]``).
CONTACT_OPTIONS = tuple(s.key for s in CONTACT_SETTINGS if s.offered)

#: The most crank revolutions simulated (analysed plus start-up) per simulation: a
#: four-bar at 200 rpm runs ~100 revolutions a second on one core, so 10 000 take minutes
#: per simulation and the integrator's step budget runs out beyond.
MAX_REVOLUTIONS = 10_000


def check_revolutions(revolutions: float, settle: int = 0, option: str = "--revolutions") -> None:
    """Refuse revolutions that are not > 0, and revolutions plus ``settle`` beyond
    :data:`MAX_REVOLUTIONS`, naming ``option``."""
    from jointplay.dynamics.cycles import analysed_revolutions, settle_revolutions

    analysed_revolutions(revolutions, option)
    settle_revolutions(settle, "--settle")
    if revolutions + settle > MAX_REVOLUTIONS:
        raise ConfigError(
            f"{option} {revolutions:g}{f' with --settle {settle}' if settle else ''} is more than "
            f"{MAX_REVOLUTIONS} revolutions per simulation; ask for fewer"
        )


def contact_model(
    values: dict[str, Any], mechanism: Any, method_option: str = "--method"
) -> ContactModel:
    """The :class:`~jointplay.dynamics.setup.ContactModel` of the contact options in
    ``values`` (strings with units, ``None`` or absent where not given): the physical default
    without any; ``--method`` one of the paper's six (frictionless and dry unless --friction,
    --lubricant-viscosity, --film-damping)."""
    from jointplay.dynamics.setup import (
        DEFAULT_FRICTION,
        ContactModel,
        FrictionSettings,
        contact_from_strings,
    )

    law, record = method_law_of(values, mechanism, method_option)
    friction = FrictionSettings(
        **_given(values, "friction"),
        law=str(values.get("friction_law") or "ambrosio"),
        coefficient=finite_number(values, "friction", 0.0 if law is not None else DEFAULT_FRICTION),
    )
    model = _given(values, "model")
    if "film_damping" in model and "lubricant_viscosity" in model:
        raise ConfigError(
            "--film-damping fixes the film's damping and --lubricant-viscosity derives it from "
            "the joints' geometry: give one of the two"
        )
    if law is not None:
        return ContactModel(
            friction=friction, law=law, method=str(values["method"]), record=record, **model
        )
    return ContactModel(settings=contact_from_strings(values), friction=friction, **model)


def _given(values: dict[str, Any], owner: str) -> dict[str, Any]:
    """The given values (not ``None``) of the declared contact settings of ``owner``
    (``"model"``, ``"friction"``), by their fields on it; a plain number checked as one
    (:func:`finite_number`), text as it came (the record reads its unit). The friction's
    ``law`` and ``coefficient`` are read by :func:`contact_model` itself."""
    return {
        s.field: finite_number(values, s.key, 0.0) if s.kind is float else values[s.key]
        for s in CONTACT_SETTINGS
        if s.owner == owner
        and values.get(s.key) is not None
        and (owner, s.field) not in (("friction", "law"), ("friction", "coefficient"))
    }


#: The keys that name a contact law (``--method``, ``--contact``) and the law's parameters:
#: a law named on the command line replaces all of these of the ``[simulation]`` table
#: (:func:`over_table`).
LAW_KEYS = (
    "method", "ecs_source", *(s.key for s in CONTACT_SETTINGS if s.owner == "settings"),
)  # fmt: skip
#: The keys that set the stiffness, one way or the other: one given on the command line
#: replaces the others of the table.
STIFFNESS_KEYS = ("k", "stiffness_law", "fit_depth")


def over_table(table: dict[str, Any], given: dict[str, Any]) -> dict[str, Any]:
    """The values of a run: the command line's options ``given`` (``None``: not given) over
    the ``[simulation]`` table ``table`` of the file or preset, key by key, except that a law
    named on the command line (``--method``, ``--contact``) comes with its own parameters:
    the table's law and its parameters (:data:`LAW_KEYS`) are dropped, and a stiffness given
    (``--k``, ``--stiffness-law``) drops the table's other stiffness keys. So
    ``--preset flores-slider-crank --method ifm-conventional`` runs the paper's method, not a
    clash with the preset's published law (docs/contact.md, "Presets carry their published
    contact")."""
    options = {key: value for key, value in given.items() if value is not None}
    dropped: tuple[str, ...] = ()
    if "method" in options or "contact" in options:
        dropped = LAW_KEYS
    elif any(key in options for key in STIFFNESS_KEYS):
        dropped = STIFFNESS_KEYS
    return {**{k: v for k, v in table.items() if k not in dropped}, **options}


def contact_from_options(
    config: Any,
    mechanism: Any,
    method_option: str = "--method",
    *,
    preset: str | None = None,
    **given: Any,
) -> ContactModel:
    """:func:`contact_model` of the contact options ``given`` (``None``: not given) over the
    same keys of the ``[simulation]`` table of the ``config`` file (a path or ``None``: the
    table of ``preset``), as :func:`over_table` merges them; ``method_option``: the name of
    ``method`` on this command."""
    from jointplay.io.config import simulation_settings

    table = simulation_settings(config, preset)
    unknown = set(given) - set(CONTACT_OPTIONS)
    if unknown:
        raise TypeError(f"not contact options: {sorted(unknown)}")
    values = over_table({key: table[key] for key in CONTACT_OPTIONS if key in table}, given)
    return contact_model(values, mechanism, method_option)


def method_law_of(
    values: dict[str, Any], mechanism: Any, method_option: str = "--method"
) -> tuple[Any, dict[str, Any] | None]:
    """The contact law of ``--method`` (None without one) and its parameter record;
    ``method_option``: the option's name on this command, for messages."""
    from jointplay.study.methods import PAPER_RESTITUTION, method_law

    name = values.get("method")
    if name is None:
        if values.get("ecs_source") is not None:
            raise ConfigError(
                f"--ecs-source applies to the paper's ECS methods: give {method_option} too"
            )
        return None, None
    clash = [key for key in CONTACT_KEYS if values.get(key) is not None]
    if clash:
        options = ", ".join(_option(key) for key in clash)
        raise ConfigError(
            f"{method_option} sets the contact law and its parameters; drop {options} or drop "
            f"{method_option}"
        )
    restitution = values.get("restitution")
    return method_law(
        str(name),
        mechanism,
        ecs_source=str(values.get("ecs_source", "computed")),
        restitution=PAPER_RESTITUTION
        if restitution is None
        else finite_number(values, "restitution", 0.0),
    )


#: The integrator's absolute tolerance on velocities per unit of its tolerance on positions,
#: 1/s: ``--atol`` sets the position tolerance and the velocity tolerance at this ratio, that
#: of :class:`~jointplay.dynamics.simulate.SolverOptions`' defaults (1e-6 m/s over 1e-10 m),
#: so that one option tightens both alike (docs/cli.md, "Tolerances").
ATOL_VELOCITY_PER_POSITION = 1e4
#: The largest ``--atol``: a position tolerance of a micrometre already spans the smaller
#: clearances (MIN_CLEARANCE of the joints), and the contact would not be resolved.
LARGEST_ATOL = 1e-6


class SolverTolerances(TypedDict, total=False):
    """The tolerances :func:`solver_tolerances` reads, by their
    :class:`~jointplay.dynamics.simulate.SolverOptions` fields (m, m/s, m)."""

    atol_position: float
    atol_velocity: float
    onset_tolerance: float


def solver_tolerances(values: dict[str, Any]) -> SolverTolerances:
    """The integrator's tolerances that ``values`` give (options over ``[simulation]``), as
    :class:`~jointplay.dynamics.simulate.SolverOptions` fields in SI: ``atol`` (a length,
    ``"1e-12 m"``) as ``atol_position`` and ``atol_velocity`` (at
    :data:`ATOL_VELOCITY_PER_POSITION`), ``onset_tolerance`` (a length, ``"2 nm"``). Checked
    here, before the numerical stack loads: each > 0, ``atol`` at most :data:`LARGEST_ATOL`
    (the onset tolerance against the clearances where the joints are built:
    :func:`jointplay.dynamics.system.check_onset_tolerance`)."""
    from jointplay.units import parse_quantity

    out = SolverTolerances()
    if values.get("atol") is not None:
        atol = parse_quantity(values["atol"], "m", field=_option("atol"))
        if not 0.0 < atol <= LARGEST_ATOL:
            raise ConfigError(
                f"{_option('atol')} must be a length > 0 and at most {LARGEST_ATOL * 1e6:g} um, "
                f"e.g. '1e-12 m' (default 1e-10 m), got {values['atol']!r}"
            )
        out["atol_position"] = atol
        out["atol_velocity"] = atol * ATOL_VELOCITY_PER_POSITION
    if values.get("onset_tolerance") is not None:
        onset = parse_quantity(values["onset_tolerance"], "m", field=_option("onset_tolerance"))
        if not onset > 0.0:
            raise ConfigError(
                f"{_option('onset_tolerance')} must be a length > 0 below the smallest "
                f"clearance, e.g. '2 nm', got {values['onset_tolerance']!r}"
            )
        out["onset_tolerance"] = onset
    return out


def finite_number(values: dict[str, Any], key: str, default: float) -> float:
    """``values[key]`` (a CLI option or a ``[simulation]`` entry) as a finite float."""
    value = values.get(key)
    value = default if value is None else value
    option = _option(key)
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise ConfigError(f"{option} must be a number, got {value!r}")
    if not math.isfinite(value):
        raise ConfigError(f"{option} must be a finite number, got {value!r}")
    return float(value)


def _option(key: str) -> str:
    """The option of ``key`` (a ``[simulation]`` key): a contact setting's declared one, else
    the key's own spelling (``max_step``: ``--max-step``)."""
    declared: Setting | None = next(
        (s for s in (*CONTACT_SETTINGS, *RUN_SETTINGS) if s.key == key), None
    )
    return "--" + key.replace("_", "-") if declared is None else declared.option


def joint_list(value: Any) -> list[str] | None:
    """``--joints`` (or ``[simulation] joints``) as a list of joint names (None: not given)."""
    if value is None:
        return None
    names = value if isinstance(value, list) else str(value).split(",")
    names = [str(n).strip() for n in names if str(n).strip()]
    if not names:
        raise ConfigError("--joints is empty; give e.g. O2,A,B,O4")
    return names
