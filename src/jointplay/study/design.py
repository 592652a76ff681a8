"""Tolerance synthesis through the dynamics: which fit and which length class to put on the
drawing.

:func:`design_study` evaluates every combination (a *scheme*) of an ISO 286 fit — one for all
pin joints, or one per named joint — and an ISO 2768-1 class for the link lengths:

1. a Monte Carlo of the parts as made (:mod:`jointplay.tolerance.parts`): each link length in
   its class's ±deviation, each joint's hole and pin diameters in their own ISO 286 zones,
   the radial clearance their half difference (or, ``Process(sampling="band")``, the
   clearance over the fit's worst-case band), with the same seed for every scheme and every
   round (common random numbers: schemes differ by their tolerances, not by their luck);
   ``samples="auto"`` adds rounds (:func:`sample_rounds`) while a scheme is undecided and
   could still be the answer;
2. each sample through the steady running dynamics (steady start, ``settle`` start-up
   revolutions left out) — or through the ideal-joint kinematics when every requirement is
   kinematic. When a requirement needs each sample's trajectory (``rocker_speed_error``,
   ``wear_rate``, ``life``: :func:`trajectory_requirements`), one single-engine simulation per
   sample (:class:`~jointplay.tolerance.responses.RunningResponses`); otherwise the batch
   engine (:class:`~jointplay.tolerance.responses.PeakResponses`), which runs on every
   backend, the GPU included, and gives the peaks, ``joint_force`` and ``contact_pressure``
   (the engines agree on forces within 1e-3, on ω peaks within their integration errors:
   docs/design.md);
3. per scheme (:mod:`jointplay.tolerance.confidence`): every response's mean, std and value
   at the confidence level (a distribution-free order-statistic bound, or a named
   normal-model estimate with too few samples); per requirement the failures (a failed
   simulation counts as one), the yield and DPM with their exact 95 % intervals and the
   verdict ``meets``/``fails``/``undecided``; the relative cost; with ``rare``, the defect
   rate of the schemes left undecided by importance sampling
   (:mod:`jointplay.tolerance.rare`);
4. the cheapest scheme whose every requirement ``meets`` — or, if none does, the requirement
   that binds (the one whose best yield over all schemes is lowest) and what would decide
   the undecided ones — and the Pareto fronts of cost against the yield and each response;
5. dynamic studies: whether the samples are physical. Every sample's pin of each clearance
   joint must stay within its radial clearance (``penetration_ratio_<joint>``, the deepest
   penetration over the analysed revolutions / that sample's radial clearance, see
   :mod:`jointplay.tolerance.responses`); each scheme counts the successful samples beyond it
   (``penetration_exceeds_<joint>``) and keeps the largest ratio
   (``penetration_ratio_max_<joint>``), and :attr:`DesignResult.diagnostics` has one
   ``penetration-exceeds-clearance`` warning per joint concerned in some scheme
   (:class:`DesignDiagnostic`: how many samples of how many schemes, the worst ratio and its
   scheme, whether the recommended scheme is among them).

Each round's samples of all open schemes run as one batch on one backend
(:func:`jointplay.tolerance.execution.run`), scheme after scheme: Ctrl-C keeps the rounds
that finished.

Responses of the dynamic model (SI): the tolerance study's peaks (``omega<k>_peak``,
``alpha<k>_peak``, ``F_<joint>_peak``, ``torque_peak``) and

* ``rocker_speed_error`` — largest deviation of the output link's angular velocity from the
  nominal ideal-joint one at the same crank angle, as a fraction of its largest ideal value
  (:func:`jointplay.dynamics.wear.speed_error`);
* ``joint_force`` — the largest peak contact force over the joints, N;
* ``contact_pressure`` — the largest peak Hertz line-contact pressure over the joints, Pa;
* ``wear_rate`` — the fastest Archard growth of a radial clearance, m/s
  (:func:`jointplay.dynamics.wear.cycle_wear`);
* ``life`` — the time until the first joint's clearance passes its limit at that rate, s
  (computed per scheme, since the limit may follow the fit).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from jointplay.errors import ConfigError, PartialInterrupt, SettingError, name_settings
from jointplay.model.mechanism import Mechanism, RevoluteJoint
from jointplay.study.requirements import Requirement, parse_requirement
from jointplay.tolerance import iso286, iso2768
from jointplay.tolerance.analysis import (
    ConvergenceCheck,
    StudyDiagnostic,
    convergence_finding,
    penetration_warning,
)
from jointplay.tolerance.confidence import YieldEstimate, quantile_value, verdict
from jointplay.tolerance.cost import CostModel, fit_cost, length_class_cost
from jointplay.tolerance.definitions import response_definitions
from jointplay.tolerance.execution import NOT_RUN, OK, STATUS, Backend, run
from jointplay.tolerance.methods import distribution_note, truncated_at_limits
from jointplay.tolerance.parts import Process, fit_features, model_inputs
from jointplay.tolerance.rare import RareEstimate, cross_entropy_importance_sampling
from jointplay.tolerance.responses import (
    ELASTIC_RATIO,
    PENETRATION_RATIO,
    RUNNING_RESPONSES,
    PeakResponses,
    ResponseModel,
    RunningResponses,
    contact_parts,
    dynamic_model,
    kinematic_model,
)
from jointplay.tolerance.sampling import sample
from jointplay.tolerance.spec import (
    InputTolerance,
    JointTolerance,
    LinkTolerance,
    ToleranceSpec,
    in_template_order,
    template_lengths,
)

if TYPE_CHECKING:
    from jointplay.contact.laws import ContactLaw
    from jointplay.dynamics.settings import RunSettings
    from jointplay.dynamics.setup import ContactModel
    from jointplay.dynamics.simulate import SolverOptions
    from jointplay.dynamics.wear import WearSettings

__all__ = [
    "DEFAULT_CONFIDENCE",
    "DEFAULT_MAX_SAMPLES",
    "DERIVED_RESPONSES",
    "FIRST_ROUND",
    "Callout",
    "DesignDiagnostic",
    "DesignResult",
    "RareDefects",
    "Scheme",
    "design_study",
    "design_units",
    "parse_requirements",
    "penetration_diagnostics",
    "resolve_responses",
    "sample_rounds",
    "schemes",
    "trajectory_requirements",
]

FloatArray = NDArray[np.float64]

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
TRAJECTORY_RESPONSES = ("rocker_speed_error", "wear_rate", "life")


def trajectory_requirements(requirements: Sequence[Requirement]) -> list[str]:
    """The requirements (as written) whose response needs each sample's trajectory."""
    return [
        r.text
        for r in requirements
        if r.response in TRAJECTORY_RESPONSES or r.response.startswith("wear_rate_")
    ]


# --- plausibility -----------------------------------------------------------------------------


@dataclass(frozen=True)
class DesignDiagnostic(StudyDiagnostic):
    """A plausibility finding over the samples of every finished scheme.

    The fields of :class:`~jointplay.tolerance.analysis.StudyDiagnostic` count over all
    schemes together (``count`` samples concerned of ``out_of`` successful ones;
    ``worst_sample`` is the ``sample`` column of ``samples.parquet`` *within*
    ``worst_scheme``; ``worst_inputs`` SI); in addition:

    Attributes:
        schemes: finished schemes with at least one sample concerned.
        out_of_schemes: finished schemes.
        worst_scheme: label of the scheme of the worst sample.
        best: the recommended scheme (:attr:`DesignResult.best`), or ``None``.
        best_count: samples of the recommended scheme concerned (0 when none is, or when
            there is no recommended scheme).
        best_out_of: successful samples of the recommended scheme (0 without one).
    """

    schemes: int
    out_of_schemes: int
    worst_scheme: str
    best: str | None
    best_count: int
    best_out_of: int

    @property
    def best_concerned(self) -> bool:
        """The recommended scheme has samples concerned."""
        return self.best_count > 0

    def as_dict(self) -> dict[str, Any]:
        """JSON-ready: :meth:`StudyDiagnostic.as_dict` plus ``schemes``, ``out_of_schemes``,
        ``worst_scheme``, ``best``, ``best_concerned``, ``best_count`` and ``best_out_of``."""
        return {
            **super().as_dict(),
            "schemes": self.schemes,
            "out_of_schemes": self.out_of_schemes,
            "worst_scheme": self.worst_scheme,
            "best": self.best,
            "best_concerned": self.best_concerned,
            "best_count": self.best_count,
            "best_out_of": self.best_out_of,
        }


def _penetration_columns(check_names: Sequence[str]) -> dict[str, str]:
    """Joint → its penetration-ratio check (``penetration_ratio_<joint>``) among ``check_names``."""
    return {
        name.removeprefix(PENETRATION_RATIO): name
        for name in check_names
        if name.startswith(PENETRATION_RATIO)
    }


def _scheme_penetration(
    check_names: Sequence[str], checks: FloatArray, ok: NDArray[np.bool_]
) -> dict[str, Any]:
    """A scheme's row entries of the penetration checks, per clearance joint:
    ``penetration_exceeds_<joint>`` (successful samples whose ratio passes 1) and
    ``penetration_ratio_max_<joint>`` (the largest ratio of its successful samples,
    dimensionless; NaN when none succeeded).

    Args:
        check_names: the model's checks.
        checks: (n, c) their values per sample (NaN where a sample failed).
        ok: (n,) which samples succeeded.
    """
    row: dict[str, Any] = {}
    for joint, name in _penetration_columns(check_names).items():
        ratio = checks[ok, list(check_names).index(name)]
        ratio = ratio[np.isfinite(ratio)]
        row[f"penetration_exceeds_{joint}"] = int(np.sum(ratio > 1.0))
        row[f"penetration_ratio_max_{joint}"] = float(ratio.max()) if len(ratio) else math.nan
    return row


def penetration_diagnostics(
    samples: pd.DataFrame,
    check_names: Sequence[str],
    input_names: Sequence[str],
    best: str | None,
) -> tuple[DesignDiagnostic, ...]:
    """One ``penetration-exceeds-clearance`` warning per clearance joint whose pin, in some
    successful samples of some scheme, sinks deeper into its bearing than the radial
    clearance (``penetration_ratio_<joint>`` > 1), and one ``penetration-exceeds-elastic``
    per joint whose pin sinks deeper than ``ELASTIC_FACTOR`` times its Hertz approach
    (``elastic_ratio_<joint>``, :mod:`jointplay.dynamics.diagnostics`).

    The tolerance study's :func:`~jointplay.tolerance.analysis.penetration_findings` judges
    the samples of one study; this counts them over the schemes, names the worst sample's
    scheme and says whether the recommended one is concerned.

    Args:
        samples: one row per sample (:attr:`DesignResult.samples`): ``scheme``, ``sample``,
            the inputs, the checks, ``status``.
        check_names: the model's checks (none: no warning).
        input_names: the inputs, SI.
        best: the recommended scheme, or ``None``.
    """
    from jointplay.dynamics.diagnostics import ELASTIC_FACTOR, Diagnostic

    kinds = [(joint, name, 1.0) for joint, name in _penetration_columns(check_names).items()] + [
        (name.removeprefix(ELASTIC_RATIO), name, ELASTIC_FACTOR)
        for name in check_names
        if name.startswith(ELASTIC_RATIO)
    ]
    if not kinds or not len(samples):
        return ()
    ok = (samples["status"] == STATUS[OK]).to_numpy()
    scheme = samples["scheme"].to_numpy()
    labels = list(dict.fromkeys(scheme))
    out_of = int(ok.sum())
    findings = []
    for joint, name, limit in kinds:
        ratio = np.where(ok, samples[name].to_numpy(dtype=float), np.nan)
        exceeds = ratio > limit  # NaN compares False
        count = int(exceeds.sum())
        if count == 0:
            continue
        per_scheme = {label: int(exceeds[scheme == label].sum()) for label in labels}
        concerned = sum(1 for n in per_scheme.values() if n)
        worst = int(np.argmax(np.where(exceeds, ratio, -np.inf)))
        worst_scheme = str(scheme[worst])
        worst_sample = int(samples["sample"].iloc[worst])
        best_count = per_scheme.get(best, 0) if best is not None else 0
        best_out_of = int(ok[scheme == best].sum()) if best is not None else 0
        if best is None:
            verdict = ""
        elif best_count:
            verdict = (
                f"; the recommended scheme {best} is concerned ({best_count} of its "
                f"{best_out_of} samples): its yield cannot be trusted"
            )
        else:
            verdict = (
                f"; the recommended scheme {best} is not concerned, but the schemes it was "
                "chosen over were judged on these samples"
            )
        what = (
            "the radial clearance"
            if limit == 1.0
            else "the elastic approach of the joint's own Hertz law at its peak force"
        )
        per_scheme_column = (
            f", penetration_exceeds_{joint} per scheme in design.parquet" if limit == 1.0 else ""
        )
        message = (
            f"{count} of {out_of} samples ({100.0 * count / out_of:.3g} %) in {concerned} of "
            f"{len(labels)} schemes: the pin of {joint} penetrates its bearing by up to "
            f"{ratio[worst]:.3g} times {what} (scheme {worst_scheme}, sample "
            f"{worst_sample}; {name} in samples.parquet{per_scheme_column}); those samples' "
            f"responses are not physical{verdict}; the contact stiffness is far too low for "
            "the load: use a stiffness from the joints' geometry (the default contact, or "
            "a stiffness law)"
        )
        diagnostic = (
            penetration_warning(joint, float(ratio[worst]), message)
            if limit == 1.0
            else Diagnostic(
                "warning", "penetration-exceeds-elastic", joint, float(ratio[worst]), limit,
                message,
            )
        )  # fmt: skip
        findings.append(
            DesignDiagnostic(
                diagnostic,
                count=count,
                out_of=out_of,
                worst_sample=worst_sample,
                worst_inputs={n: float(samples[n].iloc[worst]) for n in input_names},
                schemes=concerned,
                out_of_schemes=len(labels),
                worst_scheme=worst_scheme,
                best=best,
                best_count=best_count,
                best_out_of=best_out_of,
            )
        )
    return tuple(findings)


# --- the study -------------------------------------------------------------------------------


@dataclass(frozen=True)
class DesignResult:
    """A finished (or interrupted) design study.

    Attributes:
        mechanism: the nominal mechanism.
        responses: ``"kinematic"`` or ``"dynamic"``.
        requirements: the requirements.
        confidence: the study's confidence level (fraction).
        table: one row per finished scheme (:meth:`to_dataframe`); dynamic studies add
            ``penetration_exceeds_<joint>`` and ``penetration_ratio_max_<joint>`` per
            clearance joint.
        samples: one row per sample of the finished schemes: scheme, the features as made
            (``hole_<joint>``, ``pin_<joint>`` diameters), the model's inputs (lengths,
            clearances), responses, dynamic studies' ``penetration_ratio_<joint>``
            (dimensionless; above 1: not physical), status.
        best: label of the cheapest scheme shown to meet every requirement (verdict
            ``meets``: the lower bound of each yield's exact 95 % interval at or above the
            confidence level), or ``None`` (always for an interrupted study: a choice among
            some of the schemes is no choice).
        binding: when none is: the requirement whose best observed yield is lowest
            (``None`` for an interrupted study).
        interrupted: Ctrl-C stopped the run; only finished schemes are in ``table``.
        settings: samples, seed, model description, cost model, clearance limits.
        diagnostics: plausibility warnings over the samples of the finished schemes
            (:func:`penetration_diagnostics`, then the ``peaks-not-converged`` warning of
            :attr:`convergence`); empty when every sample is physical and converged, and for
            kinematic studies.
        convergence: dynamic studies: the integrator's share of the responses' scatter
            (:func:`~jointplay.tolerance.analysis.convergence_finding`, over the first
            round's samples; ``None`` when not checked).
        candidates: every scheme of the study (finished or not).
    """

    mechanism: Mechanism
    responses: str
    requirements: tuple[Requirement, ...]
    confidence: float
    table: pd.DataFrame = field(repr=False)
    samples: pd.DataFrame = field(repr=False)
    best: str | None
    binding: str | None
    interrupted: bool
    settings: Mapping[str, Any] = field(default_factory=dict)
    diagnostics: tuple[StudyDiagnostic, ...] = ()
    convergence: ConvergenceCheck | None = None
    candidates: tuple[Scheme, ...] = ()

    def to_dataframe(self) -> pd.DataFrame:
        """One row per scheme (the content of ``design.parquet``)."""
        return self.table.copy()

    @property
    def best_row(self) -> Mapping[str, Any] | None:
        if self.best is None:
            return None
        row = self.table[self.table["scheme"] == self.best].iloc[0]
        return {str(k): _plain(v) for k, v in row.items()}

    @property
    def drawing(self) -> tuple[Callout, ...]:
        """The drawing callouts of the answer (none without one)."""
        for scheme in self.candidates:
            if scheme.label == self.best:
                return scheme.callouts(self.mechanism)
        return ()

    @property
    def undecided(self) -> pd.DataFrame:
        """The undecided schemes cheaper than the answer (all of them without one), by cost."""
        if not len(self.table):
            return self.table
        rows = self.table[self.table["verdict"] == "undecided"]
        if self.best is not None:
            rows = rows[rows["cost"] < self.best_row["cost"]]  # type: ignore[index]
        return rows.sort_values("cost")

    @property
    def to_decide(self) -> str | None:
        """What would decide the undecided schemes that could change the answer, or ``None``."""
        return self.what_decides()

    def what_decides(self, names: Mapping[str, str] | None = None) -> str | None:
        """:attr:`to_decide`, the settings it advises on called by ``names`` (setting →
        name, :func:`~jointplay.errors.name_settings`; the command line its options')."""
        rows = self.undecided
        if not len(rows):
            return None
        row = rows.iloc[0]
        m = row["samples_to_decide"]
        text = f"undecided: {row['scheme']} after {row['samples']:,} samples (" + (
            name_settings(
                f"about {int(m):,} would decide it at its observed defect rate: "
                f"{{max_samples}} {int(m)})",
                names,
            )
            if not pd.isna(m)
            else "its observed defect rate sits at the level: more samples may not decide it)"
        )
        if len(rows) > 1:
            text += f", and {len(rows) - 1} dearer undecided scheme(s)"
        return text

    @property
    def verdict(self) -> str:
        """The answer in one sentence."""
        if self.interrupted:
            return (
                f"interrupted: {len(self.table)} of {self.settings.get('schemes', '?')} schemes "
                "with finished rounds; no recommendation from some of the schemes (run the "
                "study again)"
            )
        if self.best is not None:
            text = f"cheapest scheme shown to meet every requirement: {self.best}"
        elif not len(self.table):
            return "no finished scheme"
        elif (self.table["verdict"] == "fails").all():
            text = "every scheme fails"
            if self.binding is not None:
                text += f"; binding requirement: {self.binding}"
            return text
        else:
            text = "no scheme is shown to meet every requirement"
            if self.binding is not None:
                text += f"; binding requirement: {self.binding}"
        if self.to_decide is not None:
            text += f"; {'cheaper, ' if self.best is not None else ''}{self.to_decide}"
        return text

    def summary(self) -> dict[str, Any]:
        """The ``summary.json`` content (SI; yields and their intervals as fractions in
        ``schemes[].requirements[]``, as % in the flat scheme columns)."""
        return {
            "mechanism": self.mechanism.name,
            "responses_kind": self.responses,
            "confidence": self.confidence,
            "requirements": [r.describe() for r in self.requirements],
            "verdict": self.verdict,
            "best": self.best,
            "best_scheme": self.best_row,
            "drawing": [c.as_dict() for c in self.drawing],
            "binding": self.binding,
            "to_decide": self.to_decide,
            "interrupted": self.interrupted,
            "settings": dict(self.settings),
            "response_definitions": response_definitions(self.reported_responses),
            "schemes": [self._record(row) for row in self.table.to_dict(orient="records")],
            "diagnostics": [finding.as_dict() for finding in self.diagnostics],
            "convergence_check": None if self.convergence is None else self.convergence.as_dict(),
        }

    def _record(self, row: Mapping[Any, Any]) -> dict[str, Any]:
        """A scheme's summary: its flat columns, the per-requirement ones gathered in
        ``requirements`` (fractions)."""
        own = {f"_{r.text}" for r in self.requirements}
        record = {
            str(k): _plain(v) for k, v in row.items() if not any(str(k).endswith(o) for o in own)
        }
        record["requirements"] = [
            {
                "requirement": r.text,
                "confidence": r.confidence if r.confidence is not None else self.confidence,
                "failures": _plain(row[f"failures_{r.text}"]),
                "samples": _plain(row["samples"]),
                "yield": row[f"yield_{r.text}"] / 100.0,
                "yield_ci95": [
                    row[f"yield_low_{r.text}"] / 100.0,
                    row[f"yield_high_{r.text}"] / 100.0,
                ],
                "dpm": row[f"dpm_{r.text}"],
                "dpm_ci95": [row[f"dpm_low_{r.text}"], row[f"dpm_high_{r.text}"]],
                "verdict": row[f"verdict_{r.text}"],
                "samples_to_decide": _plain(row[f"samples_to_decide_{r.text}"]),
            }
            for r in self.requirements
        ]
        return record

    @property
    def reported_responses(self) -> tuple[str, ...]:
        """The responses the scheme table reports: those the requirements name, in order."""
        names = [r.response for r in self.requirements]
        return tuple(dict.fromkeys(names))


def _plain(value: Any) -> Any:
    """A table cell as plain JSON-ready Python (missing → ``None``)."""
    if value is None or (not isinstance(value, str | bool) and pd.isna(value)):
        return None
    return value.item() if hasattr(value, "item") else value


#: ``samples="auto"``: samples per scheme of the first round; each round doubles the total.
FIRST_ROUND = 100
#: ``samples="auto"``: default largest number of samples per scheme.
DEFAULT_MAX_SAMPLES = 4000


def sample_rounds(samples: int | Literal["auto"], max_samples: int) -> tuple[int, ...]:
    """Total samples per scheme after each round: ``(samples,)`` for a number, else
    :data:`FIRST_ROUND`, doubling, up to ``max_samples`` (its last round)."""
    if samples != "auto":
        if isinstance(samples, bool) or not isinstance(samples, int) or samples < 1:
            raise ConfigError(f"samples must be a positive integer or 'auto', got {samples!r}")
        return (samples,)
    if isinstance(max_samples, bool) or not isinstance(max_samples, int) or max_samples < 1:
        raise ConfigError(f"max_samples must be a positive integer, got {max_samples!r}")
    out = [min(FIRST_ROUND, max_samples)]
    while out[-1] < max_samples:
        out.append(min(2 * out[-1], max_samples))
    return tuple(out)


@dataclass
class _Evaluated:
    """The samples one evaluation key (a scheme; a length class when kinematic) has run."""

    features: list[FloatArray] = field(default_factory=list)
    x: list[FloatArray] = field(default_factory=list)
    values: list[FloatArray] = field(default_factory=list)
    status: list[NDArray[np.int8]] = field(default_factory=list)
    checks: list[FloatArray] = field(default_factory=list)
    errors: list[str] = field(default_factory=list)

    @property
    def n(self) -> int:
        return sum(len(s) for s in self.status)

    def add(self, features: FloatArray, x: FloatArray, outcome: Any, part: slice) -> None:
        n = len(features)
        self.features.append(features)
        self.x.append(x[part])
        self.values.append(outcome.values[part])
        self.status.append(outcome.status[part])
        checks = outcome.checks[part] if outcome.checks is not None else np.empty((n, 0))
        self.checks.append(checks)
        self.errors.extend(outcome.errors[part])


def design_study(
    mechanism: Mechanism,
    fits: Sequence[str | Mapping[str, str]],
    classes: Sequence[str],
    requirements: Sequence[str | Requirement],
    *,
    samples: int | Literal["auto"] = "auto",
    max_samples: int = DEFAULT_MAX_SAMPLES,
    seed: int = 0,
    confidence: float = DEFAULT_CONFIDENCE,
    responses: Literal["auto", "kinematic", "dynamic"] = "auto",
    cost: CostModel | None = None,
    clearance_limit: Mapping[str, float] | float | None = None,
    clearance_allowance: float | None = None,
    wear: WearSettings | None = None,
    run_settings: RunSettings | None = None,
    contact: str | ContactLaw | ContactModel | None = None,
    settle: int | None = None,
    revolutions: float | None = None,
    solver: SolverOptions | None = None,
    process: Process | None = None,
    truncate: bool = True,
    rare: RareDefects | None = None,
    backend: Backend | None = None,
    progress: bool = False,
) -> DesignResult:
    """Find the cheapest fit and length class shown to meet ``requirements``.

    Args:
        mechanism: the nominal mechanism (template four-bar or slider-crank; pin joints with
            a diameter).
        fits: candidate fits: text (every joint) or a mapping joint → fit.
        classes: candidate ISO 2768-1 classes.
        requirements: requirements as text (:mod:`jointplay.study.requirements`) or objects.
        samples: Monte Carlo samples per scheme, or ``"auto"``: rounds of samples
            (:func:`sample_rounds`) until every scheme is decided, can no longer be the
            cheapest feasible one, or has ``max_samples``.
        max_samples: ``"auto"``: the most samples per scheme.
        seed: the seed (the same for every scheme and every round: common random numbers).
        confidence: share of parts that must meet a requirement without its own ``@``.
        responses: ``"dynamic"`` (clearance joints, steady running), ``"kinematic"`` (ideal
            joints, lengths only) or ``"auto"`` (kinematic when every requirement is).
        cost: the cost–tolerance model (default :class:`CostModel`).
        clearance_limit: radial clearance limit for ``life``, m (one for all, or per joint).
        clearance_allowance: instead: the fit's largest radial clearance plus this, m.
        wear: Archard parameters (default steel on steel, :mod:`jointplay.dynamics.wear`).
        run_settings: dynamic: how the clearance dynamics run
            (:class:`~jointplay.dynamics.settings.RunSettings`: contact, start, settle,
            revolutions, solver), as the command line builds it; or, in its place, the loose
            keywords below (giving both is an error).
        contact: dynamic: a :class:`~jointplay.dynamics.setup.ContactModel`; ``None``
            (default): the physical default ``ContactModel()``, as every command;
            ``"ifm-conventional"``: the paper's conventional IFM set, frictionless; a contact
            law: that law (:func:`jointplay.tolerance.analysis.study_contact`).
        settle, revolutions: dynamic: start-up revolutions left out (default 2), analysed
            revolutions (default 1).
        solver: dynamic: integration settings (default :class:`SolverOptions`).
        process: how the parts are made (default: hole and pin apart, normal ±3σ at their
            limits; :class:`~jointplay.tolerance.parts.Process`).
        truncate: draw normal features from the normal truncated at their limits (default:
            out-of-tolerance parts are rejected at inspection;
            :func:`jointplay.tolerance.methods.truncated_at_limits`), else untruncated.
        rare: estimate the defect rate of the schemes Monte Carlo left undecided (cheapest
            first) by cross-entropy importance sampling (:mod:`jointplay.tolerance.rare`);
            its 95 % interval decides them (``verdict_basis``). ``None``: Monte Carlo only.
        backend: where the samples run (default local processes).
        progress: show a progress bar.

    Raises:
        ConfigError: a malformed requirement, an unknown response, bad candidates.
        PartialInterrupt: interrupted during the convergence check, after every scheme
            finished; its ``partial`` is the result without the check.
    """
    if not 0.0 < confidence < 1.0:
        raise ConfigError(f"confidence must lie between 0 and 100 %, got {100 * confidence:g} %")
    rounds = sample_rounds(samples, max_samples)
    process = process or Process()
    cost = cost or CostModel()
    candidates = schemes(mechanism, fits, classes)
    parsed = parse_requirements(mechanism, requirements)
    responses = resolve_responses(mechanism, parsed, responses)
    kinematic_units = design_units(mechanism, "kinematic")
    dynamic_units = design_units(mechanism, "dynamic")
    # A dynamic study gives the ideal-joint kinematic responses of each sample's lengths too,
    # so requirements may mix them (the dynamic peaks keep their own names).
    units = kinematic_units if responses == "kinematic" else {**kinematic_units, **dynamic_units}
    for item in parsed:
        if item.response not in units:
            raise ConfigError(
                f"requirement {item.text!r}: response {item.response!r} is not a "
                f"{responses} response; expected one of {', '.join(sorted(units))}"
            )
    if any(r.response == "life" for r in parsed) and (
        clearance_limit is None and clearance_allowance is None
    ):
        raise ConfigError(
            "a 'life' requirement needs a clearance limit: clearance_limit or clearance_allowance"
        )

    specs = [s.spec(mechanism, process) for s in candidates]
    if responses == "kinematic":
        specs = [s.only("length") for s in specs]
    specs = [truncated_at_limits(s) if truncate else s for s in specs]
    feature_names = specs[0].names
    names, _ = model_inputs(feature_names, np.empty((0, len(feature_names))))
    model = _response_model(
        mechanism, names, parsed, responses, dynamic_units,
        run=run_settings, contact=contact, settle=settle, revolutions=revolutions, solver=solver,
        wear=wear, backend=backend,
    )  # fmt: skip
    # evaluation key of each scheme: fits do not move ideal joints, so a kinematic study
    # evaluates each length class once
    first_of_class: dict[str, int] = {}
    for i, scheme in enumerate(candidates):
        first_of_class.setdefault(scheme.length_class, i)
    key = [
        first_of_class[s.length_class] if responses == "kinematic" else i
        for i, s in enumerate(candidates)
    ]
    evaluated = {k: _Evaluated() for k in set(key)}
    active = set(range(len(candidates)))
    rows: dict[int, dict[str, Any]] = {}
    interrupted = False
    first: tuple[FloatArray, Any] | None = None  # the first round, for the convergence check
    executions = []
    for target in rounds:
        keys = sorted({key[i] for i in active if evaluated[key[i]].n < target})
        if not keys:
            break
        drawn = [sample(specs[k], target, seed).values[evaluated[k].n :] for k in keys]
        features = np.vstack(drawn)
        _, x = model_inputs(feature_names, features)
        outcome = run(model, x, backend=backend, progress=progress)
        executions.append(outcome.describe())
        if first is None:
            first = (x, outcome)
        start = 0
        for k, block in zip(keys, drawn, strict=True):
            part = slice(start, start + len(block))
            start += len(block)
            if not np.any(outcome.status[part] == NOT_RUN):  # else interrupted: not kept
                evaluated[k].add(block, x, outcome, part)
        for i, scheme in enumerate(candidates):
            if evaluated[key[i]].n:
                rows[i] = _scheme_row(
                    scheme, mechanism, cost, evaluated[key[i]], names, model, outcome.check_names,
                    parsed, confidence, clearance_limit, clearance_allowance,
                )  # fmt: skip
        if outcome.interrupted:
            interrupted = True
            break
        active = _still_open(active, rows)
    if rare is not None and not interrupted:
        try:
            for i in sorted(active, key=lambda j: rows[j]["cost"]):
                if i not in _still_open({i}, rows):
                    continue  # a cheaper one was shown feasible meanwhile
                estimate = _rare_defects(
                    candidates[i], mechanism, specs[key[i]], feature_names, names, model,
                    parsed, rare, seed, clearance_limit, clearance_allowance, backend,
                )  # fmt: skip
                if estimate is None:
                    interrupted = True
                    break
                rows[i].update(_rare_columns(estimate, parsed, confidence, rows[i]["verdict"]))
                rows[i]["feasible"] = rows[i]["verdict"] == "meets"
        except KeyboardInterrupt:  # between two stages: the Monte Carlo rounds are kept
            interrupted = True

    table = pd.DataFrame([rows[i] for i in sorted(rows)])
    best = binding = None
    if len(table):
        table["samples_to_decide"] = table["samples_to_decide"].astype("Int64")
        _pareto(table, parsed, tuple(model.response_names))
    if len(table) and not interrupted:  # no recommendation from some schemes only
        feasible_rows = table[table["feasible"]]
        if len(feasible_rows):
            best = str(
                feasible_rows.sort_values(["cost", "yield"], ascending=[True, False]).iloc[0][
                    "scheme"
                ]
            )
        elif parsed:
            best_yield = {r.text: float(table[f"yield_{r.text}"].max()) for r in parsed}
            binding = min(best_yield, key=lambda t: best_yield[t])
    sample_frames = []
    check_names = first[1].check_names if first is not None else ()
    for i, scheme in enumerate(candidates):
        if i in rows:
            done = evaluated[key[i]]
            values = _responses(
                scheme, mechanism, done, names, model, clearance_limit, clearance_allowance
            )
            sample_frames.append(
                _sample_frame(scheme, done, feature_names, names, values, check_names)
            )
    every_sample = pd.concat(sample_frames, ignore_index=True) if sample_frames else pd.DataFrame()
    settings = {
        "samples": samples,
        "max_samples": max_samples if samples == "auto" else samples,
        "rounds": list(rounds),
        "seed": seed,
        "process": process.describe(),
        "truncated_at_limits": bool(truncate),
        "sampling_distributions": distribution_note(specs[0], truncate) if specs else "",
        "interval": "exact (Clopper-Pearson) two-sided 95 % interval of each yield",
        "rare_defects": None if rare is None else dataclasses.asdict(rare),
        "responses": responses,
        "cost_model": cost.describe(),
        "clearance_limit_m": clearance_limit,
        "clearance_allowance_m": clearance_allowance,
        "model": model.describe(),
        "execution": executions[-1] if executions else {},
        "execution_rounds": executions,
        "schemes": len(candidates),
        "finished_schemes": len(rows),
    }
    diagnostics: tuple[StudyDiagnostic, ...] = penetration_diagnostics(
        every_sample, check_names, names, best
    )
    result = DesignResult(
        mechanism=mechanism,
        responses=responses,
        requirements=parsed,
        confidence=confidence,
        table=table,
        samples=every_sample,
        best=best,
        binding=binding,
        interrupted=interrupted,
        settings=settings,
        diagnostics=diagnostics,
        candidates=candidates,
    )
    if interrupted or responses == "kinematic" or first is None:
        return result
    try:
        convergence = convergence_finding(model, first[0], first[1], backend)
    except KeyboardInterrupt:  # every scheme finished: they go on with the interrupt
        raise PartialInterrupt(result, "interrupted during the convergence check") from None
    if convergence is not None and convergence.finding is not None:
        diagnostics = (*diagnostics, convergence.finding)
    return dataclasses.replace(result, diagnostics=diagnostics, convergence=convergence)


@dataclass(frozen=True)
class RareDefects:
    """Settings of the rare-defect estimate (:func:`~jointplay.tolerance.rare.
    cross_entropy_importance_sampling`): ``max_stages`` pilot stages of ``n_stage`` samples
    and ``n_final`` final samples per scheme (default at most 8 000 + 10 000)."""

    n_stage: int = 1000
    n_final: int = 10000
    max_stages: int = 8

    def __post_init__(self) -> None:
        if min(self.n_stage, self.n_final) < 10 or self.max_stages < 1:
            raise ConfigError(
                "rare defects: n_stage and n_final must be >= 10 and max_stages >= 1, got "
                f"{self.n_stage}, {self.n_final}, {self.max_stages}"
            )


def _rare_defects(
    scheme: Scheme,
    mechanism: Mechanism,
    spec: ToleranceSpec,
    feature_names: tuple[str, ...],
    names: tuple[str, ...],
    model: ResponseModel,
    parsed: Sequence[Requirement],
    settings: RareDefects,
    seed: int,
    limit: Mapping[str, float] | float | None,
    allowance: float | None,
    backend: Backend | None,
) -> RareEstimate | None:
    """The probability that a part of ``scheme`` misses some requirement, by importance
    sampling through the response model on ``backend`` (``None`` when interrupted)."""
    from scipy.special import ndtr

    stopped = False

    def excess(z: FloatArray) -> FloatArray:
        nonlocal stopped
        if stopped:
            return np.full(len(z), np.nan)
        u = np.clip(ndtr(z), 1e-300, 1.0 - 2.0**-53)
        features = np.column_stack(
            [item.tolerance.ppf(u[:, c]) for c, item in enumerate(spec.inputs)]
        )
        _, x = model_inputs(feature_names, features)
        outcome = run(model, x, backend=backend)
        stopped = outcome.interrupted
        done = _Evaluated()
        done.add(features, x, outcome, slice(0, len(x)))
        values = _responses(scheme, mechanism, done, names, model, limit, allowance)
        worst = np.full(len(z), -np.inf)
        for r in parsed:
            y = values[r.response]
            scale = abs(r.limit) or 1.0
            worst = np.maximum(worst, (y - r.limit if r.upper else r.limit - y) / scale)
        return np.where(outcome.status == OK, worst, np.nan)

    estimate = cross_entropy_importance_sampling(
        excess,
        len(spec),
        seed=seed,
        n_stage=settings.n_stage,
        n_final=settings.n_final,
        max_stages=settings.max_stages,
    )
    return None if stopped else estimate


def _rare_columns(
    estimate: RareEstimate, parsed: Sequence[Requirement], confidence: float, verdict: str
) -> dict[str, Any]:
    """A scheme's rare-defect columns, and its verdict when Monte Carlo left it undecided:
    ``meets`` when the upper bound of the defect rate of every requirement together is
    within the strictest level (then each requirement's is), ``fails`` (one requirement only)
    when its lower bound passes the level."""
    levels = [r.confidence if r.confidence is not None else confidence for r in parsed]
    low, high = estimate.interval
    basis = "monte-carlo"
    if verdict == "undecided" and estimate.converged:
        if high <= 1.0 - max(levels):
            verdict, basis = "meets", "importance-sampling"
        elif len(parsed) == 1 and low > 1.0 - levels[0]:
            # with several requirements, the rate of missing any does not show which one fails
            verdict, basis = "fails", "importance-sampling"
    return {
        "dpm_rare": estimate.dpm,
        "dpm_rare_low": estimate.dpm_interval[0],
        "dpm_rare_high": estimate.dpm_interval[1],
        "rare_samples": estimate.samples,
        "rare_converged": estimate.converged,
        "verdict": verdict,
        "verdict_basis": basis,
    }


def _response_model(
    mechanism: Mechanism,
    names: tuple[str, ...],
    parsed: Sequence[Requirement],
    responses: str,
    dynamic_units: Mapping[str, str],
    *,
    run: RunSettings | None,
    contact: str | ContactLaw | ContactModel | None,
    settle: int | None,
    revolutions: float | None,
    solver: SolverOptions | None,
    wear: WearSettings | None,
    backend: Backend | None,
) -> ResponseModel:
    """The response model of a design study over the inputs ``names``; dynamic: the run
    settings built once here (:meth:`RunSettings.of`) from ``run`` or the loose keywords."""
    if responses == "kinematic":
        return kinematic_model(mechanism, names)
    from jointplay.dynamics.settings import RunSettings
    from jointplay.dynamics.wear import OutputSpeedReference, WearSettings

    settings = RunSettings.of(
        run, contact=contact, settle=settle, revolutions=revolutions, solver=solver
    )
    base = dynamic_model(
        mechanism,
        names,
        **contact_parts(mechanism, settings.contact),
        start=settings.start,
        settle=settings.settle,
        revolutions=settings.revolutions,
        solver=settings.solver,
    )
    lengths = [n for n in names if n.startswith("length_")]
    mixed = any(r.response not in dynamic_units for r in parsed)  # a kinematic one too
    kinematic = kinematic_model(mechanism, lengths) if lengths and mixed else None
    need_trajectories = trajectory_requirements(parsed)
    if need_trajectories:
        if backend is not None and backend.kind == "gpu":
            raise ConfigError(
                f"backend gpu: {', '.join(repr(t) for t in need_trajectories)} need(s) each "
                "sample's trajectory, which the GPU's batch engine does not keep (it gives "
                "peaks: omega, alpha, forces, torque, joint_force, contact_pressure); use "
                "local, processes or dask"
            )
        return RunningResponses(
            base,
            OutputSpeedReference.of(mechanism),
            wear or WearSettings(),
            kinematic=kinematic,
        )
    fields = {f.name: getattr(base, f.name) for f in dataclasses.fields(base)}
    return PeakResponses(**fields, kinematic=kinematic)


def _responses(
    scheme: Scheme,
    mechanism: Mechanism,
    done: _Evaluated,
    names: tuple[str, ...],
    model: ResponseModel,
    limit: Mapping[str, float] | float | None,
    allowance: float | None,
) -> dict[str, FloatArray]:
    """Every response of a scheme's samples by name (``life`` added for running models)."""
    values = dict(zip(model.response_names, np.vstack(done.values).T, strict=True))
    if isinstance(model, RunningResponses):
        values["life"] = _life(
            scheme, mechanism, names, np.vstack(done.x), values, limit, allowance
        )
    return values


def _scheme_row(
    scheme: Scheme,
    mechanism: Mechanism,
    cost: CostModel,
    done: _Evaluated,
    names: tuple[str, ...],
    model: ResponseModel,
    check_names: Sequence[str],
    parsed: Sequence[Requirement],
    confidence: float,
    limit: Mapping[str, float] | float | None,
    allowance: float | None,
) -> dict[str, Any]:
    """One scheme's row: its budget, each response's statistics, and per requirement the
    failures, the yield and DPM with their exact intervals and the verdict."""
    status = np.concatenate(done.status)
    n = len(status)
    ok = status == OK
    values = _responses(scheme, mechanism, done, names, model, limit, allowance)
    row: dict[str, Any] = {
        "scheme": scheme.label,
        "fit": scheme.fit_label,
        **{f"fit_{j}": f for j, f in scheme.fits.items()},
        "length_class": scheme.length_class,
        "cost": scheme.cost(mechanism, cost),
        "samples": n,
        "ok": int(ok.sum()),
        "failed": int((~ok).sum()),
    }
    for name, y in values.items():
        good = y[ok & np.isfinite(y)]
        row[f"{name}_mean"] = float(good.mean()) if len(good) else math.nan
        row[f"{name}_std"] = float(good.std(ddof=1)) if len(good) > 1 else math.nan
        lower = name == "life" or any(r.response == name and not r.upper for r in parsed)
        at = quantile_value(np.where(ok, y, math.nan), confidence, upper=not lower)
        row[f"{name}_at_confidence"] = at.value
        row[f"{name}_at_confidence_basis"] = at.basis
    every = np.ones(n, dtype=bool)
    verdicts = []
    to_decide: list[int | None] = []
    for r in parsed:
        met = r.met(values[r.response]) & ok
        every &= met
        estimate = YieldEstimate(int(n - met.sum()), n)
        judged = verdict(estimate, r.confidence if r.confidence is not None else confidence)
        verdicts.append(judged.name)
        if judged.name == "undecided":
            to_decide.append(judged.samples_to_decide)
        row[f"failures_{r.text}"] = estimate.failures
        row.update(_yield_columns(estimate, f"_{r.text}"))
        row[f"verdict_{r.text}"] = judged.name
        row[f"samples_to_decide_{r.text}"] = judged.samples_to_decide
    row.update(_yield_columns(YieldEstimate(int(n - every.sum()), n), ""))
    row["verdict"] = (
        "fails" if "fails" in verdicts else "undecided" if "undecided" in verdicts else "meets"
    )
    row["verdict_basis"] = "monte-carlo"
    row["feasible"] = row["verdict"] == "meets"
    reachable = [m for m in to_decide if m is not None]
    row["samples_to_decide"] = (
        max(reachable) if reachable and len(reachable) == len(to_decide) else None
    )
    checks = np.vstack(done.checks)
    row.update(_scheme_penetration(check_names, checks, ok))
    return row


def _yield_columns(estimate: YieldEstimate, suffix: str) -> dict[str, float]:
    """``yield``, its interval ``yield_low``/``yield_high`` (%), ``dpm``, ``dpm_low``,
    ``dpm_high``, each name followed by ``suffix``."""
    low, high = estimate.interval
    dpm_low, dpm_high = estimate.dpm_interval
    return {
        f"yield{suffix}": 100.0 * estimate.value,
        f"yield_low{suffix}": 100.0 * low,
        f"yield_high{suffix}": 100.0 * high,
        f"dpm{suffix}": estimate.dpm,
        f"dpm_low{suffix}": dpm_low,
        f"dpm_high{suffix}": dpm_high,
    }


def _still_open(active: set[int], rows: Mapping[int, Mapping[str, Any]]) -> set[int]:
    """The schemes worth another round: undecided, and not dearer than a scheme already
    shown to meet every requirement (they can no longer be the cheapest feasible one)."""
    shown = [row["cost"] for row in rows.values() if row["feasible"]]
    ceiling = min(shown) if shown else math.inf
    return {
        i
        for i in active
        if i in rows and rows[i]["verdict"] == "undecided" and rows[i]["cost"] <= ceiling
    }


def _sample_frame(
    scheme: Scheme,
    done: _Evaluated,
    feature_names: Sequence[str],
    names: Sequence[str],
    values: Mapping[str, FloatArray],
    check_names: Sequence[str],
) -> pd.DataFrame:
    """One row per sample of a scheme: the features as made (``hole_<J>``, ``pin_<J>``
    diameters when sampled as parts), the model's inputs, the responses, the checks, the
    status."""
    frame = pd.DataFrame(np.vstack(done.features), columns=list(feature_names))
    x = np.vstack(done.x)
    for c, name in enumerate(names):
        frame[name] = x[:, c]
    frame.insert(0, "scheme", scheme.label)
    frame.insert(1, "sample", np.arange(len(frame)))
    for name, y in values.items():
        frame[name] = y
    checks = np.vstack(done.checks)
    for c, name in enumerate(check_names):
        frame[name] = checks[:, c]
    frame["status"] = [STATUS[int(s)] for s in np.concatenate(done.status)]
    frame["error"] = list(done.errors)
    return frame


def _life(
    scheme: Scheme,
    mechanism: Mechanism,
    names: Sequence[str],
    x: FloatArray,
    values: Mapping[str, FloatArray],
    limit: Mapping[str, float] | float | None,
    allowance: float | None,
) -> FloatArray:
    """Seconds until the first joint's clearance passes its limit at the sample's wear rate."""
    life = np.full(len(x), np.inf)
    if limit is None and allowance is None:
        return np.full(len(x), np.nan)
    for joint, fit in scheme.fits.items():
        if f"clearance_{joint}" not in names:
            continue
        if allowance is not None:
            bound = iso286.fit(fit, _diameter(mechanism, joint)).radial_clearance_max + allowance
        elif isinstance(limit, Mapping):
            bound = float(limit[joint])
        else:
            bound = float(limit)  # type: ignore[arg-type]
        c = x[:, list(names).index(f"clearance_{joint}")]
        rate = values[f"wear_rate_{joint}"]
        with np.errstate(divide="ignore", invalid="ignore"):
            t = np.where(c >= bound, 0.0, np.where(rate > 0, (bound - c) / rate, np.inf))
        life = np.fmin(life, np.where(np.isnan(rate), np.nan, t))
    return life


def _pareto(table: pd.DataFrame, requirements: Sequence[Requirement], names: Sequence[str]) -> None:
    """Mark the schemes on the Pareto front of cost against the yield and each response."""
    cost = table["cost"].to_numpy()

    def front(value: FloatArray) -> NDArray[np.bool_]:
        # minimise cost and value
        out = np.ones(len(value), dtype=bool)
        for i in range(len(value)):
            better = (
                (cost <= cost[i]) & (value <= value[i]) & ((cost < cost[i]) | (value < value[i]))
            )
            out[i] = not better.any()
        return out

    table["pareto_yield"] = front(-table["yield"].to_numpy())
    for name in (*names, "life"):
        column = f"{name}_at_confidence"
        if column not in table:
            continue
        lower = name == "life" or any(r.response == name and not r.upper for r in requirements)
        value = table[column].to_numpy(dtype=float)
        value = np.where(np.isnan(value), np.inf, -value if lower else value)
        table[f"pareto_{name}"] = front(value)
