"""The options and settings shared by the commands that simulate the clearance dynamics
(``simulate``, ``animate``, ``tolerance``, ``design``, ``wear``, ``calibrate``, ``compare``):
one declaration of each option, and the :class:`~jointplay.dynamics.settings.RunSettings` of
their values. The contact options are built from their declarations
(:data:`~jointplay.dynamics.declared.CONTACT_SETTINGS`) by :func:`with_contact_options`. The
values are read by :mod:`jointplay.settings.simulation` (the contact model of the contact
options, or of the ``[simulation]`` keys of the same names), which ``jointplay explore``
reads them with too."""

from __future__ import annotations

import dataclasses
import functools
import inspect
from collections.abc import Callable, Mapping
from types import MappingProxyType
from typing import TYPE_CHECKING, Annotated, Any, TypeVar

import typer

from jointplay.cli._panels import CONTACT_PANEL
from jointplay.dynamics.declared import CONTACT_SETTINGS, RUN_SETTINGS, Setting, run_setting
from jointplay.settings.simulation import finite_number, solver_tolerances

if TYPE_CHECKING:  # the dynamics import Numba: loaded when a command runs
    from jointplay.dynamics.settings import RunSettings
    from jointplay.dynamics.setup import ContactModel

Command = TypeVar("Command", bound=Callable[..., Any])

#: The values of a command's contact options (:func:`with_contact_options`): each offered
#: setting's ``[simulation]`` key and the option's value, ``None`` where not given.
ContactValues = Mapping[str, Any]
#: The default of a command's ``contact_options`` parameter (always given when it runs).
NO_CONTACT_OPTIONS: ContactValues = MappingProxyType({})


def with_contact_options(
    *, renamed: Mapping[str, tuple[str, str]] | None = None
) -> Callable[[Command], Command]:
    """A command's contact options, built from their declarations
    (:data:`~jointplay.dynamics.declared.CONTACT_SETTINGS`, those ``offered``): the decorated
    function's parameter ``contact_options`` stands for them in its signature, which Typer
    reads, and receives their values (:data:`ContactValues`). ``renamed``: a setting's key to
    the option and help it has on this command (``tolerance``'s ``--paper-method``: its
    ``--method`` is the tolerance method). Each option keeps its declared kind (a number or
    text), help and panel; all are keyword parameters."""
    renamed = dict(renamed or {})

    def decorate(command: Command) -> Command:
        signature = inspect.signature(command, eval_str=True)
        names = list(signature.parameters)
        if "contact_options" not in names:
            raise TypeError(f"{command.__name__} has no parameter contact_options")
        built: dict[str, inspect.Parameter] = {}
        keys: dict[str, str] = {}  # parameter name -> setting key
        for declared in (s for s in CONTACT_SETTINGS if s.offered):
            option, help_text = renamed.pop(declared.key, (declared.option, declared.help))
            name = option.lstrip("-").replace("-", "_")
            if name in names or name in built:
                raise TypeError(f"{command.__name__}: {option} is already a parameter")
            option_info = declared_option(
                dataclasses.replace(declared, option=option, help=help_text)
            )
            built[name] = inspect.Parameter(
                name,
                inspect.Parameter.KEYWORD_ONLY,
                default=None,
                annotation=Annotated[declared.kind | None, option_info],
            )
            keys[name] = declared.key
        if renamed:
            raise TypeError(f"not contact settings: {sorted(renamed)}")
        parameters: list[inspect.Parameter] = []
        for parameter in signature.parameters.values():
            if parameter.name == "contact_options":
                parameters.extend(built.values())
            else:  # keyword parameters: no order of defaults to keep
                parameters.append(parameter.replace(kind=inspect.Parameter.KEYWORD_ONLY))

        @functools.wraps(command)
        def with_options(**given: Any) -> Any:
            values = {key: given.pop(name) for name, key in keys.items()}
            return command(**given, contact_options=values)

        with_options.__signature__ = signature.replace(parameters=parameters)  # type: ignore[attr-defined]
        with_options.__annotations__ = {
            name: hint
            for name, hint in command.__annotations__.items()
            if name != "contact_options"
        }
        return with_options  # type: ignore[return-value]

    return decorate


def _opt(help_text: str, *names: str, panel: str = CONTACT_PANEL) -> Any:
    """A contact option (in the help's "Contact" panel unless ``panel``)."""
    return typer.Option(*names, help=help_text, rich_help_panel=panel)


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


def declared_option(declared: Setting, **click: Any) -> Any:
    """The Typer option of a declared setting (:mod:`jointplay.dynamics.declared`): its
    option, help and panel (``click``: Click's own settings, e.g. ``min``)."""
    return typer.Option(
        declared.option, help=declared.help, rich_help_panel=declared.panel, **click
    )


StartOption = Annotated[str | None, declared_option(run_setting("start"))]
RampTimeOption = Annotated[str | None, declared_option(run_setting("ramp_time"))]
RtolOption = Annotated[float | None, declared_option(run_setting("rtol"))]
IntegratorOption = Annotated[str | None, declared_option(run_setting("integrator"))]
MaxStepOption = Annotated[str | None, declared_option(run_setting("max_step"))]
AtolOption = Annotated[str | None, declared_option(run_setting("atol"))]
OnsetToleranceOption = Annotated[str | None, declared_option(run_setting("onset_tolerance"))]

#: The option of each setting that the layers below name in their errors
#: (:class:`~jointplay.errors.SettingError`) and in the diagnostics' advice
#: (:meth:`~jointplay.dynamics.diagnostics.Diagnostic.named`): the command line shows these
#: names.
SETTING_OPTIONS = {
    **{declared.name: declared.option for declared in (*CONTACT_SETTINGS, *RUN_SETTINGS)},
    "max_samples": "--max-samples",
    "joints": "--joints",
    "clearance": "--clearance",
    "output folder": "--out",
    "force=True": "--force",
    "format": "--format",
    "fit": "--fit",
    "responses": "--responses",
    "output_step": "--output-step",
    "sample_deg": "--sample-deg",
    "wear_coefficient": "--wear-coefficient",
    "hardness": "--hardness",
    "speed_column": "--speed-column",
    "angle_column": "--angle-column",
    "fps": "--fps",
    "frames": "--frames",
    "magnification": "--magnification",
    "size": "--size",
}


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
    :func:`~jointplay.settings.simulation.contact_from_options`, ``--start`` (and
    ``--ramp-time``, s), ``--settle``, ``--revolutions`` and ``--rtol``. Its checks raise SettingErrors that name settings;
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
    ``atol`` and ``onset_tolerance`` (:func:`~jointplay.settings.simulation.solver_tolerances`),
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
        **solver_tolerances(values),
    )
    default = settle if settle is not None else DEFAULT_SETTLE if mode == "steady" else 0
    return RunSettings(
        contact=contact,
        start=Start(mode, ramp),  # type: ignore[arg-type]  # validated by Start
        settle=values.get("settle", default),
        revolutions=revolutions,
        solver=solver,
    )
