"""Tolerance synthesis through the dynamics: which fit and which length class to put on the
drawing.

This module runs the study (the blocks of samples, the verdicts, the rare-defect estimates);
its candidates — schemes, callouts, requirements, looks — are in
:mod:`jointplay.study.design_schemes` and its result — :class:`DesignResult` and the
findings over the samples — in :mod:`jointplay.study.design_result`; both are re-exported
here, the one import path.

:func:`design_study` evaluates every combination (a *scheme*) of an ISO 286 fit — one for all
pin joints, or one per named joint — and an ISO 2768-1 class for the link lengths:

1. a Monte Carlo of the parts as made (:mod:`jointplay.tolerance.parts`): each link length in
   its class's ±deviation, each joint's hole and pin diameters in their own ISO 286 zones,
   the radial clearance their half difference (or, ``Process(sampling="band")``, the
   clearance over the fit's worst-case band), with the same seed for every scheme and every
   block (common random numbers: schemes differ by their tolerances, not by their luck);
   ``samples="auto"`` adds blocks (:func:`sample_looks`) while a scheme is undecided and
   could still be the answer;
2. each sample through the steady running dynamics (steady start, ``settle`` start-up
   revolutions left out) — or through the ideal-joint kinematics when every requirement is
   kinematic. Every dynamic design runs the batch engine: the peaks, ``joint_force`` and
   ``contact_pressure`` (:class:`~jointplay.tolerance.responses.PeakResponses`) and, when a
   requirement needs them (``rocker_speed_error``, ``wear_rate``, ``life``:
   :func:`trajectory_requirements`), the running responses computed in its lanes
   (:class:`~jointplay.tolerance.responses.RunningResponses`, the sustained-contact mode's
   on the CPU backends' implicit lanes); the engines agree on forces within 1e-3,
   on ω peaks within their integration errors (docs/design.md);
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

Each block's samples of all open schemes run as one batch on one backend
(:func:`jointplay.tolerance.execution.run`), scheme after scheme: Ctrl-C keeps the blocks
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
  (computed per scheme, since the limit may follow the fit);
* ``functional_life`` — with a life-quantile requirement (``"B10 >= 2000 h"``,
  :mod:`jointplay.study.requirements`): each sample's functional life
  (:func:`jointplay.study.life.functional_lives`), s: the sample worn, its dynamics
  re-simulated as its clearances grow (``life_step`` the first step), until its first other
  requirement or clearance limit fails, censored at the largest B_p hours. ``Bp >= X`` is then
  the yield of ``functional_life >= X`` against the target 1 − p, decided as every other
  requirement (the same verdicts, intervals and samples to decide). The lives of each block
  are computed once, when it is run, and kept in ``samples.parquet`` (``functional_life``,
  ``functional_life_censored``, ``functional_life_failing``, ``functional_life_simulations``).
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from jointplay.errors import ConfigError, PartialInterrupt
from jointplay.execution.progress import study_bar
from jointplay.model.mechanism import Mechanism

# The study's parts (this module runs the study; the candidates and the result live apart):
# re-exported, so that jointplay.study.design stays the one import path.
from jointplay.study.design_result import (
    DesignDiagnostic,
    DesignResult,
    _scheme_penetration,
    _scheme_regimes,
    penetration_diagnostics,
)
from jointplay.study.design_schemes import (
    BLOCK,
    DEFAULT_CONFIDENCE,
    DEFAULT_MAX_SAMPLES,
    DERIVED_RESPONSES,
    Callout,
    Scheme,
    _diameter,
    design_units,
    parse_requirements,
    resolve_responses,
    sample_looks,
    schemes,
    trajectory_requirements,
)
from jointplay.study.life import (
    DEFAULT_TOLERANCE as DEFAULT_LIFE_TOLERANCE,
)
from jointplay.study.life import (
    Criterion,
    clearance_criteria,
    functional_lives,
    requirement_criteria,
    scheme_limits,
)
from jointplay.study.life_result import Lives
from jointplay.study.requirements import FUNCTIONAL_LIFE, Requirement
from jointplay.tolerance import iso286
from jointplay.tolerance.analysis import StudyDiagnostic, convergence_finding
from jointplay.tolerance.confidence import (
    RULE_INTERVALS,
    Rule,
    YieldEstimate,
    interval,
    quantile_value,
    verdict,
)
from jointplay.tolerance.cost import CostModel
from jointplay.tolerance.execution import NOT_RUN, OK, STATUS, Backend, run
from jointplay.tolerance.methods import distribution_note, truncated_at_limits
from jointplay.tolerance.parts import Process, model_inputs
from jointplay.tolerance.rare import RareEstimate, cross_entropy_importance_sampling
from jointplay.tolerance.response_running import check_running_backend
from jointplay.tolerance.responses import (
    CheckedModel,
    PeakResponses,
    ResponseModel,
    RunningResponses,
    kinematic_model,
    run_model,
)
from jointplay.tolerance.sampling import sample
from jointplay.tolerance.spec import ToleranceSpec

if TYPE_CHECKING:
    from jointplay.contact.laws import ContactLaw
    from jointplay.dynamics.settings import RunSettings
    from jointplay.dynamics.setup import ContactModel
    from jointplay.dynamics.simulate import SolverOptions
    from jointplay.dynamics.wear import WearSettings

__all__ = [
    "BLOCK",
    "DEFAULT_CONFIDENCE",
    "DEFAULT_MAX_SAMPLES",
    "DERIVED_RESPONSES",
    "Callout",
    "DesignDiagnostic",
    "DesignResult",
    "Earlier",
    "RareDefects",
    "Scheme",
    "design_study",
    "design_units",
    "life_settings",
    "parse_requirements",
    "penetration_diagnostics",
    "resolve_responses",
    "sample_looks",
    "schemes",
    "trajectory_requirements",
]

FloatArray = NDArray[np.float64]


@dataclass
class _Evaluated:
    """The samples one evaluation key (a scheme; a length class when kinematic) has run, in
    the order of its sample stream."""

    features: list[FloatArray] = field(default_factory=list)
    x: list[FloatArray] = field(default_factory=list)
    values: list[FloatArray] = field(default_factory=list)
    status: list[NDArray[np.int8]] = field(default_factory=list)
    checks: list[FloatArray] = field(default_factory=list)
    errors: list[str] = field(default_factory=list)
    #: a study with a B_p requirement: each sample's functional life (``Lives`` parts)
    lives: list[Lives] = field(default_factory=list)

    @property
    def n(self) -> int:
        return sum(len(s) for s in self.status)

    @property
    def life_columns(self) -> dict[str, Any]:
        """The functional lives as ``samples.parquet`` holds them (none without)."""
        if not self.lives:
            return {}
        lives = Lives.concatenate(self.lives)
        return {
            FUNCTIONAL_LIFE: lives.life,
            f"{FUNCTIONAL_LIFE}_censored": lives.censored,
            f"{FUNCTIONAL_LIFE}_failing": list(lives.failing),
            f"{FUNCTIONAL_LIFE}_simulations": lives.resimulations,
        }

    def add(
        self, features: FloatArray, x: FloatArray, outcome: Any, part: slice, lives: Lives | None
    ) -> None:
        if lives is not None:
            self.lives.append(lives)
        n = len(features)
        self.features.append(features)
        self.x.append(x[part])
        self.values.append(outcome.values[part])
        self.status.append(outcome.status[part])
        checks = outcome.checks[part] if outcome.checks is not None else np.empty((n, 0))
        self.checks.append(checks)
        self.errors.extend(outcome.errors[part])

    def head(self, n: int) -> _Evaluated:
        """The first ``n`` samples (all of them when there are fewer)."""
        if not self.status:
            return self
        return _Evaluated(
            [np.vstack(self.features)[:n]],
            [np.vstack(self.x)[:n]],
            [np.vstack(self.values)[:n]],
            [np.concatenate(self.status)[:n]],
            [np.vstack(self.checks)[:n]],
            list(self.errors[:n]),
            [_head_lives(Lives.concatenate(self.lives), n)] if self.lives else [],
        )


def _head_lives(lives: Lives, n: int) -> Lives:
    """The first ``n`` lives."""
    return dataclasses.replace(
        lives,
        life=lives.life[:n],
        censored=lives.censored[:n],
        failing=lives.failing[:n],
        resimulations=lives.resimulations[:n],
        history=lives.history[:n],
        floor_steps=None if lives.floor_steps is None else lives.floor_steps[:n],
        worst_error=None if lives.worst_error is None else lives.worst_error[:n],
    )


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
    resume: Earlier | None = None,
    max_time: float | None = None,
    life_step: float | None = None,
    model: ResponseModel | None = None,
    check_convergence: bool = True,
) -> DesignResult:
    """Find the cheapest fit and length class shown to meet ``requirements``.

    Args:
        mechanism: the nominal mechanism (template four-bar or slider-crank; pin joints with
            a diameter).
        fits: candidate fits: text (every joint) or a mapping joint → fit.
        classes: candidate ISO 2768-1 classes.
        requirements: requirements as text (:mod:`jointplay.study.requirements`) or objects.
        samples: Monte Carlo samples per scheme (verdicts on the exact interval at that
            fixed n), or ``"auto"``: blocks of samples (:func:`sample_looks`), the verdicts
            looked at after each on the confidence sequence
            (:func:`~jointplay.tolerance.confidence.confidence_sequence`, valid at every
            look), until every scheme is decided, can no longer be the
            cheapest feasible one, or has ``max_samples``.
        max_samples: ``"auto"``: the most samples per scheme.
        seed: the seed (the same for every scheme and every block: common random numbers).
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
        progress: show one progress bar for the whole study: samples done of the most it
            can still need (every open scheme to ``max_samples``), schemes decided, the time
            left at the measured rate.
        max_time: a time budget, s: no block is started that would end after it at the
            measured rate (the first always runs); the schemes still open stop (``stopped``
            = ``time``) with the verdicts reached, :attr:`DesignResult.time_note` says what
            would decide them. ``None``: no budget.
        resume: an earlier run of the same study (:class:`Earlier`, ``--resume``): its
            samples are kept (each scheme's stream goes on from where it stopped: the result
            is the one an uninterrupted run with these settings gives, bit for bit) and its
            runs are listed in ``settings["runs"]``. Refused (ConfigError naming the
            difference) when the mechanism, the model, a requirement, the schemes, the seed,
            the sampling or the costs differ; ``samples``, ``max_samples``, the backend may.
        life_step: with a B_p requirement: the first step between the re-simulations of a
            sample's functional life, s (default a tenth of the largest B_p hours).
        model: the response model (default: built from the requirements and the run
            settings); a test's stub.
        check_convergence: a dynamic design re-runs its first samples with tighter
            tolerances (:func:`~jointplay.tolerance.analysis.convergence_finding`); the
            model-sensitivity re-runs, which report yields only, turn it off.

    Raises:
        ConfigError: a malformed requirement, an unknown response, bad candidates, a resumed
            study that differs.
        PartialInterrupt: interrupted during the convergence check, after every scheme
            finished; its ``partial`` is the result without the check.
    """
    if not 0.0 < confidence < 1.0:
        raise ConfigError(f"confidence must lie between 0 and 100 %, got {100 * confidence:g} %")
    looks = sample_looks(samples, max_samples)
    rule: Rule = "fixed" if samples != "auto" else "sequential"
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
    quantiles = [r for r in parsed if r.quantile is not None]
    for item in parsed:
        if item.quantile is None and item.response not in units:
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

    life_hours, life_step = life_settings(
        quantiles, parsed, clearance_limit, clearance_allowance, life_step, rare
    )
    specs = [s.spec(mechanism, process) for s in candidates]
    if responses == "kinematic":
        specs = [s.only("length") for s in specs]
    specs = [truncated_at_limits(s) if truncate else s for s in specs]
    feature_names = specs[0].names
    names, _ = model_inputs(feature_names, np.empty((0, len(feature_names))))
    if model is None:
        model = _response_model(
            mechanism, names, parsed, responses, dynamic_units,
            run=run_settings, contact=contact, settle=settle, revolutions=revolutions,
            solver=solver, wear=wear, backend=backend,
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
    model_checks = tuple(model.check_names) if isinstance(model, CheckedModel) else ()
    identity = _identity(
        mechanism, model, parsed, confidence, candidates, seed, process, truncate, responses,
        cost, clearance_limit, clearance_allowance, life_step,
    )  # fmt: skip
    evaluated = {k: _Evaluated() for k in set(key)}
    runs: list[dict[str, Any]] = []
    if resume is not None:
        resume.check(identity)
        kept = resume.evaluated(
            candidates, key, feature_names, names, tuple(model.response_names), model_checks,
            lives=bool(quantiles),
        )  # fmt: skip
        for k, done in kept.items():
            check = sample(specs[k], max(done.n, 1), seed).values
            if done.n and not np.array_equal(np.vstack(done.features), check):
                raise ConfigError(
                    f"--resume: the samples kept in {resume.folder} are not this study's sample "
                    "stream (the tolerances or the sampling changed); run the study into a new "
                    "--out folder"
                )
            evaluated[k] = done
        runs = [dict(r) for r in resume.runs]
    kept_samples = sum(e.n for e in evaluated.values())
    active = set(range(len(candidates)))
    costs = [s.cost(mechanism, cost) for s in candidates]
    looked = [0] * len(candidates)  # the look each scheme was last judged at (0: none yet)
    reached = dict.fromkeys(evaluated, 0)  # samples of each key the schedule has asked for
    free = _free_lanes(backend) if rule == "sequential" else None
    rows: dict[int, dict[str, Any]] = {}
    interrupted = False
    first: tuple[FloatArray, Any] | None = None  # the first block, for the convergence check
    executions = []
    stops: dict[int, str] = {}  # why each scheme stopped
    started = time.perf_counter()
    computed_now, computing_s, out_of_time = 0, 0.0, False
    with study_bar(
        progress, _most_needed(active, key, evaluated, looks[-1]), _bar_text(len(candidates), {})
    ) as shown:
        while active:
            plan = _plan(active, costs, key, looks, looked, reached, free)
            need: dict[int, int] = {}
            for i, target in plan.items():
                need[key[i]] = max(need.get(key[i], 0), target)
            keys = sorted(k for k, target in need.items() if evaluated[k].n < target)
            if keys:
                drawn = [sample(specs[k], need[k], seed).values[evaluated[k].n :] for k in keys]
                features = np.vstack(drawn)
                _, x = model_inputs(feature_names, features)
                if max_time is not None and computed_now:
                    rate = computed_now / computing_s
                    if time.perf_counter() - started + len(x) / rate > max_time:
                        out_of_time = True
                        break
                began = time.perf_counter()
                advanced = [0]

                def advance(count: int, advanced: list[int] = advanced) -> None:
                    advanced[0] += count
                    shown.advance(count)

                outcome = run(model, x, backend=backend, on_samples=advance)
                computing_s += time.perf_counter() - began
                ran = int(np.sum(outcome.status != NOT_RUN))
                shown.advance(max(0, ran - advanced[0]))  # the failed blocks' samples too
                computed_now += ran
                executions.append(outcome.describe())
                if first is None:
                    first = (x, outcome)
                start = 0
                for k, block in zip(keys, drawn, strict=True):
                    part = slice(start, start + len(block))
                    start += len(block)
                    if np.any(outcome.status[part] == NOT_RUN) or interrupted:
                        continue  # interrupted: not kept
                    lives = None
                    if life_hours is not None:  # each sample worn to its first failure
                        try:
                            lives = functional_lives(
                                model, x[part],
                                _life_criteria(
                                    candidates[k], mechanism, parsed, clearance_limit,
                                    clearance_allowance,
                                ),
                                hours=life_hours, first_step=float(life_step or life_hours),
                                backend=backend,
                                as_made=dataclasses.replace(  # its first state: not re-run
                                    outcome, values=outcome.values[part],
                                    status=outcome.status[part],
                                ),
                            )  # fmt: skip
                        except KeyboardInterrupt:  # lives cut short: the block is not kept
                            interrupted = True
                            continue
                    evaluated[k].add(block, x, outcome, part, lives)
                if outcome.interrupted:
                    interrupted = True
            for k, target in need.items():
                reached[k] = max(reached[k], target)
            for i in sorted(plan):
                # each scheme is judged on the first `target` samples of its stream (a resumed
                # study may hold more), those it has when interrupted
                done = evaluated[key[i]].head(plan[i])
                if done.n and (i not in rows or done.n > rows[i]["samples"]):
                    rows[i] = _scheme_row(
                        candidates[i], mechanism, cost, done, names, model, model_checks,
                        parsed, confidence, clearance_limit, clearance_allowance, rule,
                    )  # fmt: skip
                looked[i] = plan[i]
            if interrupted:
                break
            still = _still_open(active, rows, costs)
            for i in active - still:
                decided = i in rows and rows[i]["verdict"] != "undecided"
                stops[i] = "decided" if decided else "dearer"
            for i in still & set(plan):
                if looked[i] >= looks[-1]:  # undecided at the most samples
                    stops[i] = "max-samples"
                    still.discard(i)
            active = still
            shown.update(
                total=computed_now + _most_needed(active, key, evaluated, looks[-1]),
                description=_bar_text(len(candidates), stops),
            )
    for i in active:
        stops[i] = "interrupted" if interrupted else "time" if out_of_time else "max-samples"
    for i, row in rows.items():
        row["stopped"] = stops.get(i, "interrupted")
        row["decided_at"] = row["samples"] if row["verdict"] != "undecided" else None
    not_run = [
        {"scheme": candidates[i].label, "cost": costs[i], "stopped": stops.get(i, "interrupted")}
        for i in range(len(candidates))
        if i not in rows
    ]
    if rare is not None and not interrupted and not out_of_time:
        try:
            undecided = [i for i, why in stops.items() if why == "max-samples" and i in rows]
            for i in sorted(undecided, key=lambda j: (costs[j], j)):
                if i not in _still_open({i}, rows, costs):
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
        except KeyboardInterrupt:  # between two stages: the Monte Carlo blocks are kept
            interrupted = True

    table = pd.DataFrame([rows[i] for i in sorted(rows)])
    best = binding = None
    if len(table):
        table["samples_to_decide"] = table["samples_to_decide"].astype("Int64")
        table["decided_at"] = table["decided_at"].astype("Int64")
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
            binding = _binding(table, [r.text for r in parsed])
    sample_frames = []
    checks = model_checks
    for i, scheme in enumerate(candidates):
        if i in rows:
            done = evaluated[key[i]].head(int(rows[i]["samples"]))
            values = _responses(
                scheme, mechanism, done, names, model, clearance_limit, clearance_allowance
            )
            sample_frames.append(_sample_frame(scheme, done, feature_names, names, values, checks))
    every_sample = pd.concat(sample_frames, ignore_index=True) if sample_frames else pd.DataFrame()
    computed = sum(e.n for e in evaluated.values()) - kept_samples
    runs.append(
        {
            "run": len(runs) + 1,
            "samples_computed": int(computed),
            "samples_kept": int(kept_samples),
            "max_samples": max_samples if samples == "auto" else samples,
            "interrupted": interrupted,
        }
    )
    settings = {
        "identity": identity,
        "runs": runs,
        "resumed_from": None if resume is None else str(resume.folder),
        "max_time_s": max_time,
        "stopped_at_max_time": out_of_time,
        "elapsed_s": time.perf_counter() - started,
        "samples_per_s": computed_now / computing_s if computing_s > 0 else None,
        "samples": samples,
        "max_samples": max_samples if samples == "auto" else samples,
        "looks": list(looks),
        "verdict_rule": rule,
        "verdict_interval": RULE_INTERVALS[rule],
        "seed": seed,
        "process": process.describe(),
        "truncated_at_limits": bool(truncate),
        "sampling_distributions": distribution_note(specs[0], truncate) if specs else "",
        "interval": "exact (Clopper-Pearson) two-sided 95 % interval of each yield (the "
        "estimate reported); the verdicts: verdict_interval",
        "rare_defects": None if rare is None else dataclasses.asdict(rare),
        "responses": responses,
        "cost_model": cost.describe(),
        "clearance_limit_m": clearance_limit,
        "clearance_allowance_m": clearance_allowance,
        "functional_life": None
        if life_hours is None
        else {
            "hours_s": life_hours,
            "first_step_s": life_step,
            "tolerance": DEFAULT_LIFE_TOLERANCE,
            "criteria": [
                c.label
                for c in _life_criteria(
                    candidates[0], mechanism, parsed, clearance_limit, clearance_allowance
                )
            ],
            "simulations": int(
                sum(int(lv.resimulations.sum()) for e in evaluated.values() for lv in e.lives)
            ),
        },
        "model": model.describe(),
        "execution": executions[-1] if executions else {},
        "execution_blocks": executions,
        "schemes": len(candidates),
        "finished_schemes": len(rows),
        "schedule": "cost-ordered" if free is not None else "every scheme",
        "not_run": not_run,
    }
    diagnostics: tuple[StudyDiagnostic, ...] = penetration_diagnostics(
        every_sample, checks, names, best
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
    if interrupted or responses == "kinematic" or first is None or not check_convergence:
        return result
    try:
        convergence = convergence_finding(model, first[0], first[1], backend)
    except KeyboardInterrupt:  # every scheme finished: they go on with the interrupt
        raise PartialInterrupt(result, "interrupted during the convergence check") from None
    if convergence is not None:  # the per-sample rule's warning, or the statistics rule's note
        said = convergence.finding if convergence.finding is not None else convergence.note
        if said is not None:
            diagnostics = (*diagnostics, said)
    return dataclasses.replace(result, diagnostics=diagnostics, convergence=convergence)


def _most_needed(
    active: set[int], key: Sequence[int], evaluated: Mapping[int, _Evaluated], most: int
) -> int:
    """Samples the open schemes can still need: each open evaluation key to ``most``."""
    return sum(max(0, most - evaluated[k].n) for k in {key[i] for i in active})


def _bar_text(schemes: int, stops: Mapping[int, str]) -> str:
    """The study bar's label: schemes decided of all."""
    decided = sum(1 for why in stops.values() if why in ("decided", "dearer"))
    return f"design: {decided}/{schemes} schemes decided; samples"


def _identity(
    mechanism: Mechanism,
    model: ResponseModel,
    parsed: Sequence[Requirement],
    confidence: float,
    candidates: Sequence[Scheme],
    seed: int,
    process: Process,
    truncate: bool,
    responses: str,
    cost: CostModel,
    limit: Mapping[str, float] | float | None,
    allowance: float | None,
    life_step: float | None = None,
) -> dict[str, Any]:
    """What makes two runs the same study (``settings["identity"]``, JSON-ready): a resumed
    run must match every entry."""
    import hashlib

    return _plain_json(
        {
            "mechanism": {
                "name": mechanism.name,
                "sha256": hashlib.sha256(repr(mechanism).encode()).hexdigest()[:16],
            },
            "model": model.describe(),
            "requirements": [r.describe() for r in parsed],
            "confidence": confidence,
            "schemes": [s.label for s in candidates],
            "seed": seed,
            "process": process.describe(),
            "truncated_at_limits": bool(truncate),
            "responses": responses,
            "cost_model": cost.describe(),
            "clearance_limit_m": limit,
            "clearance_allowance_m": allowance,
            "life_step_s": life_step,
            "block": BLOCK,
        }
    )


def _plain_json(value: Any) -> Any:
    """``value`` as ``summary.json`` holds it (through the one JSON sanitiser, floats to
    their significant digits), so that a stored identity compares equal."""
    import json

    from jointplay.io.output import json_text

    return json.loads(json_text(json.loads(json.dumps(value, default=str))))


@dataclass(frozen=True)
class Earlier:
    """An earlier run of a design study (``--resume``): what its result folder holds.

    Attributes:
        folder: where it was read from (for the messages).
        settings: its ``summary.json`` settings (``identity``, ``runs``).
        samples: its ``samples.parquet``: one row per sample of each scheme.
    """

    folder: str
    settings: Mapping[str, Any]
    samples: pd.DataFrame = field(repr=False)

    @property
    def runs(self) -> tuple[Mapping[str, Any], ...]:
        """The runs it merged, itself the last."""
        return tuple(self.settings.get("runs") or ())

    def check(self, identity: Mapping[str, Any]) -> None:
        """ConfigError naming the first entry of the study's identity that differs."""
        before = self.settings.get("identity")
        if not isinstance(before, Mapping):
            raise ConfigError(
                f"--resume: {self.folder} holds a design result without the study's identity "
                "(written before --resume existed); run the study into a new --out folder"
            )
        for name in dict.fromkeys([*identity, *before]):
            was, now = before.get(name), identity.get(name)
            if was != now:
                where, was, now = _difference(name, was, now)
                raise ConfigError(
                    f"--resume: the study in {self.folder} has a different {where}: "
                    f"{_short(was, now)}; resume with the same {name}, or run the changed study "
                    "into a new --out folder"
                )

    def evaluated(
        self,
        candidates: Sequence[Scheme],
        key: Sequence[int],
        feature_names: Sequence[str],
        names: Sequence[str],
        response_names: Sequence[str],
        check_names: Sequence[str],
        lives: bool = False,
    ) -> dict[int, _Evaluated]:
        """The samples of each evaluation key (the longest of its schemes' streams), with
        their functional lives when ``lives`` (a study with a B_p requirement)."""
        codes = {text: code for code, text in STATUS.items()}
        frame = self.samples
        out: dict[int, _Evaluated] = {}
        for i, scheme in enumerate(candidates):
            rows = frame[frame["scheme"] == scheme.label].sort_values("sample")
            if not len(rows) or (key[i] in out and out[key[i]].n >= len(rows)):
                continue
            n = len(rows)
            columns = [*feature_names, *names, *response_names, *check_names]
            if lives:
                columns += [FUNCTIONAL_LIFE, *(f"{FUNCTIONAL_LIFE}_{c}" for c in LIFE_COLUMNS)]
            missing = [c for c in columns if c not in rows]
            if missing:
                raise ConfigError(
                    f"--resume: the samples in {self.folder} lack {', '.join(missing[:3])}; "
                    "run the study into a new --out folder"
                )

            def block(which: Sequence[str], rows: pd.DataFrame = rows, n: int = n) -> FloatArray:
                return rows[list(which)].to_numpy(dtype=float).reshape(n, len(which))

            out[key[i]] = _Evaluated(
                [block(feature_names)],
                [block(names)],
                [block(response_names)],
                [np.asarray(rows["status"].map(codes), dtype=np.int8)],
                [block(check_names)],
                ["" if e is None else str(e) for e in rows["error"]],
                [kept_lives(rows)] if lives else [],
            )
        return out


#: The per-sample columns of the functional life beside ``functional_life`` itself.
LIFE_COLUMNS = ("censored", "failing", "simulations")


def kept_lives(rows: pd.DataFrame, hours: float = math.nan) -> Lives:
    """The functional lives of sample rows (a resumed study's, or a scheme's for its report),
    without clearance histories; ``hours``: the censoring time, s."""
    n = len(rows)
    return Lives(
        joints=(),
        life=rows[FUNCTIONAL_LIFE].to_numpy(dtype=float),
        censored=rows[f"{FUNCTIONAL_LIFE}_censored"].to_numpy(dtype=bool),
        failing=tuple(str(f) for f in rows[f"{FUNCTIONAL_LIFE}_failing"]),
        resimulations=rows[f"{FUNCTIONAL_LIFE}_simulations"].to_numpy(dtype=np.int64),
        history=((),) * n,
        hours=hours,
    )


def _difference(where: str, was: Any, now: Any) -> tuple[str, Any, Any]:
    """The first place where two JSON values differ: its path and the two values there."""
    if isinstance(was, Mapping) and isinstance(now, Mapping):
        for name in dict.fromkeys([*was, *now]):
            if was.get(name) != now.get(name):
                return _difference(f"{where}.{name}", was.get(name), now.get(name))
    if isinstance(was, list) and isinstance(now, list) and len(was) == len(now):
        for i, (a, b) in enumerate(zip(was, now, strict=True)):
            if a != b:
                return _difference(f"{where}[{i}]", a, b)
    return where, was, now


def _short(was: Any, now: Any) -> str:
    """``was`` there and ``now`` here, each cut to a readable length."""

    def cut(value: Any) -> str:
        text = repr(value)
        return text if len(text) <= 80 else text[:77] + "..."

    return f"{cut(was)} there, {cut(now)} now"


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
        done.add(features, x, outcome, slice(0, len(x)), None)
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
    base = run_model(mechanism, names, settings)
    lengths = [n for n in names if n.startswith("length_")]
    mixed = any(r.response not in dynamic_units for r in parsed)  # a kinematic one too
    kinematic = kinematic_model(mechanism, lengths) if lengths and mixed else None
    need_trajectories = trajectory_requirements(parsed)
    if need_trajectories:
        check_running_backend(
            base,
            backend,
            f"{', '.join(repr(t) for t in need_trajectories)} (the running responses: the "
            "speed error and the wear rate)",
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
    if done.lives:
        values[FUNCTIONAL_LIFE] = Lives.concatenate(done.lives).life
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
    rule: Rule = "fixed",
) -> dict[str, Any]:
    """One scheme's row: its budget, each response's statistics, and per requirement the
    failures, the yield and DPM with their exact intervals, the verdict and the interval it
    was decided on (``verdict_low_<r>``, ``verdict_high_<r>``, %: the exact one for a fixed
    sample size, the confidence sequence for ``rule="sequential"``)."""
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
        level = r.confidence if r.confidence is not None else confidence
        judged = verdict(estimate, level, rule=rule)
        verdicts.append(judged.name)
        if judged.name == "undecided":
            to_decide.append(judged.samples_to_decide)
        row[f"failures_{r.text}"] = estimate.failures
        row.update(_yield_columns(estimate, f"_{r.text}"))
        row[f"verdict_{r.text}"] = judged.name
        low, high = interval(n - estimate.failures, n, level, rule)
        row[f"verdict_low_{r.text}"] = 100.0 * low
        row[f"verdict_high_{r.text}"] = 100.0 * high
        row[f"samples_to_decide_{r.text}"] = judged.samples_to_decide
    row.update(_yield_columns(YieldEstimate(int(n - every.sum()), n), ""))
    row["verdict"] = (
        "fails" if "fails" in verdicts else "undecided" if "undecided" in verdicts else "meets"
    )
    row["verdict_basis"] = "monte-carlo"
    row["verdict_interval"] = rule
    row["feasible"] = row["verdict"] == "meets"
    reachable = [m for m in to_decide if m is not None]
    row["samples_to_decide"] = (
        max(reachable) if reachable and len(reachable) == len(to_decide) else None
    )
    checks = np.vstack(done.checks)
    row.update(_scheme_penetration(check_names, checks, ok))
    row.update(_scheme_regimes(check_names, checks, ok))
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


def _still_open(
    active: set[int], rows: Mapping[int, Mapping[str, Any]], costs: Sequence[float]
) -> set[int]:
    """The schemes worth more samples: undecided (or not run yet), and not dearer than a
    scheme already shown to meet every requirement (they can no longer be the cheapest
    feasible one)."""
    shown = [row["cost"] for row in rows.values() if row["feasible"]]
    ceiling = min(shown) if shown else math.inf
    return {
        i
        for i in active
        if (i not in rows or rows[i]["verdict"] == "undecided") and costs[i] <= ceiling
    }


def _free_lanes(backend: Backend | None) -> int:
    """Lanes of the batch engine that a block runs at no extra cost, for the cost-ordered
    schedule (:func:`_plan`): on a device (``gpu``, ``cuda``) a run's first chunk has the
    smallest of :data:`~jointplay.execution.executors.GPU_CHUNKS` lanes (or the backend's
    ``chunk_size``), one GPU thread each, so a block of fewer samples leaves the rest idle; on the
    CPU backends every lane costs a core its own time, so none are free (1: blocks are not
    rounded up)."""
    if backend is None or not backend.on_device:
        return 1
    from jointplay.execution.executors import GPU_CHUNKS

    return int(backend.chunk_size or GPU_CHUNKS[0])


def _plan(
    active: set[int],
    costs: Sequence[float],
    key: Sequence[int],
    looks: Sequence[int],
    looked: Sequence[int],
    reached: Mapping[int, int],
    free: int | None,
) -> dict[int, int]:
    """The schemes of the next block, each with the look (its samples in all) it is judged at.

    ``free`` ``None`` (a sample size fixed in advance): every open scheme. Else the
    **cost-ordered schedule**: the cheapest open scheme(s) (equal cost: all of them) get
    their next look; a dearer open scheme waits — until every cheaper one is decided
    ``fails``, stopped at ``max_samples`` or can no longer be chosen — except (1) in cost
    order, while its samples fit in the lanes the block leaves free (``free``: the block is
    rounded up to a multiple of it, :func:`_free_lanes`), and (2) when its stream already
    holds its next look's samples (a kinematic study's schemes of one length class share
    one stream). The schedule depends on the verdicts and the looks alone — never on the
    samples a resumed study kept — so a resumed study replays it block for block.
    """

    def following(i: int) -> int:
        return next(n for n in looks if n > looked[i])

    if free is None:
        return {i: following(i) for i in active}
    order = sorted(active, key=lambda i: (costs[i], i))
    need = dict(reached)
    plan: dict[int, int] = {}

    def take(i: int) -> None:
        plan[i] = following(i)
        need[key[i]] = max(need[key[i]], plan[i])

    for i in order:
        if costs[i] == costs[order[0]]:
            take(i)
    asked = sum(need[k] - reached[k] for k in need)
    capacity = -(-asked // free) * free
    for i in order:
        if i in plan:
            continue
        extra = max(0, following(i) - need[key[i]])
        if asked + extra > capacity:
            break
        take(i)
        asked += extra
    for i in order:  # its stream holds the samples already: judged at no cost
        if i not in plan and following(i) <= need[key[i]]:
            take(i)
    return plan


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
    for name, column in done.life_columns.items():
        frame[name] = column
    checks = np.vstack(done.checks)
    for c, name in enumerate(check_names):
        frame[name] = checks[:, c]
    frame["status"] = [STATUS[int(s)] for s in np.concatenate(done.status)]
    frame["error"] = list(done.errors)
    return frame


def life_settings(
    quantiles: Sequence[Requirement],
    parsed: Sequence[Requirement],
    limit: Mapping[str, float] | float | None,
    allowance: float | None,
    step: float | None,
    rare: RareDefects | None,
) -> tuple[float | None, float | None]:
    """The hours each sample's functional life is followed (the largest B_p hours) and its
    first step (default a tenth of them); ``(None, None)`` without a B_p requirement.

    Raises:
        ConfigError: nothing would end a life, a step beyond the hours, or rare defects.
    """
    if not quantiles:
        return None, None
    first = quantiles[0].text
    if not _life_ends(parsed) and limit is None and allowance is None:
        raise ConfigError(
            f"requirement {first!r}: nothing ends a life; add the requirement whose first "
            "failure ends it (e.g. 'rocker_speed_error <= 3 %') or a clearance limit "
            "('--clearance-limit +20 um')"
        )
    if rare is not None:
        raise ConfigError(
            f"requirement {first!r}: the rare-defect estimate samples single simulations, "
            "not lives; drop --rare-defects or the B_p requirement"
        )
    hours = max(r.limit for r in quantiles)
    step = hours / 10.0 if step is None else float(step)
    if not (math.isfinite(step) and 0.0 < step <= hours):
        raise ConfigError(
            f"--update-hours: the first step of a life must be > 0 and at most the B_p "
            f"hours ({hours / 3600.0:g} h), got {step / 3600.0:g} h"
        )
    return hours, step


def _life_ends(parsed: Sequence[Requirement]) -> list[Requirement]:
    """The requirements whose first failure ends a sample's functional life: all but the
    B_p requirements and the constant-rate ``life``."""
    return [r for r in parsed if r.quantile is None and r.response != "life"]


def _life_criteria(
    scheme: Scheme,
    mechanism: Mechanism,
    parsed: Sequence[Requirement],
    limit: Mapping[str, float] | float | None,
    allowance: float | None,
) -> tuple[Criterion, ...]:
    """What ends a sample's functional life: the other requirements, then each joint's
    clearance limit (:func:`jointplay.study.life.scheme_limits`)."""
    return (
        *requirement_criteria(_life_ends(parsed)),
        *clearance_criteria(scheme_limits(mechanism, scheme, limit, allowance)),
    )


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


def _binding(table: pd.DataFrame, requirements: Sequence[str]) -> str:
    """The requirement that binds where no scheme is shown to meet them all: the lowest best
    yield over the schemes; of requirements tied there (e.g. every one met by every sample
    of the best scheme, which is not yet shown to meet them), the one the schemes fail most
    (lowest mean yield), then the first given."""
    return min(
        requirements,
        key=lambda t: (float(table[f"yield_{t}"].max()), float(table[f"yield_{t}"].mean())),
    )
