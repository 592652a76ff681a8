"""The tolerance study of a mechanism: one call from the mechanism to the answer.

:func:`tolerance_study` picks the response model (kinematic: ideal joints, toleranced
lengths; dynamic: clearance joints, toleranced lengths and clearances), runs the method
(:mod:`jointplay.tolerance.methods`, a name or an instance) on a backend
(:mod:`jointplay.tolerance.execution`) and returns a frozen :class:`ToleranceStudyResult`:
one row per evaluated point (:meth:`~ToleranceStudyResult.to_dataframe`) and the statistics
(:meth:`~ToleranceStudyResult.summary`), all SI. Files, plots and the HTML report are
:mod:`jointplay.report.tolerance`'s.

A result that is not physical is flagged: dynamic and running studies check every sample's
penetration (``penetration_ratio_<joint>``, see :mod:`jointplay.tolerance.responses`), and
:attr:`ToleranceStudyResult.diagnostics` has one ``penetration-exceeds-clearance`` warning
per clearance joint whose pin sinks deeper than the radial clearance in some successful
samples (:func:`penetration_findings`): how many, the worst ratio and its sample. They also
check that the scatter they report is the mechanism's, not the integrator's
(:func:`convergence_finding`): a few successful samples are run again with tolerances 100×
tighter, and a ``peaks-not-converged`` warning names the response whose values moved by more
than a tenth of their spread over the study, with the shift of their mean and its interval:
a shift says the integration biases the study, single samples moving about an unshifted mean
say the motion is sensitive (a settled peak is one draw of its scatter). The warning ends with
a verdict (:func:`convergence_verdict`): usable only where the mean is shown to stay within
the same tenth of the spread. Where every sample that moved runs irregularly (dry joints
rattle: the single engine's periodicity check), the study is judged instead on the statistics
it reports — the mean and 95th percentile of each response over 16 samples run again, each
within the interval of a paired randomization test — with a ``statistics-converged`` note or
a ``statistics-not-converged`` warning (docs/cli.md, "Converged?").
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass
from functools import cached_property
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from jointplay.dynamics.diagnostics import Diagnostic, Level
from jointplay.dynamics.irregular import PairedShift
from jointplay.errors import ConfigError, PartialInterrupt, name_settings
from jointplay.model.mechanism import Mechanism
from jointplay.tolerance.execution import OK, STATUS, Backend, RunResult, prepare
from jointplay.tolerance.methods import (
    Failure,
    MethodResult,
    ResponseSummary,
    SpecLimits,
    ToleranceMethod,
    get_method,
)
from jointplay.tolerance.response_base import REGIME_DEFINITION, regime_fractions
from jointplay.tolerance.responses import (
    ELASTIC_RATIO,
    PENETRATION_RATIO,
    DynamicResponses,
    ResponseModel,
    RunningResponses,
    contact_parts,
    kinematic_model,
    run_model,
)
from jointplay.tolerance.spec import JointTolerance, ToleranceSpec

if TYPE_CHECKING:  # the dynamics import Numba: loaded only by dynamic studies
    from jointplay.contact.friction import FrictionLaw
    from jointplay.contact.laws import ContactLaw
    from jointplay.dynamics.settings import RunSettings
    from jointplay.dynamics.setup import ContactModel
    from jointplay.dynamics.simulate import SolverOptions, Start

__all__ = [
    "RESPONSE_KINDS",
    "ConvergenceCheck",
    "StudyDiagnostic",
    "ToleranceStudyResult",
    "build_model",
    "convergence_finding",
    "penetration_findings",
    "penetration_warning",
    "response_units",
    "tolerance_study",
]

ResponseKind = Literal["kinematic", "dynamic", "running"]
FloatArray = NDArray[np.float64]

#: Response kinds of :func:`tolerance_study`.
RESPONSE_KINDS: tuple[str, ...] = ("kinematic", "dynamic")

#: How many failures summary.json lists in full (samples.parquet has every one).
MAX_LISTED_FAILURES = 1000


@dataclass(frozen=True)
class StudyDiagnostic:
    """A plausibility finding over the points of a study.

    Attributes:
        diagnostic: the finding in the words of :mod:`jointplay.dynamics.diagnostics`
            (level, code, joint, message); ``value`` is the worst point's ratio and ``limit``
            the ratio it must not pass (1 for ``penetration-exceeds-clearance``).
        count: successful points concerned.
        out_of: successful points checked.
        worst_sample: row of the worst point (the ``sample`` column of ``samples.parquet``).
        worst_inputs: its inputs, SI.
    """

    diagnostic: Diagnostic
    count: int
    out_of: int
    worst_sample: int
    worst_inputs: Mapping[str, float]

    @property
    def share(self) -> float:
        """``count / out_of``."""
        return self.count / self.out_of if self.out_of else 0.0

    def line(self, names: Mapping[str, str] | None = None) -> str:
        """One console line (as :meth:`Diagnostic.line`, ``names`` too)."""
        return self.diagnostic.line(names)

    def as_dict(self) -> dict[str, Any]:
        """JSON-ready: the diagnostic's record plus ``count``, ``out_of``, ``share``,
        ``worst_sample`` and ``worst_inputs``."""
        return {
            **self.diagnostic.as_dict(),
            "count": self.count,
            "out_of": self.out_of,
            "share": self.share,
            "worst_sample": self.worst_sample,
            "worst_inputs": dict(self.worst_inputs),
        }


def penetration_warning(joint: str, worst_ratio: float, message: str) -> Diagnostic:
    """The ``penetration-exceeds-clearance`` warning of a study: ``value`` the worst point's
    penetration / clearance ratio, ``limit`` 1."""
    return Diagnostic("warning", "penetration-exceeds-clearance", joint, worst_ratio, 1.0, message)


def penetration_findings(result: MethodResult) -> tuple[StudyDiagnostic, ...]:
    """One ``penetration-exceeds-clearance`` warning per clearance joint whose pin, in some
    successful points, sinks deeper into its bearing than the radial clearance
    (``penetration_ratio_<joint>`` > 1), and one ``penetration-exceeds-elastic`` warning per
    joint whose pin sinks deeper than :data:`~jointplay.dynamics.diagnostics.ELASTIC_FACTOR`
    times its Hertz approach at the peak force (``elastic_ratio_<joint>``); none for a model
    without these checks.

    The single engine's :func:`jointplay.dynamics.diagnostics.check_penetration` and
    ``check_elastic`` judge one simulation; this counts the points of a study and names the
    worst.
    """
    from jointplay.dynamics.diagnostics import ELASTIC_FACTOR

    run = result.run
    if run.checks is None:
        return ()
    ok = run.status == OK
    noun = "samples" if result.method == "monte-carlo" else "points"
    findings = []
    for column, name in enumerate(run.check_names):
        if name.startswith(PENETRATION_RATIO):
            joint, limit = name.removeprefix(PENETRATION_RATIO), 1.0
        elif name.startswith(ELASTIC_RATIO):
            joint, limit = name.removeprefix(ELASTIC_RATIO), ELASTIC_FACTOR
        else:
            continue
        ratio = np.where(ok, run.checks[:, column], np.nan)
        exceeds = ratio > limit  # NaN compares False
        count = int(np.sum(exceeds))
        if count == 0:
            continue
        worst = int(np.argmax(np.where(exceeds, ratio, -np.inf)))
        out_of = int(np.sum(ok))
        share = f"{count} of {out_of} {noun} ({100.0 * count / out_of:.3g} %)"
        where = f"(sample {worst}; {name} in samples.parquet)"
        if limit == 1.0:
            diagnostic = penetration_warning(
                joint,
                float(ratio[worst]),
                f"{share}: the pin of {joint} penetrates its bearing by up to "
                f"{ratio[worst]:.3g} times the radial clearance {where}; those {noun}' peaks "
                "are not physical: the contact stiffness is far too low for the load; use a "
                "stiffness from the joints' geometry (the default contact, or a stiffness law)",
            )
        else:
            diagnostic = Diagnostic(
                "warning",
                "penetration-exceeds-elastic",
                joint,
                float(ratio[worst]),
                limit,
                f"{share}: the pin of {joint} penetrates its bearing by up to "
                f"{ratio[worst]:.3g} times the elastic approach of the joint's own Hertz law "
                f"at its peak force {where}: the contact is far softer than the joint's "
                "materials; use a stiffness from the joints' geometry (the default contact, "
                "or a stiffness law)",
            )
        findings.append(
            StudyDiagnostic(
                diagnostic,
                count=count,
                out_of=out_of,
                worst_sample=worst,
                worst_inputs=dict(
                    zip(result.input_names, map(float, result.x[worst]), strict=True)
                ),
            )
        )
    return tuple(findings)


#: Samples run again by :func:`convergence_finding`, the fewest successful points a study needs
#: for the check (a spread from fewer is not worth comparing with, and the check would cost
#: more than half the study: each sample costs ~2.5 at tolerances 100x tighter), the factor on
#: their tolerances, and the share of a response's spread over the study its change may reach.
CONVERGENCE_SAMPLES = 8
CONVERGENCE_MIN_POINTS = 40
CONVERGENCE_TIGHTENING = 100.0
CONVERGENCE_LIMIT = 0.1
#: Family-wise confidence of the mean shifts' intervals (Bonferroni over the responses), and
#: of the statistics' intervals of irregular motion (over the responses and statistics).
CONVERGENCE_CONFIDENCE = 0.95
#: Samples run again in all when every sample that moved runs irregularly: the statistics
#: over them are judged (:func:`jointplay.dynamics.irregular.paired_shifts`; 16 pairs give
#: 65 536 swap patterns, enough to judge 2 statistics of up to ~800 responses at 95 %).
CONVERGENCE_STATISTIC_SAMPLES = 16
#: Analysed revolutions (at least) of the single-engine run that classifies the motion of a
#: sample that moved (its periodicity check: a period of k revolutions shows in 2k + 1).
MOTION_REVOLUTIONS = 8

#: The rules of :func:`convergence_finding`, in words (``summary.json``).
RULES = {
    "per-sample": (
        "each sample run again must move by at most the limit's share of the response's "
        "spread over the study; where some moved, their mean's shift decides whether the "
        "statistics are usable (convergence_verdict)"
    ),
    "statistics": (
        "every sample that moved beyond the limit runs irregularly (its once-per-revolution "
        "Poincare section does not repeat over the classifying run: each peak is a draw), so "
        "the statistics the study reports are judged instead: the mean and the 95th "
        "percentile of each response over the samples run again, default against tight, "
        "each against the interval of a paired randomization test (the two values of each "
        "sample swapped in all 2^n patterns); under the hypothesis that the tolerances change "
        "only the draw, the chance that any statistic moves beyond its interval is at most "
        "5 % (each at 5 % / the number judged, Bonferroni); a bias larger than about the "
        "interval is found, a smaller one is not resolved by these samples"
    ),
}


@dataclass(frozen=True)
class ConvergenceCheck:
    """What :func:`convergence_finding` measured (``summary.json`` → ``convergence_check``).

    Attributes:
        samples: successful points run again.
        tightening: the factor on every integration tolerance.
        response: the response whose change was the largest share of its spread.
        share: that share (largest change / standard deviation over the study's successful
            points).
        limit: the share above which a sample moved.
        finding: the ``peaks-not-converged`` (per-sample rule) or
            ``statistics-not-converged`` (statistics rule) warning, or ``None``.
        mean_shift: that response's mean change over the samples run again (tight − default),
            over its spread; where single samples move but this does not, the motion is
            sensitive (each settled peak one draw of its revolution-to-revolution scatter,
            ``docs/contact.md``) rather than the integration biased.
        mean_shift_interval: its confidence interval (Student t over the samples run again,
            :data:`CONVERGENCE_CONFIDENCE` family-wise over the responses compared, Bonferroni),
            over the spread; a shift beyond it would have shown.
        usable: whether the study's statistics are usable by the rule of
            :func:`convergence_verdict` (always when it converged).
        verdict: that verdict in words (how far the peaks, or their mean, moved).
        rule: the rule that judged the study (:data:`RULES`): ``"per-sample"`` or
            ``"statistics"``.
        moved: samples run again that moved by more than :attr:`limit` of a spread.
        irregular: of those, the samples whose motion is irregular (classified by the single
            engine's periodicity check over :data:`MOTION_REVOLUTIONS` revolutions).
        statistics: the statistics rule: per response, the move of its mean and of its 95th
            percentile over the samples run again, with their intervals (SI).
        note: the statistics rule's ``statistics-converged`` information (the output's
            sentence saying which rule judged), or ``None``.
    """

    samples: int
    tightening: float
    response: str
    share: float
    limit: float
    finding: StudyDiagnostic | None
    mean_shift: float = float("nan")
    mean_shift_interval: tuple[float, float] = (float("nan"), float("nan"))
    usable: bool = True
    verdict: str = ""
    rule: str = "per-sample"
    moved: int = 0
    irregular: int = 0
    statistics: Mapping[str, tuple[PairedShift, ...]] = dataclasses.field(default_factory=dict)
    note: StudyDiagnostic | None = None

    def as_dict(self) -> dict[str, Any]:
        return {
            "samples": self.samples,
            "tolerances_tightened_by": self.tightening,
            "response": self.response,
            "largest_change_over_spread": self.share,
            "taken": (
                f"the first {self.samples} successful samples run again with every integration "
                f"tolerance {self.tightening:g}x tighter; the largest change of each response "
                "over its standard deviation across the study's successful samples; the "
                "response with the largest share is reported"
            ),
            "limit": self.limit,
            "converged": self.finding is None,
            "usable": self.usable,
            "verdict": self.verdict,
            "rule": self.rule,
            "rule_taken": RULES[self.rule],
            "moved_samples": self.moved,
            "irregular_samples": self.irregular,
            "statistics": {
                name: {s.statistic: s.as_dict() for s in shifts}
                for name, shifts in self.statistics.items()
            },
            "mean_change_over_spread": self.mean_shift,
            "mean_change_interval_over_spread": list(self.mean_shift_interval),
            "mean_change_taken": (
                f"the mean of the {self.samples} samples' changes (tight - default) of the same "
                f"response over its standard deviation across the study; the interval a "
                f"Student t interval at {100 * CONVERGENCE_CONFIDENCE:.0f} % family-wise over the "
                "responses compared (Bonferroni)"
            ),
        }


def _rerun_finding(
    diagnostic: Diagnostic, count: int, rows: Any, worst: int, model: Any, x: FloatArray
) -> StudyDiagnostic:
    """The convergence check's finding: ``count`` of the re-run samples ``rows`` concerned,
    the worst one (a row of ``x``) named with its inputs."""
    return StudyDiagnostic(
        diagnostic,
        count=count,
        out_of=len(rows),
        worst_sample=worst,
        worst_inputs=dict(zip(model.input_names, map(float, x[worst]), strict=True)),
    )


def convergence_finding(
    model: ResponseModel, x: FloatArray, outcome: RunResult, backend: Backend | None = None
) -> ConvergenceCheck | None:
    """Whether the scatter of a dynamic study's responses is the mechanism's, not the
    integrator's.

    ``x`` are the study's points and ``outcome`` their run
    (:func:`jointplay.tolerance.execution.run` of ``model``). The first
    :data:`CONVERGENCE_SAMPLES` successful points are evaluated again with every integration
    tolerance :data:`CONVERGENCE_TIGHTENING` times tighter (on ``backend``, or here for the
    GPU). Each response's largest change is compared with its spread over the
    study (the standard deviation of its successful points); the response with the largest
    share is recorded. Within :data:`CONVERGENCE_LIMIT` the study converged (the per-sample
    rule). Beyond it, the samples that moved are classified by the single engine's
    periodicity check (settle and :data:`MOTION_REVOLUTIONS` analysed revolutions, at the
    tightened tolerances: :func:`_motions`):

    - where one of them runs periodically (or its class is unknown), the per-sample rule
      judges: a ``peaks-not-converged`` warning (``value`` the share, ``limit`` the limit)
      with the verdict of :func:`convergence_verdict`;
    - where all of them run irregularly, each peak is a draw and the statistics the study
      reports are judged instead (the statistics rule, :data:`RULES`): the samples run again
      grow to :data:`CONVERGENCE_STATISTIC_SAMPLES` (those that move among the new ones are
      classified too), and the mean and 95th percentile of every response over them, default
      against tight, must move within their paired randomization intervals
      (:func:`jointplay.dynamics.irregular.paired_shifts`, :data:`CONVERGENCE_CONFIDENCE`
      family-wise): a ``statistics-converged`` note (usable) or a
      ``statistics-not-converged`` warning (not usable: the integration biases the
      statistics).

    ``None`` for models without an integrator (kinematic, custom) and for studies with fewer
    than :data:`CONVERGENCE_MIN_POINTS` successful points.
    """
    dynamic = model.base if isinstance(model, RunningResponses) else model
    if not isinstance(dynamic, DynamicResponses):
        return None
    ok = np.flatnonzero(outcome.status == OK)
    if len(ok) < CONVERGENCE_MIN_POINTS:
        return None
    rows = ok[:CONVERGENCE_SAMPLES]
    tightened, tight_rtol = _tightened(model, dynamic)
    where = Backend("local") if backend is None or backend.on_device else backend
    again = _run_again(tightened, x[rows], where)
    if again is None:
        return None
    values = outcome.values
    with np.errstate(divide="ignore", invalid="ignore"):
        spread = np.nanstd(values[ok], axis=0, ddof=1)
    moves = _moves(values[rows], again, spread)
    if np.all(np.isnan(moves.share)):
        return None
    j = int(np.nanargmax(moves.share))
    name = model.response_names[j]
    compared = int(np.sum(~np.isnan(moves.share)))
    if moves.share[j] <= CONVERGENCE_LIMIT:
        shift, interval = _mean_shift(moves.signed[:, j], spread[j], compared)
        verdict = (
            f"usable: the peaks moved at most {100 * moves.share[j]:.0f} % of their spread "
            f"({name}), within the ±{100 * CONVERGENCE_LIMIT:.0f} % limit"
        )
        return ConvergenceCheck(
            len(rows), CONVERGENCE_TIGHTENING, name, float(moves.share[j]), CONVERGENCE_LIMIT,
            None, shift, interval, True, verdict,
        )  # fmt: skip
    # some samples moved: the class of their motion decides the rule
    # classified at the tight tolerances: a coarse integration can make a periodic motion
    # look irregular, and the per-sample rule must hold it
    tight_dynamic = tightened.base if isinstance(tightened, RunningResponses) else tightened
    assert isinstance(tight_dynamic, DynamicResponses)
    motions = _motions(tight_dynamic, x[rows[moves.moved]])
    if all(motion == "irregular" for motion in motions):
        more = ok[len(rows) : CONVERGENCE_STATISTIC_SAMPLES]
        if len(more):
            extra = _run_again(tightened, x[more], where)
            if extra is not None:
                rows = np.concatenate([rows, more])
                again = _concatenate(again, extra)
                added = _moves(values[more], extra, spread)
                motions = [*motions, *_motions(tight_dynamic, x[more[added.moved]])]
                moves = _moves(values[rows], again, spread)
                j = int(np.nanargmax(moves.share))
                name = model.response_names[j]
    irregular = sum(motion == "irregular" for motion in motions)
    if irregular == len(motions):
        return _statistics_check(
            model, x, values, rows, again, spread, moves, name, tight_rtol, irregular
        )
    return _per_sample_check(
        model, x, rows, spread, moves, j, tight_rtol, compared, motions, irregular
    )


@dataclass(frozen=True)
class _Moves:
    """The paired changes of the samples run again (tight − default) and their largest share
    of each response's spread (NaN where unknown); ``moved``: the samples whose change
    exceeds :data:`CONVERGENCE_LIMIT` of a spread."""

    signed: FloatArray
    change: FloatArray
    largest: FloatArray
    share: FloatArray
    moved: NDArray[np.bool_]


def _moves(default: FloatArray, again: RunResult, spread: FloatArray) -> _Moves:
    with np.errstate(divide="ignore", invalid="ignore"):
        signed = again.values - default
        signed[again.status != OK] = np.nan
        change = np.abs(signed)
        # the largest change per response, NaN where none is known (np.nanmax warns there)
        known = ~np.isnan(change)
        largest = np.where(known.any(axis=0), np.max(np.where(known, change, 0.0), axis=0), np.nan)
        share = np.where(spread > 0, largest / spread, np.nan)
        moved = np.any(change > CONVERGENCE_LIMIT * np.where(spread > 0, spread, np.inf), axis=1)
    return _Moves(signed, change, largest, share, moved)


def _tightened(model: ResponseModel, dynamic: DynamicResponses) -> tuple[ResponseModel, float]:
    """``model`` with every integration tolerance :data:`CONVERGENCE_TIGHTENING` times
    tighter, and its relative tolerance."""
    loose = dynamic.solver
    tight = dataclasses.replace(
        loose,
        rtol=loose.rtol / CONVERGENCE_TIGHTENING,
        atol_position=loose.atol_position / CONVERGENCE_TIGHTENING,
        atol_velocity=loose.atol_velocity / CONVERGENCE_TIGHTENING,
    )
    tight_dynamic = dataclasses.replace(dynamic, solver=tight)
    if isinstance(model, RunningResponses):
        return dataclasses.replace(model, base=tight_dynamic), tight.rtol
    return tight_dynamic, tight.rtol


def _run_again(model: ResponseModel, x: FloatArray, where: Backend) -> RunResult | None:
    """The run of ``x`` with ``model``; ``None`` where none ran (e.g. a Dask cluster lost)."""
    from jointplay.tolerance.execution import run

    again = run(model, x, backend=where)
    if again.interrupted:  # a check of some samples is no check
        raise KeyboardInterrupt("interrupted during the convergence check")
    if not np.any(again.status == OK):
        return None
    return again


def _concatenate(first: RunResult, second: RunResult) -> RunResult:
    """Two runs of samples, in order (the first run's execution details)."""
    checks = None
    if first.checks is not None and second.checks is not None:
        checks = np.concatenate([first.checks, second.checks])
    return dataclasses.replace(
        first,
        values=np.concatenate([first.values, second.values]),
        status=np.concatenate([first.status, second.status]),
        errors=(*first.errors, *second.errors),
        checks=checks,
    )


def _motions(dynamic: DynamicResponses, x: FloatArray) -> list[str]:
    """The motion of each sample of ``x``: ``"irregular"`` (its once-per-revolution Poincaré
    section does not repeat and its steps do not shrink), ``"converging"`` (a section that
    does not repeat yet but approaches a cycle smoothly:
    :attr:`~jointplay.dynamics.cycles.Periodicity.converging`), ``"periodic (period k)"``, or
    ``"failed"``; by the single engine at the study's settle and start, over at least
    :data:`MOTION_REVOLUTIONS` analysed revolutions, at ``dynamic``'s tolerances (the check
    passes the tightened ones: at a coarse tolerance (rtol 1e-3) the conventional set's
    periodic motion looks irregular).

    Broader than :func:`jointplay.dynamics.running.rattling`, which also sets apart a section
    that repeats from a later revolution on (asking ``simulate`` for more ``settle``): the
    study's analysed revolutions lie before that revolution, where the motion does not repeat
    either (measured on the dry paper four-bar: such a sample at the default tolerances was
    rattling at 100x tighter ones)."""
    from jointplay.errors import JointplayError

    revolutions = max(float(MOTION_REVOLUTIONS), math.floor(dynamic.revolutions + 1e-9))
    classify = dataclasses.replace(dynamic, revolutions=revolutions)
    out = []
    for row in np.asarray(x, dtype=float):
        try:
            result = classify.simulate_one(row)
            if not result.success:
                out.append("failed")
                continue
            running = result.running
        except (JointplayError, np.linalg.LinAlgError):
            out.append("failed")
            continue
        section = running.periodicity
        if section.verdict != "not periodic":
            out.append(section.verdict)
        elif section.converging:  # a smooth approach to a cycle: its peaks are not draws
            out.append("converging")
        else:
            out.append("irregular")
    return out


def _per_sample_check(
    model: ResponseModel,
    x: FloatArray,
    rows: NDArray[np.intp],
    spread: FloatArray,
    moves: _Moves,
    j: int,
    tight_rtol: float,
    compared: int,
    motions: list[str],
    irregular: int,
) -> ConvergenceCheck:
    """The per-sample rule's ``peaks-not-converged`` warning and verdict (some sample that
    moved does not run irregularly)."""
    name = model.response_names[j]
    share, largest, change = moves.share, moves.largest, moves.change
    shift, interval = _mean_shift(moves.signed[:, j], spread[j], compared)
    worst = int(rows[int(np.nanargmax(change[:, j]))])
    count = int(np.sum(change[:, j] > CONVERGENCE_LIMIT * spread[j]))
    loose_rtol = tight_rtol * CONVERGENCE_TIGHTENING
    message = (
        f"{name}: {count} of {len(rows)} samples run again with tolerances "
        f"{CONVERGENCE_TIGHTENING:g}x tighter (rtol {loose_rtol:.0e} -> {tight_rtol:.0e}) "
        f"moved by up to {largest[j]:.3g} {model.units.get(name, '')}, "
        f"{100 * share[j]:.0f} % of its spread over the study (std {spread[j]:.3g}); "
    )
    if irregular:  # why the statistics rule did not judge
        regular = len(motions) - irregular
        message += (
            f"{regular} of the {len(motions)} samples that moved "
            f"{'does' if regular == 1 else 'do'} not run irregularly, so each sample is held "
            "to the limit; "
        )
    usable, sentence = convergence_verdict(shift, interval, len(rows), tight_rtol)
    others = [k for k in range(len(share)) if k != j and np.isfinite(share[k])]
    if others:  # the verdict is the worst response's; say where the others stand
        within = sum(int(share[k] <= CONVERGENCE_LIMIT) for k in others)
        sentence += (
            f"; of the other {len(others)} responses, {within} moved within "
            f"±{100 * CONVERGENCE_LIMIT:.0f} % of their spread (usable)"
        )
    message += sentence
    verdict = name_settings(sentence[sentence.index("Verdict: ") + len("Verdict: ") :])
    warning = Diagnostic.advising(
        "warning", "peaks-not-converged", None, float(share[j]), CONVERGENCE_LIMIT, message
    )
    finding = _rerun_finding(warning, count, rows, worst, model, x)
    return ConvergenceCheck(
        len(rows), CONVERGENCE_TIGHTENING, name, float(share[j]), CONVERGENCE_LIMIT, finding,
        shift, interval, usable, verdict, "per-sample", len(motions), irregular,
    )  # fmt: skip


def _statistics_check(
    model: ResponseModel,
    x: FloatArray,
    values: FloatArray,
    rows: NDArray[np.intp],
    again: RunResult,
    spread: FloatArray,
    moves: _Moves,
    name: str,
    tight_rtol: float,
    irregular: int,
) -> ConvergenceCheck:
    """The statistics rule (every sample that moved runs irregularly): the mean and 95th
    percentile of every response over the samples run again, default against tight, each
    within its paired randomization interval; a ``statistics-converged`` note or a
    ``statistics-not-converged`` warning."""
    from jointplay.dynamics.irregular import paired_shifts, pairs_to_judge

    j = model.response_names.index(name)
    share = moves.share
    paired = np.flatnonzero(again.status == OK)
    judged = [k for k in range(len(share)) if np.isfinite(share[k])]
    level = (1.0 - CONVERGENCE_CONFIDENCE) / (2 * len(judged))
    enough = len(paired) >= max(2, pairs_to_judge(level))
    statistics = {
        model.response_names[k]: paired_shifts(
            values[rows[paired], k], again.values[paired, k], level
        )
        for k in (judged if enough else ())
    }
    units = model.units
    shift, interval = _mean_shift(moves.signed[:, j], spread[j], len(judged))
    moved = (
        f"irregular motion in {irregular} of the {len(rows)} samples run again with tolerances "
        f"{CONVERGENCE_TIGHTENING:g}x tighter (rtol {tight_rtol * CONVERGENCE_TIGHTENING:.0e} "
        f"-> {tight_rtol:.0e}), every one of them that moved beyond "
        f"±{100 * CONVERGENCE_LIMIT:.0f} % of a spread (their peaks are draws: {name} moved "
        f"up to {100 * share[j]:.0f} % of its spread); so the study is judged on the "
        "statistics it reports"
    )
    count = int(np.sum(moves.moved))

    def said(item: tuple[str, PairedShift]) -> str:
        response, s = item
        unit = f" {units.get(response, '')}".rstrip()
        return (
            f"the {s.statistic} of {response} over the {s.pairs} samples moved "
            f"{s.shift:+.3g}{unit} ({s.first:.4g} -> {s.second:.4g}{unit})"
        )

    shifts = [(response, s) for response, pair in statistics.items() for s in pair]
    rate = f"{100 * CONVERGENCE_CONFIDENCE:.0f} %"
    level_word: Level
    if not enough:
        diagnostic = Diagnostic.advising(
            "warning", "statistics-not-converged", None, math.nan, 1.0,
            f"{moved}, but {len(paired)} samples ran again, too few to show a move of "
            f"{2 * len(judged)} statistics at {rate} (at least {pairs_to_judge(level)}). "
            "Verdict: not usable as it stands (the statistics are not judged)",
        )  # fmt: skip
        finding = StudyDiagnostic(diagnostic, count, len(rows), int(rows[0]), {})
        verdict = "not usable as it stands (the statistics are not judged)"
        return ConvergenceCheck(
            len(rows), CONVERGENCE_TIGHTENING, name, float(share[j]), CONVERGENCE_LIMIT,
            finding, shift, interval, False, verdict, "statistics", count, irregular,
        )  # fmt: skip
    # a statistic whose interval is the largest move any swap gives cannot be judged (a 95th
    # percentile of 16 samples, set by their largest two; a response that did not move at
    # all): the verdict rests on the others
    judgeable = [item for item in shifts if item[1].judged] or shifts
    ratio = [
        abs(s.shift) / s.half_width if s.half_width > 0 else (0.0 if s.shift == 0 else math.inf)
        for _, s in judgeable
    ]
    worst = judgeable[int(np.argmax(ratio))]
    unit = f" {units.get(worst[0], '')}".rstrip()
    scope = _scope(shifts, len(judged), len(paired))
    if all(s.within for _, s in shifts):
        usable = True
        code, level_word = "statistics-converged", "info"
        sentence = (
            f"{moved}: {scope} moved within their {rate} intervals (largest against its "
            f"interval: {said(worst)}, within ±{worst[1].half_width:.3g}{unit}). Verdict: "
            "usable for its statistics (mean, spread, quantiles, yield), not sample by "
            'sample: converged on the statistics rule (docs/cli.md, "Converged?")'
        )
    else:
        usable = False
        code, level_word = "statistics-not-converged", "warning"
        beyond = [item for item in shifts if not item[1].within]
        sentence = (
            f"{moved}: {said(worst)}, beyond its ±{worst[1].half_width:.3g}{unit} interval "
            f"({len(beyond)} of the {sum(s.judged for _, s in shifts)} statistics judged "
            "beyond theirs). "
            "Verdict: not usable: the integration biases the study's statistics; tighten the "
            f"integration ({{rtol}} {tight_rtol:.0e})"
        )
    verdict = name_settings(sentence[sentence.index("Verdict: ") + len("Verdict: ") :])
    ratio_worst = float(np.max(ratio))  # the largest move over its interval
    diagnostic = Diagnostic.advising(level_word, code, None, ratio_worst, 1.0, sentence)
    k = model.response_names.index(worst[0])
    sample = int(rows[int(np.nanargmax(moves.change[:, k]))])
    found = _rerun_finding(diagnostic, count, rows, sample, model, x)
    return ConvergenceCheck(
        len(rows), CONVERGENCE_TIGHTENING, name, float(share[j]), CONVERGENCE_LIMIT,
        None if usable else found, shift, interval, usable, verdict, "statistics", count,
        irregular, statistics, found if usable else None,
    )  # fmt: skip


def _scope(shifts: list[tuple[str, PairedShift]], responses: int, pairs: int) -> str:
    """Which statistics the verdict rests on, in words: a mean or 95th percentile whose
    interval is the largest move any swap gives cannot be judged (said so), unless no
    sample moved it at all."""
    cannot = (
        f"cannot be judged by {pairs} samples, their interval being the largest move any swap gives"
    )

    heads, notes = [], []
    for kind, chosen in (
        ("means", [s for _, s in shifts if s.statistic == "mean"]),
        ("95th percentiles", [s for _, s in shifts if s.statistic != "mean"]),
    ):
        judged = sum(s.judged for s in chosen)
        still = sum(not s.judged and s.largest == 0.0 for s in chosen)
        left = len(chosen) - judged - still
        if judged:
            heads.append(
                f"the {kind} of the {responses} responses"
                if judged == len(chosen)
                else f"the {kind} of {judged} of the {responses} responses"
            )
        said = [f"{still} did not move at all"] if still else []
        said += [f"{left} {cannot}"] if left else []
        if said:
            notes.append(f"{kind}: {'; '.join(said)}")
    return " and ".join(heads or ["no statistic"]) + (f" ({'; '.join(notes)})" if notes else "")


def _mean_shift(
    changes: FloatArray, spread: float, compared: int
) -> tuple[float, tuple[float, float]]:
    """The mean of paired ``changes`` (NaN: a sample that failed) over ``spread``, and its
    Student t interval at :data:`CONVERGENCE_CONFIDENCE` shared by ``compared`` responses
    (Bonferroni); NaN where fewer than two changes or no spread."""
    from scipy import stats

    d = changes[~np.isnan(changes)]
    nan = float("nan")
    if len(d) < 2 or not spread > 0:
        return nan, (nan, nan)
    alpha = (1.0 - CONVERGENCE_CONFIDENCE) / max(compared, 1)
    half = (
        float(stats.t.ppf(1.0 - alpha / 2.0, len(d) - 1))
        * float(np.std(d, ddof=1))
        / np.sqrt(len(d))
    )
    mean = float(np.mean(d))
    return mean / spread, ((mean - half) / spread, (mean + half) / spread)


def convergence_verdict(
    shift: float, interval: tuple[float, float], samples: int, tight_rtol: float
) -> tuple[bool, str]:
    """Whether a study that warns ``peaks-not-converged`` is usable, and the sentence that
    ends its warning with that verdict.

    The rule (docs/cli.md, "Converged?"): single samples moved by more than
    :data:`CONVERGENCE_LIMIT` of the spread, so the study is usable only for its statistics
    (mean, spread, quantiles, yield), and only where the tightened run showed that their mean
    did not move: the mean change's interval (``interval``, over the spread,
    :func:`_mean_shift`) lies within ±:data:`CONVERGENCE_LIMIT`, the same share single samples
    are held to. An interval that excludes zero is a bias of the integration (not usable:
    tighten it); one that holds zero but reaches beyond the limit leaves the statistics
    unproven (not usable as it stands).

    Args:
        shift: the mean change over the spread.
        interval: its confidence interval over the spread.
        samples: the samples run again.
        tight_rtol: the tightened relative tolerance (for the advice).

    Returns:
        ``(usable, sentence)``; the sentence names the setting it advises on as a
        ``{rtol}`` field (:func:`~jointplay.errors.name_settings`).
    """
    low, high = interval
    moved = (
        f"their mean moved {100 * shift:+.0f} % of the spread "
        f"({100 * CONVERGENCE_CONFIDENCE:.0f} % interval {100 * low:+.0f} to {100 * high:+.0f} %)"
    )
    limit = f"±{100 * CONVERGENCE_LIMIT:.0f} %"
    if not (np.isfinite(low) and np.isfinite(high)):
        return False, (
            f"too few of the {samples} samples ran again to bound their mean. Verdict: not "
            f"usable as it stands (the rule: the mean within {limit} of the spread)"
        )
    if high < 0.0 or low > 0.0:
        return False, (
            f"{moved}. Verdict: not usable: the integration biases the study (the interval "
            f"excludes zero); tighten the integration ({{rtol}} {tight_rtol:.0e})"
        )
    if max(-low, high) <= CONVERGENCE_LIMIT:
        return True, (
            f"{moved}. Verdict: usable for its statistics (mean, spread, yield), not sample by "
            f"sample: the mean stayed within {limit} of the spread (the motion is sensitive, "
            "docs/contact.md)"
        )
    return False, (
        f"{moved}. Verdict: not usable as it stands: {samples} samples bound the mean's move "
        f"only to {100 * max(-low, high):.0f} % of the spread, beyond the {limit} that would "
        "show the statistics hold (the motion is sensitive, docs/contact.md: tighter "
        "tolerances do not remove that scatter)"
    )


@dataclass(frozen=True)
class ToleranceStudyResult:
    """A finished (or interrupted) tolerance study.

    Attributes:
        mechanism: the nominal mechanism.
        responses: ``"kinematic"``, ``"dynamic"``, ``"running"`` or ``"custom"``.
        spec: the toleranced inputs actually varied.
        model: description of the response model and its settings.
        result: the method's points, responses, summaries and failures.
        ideal: dynamic studies: each response of the nominal mechanism with ideal joints.
        convergence: dynamic studies: the integrator's share of the responses' scatter
            (:func:`convergence_finding`; ``None`` for other studies).
    """

    mechanism: Mechanism
    responses: str
    spec: ToleranceSpec
    model: Mapping[str, Any]
    result: MethodResult
    ideal: Mapping[str, float] | None = None
    convergence: ConvergenceCheck | None = None

    @property
    def method(self) -> str:
        return self.result.method

    @property
    def summaries(self) -> Mapping[str, ResponseSummary]:
        return self.result.summaries

    @property
    def failures(self) -> tuple[Failure, ...]:
        return self.result.failures

    @property
    def interrupted(self) -> bool:
        return self.result.interrupted

    @property
    def seed(self) -> int | None:
        seed = self.result.settings.get("seed")
        return None if seed is None else int(seed)

    @cached_property
    def diagnostics(self) -> tuple[StudyDiagnostic, ...]:
        """Plausibility warnings over the points (:func:`penetration_findings`, then
        :attr:`convergence`'s warning, or its ``statistics-converged`` note: which rule
        judged an irregular study); empty when every point is physical and converged sample
        by sample, or the model has no checks (kinematic studies)."""
        found = penetration_findings(self.result)
        check = self.convergence
        if check is None:
            return found
        said = check.finding if check.finding is not None else check.note
        return found if said is None else (*found, said)

    def to_dataframe(self) -> pd.DataFrame:
        """One row per evaluated point (the content of ``samples.parquet``): ``sample``,
        ``role``, the inputs, the responses, the model's checks (dynamic studies:
        ``penetration_ratio_<joint>``), ``status`` and ``error``; SI."""
        r = self.result
        columns: dict[str, Any] = {
            "sample": np.arange(len(r.x), dtype=np.int64),
            "role": list(r.roles),
        }
        for i, name in enumerate(r.input_names):
            columns[name] = r.x[:, i]
        for j, name in enumerate(r.response_names):
            columns[name] = r.run.values[:, j]
        if r.run.checks is not None:
            for j, name in enumerate(r.run.check_names):
                columns[name] = r.run.checks[:, j]
        columns["status"] = [STATUS[int(s)] for s in r.run.status]
        columns["error"] = list(r.run.errors)
        return pd.DataFrame(columns)

    def summary(self) -> dict[str, Any]:
        """The ``summary.json`` content without provenance (SI)."""
        from jointplay.model.summary import mechanism_summary

        r = self.result
        responses = {}
        for name, item in r.summaries.items():
            entry = item.describe()
            if self.ideal is not None and name in self.ideal:
                entry["ideal_joints"] = self.ideal[name]
            responses[name] = entry
        status = r.run.status
        return {
            "mechanism": self.mechanism.name,
            "method": r.method,
            "responses_kind": self.responses,
            "seed": self.seed,
            "settings": dict(r.settings),
            "model": dict(self.model),
            "inputs": self.spec.describe(),
            "counts": {
                "points": len(status),
                "ok": int(np.sum(status == 0)),
                "failed": int(np.sum(status == 1)),
                "not_run": int(np.sum(status == 2)),
            },
            "interrupted": r.interrupted,
            "responses": responses,
            "most_influential": {name: s.most_influential for name, s in r.summaries.items()},
            "failures": [
                {"sample": f.index, "role": f.role, "inputs": dict(f.inputs), "error": f.error}
                for f in r.failures[:MAX_LISTED_FAILURES]
            ],
            "diagnostics": [finding.as_dict() for finding in self.diagnostics],
            **_lubrication_regimes(r.run),
            "convergence_check": None if self.convergence is None else self.convergence.as_dict(),
            "configuration": mechanism_summary(self.mechanism),
            "execution": r.run.describe(),
        }


def _lubrication_regimes(run: Any) -> dict[str, Any]:
    """``lubrication_regimes`` of ``summary.json``: per lubricated joint, the mean fractions
    of the analysed time in full film, mixed and boundary lubrication over the successful
    samples, and how many samples ever left full film
    (:func:`~jointplay.tolerance.response_base.regime_fractions`); nothing for a study
    without a film."""
    regimes = regime_fractions(run.check_names, run.checks, run.status == OK)
    if not regimes:
        return {}
    return {
        "lubrication_regimes": {
            "definition": REGIME_DEFINITION,
            "joints": regimes,
        }
    }


def tolerance_study(
    mechanism: Mechanism,
    spec: ToleranceSpec | None = None,
    *,
    method: str | ToleranceMethod = "monte-carlo",
    responses: ResponseKind = "kinematic",
    limits: Mapping[str, SpecLimits] | None = None,
    run_settings: RunSettings | None = None,
    contact: str | ContactLaw | ContactModel | None = None,
    friction: FrictionLaw | None = None,
    start: str | Start | None = None,
    settle: int | None = None,
    revolutions: float | None = None,
    solver: SolverOptions | None = None,
    backend: Backend | None = None,
    progress: bool = False,
    model: ResponseModel | None = None,
    **method_options: Any,
) -> ToleranceStudyResult:
    """Run a tolerance study of ``mechanism``.

    Args:
        mechanism: the nominal mechanism.
        spec: the toleranced inputs (default: :meth:`ToleranceSpec.from_mechanism`). Kinematic
            studies use its length inputs, dynamic studies lengths and clearances.
        method: ``"monte-carlo"``, ``"worst-case"``, ``"rss"`` or a method instance
            (:class:`~jointplay.tolerance.methods.MonteCarlo`, ``WorstCase``, ``Rss``).
        responses: ``"kinematic"`` (ideal joints), ``"dynamic"`` (clearance joints: peaks)
            or ``"running"`` (the dynamic peaks plus rocker-speed error, largest joint force
            and contact pressure, Archard wear rates).
        limits: specification limits per response name (SI).
        run_settings: dynamic: how the clearance dynamics run
            (:class:`~jointplay.dynamics.settings.RunSettings`: contact, start, settle,
            revolutions, solver), as the command line builds it; or, in its place, the loose
            keywords ``contact``, ``start``, ``settle``, ``revolutions``, ``solver`` (giving
            both is an error).
        contact: dynamic: a :class:`~jointplay.dynamics.setup.ContactModel` (its stiffness
            from each joint's geometry is refitted to every sample's clearance); ``None``
            (default): the physical default ``ContactModel()`` of docs/contact.md, as every
            command (Liu stiffness per joint, Hunt–Crossley e = 0.8, friction 0.1);
            ``"ifm-conventional"``: the paper's conventional IFM set
            (:data:`jointplay.dynamics.setup.DEFAULT_IMPACT`), frictionless; a contact law
            instance or name: that law, frictionless.
        friction: dynamic: a friction law, or ``None`` (with a ContactModel: its friction).
        start: dynamic: ``"steady"`` (default: the mechanism as it runs), ``"rest"`` (the
            paper's start-up), ``"impulsive"``, ``"ramp"`` or a
            :class:`~jointplay.dynamics.simulate.Start`.
        settle: dynamic: start-up revolutions left out of the responses (default 2; 0 with
            ``start="rest"`` gives the start-up peaks, as the paper reports them).
        revolutions: dynamic: analysed crank revolutions after them.
        solver: dynamic: :class:`~jointplay.dynamics.simulate.SolverOptions`.
        backend: where the points run (default: local processes).
        progress: show a progress bar on stderr.
        model: a custom response model (overrides ``responses``); its inputs must be ``spec``'s.
        **method_options: options of the method (see
            :func:`~jointplay.tolerance.methods.get_method`), e.g. ``samples=2000, seed=1``
            for Monte Carlo or ``corners="all"`` for the worst case.

    Returns:
        The study; an interrupted one (Ctrl-C) keeps the points that finished
        (``interrupted`` is True).

    Raises:
        PartialInterrupt: interrupted during the convergence check, after every point
            finished; its ``partial`` is the study without the check.
    """
    analysis = get_method(method, **method_options)
    spec = spec if spec is not None else ToleranceSpec.from_mechanism(mechanism)
    ideal: dict[str, float] | None = None
    if model is not None:
        kind = "custom"
    else:
        kind = responses
        model, spec = build_model(
            mechanism,
            spec,
            responses,
            run_settings=run_settings,
            contact=contact,
            friction=friction,
            start=start,
            settle=settle,
            revolutions=revolutions,
            solver=solver,
        )
        dynamic = model.base if isinstance(model, RunningResponses) else model
        if isinstance(dynamic, DynamicResponses):
            # the batch engine's workers start while the nominal analysis runs here
            prepare(model, backend, int(getattr(analysis, "samples", 0) or 0))
            ideal = _ideal_peaks(mechanism, dynamic.peak_keys)
    outcome = analysis.run(model, spec, limits=limits, backend=backend, progress=progress)
    study = ToleranceStudyResult(mechanism, kind, spec, model.describe(), outcome, ideal)
    if outcome.interrupted:
        return study
    try:
        convergence = convergence_finding(model, outcome.x, outcome.run, backend)
    except KeyboardInterrupt:  # every sample finished: they go on with the interrupt
        raise PartialInterrupt(study, "interrupted during the convergence check") from None
    return dataclasses.replace(study, convergence=convergence)


def build_model(
    mechanism: Mechanism,
    spec: ToleranceSpec,
    responses: ResponseKind,
    *,
    run_settings: RunSettings | None = None,
    contact: str | ContactLaw | ContactModel | None = None,
    friction: FrictionLaw | None = None,
    start: str | Start | None = None,
    settle: int | None = None,
    revolutions: float | None = None,
    solver: SolverOptions | None = None,
) -> tuple[ResponseModel, ToleranceSpec]:
    """The response model of a study and the part of ``spec`` it varies.

    Kinematic studies vary the length inputs; dynamic and running studies lengths and
    clearances (see :func:`tolerance_study` for the arguments; the run settings are built
    once here, :meth:`~jointplay.dynamics.settings.RunSettings.of`). ``"running"`` adds to the
    dynamic peaks the rocker-speed error, the largest joint force and contact pressure and the
    Archard wear rates (:class:`~jointplay.tolerance.responses.RunningResponses`, default steel
    wear data).
    """
    if responses == "kinematic":
        spec = spec.only("length")
        if len(spec) == 0:
            raise ConfigError(
                f"mechanism {mechanism.name!r} has no length tolerances to study; add "
                "[tolerances.lengths.<name>] tables (or a general class) to its configuration"
            )
        return kinematic_model(mechanism, spec.names), spec
    if responses not in ("dynamic", "running"):
        raise ConfigError(f"responses must be kinematic, dynamic or running, got {responses!r}")
    from jointplay.dynamics.settings import RunSettings

    spec = spec.only("length", "clearance")
    if len(spec) == 0:
        raise ConfigError(
            f"mechanism {mechanism.name!r} has no length or clearance tolerances to study"
        )
    settings = RunSettings.of(
        run_settings,
        contact=contact,
        start=start,
        settle=settle,
        revolutions=revolutions,
        solver=solver,
    )
    radius = {
        item.joint: item.journal_radius for item in spec.inputs if isinstance(item, JointTolerance)
    }
    model = run_model(
        mechanism,
        spec.names,
        settings,
        journal_radius=radius,
        **({} if friction is None else {"friction": friction}),
    )
    if not model.clearance_joints:
        raise ConfigError(
            "a dynamic study needs clearance joints: give joints an ISO 286 fit "
            "([joints.<name>] fit and diameter) or a clearance"
        )
    if responses == "running":
        from jointplay.dynamics.wear import OutputSpeedReference, WearSettings

        return RunningResponses(model, OutputSpeedReference.of(mechanism), WearSettings()), spec
    return model, spec


def study_contact(
    mechanism: Mechanism, contact: str | ContactLaw | ContactModel | None
) -> dict[str, Any]:
    """``law``, ``friction`` and ``stiffness_from`` of a dynamic study's response model
    (:func:`jointplay.tolerance.responses.contact_parts`) for ``contact``, as
    :func:`jointplay.dynamics.setup.resolve_contact` reads it: ``None`` the physical default
    ``ContactModel()``; ``"ifm-conventional"`` the paper's conventional IFM set,
    frictionless; a law or a law's name: that law, frictionless."""
    from jointplay.dynamics.setup import ContactModel, resolve_contact

    resolved = resolve_contact(contact)
    if isinstance(resolved, ContactModel):
        return contact_parts(mechanism, resolved)
    return {"law": resolved, "friction": None, "stiffness_from": {}}


def response_units(
    mechanism: Mechanism, spec: ToleranceSpec, responses: ResponseKind, **options: Any
) -> dict[str, str]:
    """SI unit of every response of a study (e.g. to read spec limits given with units)."""
    model, _ = build_model(mechanism, spec, responses, **options)
    return dict(model.units)


def _ideal_peaks(mechanism: Mechanism, keys: tuple[str, ...]) -> dict[str, float]:
    """Largest |value| of each quantity for the nominal mechanism with ideal joints (0.1° steps)."""
    from jointplay.dynamics.nominal import nominal_analysis

    table = nominal_analysis(mechanism, step_deg=0.1).table
    return {f"{key}_peak": float(table[key].abs().max()) for key in keys if key in table}
