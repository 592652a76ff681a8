"""The options and settings shared by the commands that simulate the clearance dynamics
(``simulate``, ``animate``, ``tolerance``, ``design``, ``wear``, ``calibrate``, ``compare``):
one declaration of each option, one reader of each value. :func:`contact_model` turns the
contact options (or the ``[simulation]`` keys of the same names) into the
:class:`~jointplay.dynamics.setup.ContactModel` the layers below take."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Annotated, Any

import typer

from jointplay.errors import ConfigError

if TYPE_CHECKING:  # the dynamics import Numba: loaded when a command runs
    from jointplay.dynamics.setup import ContactModel


def _opt(help_text: str, *names: str) -> Any:
    return typer.Option(*names, help=help_text)


MethodOption = Annotated[
    str | None,
    _opt(
        "One of the paper's six methods (Table 2): ifm-conventional, rm-conventional, ifm-ecs-cylindrical, rm-ecs-cylindrical, ifm-ecs-spherical, rm-ecs-spherical. Replaces the contact options.",
        "--method",
    ),
]
EcsSourceOption = Annotated[
    str | None,
    _opt(
        "Where the ECS methods take K, delta, D from: computed (our ECS estimate, default) or paper (Tables 4 and 5).",
        "--ecs-source",
    ),
]
ContactOption = Annotated[
    str | None,
    _opt(
        "Contact law: restitution (Hunt-Crossley damping with exactly --restitution, default), impact (MSC ADAMS IMPACT), hertz, kelvin-voigt, hunt-crossley, lankarani-nikravesh, flores, gonthier, hu-guo, herbert-mcwhannell, lee-wang, zhiying-qishao. Without --k the stiffness comes from each joint's geometry (--stiffness-law; impact: 1e4 N/mm^1.5).",
        "--contact",
    ),
]
StiffnessOption = Annotated[
    str | None,
    _opt(
        "Contact stiffness with units, e.g. '1e4 N/mm^1.5' (the penalty for restitution).",
        "--k",
    ),
]
ExponentOption = Annotated[
    float | None, _opt("Force exponent (default 1.5; 1 for restitution).", "--exponent")
]
CmaxOption = Annotated[str | None, _opt("IMPACT maximum damping, e.g. '10 N*s/mm'.", "--cmax")]
DepthOption = Annotated[
    str | None, _opt("IMPACT penetration of full damping, e.g. '0.1 mm'.", "--depth")
]
RestitutionOption = Annotated[
    float | None,
    _opt(
        "Coefficient of restitution (restitution and Hunt-Crossley-type laws; default 0.8, documented range 0.6-0.95).",
        "--restitution",
    ),
]
DampingOption = Annotated[str | None, _opt("Kelvin-Voigt damping, e.g. '100 N*s/m'.", "--damping")]
StiffnessLawOption = Annotated[
    str | None,
    _opt(
        "Pin-in-hole law that gives each joint's stiffness and exponent from its radii and materials: liu (default), hertz, johnson, esdu-78035, pereira, radzimovsky.",
        "--stiffness-law",
    ),
]
ClearanceOption = Annotated[
    str | None,
    _opt(
        "Radial clearance of every clearance joint, e.g. '0.021 mm' (default: from the joints' fit data).",
        "--clearance",
    ),
]
JointsOption = Annotated[
    str | None,
    _opt(
        "Comma-separated clearance joints, e.g. O2,A,B,O4 (default: every joint with a clearance in its fit data).",
        "--joints",
    ),
]
FrictionOption = Annotated[
    float | None,
    _opt(
        "Friction coefficient in the clearance joints (default 0.1, documented range 0.01-0.2; 0: off; with --method: 0).",
        "--friction",
    ),
]
FrictionLawOption = Annotated[
    str | None,
    _opt(
        "Friction law: ambrosio (regularised Coulomb, default) or adams (STEP-based mu(v)).",
        "--friction-law",
    ),
]
StartOption = Annotated[
    str | None,
    _opt(
        "Start: steady (the nominal motion, default: the mechanism as it runs), rest (the paper's start-up: links at rest, the crank turning about its pivot at full speed), impulsive (rest velocities projected onto the driver: the crank first spins about its centre of mass) or ramp (speed ramp from rest).",
        "--start",
    ),
]
RampTimeOption = Annotated[
    str | None,
    _opt("Duration of the speed ramp for --start ramp, e.g. '50 ms'.", "--ramp-time"),
]
RtolOption = Annotated[
    float | None, _opt("Relative error tolerance of the integrator (default 1e-6).", "--rtol")
]

#: Options that set the contact law (refused together with --method).
CONTACT_KEYS = ("contact", "k", "exponent", "cmax", "depth", "damping", "stiffness_law")
#: Every contact option, by its key in ``values`` (and in ``[simulation]``).
CONTACT_OPTIONS = (*CONTACT_KEYS, "restitution", "friction", "friction_law", "method", "ecs_source")
#: The option of each setting that the layers below name in their errors
#: (:class:`~jointplay.errors.SettingError`): the command line shows these names.
SETTING_OPTIONS = {
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
}


def contact_model(
    values: dict[str, Any], mechanism: Any, method_option: str = "--method"
) -> ContactModel:
    """The :class:`~jointplay.dynamics.setup.ContactModel` of the contact options in
    ``values`` (strings with units, ``None`` or absent where not given): the physical default
    without any; ``--method`` one of the paper's six (frictionless unless --friction)."""
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
    if law is not None:
        return ContactModel(friction=friction, law=law, method=str(values["method"]), record=record)
    return ContactModel(settings=contact_from_strings(values), friction=friction)


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
