"""The settings of a run, each declared once (issue 38): the tables
:data:`CONTACT_SETTINGS` and :data:`RUN_SETTINGS` that the edges build themselves from.

A :class:`Setting` names where a setting of
:class:`~jointplay.dynamics.setup.ContactModel` (or of its
:class:`~jointplay.dynamics.setup.ContactSettings` and
:class:`~jointplay.dynamics.setup.FrictionSettings`) lands, and how it is asked for: its key
in a configuration file's ``[simulation]`` table and in the values the readers take, its
command-line option, help text and help panel, its kind (a plain number or text) and the SI
unit of its quantity. From this one table come

- the options of every command that simulates (``simulate``, ``animate``, ``tolerance``,
  ``design``, ``wear``: ``jointplay.cli._simulation.contact_options``);
- the keys of the ``[simulation]`` table and which of them are plain numbers
  (:data:`jointplay.io.config.SIMULATION_KEYS`);
- the options the readers take and refuse with ``--method``
  (:data:`jointplay.settings.simulation.CONTACT_OPTIONS`, ``CONTACT_KEYS``), and how a value
  reaches its record (:func:`jointplay.settings.simulation.contact_model`);
- the option that the command line shows in place of a setting's name in an error
  (``jointplay.cli._simulation.SETTING_OPTIONS``).

:data:`RUN_SETTINGS` declares the settings of
:class:`~jointplay.dynamics.settings.RunSettings` that the options and ``[simulation]`` name
the same way everywhere (``--start``, ``--rtol``, ...): their keys, options, units and panel,
and the help of the commands that share one option (``jointplay.cli._simulation``'s
``RtolOption``, ...; a command whose option reads differently, ``tolerance --start``, gives its
own help).

A new contact option is one entry here and its field on its record in
:mod:`jointplay.dynamics.setup` (docs/contact.md, "Adding a contact option";
``tests/settings/test_new_option.py``). Standard library only: the command line reads this
table before the numerical stack loads.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

__all__ = [
    "CONTACT_PANEL",
    "CONTACT_SETTINGS",
    "RUN_PANEL",
    "RUN_SETTINGS",
    "Setting",
    "offered",
    "run_setting",
    "setting",
    "unit_of",
]

#: The help panels of the contact options and of the run's (:mod:`jointplay.cli._panels`
#: shows their titles).
CONTACT_PANEL = "Contact"
RUN_PANEL = "The dynamic run"

#: The record a setting sets: the paper method's choice (``method``, ``ecs_source``:
#: :func:`jointplay.settings.simulation.method_law_of`), the law and its parameters
#: (:class:`~jointplay.dynamics.setup.ContactSettings`), the friction
#: (:class:`~jointplay.dynamics.setup.FrictionSettings`) or the contact model itself
#: (:class:`~jointplay.dynamics.setup.ContactModel`); the run's settings
#: (:class:`~jointplay.dynamics.settings.RunSettings`), its start
#: (:class:`~jointplay.dynamics.simulate.Start`) or its integrator's
#: (:class:`~jointplay.dynamics.simulate.SolverOptions`).
Owner = Literal["method", "settings", "friction", "model", "run", "start", "solver"]


@dataclass(frozen=True)
class Setting:
    """One contact setting, declared once.

    Attributes:
        key: its key in ``[simulation]`` and in the readers' values (``stiffness_law``).
        option: its command-line option (``--stiffness-law``), which the command line also
            shows in place of ``field`` in an error.
        field: its field on ``owner`` (``c_max`` for ``--cmax``).
        owner: the record it sets (:data:`Owner`).
        help: the option's help text.
        kind: ``float``, a plain number (a TOML number, a number option), ``int``, a whole
            number, or ``str``, text: a name, or a quantity with its unit.
        unit: the SI unit its quantity is read in (``None``: a name or a plain number).
        panel: the help panel of its option.
        offered: the simulating commands offer it as an option (``False``: a
            ``[simulation]`` key only, read by ``simulate`` and ``animate``).
        with_method: it may be given together with ``--method`` (default: unless it is a
            parameter of the law, owner ``settings``, which the method sets itself).
        named: the name the layers below call it by in their errors
            (:class:`~jointplay.errors.SettingError`), where not ``field``.
    """

    key: str
    option: str
    field: str
    owner: Owner
    help: str
    kind: type[float] | type[int] | type[str] = str
    unit: str | None = None
    panel: str = CONTACT_PANEL
    offered: bool = True
    with_method: bool | None = None
    named: str | None = None

    @property
    def allowed_with_method(self) -> bool:
        """It may be given together with ``--method`` (:attr:`with_method`)."""
        return self.owner != "settings" if self.with_method is None else self.with_method

    @property
    def name(self) -> str:
        """The setting's name in the errors of the layers below (``{c_max}``)."""
        return self.named or self.field


# fmt: off
#: Every contact setting, in the order of the commands' help.
CONTACT_SETTINGS: tuple[Setting, ...] = (
    Setting("method", "--method", "method", "method",
            "A method of the paper's Table 2 instead: ifm- or rm- with conventional, "
            "ecs-cylindrical or ecs-spherical."),
    Setting("ecs_source", "--ecs-source", "ecs_source", "method",
            "ECS K, δ, D: computed (default) or paper."),
    Setting("contact", "--contact", "law", "settings",
            "Contact law (docs/contact-laws.md): restitution (default), impact, hertz, ..."),
    Setting("k", "--k", "stiffness", "settings",
            "Stiffness, e.g. '1e4 N/mm^1.5' (default: each joint's, --stiffness-law)."),
    Setting("exponent", "--exponent", "exponent", "settings",
            "Force exponent n (1.5; restitution: 1).", kind=float),
    Setting("cmax", "--cmax", "c_max", "settings",
            "IMPACT maximum damping, e.g. '10 N*s/mm'.", unit="N*s/m"),
    Setting("depth", "--depth", "depth", "settings",
            "IMPACT full-damping depth, e.g. '0.1 mm'.", unit="m"),
    Setting("restitution", "--restitution", "restitution", "settings",
            "Restitution, 0.6-0.95 (default 0.8).", kind=float, with_method=True),
    Setting("damping", "--damping", "damping", "settings",
            "Kelvin-Voigt damping, e.g. '100 N*s/m'.", unit="N*s/m"),
    Setting("stiffness_law", "--stiffness-law", "stiffness_law", "settings",
            "Stiffness: liu (default), hertz, johnson, esdu-78035, pereira, radzimovsky."),
    Setting("fit_depth", "--fit-depth", "fit_depth", "settings",
            "The largest penetration of the stiffness law's power-law fit, e.g. '0.01 mm'.",
            unit="m", offered=False),
    Setting("friction", "--friction", "coefficient", "friction",
            "Friction coefficient (default 0.1, range 0.01-0.2; 0: off; --method: 0).",
            kind=float, named="friction"),
    Setting("friction_law", "--friction-law", "law", "friction",
            "Friction law: ambrosio (regularised Coulomb, default) or adams (STEP mu(v)).",
            named="friction_law"),
    Setting("lubricant_viscosity", "--lubricant-viscosity", "lubricant_viscosity", "model",
            "Lubricant, '0.05 Pa*s' (default); 0: dry.",
            unit="Pa*s"),
    Setting("film_damping", "--film-damping", "film_damping", "model",
            "Or a fixed film damping ('1e4 N*s/m').", unit="N*s/m"),
    Setting("film_model", "--film-model", "film_model", "model",
            "short-bearing-pi (default), -full, linear"),
    Setting("lubrication", "--lubrication", "lubrication", "model",
            "Every joint: dry, oil or grease.", with_method=True),
    Setting("roughness", "--roughness", "roughness", "model",
            "Pin and hole RMS roughness ('1.1 um').", unit="m"),
)
# fmt: on


# fmt: off
#: The run's settings that every command names alike, in the order of the commands' help.
RUN_SETTINGS: tuple[Setting, ...] = (
    Setting("start", "--start", "start", "run",
            "steady (the nominal motion, default), rest (the paper's start-up), impulsive or "
            "ramp (docs/cli.md).", panel=RUN_PANEL),
    Setting("ramp_time", "--ramp-time", "ramp_time", "start",
            "--start ramp: the ramp's duration, e.g. '50 ms'.", unit="s", panel=RUN_PANEL),
    Setting("settle", "--settle", "settle", "run", "Start-up revolutions left out.", kind=int,
            panel=RUN_PANEL),
    Setting("revolutions", "--revolutions", "revolutions", "run", "Analysed revolutions.",
            kind=float, panel=RUN_PANEL),
    Setting("rtol", "--rtol", "rtol", "solver",
            "Integrator's relative tolerance (default 1e-6).", kind=float, panel=RUN_PANEL),
    Setting("integrator", "--integrator", "integrator", "solver",
            "Integrator: radau (Radau IIA, order 5), rodas4 (linearly implicit, order 4) or "
            "dopri5 (explicit, order 5, for soft contact); default radau, rodas4 for the "
            "paper's IFM ECS methods with every joint clear, dopri5 for ifm-conventional "
            "(docs/cli.md).", panel=RUN_PANEL),
    Setting("max_step", "--max-step", "max_step", "solver",
            "Largest integration step, e.g. '1 ms' (default: 1° of crank).", unit="s",
            panel=RUN_PANEL),
    Setting("atol", "--atol", "atol_position", "solver",
            "Integrator's absolute tolerance on positions, e.g. '1e-12 m' (default 1e-10 m; "
            "the velocities' scales with it: docs/cli.md).", unit="m", panel=RUN_PANEL),
    Setting("onset_tolerance", "--onset-tolerance", "onset_tolerance", "solver",
            "Deepest entry into a contact in one step, e.g. '2 nm' (default: 0.01 % of the "
            "smallest clearance; 1 % with impact, hertz, kelvin-voigt: docs/cli.md).", unit="m",
            panel=RUN_PANEL),
)
# fmt: on


def run_setting(key: str) -> Setting:
    """The declared run setting of ``key`` (its ``[simulation]`` key)."""
    for declared in RUN_SETTINGS:
        if declared.key == key:
            return declared
    raise KeyError(f"no run setting {key!r}")


def setting(key: str) -> Setting:
    """The declared contact setting of ``key`` (its ``[simulation]`` key)."""
    for declared in CONTACT_SETTINGS:
        if declared.key == key:
            return declared
    raise KeyError(f"no contact setting {key!r}")


def unit_of(key: str) -> str:
    """The SI unit of the declared contact setting ``key``'s quantity."""
    unit = setting(key).unit
    if unit is None:
        raise KeyError(f"contact setting {key!r} is not a quantity")
    return unit


def offered() -> tuple[Setting, ...]:
    """The contact settings the simulating commands offer as options, in the help's order."""
    return tuple(s for s in CONTACT_SETTINGS if s.offered)
