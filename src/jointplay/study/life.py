"""The functional life of a production population: each mechanism, drawn from the tolerance
stack as made, worn until its first requirement fails, through the wear-coupled dynamics.

**Functional life of one mechanism** (:func:`functional_lives`): the time until the *first*
criterion fails — any requirement of :mod:`jointplay.study.requirements` (``joint_force``,
``rocker_speed_error``, ``contact_pressure``, ``wear_rate``, a kinematic response …) or a
joint's radial clearance limit — with the failing criterion named. The wear is coupled to the
dynamics: the response model (``model.evaluate(x)``, e.g.
:class:`~jointplay.tolerance.response_running.RunningResponses`) gives at each mechanism's
current clearances its responses and the Archard growth rate of every joint's radial
clearance (``wear_rate_<J>``, m/s); the clearances grow at those rates over a step Δt and
the mechanism is re-simulated there (the effective-clearance assumption of
:mod:`jointplay.dynamics.wear`).

**The update rule and its error** (stated in every result, ``LifeResult.settings``):

* each step grows the clearances by their rates integrated over it, the rates extrapolated
  linearly from the last two accepted states (second-order Adams–Bashforth, AB2; the first
  step is Euler's), and re-simulates there: one simulation per step, every response at the
  state it belongs to. The rates at the step's end give the trapezoid's growth over it, and
  the difference of the two is the step's local-error estimate (Milne's device; Hairer,
  Nørsett & Wanner, *Solving ODEs I*, §III.1). A step is accepted when that estimate is at
  most ``tolerance`` (default 1 %) of the step's clearance growth for every joint (or below
  :data:`CLEARANCE_ATOL`, 1 nm); else it is shortened to ``0.9 (tolerance/estimate)^(1/3)``
  of itself (at least a fifth) and re-simulated; the next step grows by the same rule, at
  most doubling. Where the rates are smooth, the clearances are followed to about
  ``tolerance`` of their growth (measured on the closed-form case dc/dt = a + b·c, whose
  rate grows 5.5-fold over the life: 0.54 % at 1 %, 27 simulations; 2.3 % at 5 %, 17).
  A simulated revolution's wear rate is noisy under impacts (the dry paper four-bar: lives
  move by 5 % between steps of 50 and 150 h, without bias; docs/life.md), a noise that no
  step control removes: see the smallest step below;
* a criterion that passes its limit within a step is located by linear interpolation of its
  margin over the step; a step longer than ``tolerance`` × the interpolated life is
  re-run to just short of it (½ ``tolerance`` before), then crossed with a step of at most
  ``tolerance`` × the life: the life is located within ``tolerance`` of itself;
* a step is never shorter than :data:`MIN_STEP_SHARE` of the first (``--update-hours``):
  there it is accepted whatever its estimate, counted, and the largest such estimate is
  reported (the wear rate of one simulated revolution is noisy under impacts; this noise
  averages out over the steps, while a shorter step only costs simulations);
* a simulation that fails is re-run at half the step; at the smallest step it ends the life
  there, named ``"simulation failed"``.

A mechanism that meets every criterion at ``hours`` is censored there. On a constant wear rate
the rule is exact: life = margin / rate (tests/study/test_life.py).

**Population** (:func:`population_life`): the tolerance stack of one scheme (a fit per joint
and an ISO 2768-1 length class), drawn as the design study draws it
(:meth:`~jointplay.study.design_schemes.Scheme.spec`,
:func:`~jointplay.tolerance.sampling.sample`, :func:`~jointplay.tolerance.parts.model_inputs`;
the same seed gives the same parts); every update step of all the mechanisms still running is
one block through the response model on the study's backend
(:func:`jointplay.tolerance.execution.run`). ``samples="auto"`` adds rounds (100, 200, 400 …
to ``max_samples``) until the Weibull B10's 90 % interval is as narrow as ``precision`` asks
(its half-width over B10). The statistics: :mod:`jointplay.study.weibull`.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Literal

import numpy as np
from numpy.typing import NDArray

from jointplay.errors import ConfigError
from jointplay.study.life_result import (
    SIMULATION_FAILED,
    LifeResult,
    Lives,
)
from jointplay.study.requirements import Requirement
from jointplay.tolerance.execution import NOT_RUN, OK, Backend, RunResult, run
from jointplay.tolerance.response_running import check_running_backend
from jointplay.tolerance.responses import ResponseModel

if TYPE_CHECKING:
    from jointplay.dynamics.settings import RunSettings
    from jointplay.dynamics.wear import WearSettings
    from jointplay.model.mechanism import Mechanism
    from jointplay.study.design_schemes import Scheme
    from jointplay.tolerance.parts import Process
    from jointplay.tolerance.response_running import RunningResponses

__all__ = [
    "CLEARANCE_ATOL",
    "DEFAULT_TOLERANCE",
    "MIN_STEP_SHARE",
    "Criterion",
    "clearance_criteria",
    "functional_lives",
    "life_rounds",
    "life_units",
    "parse_life_requirements",
    "population_life",
    "requirement_criteria",
    "scheme_limits",
]

FloatArray = NDArray[np.float64]

#: Default relative error of the update rule: of each step's clearance growth, and of a life.
DEFAULT_TOLERANCE = 0.01
#: A step's local clearance error below this (m) is accepted whatever its share (1 nm).
CLEARANCE_ATOL = 1e-9
#: The smallest step, as a share of the first one (two halvings): there a failed simulation
#: ends a life and a step is accepted whatever its error estimate — the wear rate of one
#: simulated revolution varies from one clearance to the next (impacts), a noise no shorter
#: step removes; such steps are counted (``Lives.floor_steps``) and their largest estimate
#: kept (``Lives.worst_error``).
MIN_STEP_SHARE = 0.25


@dataclass(frozen=True)
class Criterion:
    """One thing a mechanism must keep meeting as it wears.

    Attributes:
        label: as the reports name it, e.g. ``"rocker_speed_error <= 1 %"`` or
            ``"clearance of A <= 80 µm"``.
        response: the response it reads (``clearance_<J>`` for a clearance limit).
        upper: the response is bounded from above.
        limit: the limit, SI.
    """

    label: str
    response: str
    upper: bool
    limit: float

    def margin(self, values: FloatArray) -> FloatArray:
        """Per mechanism: the distance to the limit as a share of it (≥ 0: met; a NaN value
        fails: −inf)."""
        scale = abs(self.limit) or 1.0
        values = np.asarray(values, dtype=float)
        out = (self.limit - values if self.upper else values - self.limit) / scale
        return np.where(np.isnan(out), -np.inf, out)


def requirement_criteria(requirements: Sequence[Requirement]) -> tuple[Criterion, ...]:
    """The criteria of parsed requirements (their text as the label)."""
    return tuple(
        Criterion(r.text or r.response, r.response, r.upper, r.limit) for r in requirements
    )


def clearance_criteria(limits: Mapping[str, float]) -> tuple[Criterion, ...]:
    """One criterion per joint: its radial clearance at most ``limits[joint]`` (m)."""
    return tuple(
        Criterion(
            f"clearance of {joint} <= {limit * 1e6:.4g} µm", f"clearance_{joint}", True, limit
        )
        for joint, limit in limits.items()
    )


def life_units(mechanism: Mechanism) -> dict[str, str]:
    """SI unit of every response a life requirement may name: the design study's (kinematic
    and dynamic, without ``life`` itself) and each fitted joint's ``clearance_<J>``."""
    from jointplay.study.design_schemes import design_units

    units = {**design_units(mechanism, "kinematic"), **design_units(mechanism, "dynamic")}
    units.pop("life", None)
    for joint in mechanism.revolute_joints:
        if joint.fit is not None:
            units[f"clearance_{joint.name}"] = "m"
    return units


def parse_life_requirements(
    mechanism: Mechanism, requirements: Sequence[str | Requirement]
) -> tuple[Requirement, ...]:
    """Requirements as typed objects, against :func:`life_units`.

    Raises:
        ConfigError: a malformed requirement, an unknown response, or ``life`` or a B_p
            (the life is what this study computes: ask for the hours with ``hours``).
    """
    from jointplay.study.requirements import parse_requirement

    units = life_units(mechanism)
    out = []
    for item in requirements:
        text = item.text if isinstance(item, Requirement) else item.strip()
        if text.startswith("life"):
            parsed = None
        elif isinstance(item, Requirement):
            parsed = item
        else:
            parsed = parse_requirement(item, units)
        if parsed is None or parsed.quantile is not None:
            raise ConfigError(
                f"requirement {text!r}: the life is what this study computes; give the "
                "requirements a mechanism must keep meeting (e.g. 'rocker_speed_error <= 2 %') "
                "and the hours to run with --hours"
            )
        out.append(parsed)
    return tuple(out)


def functional_lives(
    model: ResponseModel,
    x: FloatArray,
    criteria: Sequence[Criterion],
    *,
    hours: float,
    first_step: float,
    tolerance: float = DEFAULT_TOLERANCE,
    min_step: float | None = None,
    backend: Backend | None = None,
    on_step: Callable[[int, int], None] | None = None,
    as_made: RunResult | None = None,
) -> Lives:
    """The functional life of each mechanism ``x`` (rows, the model's inputs at the start).

    Args:
        model: the response model; its inputs include ``clearance_<J>`` (m) and its
            responses ``wear_rate_<J>`` (m/s) for every joint that wears, and every
            response a criterion reads (``clearance_<J>`` are read from the inputs).
        x: (n, k) the mechanisms as made, SI, in ``model.input_names`` order.
        criteria: what each mechanism must keep meeting.
        hours: the time simulated, s (SI; lives beyond it are censored there).
        first_step: the first step, s.
        tolerance: the update rule's relative error (module docstring).
        min_step: the smallest step, s (default :data:`MIN_STEP_SHARE` of the first).
        backend: where each block of re-simulations runs (default: local processes).
        on_step: optional callback ``on_step(running, n)`` after each block.
        as_made: the model already run on ``x`` (the caller's :func:`~jointplay.tolerance.
            execution.run` of the same rows, e.g. the design study's samples): its responses
            are the lives' start, and the as-made simulation is not repeated (it still
            counts as the first of ``Lives.resimulations``). Only its rows' values and
            status are read.

    Raises:
        ConfigError: the model has no clearance input or no wear rate for it, a criterion's
            response is unknown, or a setting is out of range.
        KeyboardInterrupt: a block of re-simulations was interrupted (no life is kept: an
            interrupted population is not a population; the caller's output folder keeps
            its earlier result).
    """
    horizon = float(hours)
    if not (math.isfinite(horizon) and horizon > 0):
        raise ConfigError(f"the hours to simulate must be finite and > 0, got {hours!r}")
    if not (math.isfinite(first_step) and first_step > 0):
        raise ConfigError(f"the first step must be finite and > 0, got {first_step!r}")
    if not 0.0 < tolerance < 0.5:
        raise ConfigError(f"tolerance must lie between 0 and 50 %, got {tolerance!r}")
    inputs = list(model.input_names)
    responses = list(model.response_names)
    joints = [n.removeprefix("clearance_") for n in inputs if n.startswith("clearance_")]
    if not joints:
        raise ConfigError("the life needs clearance joints: no clearance_<joint> input")
    missing = [j for j in joints if f"wear_rate_{j}" not in responses]
    if missing:
        raise ConfigError(f"the response model gives no wear rate for joint(s) {missing}")
    for c in criteria:
        if c.response not in responses and c.response not in inputs:
            raise ConfigError(f"criterion {c.label!r}: the model has no response {c.response!r}")
    columns = [inputs.index(f"clearance_{j}") for j in joints]
    rate_columns = [responses.index(f"wear_rate_{j}") for j in joints]
    x0 = np.array(x, dtype=float, copy=True)
    n = len(x0)
    first_step = min(float(first_step), horizon)
    min_step = first_step * MIN_STEP_SHARE if min_step is None else min(min_step, first_step)

    def evaluate(block: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray, NDArray[np.bool_]]:
        """Rates (m, J), margins (m, criteria), responses and ok of a block."""
        if not len(block):
            empty = np.empty((0, len(joints)))
            return (
                empty,
                np.empty((0, len(criteria))),
                np.empty((0, len(responses))),
                np.empty(0, bool),
            )
        outcome = run(model, block, backend=backend)
        if outcome.interrupted:  # lives cut short are no lives: nothing is kept
            raise KeyboardInterrupt
        rates, margins, ok = reading(block, outcome.values, outcome.status == OK)
        return rates, margins, outcome.values, ok

    def reading(
        block: FloatArray, values: FloatArray, ok: NDArray[np.bool_]
    ) -> tuple[FloatArray, FloatArray, NDArray[np.bool_]]:
        """Rates and margins of a block's responses."""
        rates = np.clip(values[:, rate_columns], 0.0, None)
        margins = (
            np.column_stack(
                [
                    c.margin(
                        block[:, inputs.index(c.response)]
                        if c.response in inputs
                        else values[:, responses.index(c.response)]
                    )
                    for c in criteria
                ]
            )
            if criteria
            else np.empty((len(block), 0))
        )
        return rates, margins, ok

    t = np.zeros(n)
    clearance = x0[:, columns].copy()
    if as_made is None:
        rates, margins, _, ok = evaluate(x0)
    else:
        if as_made.values.shape != (n, len(responses)):
            raise ConfigError(
                f"as_made: {as_made.values.shape} responses for {n} mechanisms of "
                f"{len(responses)} responses; pass the model's run of the same rows"
            )
        if np.any(as_made.status == NOT_RUN):  # an interrupted run: no life from it
            raise KeyboardInterrupt
        rates, margins, ok = reading(x0, as_made.values, as_made.status == OK)
    resims = np.ones(n, dtype=np.int64)
    life = np.full(n, np.nan)
    failing = np.full(n, "", dtype=object)
    censored = np.zeros(n, dtype=bool)
    step = np.full(n, first_step)
    locate = np.full(n, np.inf)  # once a crossing is predicted: the step that locates it
    prev_rates = np.zeros_like(rates)
    floor_steps = np.zeros(n, dtype=np.int64)
    worst = np.zeros(n)  # the largest local-error estimate accepted, share of a step's growth
    prev_dt = np.zeros(n)
    history: list[list[tuple[float, tuple[float, ...]]]] = [
        [(0.0, tuple(map(float, clearance[i])))] for i in range(n)
    ]
    running = np.ones(n, dtype=bool)
    # as made: a failed simulation, or a criterion already missed, ends the life at 0
    for i in np.flatnonzero(~ok):
        life[i], failing[i], running[i] = 0.0, SIMULATION_FAILED, False
    for i in np.flatnonzero(ok & np.any(margins < 0, axis=1)):
        life[i], failing[i], running[i] = 0.0, criteria[int(np.argmin(margins[i]))].label, False
    if on_step is not None:
        on_step(int(running.sum()), n)
    while running.any():
        idx = np.flatnonzero(running)
        dt = np.minimum(step[idx], horizon - t[idx])
        # AB2: the rate extrapolated linearly from the last two accepted states (its slope 0
        # at the first step: Euler), integrated over the step
        slope = np.divide(
            rates[idx] - prev_rates[idx],
            prev_dt[idx, None],
            out=np.zeros_like(rates[idx]),
            where=prev_dt[idx, None] > 0,
        )
        growth = np.maximum(rates[idx] * dt[:, None] + 0.5 * slope * dt[:, None] ** 2, 0.0)
        proposed = clearance[idx] + growth
        block = x0[idx].copy()
        block[:, columns] = proposed
        new_rates, new_margins, _, new_ok = evaluate(block)
        resims[idx] += 1
        at_min = dt <= min_step * (1 + 1e-9)
        # Milne's device: the trapezoid over the step's two end rates against AB2's growth
        trapezoid = 0.5 * (rates[idx] + new_rates) * dt[:, None]
        estimate = np.abs(growth - trapezoid)
        allowed = np.maximum(tolerance * growth, CLEARANCE_ATOL)
        with np.errstate(invalid="ignore"):
            accurate = np.all(estimate <= allowed, axis=1) | at_min
        for k, i in enumerate(idx):
            if not new_ok[k]:
                if at_min[k]:
                    life[i], failing[i], running[i] = t[i] + dt[k], SIMULATION_FAILED, False
                else:
                    step[i] = 0.5 * dt[k]
                continue
            if not accurate[k]:
                ratio = float(np.max(estimate[k] / allowed[k]))
                step[i] = max(dt[k] * max(0.2, 0.9 * ratio ** (-1 / 3)), min_step)
                continue
            missed = new_margins[k] < 0
            if missed.any():
                # each missed criterion's crossing, by linear interpolation of its margin
                before, after = margins[i][missed], new_margins[k][missed]
                with np.errstate(divide="ignore", invalid="ignore"):
                    share = np.where(np.isfinite(after), before / (before - after), 1.0)
                share = np.clip(np.nan_to_num(share, nan=1.0), 0.0, 1.0)
                first = int(np.argmin(share))
                crossing = t[i] + float(share[first]) * dt[k]
                if dt[k] > tolerance * crossing and not at_min[k]:
                    # re-run to just short of it, then cross it in a short step
                    locate[i] = tolerance * crossing if crossing > 0 else min_step
                    short = crossing * (1 - 0.5 * tolerance) - t[i]
                    step[i] = max(short if short > 0 else locate[i], min_step)
                    continue
                life[i] = crossing
                failing[i] = criteria[int(np.flatnonzero(missed)[first])].label
                running[i] = False
                frac = float(share[first])
                history[i].append(
                    (
                        crossing,
                        tuple(map(float, clearance[i] + frac * (proposed[k] - clearance[i]))),
                    )
                )
                continue
            # accepted
            ratio = float(np.max(estimate[k] / allowed[k])) if estimate[k].size else 0.0
            if not ratio <= 1.0:
                floor_steps[i] += 1
            worst[i] = max(worst[i], ratio * tolerance)
            t[i] += dt[k]
            clearance[i] = proposed[k]
            prev_rates[i], prev_dt[i] = rates[i], dt[k]
            rates[i] = new_rates[k]
            margins[i] = new_margins[k]
            history[i].append((float(t[i]), tuple(map(float, clearance[i]))))
            grow = 2.0 if ratio <= (0.9 / 2.0) ** 3 else 0.9 * ratio ** (-1 / 3)
            step[i] = max(min(dt[k] * min(2.0, max(0.2, grow)), locate[i]), min_step)
            if t[i] >= horizon * (1 - 1e-12):
                life[i], censored[i], running[i] = horizon, True, False
        if on_step is not None:
            on_step(int(running.sum()), n)
    return Lives(
        joints=tuple(joints),
        life=life,
        censored=censored,
        failing=tuple(str(f) for f in failing),
        resimulations=resims,
        history=tuple(tuple(h) for h in history),
        hours=horizon,
        floor_steps=floor_steps,
        worst_error=worst,
    )


def population_life(
    mechanism: Mechanism,
    fit: str | Mapping[str, str],
    length_class: str,
    requirements: Sequence[str | Requirement],
    *,
    hours: float,
    samples: int | Literal["auto"] = "auto",
    max_samples: int = 2000,
    precision: float = 0.10,
    seed: int = 0,
    process: Process | None = None,
    truncate: bool = True,
    clearance_limit: Mapping[str, float] | float | None = None,
    clearance_allowance: float | None = None,
    wear: WearSettings | None = None,
    run_settings: RunSettings | None = None,
    first_step: float | None = None,
    tolerance: float = DEFAULT_TOLERANCE,
    backend: Backend | None = None,
    progress: Callable[[str], None] | None = None,
    model: ResponseModel | None = None,
    min_step: float | None = None,
) -> LifeResult:
    """The life distribution of the mechanisms built to one scheme.

    Args:
        mechanism: the nominal mechanism (pin joints with a diameter).
        fit: the ISO 286 fit of every pin joint, or one per joint.
        length_class: the ISO 2768-1 class of the link lengths.
        requirements: what each mechanism must keep meeting (text or parsed).
        hours: the time simulated, s (SI): lives beyond it are censored there.
        samples: mechanisms, or ``"auto"``: rounds of 100, 200, 400, … until B10's
            interval is as narrow as ``precision`` asks, or ``max_samples``.
        max_samples: ``"auto"``: the most mechanisms.
        precision: ``"auto"``: the Weibull B10 interval's half-width over B10 to reach.
        seed: the seed (the design study's: the same parts).
        process, truncate: how the parts are made (as :func:`~jointplay.study.design.
            design_study`).
        clearance_limit: a radial clearance limit per joint or for all, m, or ``None``.
        clearance_allowance: instead: the fit's largest radial clearance plus this, m.
        wear: Archard parameters.
        run_settings: how the dynamics run (:class:`~jointplay.dynamics.settings.RunSettings`).
        first_step: the first update step, s (default ``hours`` / 10).
        tolerance: the update rule's relative error.
        backend: where the re-simulations run.
        progress: optional callback with one line per update block.
        model: the response model (default: the running responses of the scheme's inputs).
        min_step: the smallest step, s (default :data:`MIN_STEP_SHARE` of the first); equal
            to ``first_step``: fixed steps, each accepted whatever its error estimate (where
            the wear rate's noise keeps every step at the smallest anyway, this saves the
            rejected tries on the way down to it; docs/life.md, "Cost").

    Raises:
        ConfigError: no criterion, a bad requirement, a bad setting.
    """
    from jointplay.study.design_schemes import schemes
    from jointplay.tolerance.methods import truncated_at_limits
    from jointplay.tolerance.parts import Process, model_inputs
    from jointplay.tolerance.sampling import sample

    if not 0.0 < precision < 1.0:
        raise ConfigError(f"precision must lie between 0 and 100 %, got {precision!r}")
    rounds = life_rounds(samples, max_samples)
    parsed = parse_life_requirements(mechanism, requirements)
    (scheme,) = schemes(mechanism, [fit], [length_class])
    limits = scheme_limits(mechanism, scheme, clearance_limit, clearance_allowance)
    criteria = (*requirement_criteria(parsed), *clearance_criteria(limits))
    if not criteria:
        raise ConfigError(
            "the life needs a criterion: a requirement (e.g. 'rocker_speed_error <= 2 %') or "
            "a clearance limit"
        )
    process = process or Process()
    spec = scheme.spec(mechanism, process)
    spec = truncated_at_limits(spec) if truncate else spec
    names, _ = model_inputs(spec.names, np.empty((0, len(spec.names))))
    if model is None:
        model = _running_model(mechanism, names, parsed, run_settings, wear)
        check_running_backend(
            model.base, backend, "the population life (each mechanism's wear rate)"
        )
    step = hours / 10.0 if first_step is None else float(first_step)
    parts: list[Lives] = []
    features: list[FloatArray] = []
    inputs: list[FloatArray] = []
    done = 0
    stopped = "samples"
    for target in rounds:
        drawn = sample(spec, target, seed).values[done:]
        _, x = model_inputs(spec.names, drawn)

        def note(running: int, total: int, start: int = done) -> None:
            if progress is not None:
                progress(f"mechanisms {start + 1}–{start + total}: {running} still running")

        parts.append(
            functional_lives(
                model,
                x,
                criteria,
                hours=hours,
                first_step=step,
                tolerance=tolerance,
                min_step=min_step,
                backend=backend,
                on_step=note,
            )
        )
        features.append(drawn)
        inputs.append(x)
        done = target
        if samples == "auto":
            lives = Lives.concatenate(parts)
            if _precise(lives, precision):
                stopped = "precision"
                break
            stopped = "max-samples"
    lives = Lives.concatenate(parts)
    settings = {
        "scheme": scheme.label,
        "fits": dict(scheme.fits),
        "length_class": scheme.length_class,
        "samples": samples,
        "max_samples": max_samples if samples == "auto" else samples,
        "precision": precision,
        "stopped_by": stopped,
        "rounds": list(rounds[: len(parts)]),
        "seed": seed,
        "process": process.describe(),
        "truncated_at_limits": bool(truncate),
        "hours_s": hours,
        "first_step_s": step,
        "min_step_s": min(step, step * MIN_STEP_SHARE if min_step is None else min_step),
        "tolerance": tolerance,
        "update_rule": (
            "each step grows the clearances by their wear rates extrapolated from the last two "
            "states (AB2) and re-simulates there; accepted when the difference from the "
            f"trapezoid over its two end rates is at most {tolerance:.3g} of its clearance "
            f"growth or {CLEARANCE_ATOL * 1e6:g} µm, else shortened"
            + (
                " (fixed steps: the smallest step is the first, so every step is accepted and "
                "its error estimate only reported, per life)"
                if min_step is not None and min_step >= step
                else ""
            )
            + "; a crossing is located by linear interpolation of the margin, within "
            f"{tolerance:.3g} of the life"
        ),
        "clearance_limit_m": limits,
        "criteria": [c.label for c in criteria],
        "model": model.describe(),
        "backend": None if backend is None else backend.kind,
    }
    return LifeResult(
        mechanism_name=getattr(mechanism, "name", ""),
        criteria=tuple(c.label for c in criteria),
        input_names=tuple(names),
        feature_names=tuple(spec.names),
        features=np.vstack(features),
        inputs=np.vstack(inputs),
        lives=lives,
        settings=settings,
    )


#: ``samples="auto"``: mechanisms in the first round (then doubling).
FIRST_ROUND = 100


def life_rounds(samples: int | Literal["auto"], max_samples: int) -> tuple[int, ...]:
    """Total mechanisms after each round: ``(samples,)`` for a number, else
    :data:`FIRST_ROUND`, doubling, up to ``max_samples`` (its last round).

    (The design study's rounds became blocks of 100 looked at on a confidence sequence,
    :func:`~jointplay.study.design_schemes.sample_looks`; a population's rounds stop on B10's
    precision, so they keep doubling: the former ``sample_rounds``.)

    Raises:
        ConfigError: ``samples`` or ``max_samples`` not a positive integer.
    """
    from jointplay.study.design_schemes import sample_looks

    looks = sample_looks(samples, max_samples)  # checks both
    if samples != "auto":
        return looks
    out = [min(FIRST_ROUND, max_samples)]
    while out[-1] < max_samples:
        out.append(min(2 * out[-1], max_samples))
    return tuple(out)


def scheme_limits(
    mechanism: Mechanism,
    scheme: Scheme,
    clearance_limit: Mapping[str, float] | float | None,
    clearance_allowance: float | None,
) -> dict[str, float]:
    """Each fitted joint's radial clearance limit, m: the fit's largest radial clearance plus
    ``clearance_allowance``, or ``clearance_limit`` (one for all, or per joint); none
    without either."""
    from jointplay.study.design_schemes import _diameter
    from jointplay.tolerance import iso286

    limits: dict[str, float] = {}
    for joint, designation in scheme.fits.items():
        if clearance_allowance is not None:
            limits[joint] = (
                iso286.fit(designation, _diameter(mechanism, joint)).radial_clearance_max
                + clearance_allowance
            )
        elif isinstance(clearance_limit, Mapping):
            if joint in clearance_limit:
                limits[joint] = float(clearance_limit[joint])
        elif clearance_limit is not None:
            limits[joint] = float(clearance_limit)
    return limits


def _precise(lives: Lives, precision: float) -> bool:
    """The Weibull B10's interval half-width is at most ``precision`` of B10."""
    from jointplay.study.weibull import fit_weibull

    positive = lives.life > 0
    fit = fit_weibull(lives.life[positive], lives.censored[positive])
    if fit is None:
        return False
    low, high = fit.quantile_interval(0.10)
    return math.isfinite(high) and 0.5 * (high - low) <= precision * fit.quantile(0.10)


def _running_model(
    mechanism: Mechanism,
    names: Sequence[str],
    parsed: Sequence[Requirement],
    run_settings: RunSettings | None,
    wear: WearSettings | None,
) -> RunningResponses:
    """The running responses (wear rates, speed error, forces, pressures) of ``names``, with
    the ideal-joint kinematic responses when a requirement names one."""
    from jointplay.dynamics.settings import RunSettings
    from jointplay.dynamics.wear import OutputSpeedReference, WearSettings
    from jointplay.study.design_schemes import design_units
    from jointplay.tolerance.responses import RunningResponses, kinematic_model, run_model

    base = run_model(mechanism, tuple(names), run_settings or RunSettings.of())
    dynamic = design_units(mechanism, "dynamic")
    lengths = [n for n in names if n.startswith("length_")]
    mixed = any(
        r.response not in dynamic and not r.response.startswith("clearance_") for r in parsed
    )
    kinematic = kinematic_model(mechanism, lengths) if lengths and mixed else None
    return RunningResponses(
        base, OutputSpeedReference.of(mechanism), wear or WearSettings(), kinematic=kinematic
    )
