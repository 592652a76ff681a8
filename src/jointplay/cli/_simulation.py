"""The options and settings shared by the commands that simulate the clearance dynamics
(``simulate`` and ``animate``): one declaration of each option, one reader of each value."""

from __future__ import annotations

import math
from typing import Annotated, Any

import typer

from jointplay.errors import ConfigError


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
        "Contact law: impact (MSC ADAMS IMPACT, default), restitution, hertz, kelvin-voigt, hunt-crossley, lankarani-nikravesh, flores, gonthier, hu-guo, herbert-mcwhannell, lee-wang, zhiying-qishao.",
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
        "Coefficient of restitution (restitution and Hunt-Crossley-type laws; default 0.8).",
        "--restitution",
    ),
]
DampingOption = Annotated[str | None, _opt("Kelvin-Voigt damping, e.g. '100 N*s/m'.", "--damping")]
StiffnessLawOption = Annotated[
    str | None,
    _opt(
        "Derive stiffness and exponent from geometry: hertz, johnson, esdu-78035, pereira, liu, radzimovsky.",
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
    _opt("Friction coefficient in the clearance joints (default 0: off).", "--friction"),
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


def method_law_of(values: dict[str, Any], mechanism: Any) -> tuple[Any, dict[str, Any] | None]:
    """The contact law of ``--method`` (None without one) and its parameter record."""
    from jointplay.study.methods import PAPER_RESTITUTION, method_law

    name = values.get("method")
    if name is None:
        if values.get("ecs_source") is not None:
            raise ConfigError("--ecs-source applies to the paper's ECS methods: give --method too")
        return None, None
    clash = [key for key in CONTACT_KEYS if values.get(key) is not None]
    if clash:
        options = ", ".join("--" + key.replace("_", "-") for key in clash)
        raise ConfigError(
            f"--method sets the contact law and its parameters; drop {options} or drop --method"
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
    value = values.get(key, default)
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
