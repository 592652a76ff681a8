"""The options and settings shared by the commands that simulate the clearance dynamics
(``simulate``, ``animate``, ``tolerance``, ``design``, ``wear``, ``calibrate``, ``compare``):
one declaration of each option, one reader of each value. :func:`contact_model` turns the
contact options (or the ``[simulation]`` keys of the same names) into the
:class:`~jointplay.dynamics.setup.ContactModel` the layers below take."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Annotated, Any

import typer

from jointplay.cli._app import CONTACT_PANEL, RUN_PANEL
from jointplay.errors import ConfigError

if TYPE_CHECKING:  # the dynamics import Numba: loaded when a command runs
    from jointplay.dynamics.settings import RunSettings
    from jointplay.dynamics.setup import ContactModel


def _opt(help_text: str, *names: str, panel: str = CONTACT_PANEL) -> Any:
    """A contact option (in the help's "Contact" panel unless ``panel``)."""
    return typer.Option(*names, help=help_text, rich_help_panel=panel)


MethodOption = Annotated[
    str | None,
    _opt(
        "A method of the paper's Table 2 instead: ifm- or rm- with conventional, ecs-cylindrical or ecs-spherical.",
        "--method",
    ),
]
EcsSourceOption = Annotated[
    str | None,
    _opt(
        "ECS K, δ, D: computed (default) or paper.",
        "--ecs-source",
    ),
]
ContactOption = Annotated[
    str | None,
    _opt(
        "Contact law (docs/contact-laws.md): restitution (default), impact, hertz, ...",
        "--contact",
    ),
]
StiffnessOption = Annotated[
    str | None,
    _opt(
        "Stiffness, e.g. '1e4 N/mm^1.5' (default: each joint's, --stiffness-law).",
        "--k",
    ),
]
ExponentOption = Annotated[
    float | None, _opt("Force exponent n (1.5; restitution: 1).", "--exponent")
]
CmaxOption = Annotated[str | None, _opt("IMPACT maximum damping, e.g. '10 N*s/mm'.", "--cmax")]
DepthOption = Annotated[str | None, _opt("IMPACT full-damping depth, e.g. '0.1 mm'.", "--depth")]
RestitutionOption = Annotated[
    float | None,
    _opt(
        "Restitution, 0.6-0.95 (default 0.8).",
        "--restitution",
    ),
]
DampingOption = Annotated[str | None, _opt("Kelvin-Voigt damping, e.g. '100 N*s/m'.", "--damping")]
StiffnessLawOption = Annotated[
    str | None,
    _opt(
        "Each joint's stiffness from its radii and materials: liu (default), hertz, johnson, esdu-78035, pereira, radzimovsky.",
        "--stiffness-law",
    ),
]
ClearanceOption = Annotated[
    str | None,
    _opt(
        "Radial clearance of every clearance joint, e.g. '0.021 mm' (default: from the fits).",
        "--clearance",
    ),
]
JointsOption = Annotated[
    str | None,
    _opt(
        "Clearance joints, e.g. O2,A,B,O4 (default: every joint with a fit).",
        "--joints",
    ),
]
FrictionOption = Annotated[
    float | None,
    _opt(
        "Friction coefficient (default 0.1, range 0.01-0.2; 0: off; --method: 0).",
        "--friction",
    ),
]
ViscosityOption = Annotated[
    str | None,
    _opt(
        "Lubricant, '0.05 Pa*s' (default; sets each joint's film damping); 0: dry.",
        "--lubricant-viscosity",
    ),
]
FilmDampingOption = Annotated[
    str | None,
    _opt(
        "Or a fixed film damping ('1e4 N*s/m').",
        "--film-damping",
    ),
]
FrictionLawOption = Annotated[
    str | None,
    _opt(
        "Friction law: ambrosio (regularised Coulomb, default) or adams (STEP mu(v)).",
        "--friction-law",
    ),
]
StartOption = Annotated[
    str | None,
    _opt(
        "steady (the nominal motion, default), rest (the paper's start-up), impulsive or ramp (docs/cli.md).",
        "--start",
        panel=RUN_PANEL,
    ),
]
RampTimeOption = Annotated[
    str | None,
    _opt("--start ramp: the ramp's duration, e.g. '50 ms'.", "--ramp-time", panel=RUN_PANEL),
]
RtolOption = Annotated[
    float | None, _opt("Integrator's relative tolerance (default 1e-6).", "--rtol", panel=RUN_PANEL)
]
IntegratorOption = Annotated[
    str | None,
    _opt(
        "Integrator: radau (Radau IIA, order 5), rodas4 (linearly implicit, order 4) or dopri5"
        " (explicit, order 5, for soft contact); default radau, rodas4 for the paper's IFM ECS"
        " methods with every joint clear, dopri5 for ifm-conventional (docs/cli.md).",
        "--integrator",
        panel=RUN_PANEL,
    ),
]

#: Options that set the contact law (refused together with --method).
CONTACT_KEYS = ("contact", "k", "exponent", "cmax", "depth", "damping", "stiffness_law")
#: Every contact option, by its key in ``values`` (and in ``[simulation]``).
CONTACT_OPTIONS = (
    *CONTACT_KEYS, "restitution", "friction", "friction_law", "lubricant_viscosity", "film_damping",
    "method", "ecs_source",
)  # fmt: skip
#: The option of each setting that the layers below name in their errors
#: (:class:`~jointplay.errors.SettingError`) and in the diagnostics' advice
#: (:meth:`~jointplay.dynamics.diagnostics.Diagnostic.named`): the command line shows these
#: names.
SETTING_OPTIONS = {
    "start": "--start",
    "settle": "--settle",
    "revolutions": "--revolutions",
    "rtol": "--rtol",
    "integrator": "--integrator",
    "max_samples": "--max-samples",
    "law": "--contact",
    "stiffness": "--k",
    "exponent": "--exponent",
    "c_max": "--cmax",
    "depth": "--depth",
    "restitution": "--restitution",
    "damping": "--damping",
    "stiffness_law": "--stiffness-law",
    "fit_depth": "--fit-depth",
    "friction": "--friction",
    "friction_law": "--friction-law",
    "film_damping": "--film-damping",
    "lubricant_viscosity": "--lubricant-viscosity",
    "joints": "--joints",
    "clearance": "--clearance",
    "output folder": "--out",
    "force=True": "--force",
    "format": "--format",
    "ecs_source": "--ecs-source",
    "fit": "--fit",
    "responses": "--responses",
    "output_step": "--output-step",
    "sample_deg": "--sample-deg",
    "max_step": "--max-step",
    "wear_coefficient": "--wear-coefficient",
    "hardness": "--hardness",
    "speed_column": "--speed-column",
    "angle_column": "--angle-column",
    "fps": "--fps",
    "frames": "--frames",
    "magnification": "--magnification",
    "size": "--size",
}


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
        law=str(values.get("friction_law") or "ambrosio"),
        coefficient=finite_number(values, "friction", 0.0 if law is not None else DEFAULT_FRICTION),
    )
    film, viscosity = values.get("film_damping"), values.get("lubricant_viscosity")
    if film is not None and viscosity is not None:
        raise ConfigError(
            "--film-damping fixes the film's damping and --lubricant-viscosity derives it from "
            "the joints' geometry: give one of the two"
        )
    if law is not None:
        return ContactModel(
            friction=friction, law=law, method=str(values["method"]), record=record,
            film_damping=film, lubricant_viscosity=viscosity,
        )  # fmt: skip
    return ContactModel(
        settings=contact_from_strings(values), friction=friction, film_damping=film,
        lubricant_viscosity=viscosity,
    )  # fmt: skip


def run_settings(
    contact: ContactModel,
    *,
    start: str | None = None,
    ramp_time: float = 0.0,
    settle: int | None = None,
    revolutions: float | None = None,
    rtol: float | None = None,
) -> RunSettings:
    """The :class:`~jointplay.dynamics.settings.RunSettings` of a simulating command, built
    once from its options (``None``: not given, the default): the contact of
    :func:`contact_from_options`, ``--start`` (and ``--ramp-time``, s), ``--settle``,
    ``--revolutions`` and ``--rtol``. Its checks raise SettingErrors that name settings;
    the command line shows their options (:data:`SETTING_OPTIONS`)."""
    from jointplay.dynamics.settings import RunSettings
    from jointplay.dynamics.simulate import SolverOptions, Start

    return RunSettings.of(
        contact=contact,
        start=None if start is None else Start(start, ramp_time),  # type: ignore[arg-type]
        settle=settle,
        revolutions=revolutions,
        solver=None if rtol is None else SolverOptions(rtol=rtol),
    )


def run_settings_of(
    values: dict[str, Any],
    mechanism: Any,
    contact: ContactModel,
    *,
    revolutions: float = 1.0,
    settle: int | None = None,
    max_step: bool = False,
) -> RunSettings:
    """:func:`run_settings` of the run options in ``values`` (options over the
    ``[simulation]`` table): ``start`` (default steady), ``ramp_time`` (default a quarter of
    the crank period with the ramp start), ``settle`` (default ``settle``, else 2 with the
    steady start and 0 with the others, whose start-up is what they show), ``rtol``,
    ``integrator`` and, with ``max_step``, ``max_step``; the one reader of simulate's and
    animate's."""
    from jointplay.dynamics.cycles import DEFAULT_SETTLE
    from jointplay.dynamics.settings import RunSettings
    from jointplay.dynamics.simulate import SolverOptions, Start
    from jointplay.units import parse_quantity

    mode = str(values.get("start", "steady"))
    ramp = (
        0.0
        if values.get("ramp_time") is None
        else parse_quantity(values["ramp_time"], "s", field="--ramp-time")
    )
    if mode == "ramp" and ramp == 0.0:
        ramp = mechanism.driver.period / 4
    solver = SolverOptions(
        rtol=finite_number(values, "rtol", 1e-6),
        max_step=None
        if not max_step or values.get("max_step") is None
        else parse_quantity(values["max_step"], "s", field="--max-step"),
        integrator=values.get("integrator"),
    )
    default = settle if settle is not None else DEFAULT_SETTLE if mode == "steady" else 0
    return RunSettings(
        contact=contact,
        start=Start(mode, ramp),  # type: ignore[arg-type]  # validated by Start
        settle=values.get("settle", default),
        revolutions=revolutions,
        solver=solver,
    )


def contact_from_options(
    config: Any, mechanism: Any, method_option: str = "--method", **given: Any
) -> ContactModel:
    """:func:`contact_model` of the contact options ``given`` (``None``: not given) over the
    same keys of the ``[simulation]`` table of the ``config`` file (a path or ``None``);
    ``method_option``: the name of ``method`` on this command."""
    from jointplay.io.config import simulation_settings

    table = simulation_settings(config)
    unknown = set(given) - set(CONTACT_OPTIONS)
    if unknown:
        raise TypeError(f"not contact options: {sorted(unknown)}")
    values = {key: table[key] for key in CONTACT_OPTIONS if key in table}
    values.update({key: value for key, value in given.items() if value is not None})
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
        options = ", ".join("--" + key.replace("_", "-") for key in clash)
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


def finite_number(values: dict[str, Any], key: str, default: float) -> float:
    """``values[key]`` (a CLI option or a ``[simulation]`` entry) as a finite float."""
    value = values.get(key)
    value = default if value is None else value
    option = "--" + key.replace("_", "-")
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise ConfigError(f"{option} must be a number, got {value!r}")
    if not math.isfinite(value):
        raise ConfigError(f"{option} must be a finite number, got {value!r}")
    return float(value)


def joint_list(value: Any) -> list[str] | None:
    """``--joints`` (or ``[simulation] joints``) as a list of joint names (None: not given)."""
    if value is None:
        return None
    names = value if isinstance(value, list) else str(value).split(",")
    names = [str(n).strip() for n in names if str(n).strip()]
    if not names:
        raise ConfigError("--joints is empty; give e.g. O2,A,B,O4")
    return names
