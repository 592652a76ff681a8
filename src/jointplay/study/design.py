"""Tolerance synthesis through the dynamics: which fit and which length class to put on the
drawing.

:func:`design_study` evaluates every combination (a *scheme*) of an ISO 286 fit — one for all
pin joints, or one per named joint — and an ISO 2768-1 class for the link lengths:

1. a Monte Carlo of the link lengths (the class's ±deviation) and the radial clearances (the
   fit's limits), distributed as in the tolerance study (:mod:`jointplay.tolerance.spec`),
   with the same seed for every scheme (common random numbers: schemes differ by their
   tolerances, not by their luck);
2. each sample through the steady running dynamics (steady start, ``settle`` start-up
   revolutions left out) — or through the ideal-joint kinematics when every requirement is
   kinematic. When a requirement needs each sample's trajectory (``rocker_speed_error``,
   ``wear_rate``, ``life``: :func:`trajectory_requirements`), one single-engine simulation per
   sample (:class:`~jointplay.tolerance.responses.RunningResponses`); otherwise the batch
   engine (:class:`~jointplay.tolerance.responses.PeakResponses`), which runs on every
   backend, the GPU included, and gives the peaks, ``joint_force`` and ``contact_pressure``
   (the engines agree on forces within 1e-3, on ω peaks within their integration errors:
   docs/design.md);
3. per scheme: every response's mean, std and value at the confidence level; the share of
   samples meeting each requirement (yield %, defects per million; a failed simulation counts
   as a defect); the relative cost (:mod:`jointplay.tolerance.cost`);
4. the cheapest scheme meeting every requirement — or, if none does, the requirement that
   binds (the one whose best yield over all schemes is lowest) — and the Pareto fronts of cost
   against the yield and against each response;
5. dynamic studies: whether the samples are physical. Every sample's pin of each clearance
   joint must stay within its radial clearance (``penetration_ratio_<joint>``, the deepest
   penetration over the analysed revolutions / that sample's radial clearance, see
   :mod:`jointplay.tolerance.responses`); each scheme counts the successful samples beyond it
   (``penetration_exceeds_<joint>``) and keeps the largest ratio
   (``penetration_ratio_max_<joint>``), and :attr:`DesignResult.diagnostics` has one
   ``penetration-exceeds-clearance`` warning per joint concerned in some scheme
   (:class:`DesignDiagnostic`: how many samples of how many schemes, the worst ratio and its
   scheme, whether the recommended scheme is among them).

All samples of all schemes run as one batch on one backend
(:func:`jointplay.tolerance.execution.run`), scheme after scheme: Ctrl-C keeps the schemes
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

from jointplay.dynamics.cycles import DEFAULT_SETTLE
from jointplay.errors import ConfigError
from jointplay.model.mechanism import Mechanism, RevoluteJoint
from jointplay.study.requirements import Requirement, parse_requirement
from jointplay.tolerance import iso286, iso2768
from jointplay.tolerance.analysis import (
    ConvergenceCheck,
    StudyDiagnostic,
    convergence_finding,
    penetration_warning,
    study_contact,
)
from jointplay.tolerance.cost import CostModel, fit_cost, length_class_cost
from jointplay.tolerance.definitions import response_definitions
from jointplay.tolerance.execution import NOT_RUN, OK, STATUS, Backend, run
from jointplay.tolerance.methods import distribution_note, truncated_at_limits
from jointplay.tolerance.responses import (
    ELASTIC_RATIO,
    PENETRATION_RATIO,
    RUNNING_RESPONSES,
    PeakResponses,
    ResponseModel,
    RunningResponses,
    dynamic_model,
    kinematic_model,
)
from jointplay.tolerance.sampling import sample
from jointplay.tolerance.spec import (
    DEFAULT_DISTRIBUTION,
    InputTolerance,
    JointTolerance,
    LinkTolerance,
    ToleranceSpec,
    in_template_order,
    template_lengths,
)

if TYPE_CHECKING:
    from jointplay.contact.laws import ContactLaw
    from jointplay.dynamics.setup import ContactModel
    from jointplay.dynamics.simulate import SolverOptions
    from jointplay.dynamics.wear import WearSettings

__all__ = [
    "DEFAULT_CONFIDENCE",
    "DERIVED_RESPONSES",
    "DesignDiagnostic",
    "DesignResult",
    "Scheme",
    "design_study",
    "design_units",
    "penetration_diagnostics",
    "resolve_responses",
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

    def spec(self, mechanism: Mechanism, distribution: str = DEFAULT_DISTRIBUTION) -> ToleranceSpec:
        """The toleranced inputs of this scheme (lengths of the class, clearances of the fits)."""
        nominal = template_lengths(mechanism)
        lengths: list[InputTolerance] = [
            LinkTolerance.general(name, value, self.length_class, distribution=distribution)  # type: ignore[arg-type]
            for name, value in nominal.items()
            if abs(value) >= 0.5e-3
        ]
        joints: list[InputTolerance] = []
        for joint, fit in self.fits.items():
            diameter = _diameter(mechanism, joint)
            joints.append(
                JointTolerance.from_fit(joint, fit, diameter, distribution=distribution)  # type: ignore[arg-type]
            )
        return ToleranceSpec(tuple(in_template_order(lengths, nominal)) + tuple(joints))

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
                    raise ConfigError(f"joint {joint!r} has no fit: name one (--fit {joint}=H7/g6)")
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


def resolve_responses(
    mechanism: Mechanism,
    requirements: Sequence[str | Requirement],
    responses: Literal["auto", "kinematic", "dynamic"] = "auto",
) -> Literal["kinematic", "dynamic"]:
    """The response model a design study runs: ``responses`` itself, or for ``"auto"``
    kinematic when every requirement (as text) names a kinematic response, else dynamic.

    Raises:
        ConfigError: a malformed requirement.
    """
    if responses != "auto":
        return responses
    units = design_units(mechanism, "kinematic")
    kinematic = bool(requirements) and all(
        isinstance(r, str) and parse_requirement_or_none(r, units) is not None for r in requirements
    )
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
            "--stiffness-law)"
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
        samples: one row per sample of the finished schemes: scheme, inputs, responses,
            dynamic studies' ``penetration_ratio_<joint>`` (dimensionless; above 1: not
            physical), status.
        best: label of the cheapest scheme meeting every requirement, or ``None``.
        binding: when none does: the requirement whose best yield is lowest.
        interrupted: Ctrl-C stopped the run; only finished schemes are in ``table``.
        settings: samples, seed, model description, cost model, clearance limits.
        diagnostics: plausibility warnings over the samples of the finished schemes
            (:func:`penetration_diagnostics`, then the ``peaks-not-converged`` warning of
            :attr:`convergence`); empty when every sample is physical and converged, and for
            kinematic studies.
        convergence: dynamic studies: the integrator's share of the responses' scatter
            (:func:`~jointplay.tolerance.analysis.convergence_finding`, over every scheme's
            samples; ``None`` when not checked).
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

    def to_dataframe(self) -> pd.DataFrame:
        """One row per scheme (the content of ``design.parquet``)."""
        return self.table.copy()

    @property
    def best_row(self) -> Mapping[str, Any] | None:
        if self.best is None:
            return None
        row = self.table[self.table["scheme"] == self.best].iloc[0]
        return {k: (v.item() if hasattr(v, "item") else v) for k, v in row.items()}  # type: ignore[misc]

    def summary(self) -> dict[str, Any]:
        """The ``summary.json`` content (SI)."""
        if self.best is not None:
            verdict = f"cheapest scheme meeting every requirement: {self.best}"
        elif self.binding is not None:
            verdict = f"no scheme meets every requirement; binding requirement: {self.binding}"
        else:
            verdict = "no finished scheme"
        records = [
            {k: (v.item() if hasattr(v, "item") else v) for k, v in row.items()}
            for row in self.table.to_dict(orient="records")
        ]
        return {
            "mechanism": self.mechanism.name,
            "responses_kind": self.responses,
            "confidence": self.confidence,
            "requirements": [r.describe() for r in self.requirements],
            "verdict": verdict,
            "best": self.best,
            "best_scheme": self.best_row,
            "binding": self.binding,
            "interrupted": self.interrupted,
            "settings": dict(self.settings),
            "response_definitions": response_definitions(self.reported_responses),
            "schemes": records,
            "diagnostics": [finding.as_dict() for finding in self.diagnostics],
            "convergence_check": None if self.convergence is None else self.convergence.as_dict(),
        }

    @property
    def reported_responses(self) -> tuple[str, ...]:
        """The responses the scheme table reports: those the requirements name, in order."""
        names = [r.response for r in self.requirements]
        return tuple(dict.fromkeys(names))


def design_study(
    mechanism: Mechanism,
    fits: Sequence[str | Mapping[str, str]],
    classes: Sequence[str],
    requirements: Sequence[str | Requirement],
    *,
    samples: int = 200,
    seed: int = 0,
    confidence: float = DEFAULT_CONFIDENCE,
    responses: Literal["auto", "kinematic", "dynamic"] = "auto",
    cost: CostModel | None = None,
    clearance_limit: Mapping[str, float] | float | None = None,
    clearance_allowance: float | None = None,
    wear: WearSettings | None = None,
    contact: str | ContactLaw | ContactModel | None = None,
    settle: int = DEFAULT_SETTLE,
    revolutions: float = 1.0,
    solver: SolverOptions | None = None,
    distribution: str = DEFAULT_DISTRIBUTION,
    truncate: bool = True,
    backend: Backend | None = None,
    progress: bool = False,
) -> DesignResult:
    """Find the cheapest fit and length class meeting ``requirements``.

    Args:
        mechanism: the nominal mechanism (template four-bar or slider-crank; pin joints with
            a diameter).
        fits: candidate fits: text (every joint) or a mapping joint → fit.
        classes: candidate ISO 2768-1 classes.
        requirements: requirements as text (:mod:`jointplay.study.requirements`) or objects.
        samples: Monte Carlo samples per scheme.
        seed: the seed (the same for every scheme).
        confidence: share of samples that must meet a requirement without its own ``@``.
        responses: ``"dynamic"`` (clearance joints, steady running), ``"kinematic"`` (ideal
            joints, lengths only) or ``"auto"`` (kinematic when every requirement is).
        cost: the cost–tolerance model (default :class:`CostModel`).
        clearance_limit: radial clearance limit for ``life``, m (one for all, or per joint).
        clearance_allowance: instead: the fit's largest radial clearance plus this, m.
        wear: Archard parameters (default steel on steel, :mod:`jointplay.dynamics.wear`).
        contact: dynamic: a :class:`~jointplay.dynamics.setup.ContactModel` (the physical
            default: ``ContactModel()``), a contact law, or ``None``: the conventional IFM set
            (:func:`jointplay.tolerance.analysis.study_contact`).
        settle, revolutions: dynamic: start-up revolutions left out, analysed revolutions.
        solver: dynamic: integration settings (default :class:`SolverOptions`).
        distribution: distribution of every toleranced input.
        truncate: draw normal inputs from the normal truncated at their limits (default:
            out-of-tolerance parts are rejected at inspection;
            :func:`jointplay.tolerance.methods.truncated_at_limits`), else untruncated.
        backend: where the samples run (default local processes).
        progress: show a progress bar.

    Raises:
        ConfigError: a malformed requirement, an unknown response, bad candidates.
    """
    if not 0.0 < confidence < 1.0:
        raise ConfigError(f"confidence must lie between 0 and 100 %, got {100 * confidence:g} %")
    cost = cost or CostModel()
    candidates = schemes(mechanism, fits, classes)
    kinematic_units = design_units(mechanism, "kinematic")
    dynamic_units = design_units(mechanism, "dynamic")
    responses = resolve_responses(mechanism, requirements, responses)
    # A dynamic study gives the ideal-joint kinematic responses of each sample's lengths too,
    # so requirements may mix them (the dynamic peaks keep their own names).
    units = kinematic_units if responses == "kinematic" else {**kinematic_units, **dynamic_units}
    parsed = tuple(
        r if isinstance(r, Requirement) else parse_requirement(r, units) for r in requirements
    )
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

    # one batch: every scheme's samples, scheme after scheme
    specs = [s.spec(mechanism, distribution) for s in candidates]
    if responses == "kinematic":
        specs = [s.only("length") for s in specs]
    names = specs[0].names
    model: ResponseModel
    if responses == "kinematic":
        model = kinematic_model(mechanism, names)
        # fits do not move ideal joints: evaluate each length class once
        unique: dict[str, int] = {}
        for i, scheme in enumerate(candidates):
            unique.setdefault(scheme.length_class, i)
        order = list(unique.values())
    else:
        from jointplay.dynamics.simulate import SolverOptions, Start
        from jointplay.dynamics.wear import OutputSpeedReference, WearSettings

        base = dynamic_model(
            mechanism,
            names,
            **study_contact(mechanism, contact),
            start=Start("steady"),
            settle=settle,
            revolutions=revolutions,
            solver=solver or SolverOptions(),
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
            model = RunningResponses(
                base,
                OutputSpeedReference.of(mechanism),
                wear or WearSettings(),
                kinematic=kinematic,
            )
        else:
            fields = {f.name: getattr(base, f.name) for f in dataclasses.fields(base)}
            model = PeakResponses(**fields, kinematic=kinematic)
        order = list(range(len(candidates)))
    drawn = [truncated_at_limits(specs[i]) if truncate else specs[i] for i in order]
    blocks = [sample(spec, samples, seed).values for spec in drawn]
    outcome = run(model, np.vstack(blocks), backend=backend, progress=progress)
    response_names = tuple(model.response_names)

    rows = []
    sample_frames = []
    evaluated = {index: k for k, index in enumerate(order)}
    for i, scheme in enumerate(candidates):
        k = evaluated[
            i if responses == "dynamic" else order[list(unique).index(scheme.length_class)]
        ]
        part = slice(k * samples, (k + 1) * samples)
        status = outcome.status[part]
        if np.any(status == NOT_RUN):
            continue  # interrupted before this scheme finished
        x = blocks[k]
        values = dict(zip(response_names, outcome.values[part].T, strict=True))
        if isinstance(model, RunningResponses):
            values["life"] = _life(
                scheme, mechanism, names, x, values, clearance_limit, clearance_allowance
            )
        ok = status == OK
        checks = outcome.checks[part] if outcome.checks is not None else np.empty((samples, 0))
        row: dict[str, Any] = {
            "scheme": scheme.label,
            "fit": scheme.fit_label,
            **{f"fit_{j}": f for j, f in scheme.fits.items()},
            "length_class": scheme.length_class,
            "cost": scheme.cost(mechanism, cost),
            "samples": samples,
            "ok": int(ok.sum()),
            "failed": int((~ok).sum()),
        }
        for name, y in values.items():
            good = y[ok & np.isfinite(y)]
            row[f"{name}_mean"] = float(good.mean()) if len(good) else math.nan
            row[f"{name}_std"] = float(good.std(ddof=1)) if len(good) > 1 else math.nan
            lower = name == "life" or any(r.response == name and not r.upper for r in parsed)
            q = 1.0 - confidence if lower else confidence
            row[f"{name}_at_confidence"] = float(np.quantile(good, q)) if len(good) else math.nan
        every = np.ones(samples, dtype=bool)
        feasible = True
        for r in parsed:
            met = r.met(values[r.response]) & ok
            every &= met
            level = r.confidence if r.confidence is not None else confidence
            share = float(met.mean())
            row[f"yield_{r.text}"] = 100.0 * share
            row[f"dpm_{r.text}"] = 1e6 * (1.0 - share)
            row[f"meets_{r.text}"] = share >= level - 1e-12
            feasible &= row[f"meets_{r.text}"]
        row["yield"] = 100.0 * float(every.mean())
        row["dpm"] = 1e6 * (1.0 - float(every.mean()))
        row["feasible"] = bool(feasible)
        row.update(_scheme_penetration(outcome.check_names, checks, ok))
        rows.append(row)
        frame = pd.DataFrame(x, columns=list(names))
        frame.insert(0, "scheme", scheme.label)
        frame.insert(1, "sample", np.arange(samples))
        for name, y in values.items():
            frame[name] = y
        for c, name in enumerate(outcome.check_names):
            frame[name] = checks[:, c]
        frame["status"] = [STATUS[int(s)] for s in status]
        frame["error"] = list(outcome.errors[part])
        sample_frames.append(frame)
    table = pd.DataFrame(rows)
    best = binding = None
    if len(table):
        _pareto(table, parsed, response_names)
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
    settings = {
        "samples": samples,
        "seed": seed,
        "distribution": distribution,
        "truncated_at_limits": bool(truncate),
        "sampling_distributions": distribution_note(drawn[0], truncate) if drawn else "",
        "responses": responses,
        "cost_model": cost.describe(),
        "clearance_limit_m": clearance_limit,
        "clearance_allowance_m": clearance_allowance,
        "model": model.describe(),
        "execution": outcome.describe(),
        "schemes": len(candidates),
        "finished_schemes": len(rows),
    }
    every_sample = pd.concat(sample_frames, ignore_index=True) if sample_frames else pd.DataFrame()
    convergence = (
        None
        if outcome.interrupted or responses == "kinematic"
        else convergence_finding(model, np.vstack(blocks), outcome, backend)
    )
    diagnostics: tuple[StudyDiagnostic, ...] = penetration_diagnostics(
        every_sample, outcome.check_names, names, best
    )
    if convergence is not None and convergence.finding is not None:
        diagnostics = (*diagnostics, convergence.finding)
    return DesignResult(
        mechanism=mechanism,
        responses=responses,
        requirements=parsed,
        confidence=confidence,
        table=table,
        samples=every_sample,
        best=best,
        binding=binding,
        interrupted=outcome.interrupted,
        settings=settings,
        diagnostics=diagnostics,
        convergence=convergence,
    )


def parse_requirement_or_none(text: str, units: Mapping[str, str]) -> Requirement | None:
    """The requirement if ``text`` names one of ``units``' responses, else ``None``
    (malformed text still raises)."""
    try:
        return parse_requirement(text, units)
    except ConfigError as exc:
        if "unknown response" in str(exc):
            return None
        raise


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
