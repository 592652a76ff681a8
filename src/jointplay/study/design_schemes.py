"""The design study's candidates: the schemes (a fit per joint and a length class), their
drawing callouts, the requirements and the responses they need, and the rounds of samples
(part of :mod:`jointplay.study.design`, which re-exports them)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any, Literal

from jointplay.errors import ConfigError, SettingError
from jointplay.model.mechanism import Mechanism, RevoluteJoint
from jointplay.study.requirements import Requirement, parse_requirement
from jointplay.tolerance import iso286, iso2768
from jointplay.tolerance.cost import CostModel, fit_cost, length_class_cost
from jointplay.tolerance.parts import Process, fit_features
from jointplay.tolerance.responses import RUNNING_RESPONSES, kinematic_model
from jointplay.tolerance.spec import (
    InputTolerance,
    JointTolerance,
    LinkTolerance,
    ToleranceSpec,
    in_template_order,
    template_lengths,
)

#: Default confidence level: ±3σ of a normal response, 99.73 %.
DEFAULT_CONFIDENCE = 0.9973

#: Responses the design study adds to the tolerance study's dynamic peaks, with SI units: the
#: running responses and the life (computed per scheme from the wear rate).
DERIVED_RESPONSES: Mapping[str, str] = {**RUNNING_RESPONSES, "life": "s"}


@dataclass(frozen=True)
class Callout:
    """One feature's line on the drawing.

    Attributes:
        feature: e.g. ``"joint O2 hole"``, ``"length crank"``.
        nominal: nominal size, m.
        lower, upper: limits of size, m.
        designation: ``"H8"``, ``"f7"`` or ``"ISO 2768-m"``.
        diameter: a diameter (``Ø``) rather than a length.
    """

    feature: str
    nominal: float
    lower: float
    upper: float
    designation: str
    diameter: bool = False

    @property
    def text(self) -> str:
        """The callout in mm, e.g. ``"joint A hole Ø10 H8 = 10.000/10.022 mm"`` or
        ``"length crank 108 ± 0.3 mm (ISO 2768-m)"``."""
        if self.diameter:
            return (
                f"{self.feature} Ø{self.nominal * 1e3:g} {self.designation} = "
                f"{self.lower * 1e3:.3f}/{self.upper * 1e3:.3f} mm"
            )
        deviation = 0.5 * (self.upper - self.lower)
        return (
            f"{self.feature} {self.nominal * 1e3:g} ± {deviation * 1e3:g} mm ({self.designation})"
        )

    def as_dict(self) -> dict[str, Any]:
        """JSON-ready (SI) with the text."""
        return {
            "feature": self.feature,
            "designation": self.designation,
            "nominal_m": self.nominal,
            "lower_m": self.lower,
            "upper_m": self.upper,
            "text": self.text,
        }


@dataclass(frozen=True)
class Scheme:
    """One tolerance scheme: a fit per pin joint and a general class for the lengths.

    Attributes:
        fits: ISO 286 fit per joint, e.g. ``{"O2": "H7/g6", ...}``.
        length_class: ISO 2768-1 class of every template length (f, m, c, v).
    """

    fits: Mapping[str, str]
    length_class: str

    def __post_init__(self) -> None:
        object.__setattr__(self, "fits", dict(self.fits))
        object.__setattr__(self, "length_class", iso2768.parse_class(self.length_class))

    @property
    def fit_label(self) -> str:
        values = set(self.fits.values())
        if len(values) == 1:
            return next(iter(values))
        return ",".join(f"{joint}={fit}" for joint, fit in self.fits.items())

    @property
    def label(self) -> str:
        return f"{self.fit_label} / {self.length_class}"

    def spec(self, mechanism: Mechanism, process: Process | None = None) -> ToleranceSpec:
        """The toleranced features of this scheme: the lengths of its class, and per joint
        the hole and pin diameters of its fit (``process.sampling == "parts"``,
        :mod:`jointplay.tolerance.parts`) or the radial clearance over the fit's band
        (``"band"``)."""
        process = process or Process()
        cpk = process.cpk.get("length")
        nominal = template_lengths(mechanism)
        lengths: list[InputTolerance] = [
            LinkTolerance.general(
                name, value, self.length_class, distribution=process.distribution, cpk=cpk
            )
            for name, value in nominal.items()
            if abs(value) >= 0.5e-3
        ]
        joints: list[InputTolerance] = []
        for joint, fit in self.fits.items():
            diameter = _diameter(mechanism, joint)
            if process.sampling == "parts":
                joints.extend(fit_features(joint, fit, diameter, process))
            else:
                joints.append(
                    JointTolerance.from_fit(joint, fit, diameter, distribution=process.distribution)
                )
        return ToleranceSpec(tuple(in_template_order(lengths, nominal)) + tuple(joints))

    def callouts(self, mechanism: Mechanism) -> tuple[Callout, ...]:
        """What goes on the drawing: per joint the hole and the pin with their ISO 286
        classes and limits of size, per template length its ISO 2768-1 ±deviation."""
        out = []
        for joint, fit in self.fits.items():
            result = iso286.fit(fit, _diameter(mechanism, joint))
            for kind, zone in (("hole", result.hole), ("pin", result.shaft)):
                out.append(
                    Callout(
                        f"joint {joint} {kind}",
                        zone.nominal_size,
                        zone.min_size,
                        zone.max_size,
                        zone.designation,
                        diameter=True,
                    )
                )
        for name, value in template_lengths(mechanism).items():
            if abs(value) < 0.5e-3:
                continue
            deviation = iso2768.general_tolerance(self.length_class, abs(value))
            out.append(
                Callout(
                    f"length {name}",
                    value,
                    value - deviation,
                    value + deviation,
                    f"ISO 2768-{self.length_class}",
                )
            )
        return tuple(out)

    def cost(self, mechanism: Mechanism, model: CostModel) -> float:
        """Relative cost: every joint's fit plus every length's class."""
        fits = sum(fit_cost(fit, _diameter(mechanism, j), model) for j, fit in self.fits.items())
        return fits + length_class_cost(self.length_class, template_lengths(mechanism), model)


def _diameter(mechanism: Mechanism, joint: str) -> float:
    item = mechanism.joint(joint)
    if not isinstance(item, RevoluteJoint) or item.fit is None:
        raise ConfigError(
            f"joint {joint!r} has no pin diameter; give it [joints.{joint}] diameter in the "
            "configuration"
        )
    return item.fit.diameter


def schemes(
    mechanism: Mechanism,
    fits: Sequence[str | Mapping[str, str]],
    classes: Sequence[str],
) -> tuple[Scheme, ...]:
    """Every combination of ``fits`` and ``classes``.

    A fit given as text applies to every pin joint with a diameter; a mapping names the fit
    of each joint (joints it leaves out take the mechanism's own fit).

    Raises:
        ConfigError: no candidates, a joint without a diameter, or a fit that is not a
            clearance fit at the joint's diameter.
    """
    joints = [j.name for j in mechanism.revolute_joints if j.fit is not None]
    if not joints:
        raise ConfigError("the design study needs pin joints with a diameter ([joints.<name>])")
    if not fits:
        raise ConfigError("the design study needs at least one candidate fit")
    if not classes:
        raise ConfigError("the design study needs at least one ISO 2768-1 class")
    own = {j.name: j.fit.fit for j in mechanism.revolute_joints if j.fit is not None}
    out = []
    for candidate in fits:
        if isinstance(candidate, str):
            chosen = dict.fromkeys(joints, candidate)
        else:
            unknown = sorted(set(candidate) - set(joints))
            if unknown:
                raise ConfigError(
                    f"fit for unknown joint(s) {unknown}; joints with a diameter: {joints}"
                )
            chosen = {}
            for joint in joints:
                fit = candidate.get(joint, own.get(joint))
                if fit is None:
                    raise SettingError(
                        "joint {joint!r} has no fit: name one ({fit} {joint}=H7/g6)", joint=joint
                    )
                chosen[joint] = fit
        for joint, fit in chosen.items():
            result = iso286.fit(fit, _diameter(mechanism, joint))
            if result.fit_type != "clearance":
                raise ConfigError(
                    f"{fit} is a {result.fit_type} fit at Ø{_diameter(mechanism, joint) * 1e3:g} "
                    f"mm (joint {joint!r}); candidates must be clearance fits"
                )
        for letter in classes:
            out.append(Scheme(chosen, letter))
    return tuple(out)


# --- the response model ----------------------------------------------------------------------


def design_units(
    mechanism: Mechanism, responses: Literal["kinematic", "dynamic"]
) -> dict[str, str]:
    """SI unit of every response a requirement may name."""
    if responses == "kinematic":
        nominal = template_lengths(mechanism)
        model = kinematic_model(
            mechanism, [f"length_{n}" for n in nominal if abs(nominal[n]) >= 0.5e-3]
        )
        return dict(model.units)
    from jointplay.model.columns import rotating_links

    units: dict[str, str] = {}
    for _, k in rotating_links(mechanism):
        units[f"omega{k}_peak"] = "rad/s"
        units[f"alpha{k}_peak"] = "rad/s^2"
    for joint in mechanism.joints:
        units[f"F_{joint.name}_peak"] = "N"
        if isinstance(joint, RevoluteJoint) and joint.fit is not None:
            units[f"wear_rate_{joint.name}"] = "m/s"
    units["torque_peak"] = "N*m"
    units.update(DERIVED_RESPONSES)
    return units


def parse_requirements(
    mechanism: Mechanism, requirements: Sequence[str | Requirement]
) -> tuple[Requirement, ...]:
    """Requirements as typed objects, each text parsed once against every response a design
    study of ``mechanism`` may give (kinematic and dynamic).

    Raises:
        ConfigError: a malformed requirement or an unknown response.
    """
    units = {**design_units(mechanism, "kinematic"), **design_units(mechanism, "dynamic")}
    return tuple(
        r if isinstance(r, Requirement) else parse_requirement(r, units) for r in requirements
    )


def resolve_responses(
    mechanism: Mechanism,
    requirements: Sequence[Requirement],
    responses: Literal["auto", "kinematic", "dynamic"] = "auto",
) -> Literal["kinematic", "dynamic"]:
    """The response model a design study runs: ``responses`` itself, or for ``"auto"``
    kinematic when every requirement names a kinematic response, else dynamic."""
    if responses != "auto":
        return responses
    units = design_units(mechanism, "kinematic")
    kinematic = bool(requirements) and all(r.response in units for r in requirements)
    return "kinematic" if kinematic else "dynamic"


#: Responses that need each sample's trajectory, not only its peaks: a design requiring one
#: runs the single engine (:class:`RunningResponses`), else the batch engine
#: (:class:`PeakResponses`, every backend including the GPU).
TRAJECTORY_RESPONSES = ("rocker_speed_error", "wear_rate", "life", "functional_life")


def trajectory_requirements(requirements: Sequence[Requirement]) -> list[str]:
    """The requirements (as written) whose response needs each sample's trajectory."""
    return [
        r.text
        for r in requirements
        if r.response in TRAJECTORY_RESPONSES or r.response.startswith("wear_rate_")
    ]


# --- plausibility -----------------------------------------------------------------------------


#: ``samples="auto"``: samples per scheme in each block; the verdicts are looked at after
#: every block (the sequential rule: :func:`jointplay.tolerance.confidence.confidence_sequence`).
BLOCK = 100
#: ``samples="auto"``: default largest number of samples per scheme.
DEFAULT_MAX_SAMPLES = 4000


def sample_looks(samples: int | Literal["auto"], max_samples: int) -> tuple[int, ...]:
    """Total samples per scheme at each look at the verdicts: ``(samples,)`` for a number
    (one look, at a sample size fixed in advance), else every :data:`BLOCK` samples up to
    ``max_samples`` (its last look)."""
    if samples != "auto":
        if isinstance(samples, bool) or not isinstance(samples, int) or samples < 1:
            raise ConfigError(f"samples must be a positive integer or 'auto', got {samples!r}")
        return (samples,)
    if isinstance(max_samples, bool) or not isinstance(max_samples, int) or max_samples < 1:
        raise ConfigError(f"max_samples must be a positive integer, got {max_samples!r}")
    return (*range(BLOCK, max_samples, BLOCK), max_samples)
