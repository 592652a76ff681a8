"""The options and settings shared by the commands that simulate the clearance dynamics
(``simulate``, ``animate``, ``tolerance``, ``design``, ``wear``, ``calibrate``, ``compare``):
one declaration of each option, and the :class:`~jointplay.dynamics.settings.RunSettings` of
their values. The values are read by :mod:`jointplay.settings.simulation` (the contact model
of the contact options, or of the ``[simulation]`` keys of the same names), which
``jointplay explore`` reads them with too."""

from __future__ import annotations

from typing import TYPE_CHECKING, Annotated, Any

import typer

from jointplay.cli._panels import CONTACT_PANEL, RUN_PANEL
from jointplay.settings.simulation import finite_number

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
