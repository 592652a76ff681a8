"""The contact settings of a run, each declared once (issue 38): the table
:data:`CONTACT_SETTINGS` that the edges build themselves from.

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

A new contact option is one entry here and its field on its record in
:mod:`jointplay.dynamics.setup` (docs/contact.md, "Adding a contact option";
``tests/settings/test_new_option.py``). Standard library only: the command line reads this
table before the numerical stack loads.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

__all__ = ["CONTACT_PANEL", "CONTACT_SETTINGS", "Setting", "offered", "setting"]

#: The help panel of the contact options (:mod:`jointplay.cli._panels` shows its title).
CONTACT_PANEL = "Contact"

#: The record a setting sets: the paper method's choice (``method``, ``ecs_source``:
#: :func:`jointplay.settings.simulation.method_law_of`), the law and its parameters
#: (:class:`~jointplay.dynamics.setup.ContactSettings`), the friction
#: (:class:`~jointplay.dynamics.setup.FrictionSettings`) or the contact model itself
#: (:class:`~jointplay.dynamics.setup.ContactModel`).
Owner = Literal["method", "settings", "friction", "model"]


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
        kind: ``float``, a plain number (a TOML number, a number option), or ``str``, text: a
            name, or a quantity with its unit.
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
    kind: type[float] | type[str] = str
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
            "Each joint's stiffness from its radii and materials: liu (default), hertz, "
            "johnson, esdu-78035, pereira, radzimovsky."),
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
            "Lubricant, '0.05 Pa*s' (default; sets each joint's film damping); 0: dry.",
            unit="Pa*s"),
    Setting("film_damping", "--film-damping", "film_damping", "model",
            "Or a fixed film damping ('1e4 N*s/m').", unit="N*s/m"),
)
# fmt: on


def setting(key: str) -> Setting:
    """The declared contact setting of ``key`` (its ``[simulation]`` key)."""
    for declared in CONTACT_SETTINGS:
        if declared.key == key:
            return declared
    raise KeyError(f"no contact setting {key!r}")


def offered() -> tuple[Setting, ...]:
    """The contact settings the simulating commands offer as options, in the help's order."""
    return tuple(s for s in CONTACT_SETTINGS if s.offered)
