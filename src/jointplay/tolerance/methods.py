"""Tolerance analysis methods: worst case, RSS and Monte Carlo, with statistics per response.

Each method is a small frozen object holding its options, registered by name in
:data:`TOLERANCE_METHODS` (APIs take a name or an instance: :func:`get_method`), with one
method, ``run(model, spec, *, limits, backend, progress)``. It builds a matrix of input
points, evaluates the response model on it through :func:`jointplay.tolerance.execution.run`
(any backend) and summarises every response in a frozen :class:`ResponseSummary`;
:class:`MethodResult` keeps the points, the responses, the status of each point and the
failures (with their inputs).

* **Worst case** (:class:`WorstCase`): all 2^k corners of the limits for k ≤ 10 inputs
  (exact extremes of responses that are monotonic in each input), reporting the corner of the
  lowest and highest response; per-input effects are the main effects of that two-level full
  factorial design. Otherwise (or on request) the *sensitivity-sign* corners: finite-difference
  sensitivities at the centre give, per response, the corner with every input at the limit
  that raises (or lowers) it. For a linear stack ``y = Σ aᵢxᵢ`` both give
  ``y_nominal ± Σ|aᵢ|hᵢ`` — the arithmetic sum.
* **RSS** (:class:`Rss`): sensitivities aᵢ = ∂y/∂xᵢ by central finite differences (or the
  model's analytic ``jacobian``) at the input means; ``σ_y = √(Σ aᵢ²σᵢ²)`` with σᵢ the input
  distributions' standard deviations, and the classical statistical stack
  ``√(Σ (aᵢhᵢ)²)`` with hᵢ the half-widths of the limits.
* **Monte Carlo** (:class:`MonteCarlo`): seeded samples (:mod:`jointplay.tolerance.sampling`);
  statistics of the successful samples; variance contributions from standardised regression
  coefficients (SRCᵢ = bᵢσᵢ/σ_y, squared and normalised; R² says how linear the response is)
  and first-order Sobol indices estimated by binning (Var E[y|xᵢ] / Var y, Saltelli et al.,
  *Global Sensitivity Analysis: The Primer*, 2008, §1.2.7); the contributions are the SRC
  shares while R² ≥ 0.7 and the normalised Sobol indices otherwise.

**Sampling distributions** (:mod:`jointplay.tolerance.spec`; h is the half-width of the
limits, m their centre): ``normal`` (the default: mean m + shift, σ = h/3 so that ±3σ span
the limits, or σ = (h − |shift|)/(3 Cpk) given a Cpk), ``uniform`` on the limits,
``triangular`` with its mode at m + shift. A normal process puts 0.27 % of its parts
outside ±3σ; such a part fails inspection and is not assembled, so by default the Monte
Carlo draws every normal input from the normal **truncated at its specification limits**
(:func:`truncated_at_limits`; scipy's ``truncnorm``): no sample lies outside the limits, and
σ of the truncated ±3σ normal is 0.9866 h/3. ``MonteCarlo(truncate=False)`` draws from the
untruncated normal (truncated only at the physical bounds, e.g. a clearance ≥ 0), as if
out-of-tolerance parts were assembled. Uniform and triangular inputs never leave their
limits. The result's ``settings`` say which was used.

Specification limits on a response give the percentage out of spec (Monte Carlo: counted;
RSS: from the normal approximation), Cp = (USL − LSL)/(6σ) and
Cpk = min(USL − μ, μ − LSL)/(3σ) (one-sided when one limit is given).
"""

from __future__ import annotations

import itertools
import math
import types
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, fields, replace
from typing import Any, ClassVar, Literal

import numpy as np
from numpy.typing import NDArray
from scipy import special

from jointplay.errors import ConfigError
from jointplay.tolerance.execution import OK, Backend, RunResult, run
from jointplay.tolerance.responses import DifferentiableModel, ResponseModel
from jointplay.tolerance.sampling import SamplingMethod, check_settings, sample
from jointplay.tolerance.spec import ToleranceSpec

__all__ = [
    "TOLERANCE_METHODS",
    "Failure",
    "MethodResult",
    "MonteCarlo",
    "ResponseSummary",
    "Rss",
    "SpecLimits",
    "ToleranceMethod",
    "WorstCase",
    "distribution_note",
    "get_method",
    "regression_contributions",
    "sobol_first_order",
    "truncated_at_limits",
]

FloatArray = NDArray[np.float64]
Corners = Literal["auto", "all", "sensitivity"]
Sensitivity = Literal["finite-difference", "analytic"]

#: Largest number of inputs for which the worst case evaluates every corner by default.
MAX_ALL_CORNER_INPUTS = 10

#: Monte Carlo contributions are squared standardised regression coefficients while a linear
#: model explains at least this share of the variance; below it (a kinked or strongly
#: nonlinear response) they are the normalised first-order Sobol indices instead.
MIN_LINEAR_R_SQUARED = 0.7

#: Percentiles reported for Monte Carlo (the ±3σ and ±2σ-equivalent tails and the median).
PERCENTILES: tuple[float, ...] = (0.135, 2.5, 50.0, 97.5, 99.865)


@dataclass(frozen=True)
class SpecLimits:
    """Specification limits of a response (SI); either may be ``None`` (one-sided)."""

    lower: float | None = None
    upper: float | None = None

    def __post_init__(self) -> None:
        if self.lower is None and self.upper is None:
            raise ConfigError("spec limits: give a lower limit, an upper limit or both")
        for name in ("lower", "upper"):
            value = getattr(self, name)
            if value is not None:
                if not math.isfinite(value):
                    raise ConfigError(f"spec limits: {name} must be finite, got {value!r}")
                object.__setattr__(self, name, float(value))
        if self.lower is not None and self.upper is not None and not self.lower < self.upper:
            raise ConfigError(
                f"spec limits: lower {self.lower:g} must be below upper {self.upper:g}"
            )

    def outside(self, values: FloatArray) -> NDArray[np.bool_]:
        """Which values are out of spec."""
        out = np.zeros(values.shape, dtype=bool)
        if self.lower is not None:
            out |= values < self.lower
        if self.upper is not None:
            out |= values > self.upper
        return out

    def capability(self, mean: float, std: float) -> tuple[float | None, float | None]:
        """(Cp, Cpk) of a process with ``mean`` and ``std``; Cp needs both limits."""
        if not (math.isfinite(std) and std > 0):
            return None, None
        cp = None
        if self.lower is not None and self.upper is not None:
            cp = (self.upper - self.lower) / (6.0 * std)
        sides = []
        if self.upper is not None:
            sides.append((self.upper - mean) / (3.0 * std))
        if self.lower is not None:
            sides.append((mean - self.lower) / (3.0 * std))
        return cp, min(sides)

    def normal_fraction_outside(self, mean: float, std: float) -> float:
        """Fraction of a normal(mean, std) population out of spec."""
        if not (math.isfinite(std) and std > 0):
            return float(bool(self.outside(np.array([mean]))[0]))
        fraction = 0.0
        if self.lower is not None:
            fraction += float(special.ndtr((self.lower - mean) / std))
        if self.upper is not None:
            fraction += float(special.ndtr((mean - self.upper) / std))
        return fraction

    def describe(self) -> dict[str, float | None]:
        return {"lower": self.lower, "upper": self.upper}


@dataclass(frozen=True)
class Failure:
    """A point whose evaluation failed: where, with which inputs, why.

    Attributes:
        index: row in the method's points (the ``sample`` column of ``samples.parquet``).
        role: ``"sample"``, ``"nominal"``, ``"corner"``, ``"centre"`` or ``"fd"``.
        inputs: input values, SI.
        error: ``"ErrorType: message"``.
    """

    index: int
    role: str
    inputs: Mapping[str, float]
    error: str


@dataclass(frozen=True)
class ResponseSummary:
    """One response under one method; fields a method does not give are ``None``.

    Attributes:
        name: response name.  unit: its SI unit.
        nominal: response at the nominal inputs.
        n_ok: successful points the statistics use.
        mean, std: Monte Carlo: sample mean and standard deviation (ddof = 1); RSS: response at
            the input means and √(Σ aᵢ²σᵢ²).
        minimum, maximum: Monte Carlo: smallest and largest sample; worst case: lowest and
            highest corner response.
        percentiles: Monte Carlo percentiles, keyed ``"p2.5"`` etc.
        half_range: worst case: (maximum − minimum)/2; RSS: √(Σ (aᵢhᵢ)²).
        low_corner, high_corner: worst case: inputs of the lowest and highest response.
        sensitivities: ∂y/∂xᵢ (RSS, sensitivity worst case) or main-effect slopes (all corners).
        contributions: share of each input, summing to 1 (variance shares for RSS and Monte
            Carlo, shares of the arithmetic stack for the worst case).
        contribution_basis: how ``contributions`` were computed: ``"src"`` (squared
            standardised regression coefficients), ``"sobol"`` (first-order Sobol indices,
            Monte Carlo with R² < 0.7), ``"sensitivities"`` (RSS, sensitivity worst case) or
            ``"main effects"`` (all-corner worst case).
        r_squared: Monte Carlo: R² of the linear regression behind the contributions.
        sobol_first_order: Monte Carlo: first-order Sobol indices (binning estimate).
        limits: the response's specification limits, if given.
        out_of_spec_percent: Monte Carlo: counted; RSS: normal approximation; worst case:
            percentage of corners out of spec.
        cp, cpk: process capability of the response against ``limits``.
        note: a caveat on the numbers (e.g. RSS of a response that is kinked at the centre).
    """

    name: str
    unit: str
    nominal: float
    n_ok: int
    mean: float | None = None
    std: float | None = None
    minimum: float | None = None
    maximum: float | None = None
    percentiles: Mapping[str, float] | None = None
    half_range: float | None = None
    low_corner: Mapping[str, float] | None = None
    high_corner: Mapping[str, float] | None = None
    sensitivities: Mapping[str, float] | None = None
    contributions: Mapping[str, float] = field(default_factory=dict)
    contribution_basis: str | None = None
    r_squared: float | None = None
    sobol_first_order: Mapping[str, float] | None = None
    limits: SpecLimits | None = None
    out_of_spec_percent: float | None = None
    cp: float | None = None
    cpk: float | None = None
    note: str | None = None

    @property
    def most_influential(self) -> str | None:
        """The input with the largest contribution."""
        if not any(value > 0 for value in self.contributions.values()):
            return None
        return max(self.contributions, key=lambda name: self.contributions[name])

    def describe(self) -> dict[str, Any]:
        """JSON-ready (SI)."""
        out: dict[str, Any] = {"unit": self.unit, "nominal": self.nominal, "n_ok": self.n_ok}
        for name in (
            "mean",
            "std",
            "minimum",
            "maximum",
            "percentiles",
            "half_range",
            "low_corner",
            "high_corner",
            "sensitivities",
            "r_squared",
            "sobol_first_order",
            "out_of_spec_percent",
            "cp",
            "cpk",
            "note",
        ):
            value = getattr(self, name)
            if value is not None:
                out[name] = dict(value) if isinstance(value, Mapping) else value
        out["contributions"] = dict(self.contributions)
        out["contribution_basis"] = self.contribution_basis
        out["most_influential"] = self.most_influential
        if self.limits is not None:
            out["spec_limits"] = self.limits.describe()
        return out


@dataclass(frozen=True)
class MethodResult:
    """Everything a method evaluated and concluded.

    Attributes:
        method: ``"monte-carlo"``, ``"worst-case"`` or ``"rss"``.
        input_names, response_names: column names.
        units: SI unit per response.
        x: (m, k) evaluated input points, SI.
        roles: m labels (``"sample"``, ``"corner"``, ``"nominal"``, ``"centre"``, ``"fd"``).
        run: responses, status and errors of the points (and the model's per-point
            checks, :attr:`~jointplay.tolerance.execution.RunResult.checks`), and the
            execution record.
        nominal: (r,) responses at the nominal inputs.
        summaries: per response.
        failures: the failed points with their inputs.
        settings: the method's settings (seed, sampling, corners, step, ...).
    """

    method: str
    input_names: tuple[str, ...]
    response_names: tuple[str, ...]
    units: Mapping[str, str]
    x: FloatArray
    roles: tuple[str, ...]
    run: RunResult
    nominal: FloatArray
    summaries: Mapping[str, ResponseSummary]
    failures: tuple[Failure, ...]
    settings: Mapping[str, Any]

    @property
    def interrupted(self) -> bool:
        return self.run.interrupted


# --- helpers -------------------------------------------------------------------------------------


def _limits_for(
    limits: Mapping[str, SpecLimits] | None, response_names: Sequence[str]
) -> dict[str, SpecLimits]:
    limits = dict(limits or {})
    unknown = sorted(set(limits) - set(response_names))
    if unknown:
        raise ConfigError(
            f"spec limits given for unknown response(s) {unknown}; responses: {list(response_names)}"
        )
    return limits


def _failures(
    x: FloatArray, roles: Sequence[str], result: RunResult, names: Sequence[str]
) -> tuple[Failure, ...]:
    failed = np.flatnonzero(result.status == 1)
    return tuple(
        Failure(
            int(i),
            roles[int(i)],
            {name: float(v) for name, v in zip(names, x[i], strict=True)},
            result.errors[i],
        )
        for i in failed
    )


def _evaluate(
    model: ResponseModel,
    spec: ToleranceSpec,
    x: FloatArray,
    backend: Backend | None,
    progress: bool,
    description: str,
) -> RunResult:
    if tuple(model.input_names) != spec.names:
        raise ConfigError(
            f"the model's inputs {list(model.input_names)} do not match the specification's "
            f"{list(spec.names)}"
        )
    return run(model, x, backend=backend, progress=progress, description=description)


def _nominal_or_raise(result: RunResult, index: int, what: str) -> FloatArray:
    if result.interrupted:  # even where this point finished: the run stops here
        raise KeyboardInterrupt
    if result.status[index] != OK:
        raise ConfigError(f"the {what} point cannot be evaluated: {result.errors[index]}")
    return np.asarray(result.values[index], dtype=float)


def _shares(weights: FloatArray, names: Sequence[str]) -> dict[str, float]:
    weights = np.where(np.isfinite(weights), np.abs(weights), 0.0)
    total = float(weights.sum())
    if total <= 0:
        return {name: 0.0 for name in names}
    return {name: float(w / total) for name, w in zip(names, weights, strict=True)}


def regression_contributions(
    x: FloatArray, y: FloatArray, names: Sequence[str]
) -> tuple[dict[str, float], float | None]:
    """Squared standardised regression coefficients, normalised to sum 1, and R².

    SRCᵢ = bᵢ σ(xᵢ)/σ(y) with b the least-squares coefficients of y on x (with intercept).
    Inputs that do not vary get 0. Returns zeros and ``None`` with too few points.
    """
    n, k = x.shape
    sx = x.std(axis=0)
    sy = float(y.std())
    if n < k + 2 or sy == 0.0:
        return {name: 0.0 for name in names}, None
    varying = sx > 0
    xs = (x[:, varying] - x[:, varying].mean(axis=0)) / sx[varying]
    ys = (y - y.mean()) / sy
    beta, *_ = np.linalg.lstsq(xs, ys, rcond=None)
    residual = ys - xs @ beta
    r_squared = float(1.0 - residual @ residual / (ys @ ys))
    src = np.zeros(k)
    src[varying] = beta
    return _shares(src**2, names), r_squared


def sobol_first_order(x: FloatArray, y: FloatArray, names: Sequence[str]) -> dict[str, float]:
    """First-order Sobol indices Sᵢ = Var(E[y|xᵢ])/Var(y) of one response, estimated by binning.

    Each input is cut into √n (at most 100) equal-count bins; the variance of the bin means,
    less its sampling noise (mean within-bin variance / bin size), estimates Var(E[y|xᵢ]).
    """
    indices = _sobol_matrix(x, np.asarray(y, dtype=float)[:, None])[0]
    return {name: float(v) for name, v in zip(names, indices, strict=True)}


def _sobol_matrix(x: FloatArray, y: FloatArray) -> FloatArray:
    """(r, k) first-order indices of the r columns of ``y`` (see :func:`sobol_first_order`)."""
    n, k = x.shape
    out = np.zeros((y.shape[1], k))
    if n < 20:  # too few samples to bin (none at all when every sample failed)
        return out
    var = y.var(axis=0)
    bins = int(min(100, max(2, math.isqrt(n))))
    edges = np.linspace(0, n, bins + 1).astype(np.intp)
    sizes = np.diff(edges).astype(float)[:, None]
    mean = y.mean(axis=0)
    for column in range(k):
        ordered = y[np.argsort(x[:, column], kind="stable")]
        sums = np.add.reduceat(ordered, edges[:-1], axis=0)
        squares = np.add.reduceat(ordered * ordered, edges[:-1], axis=0)
        means = sums / sizes
        within = np.maximum(squares - sizes * means**2, 0.0) / np.maximum(sizes - 1.0, 1.0)
        between = np.sum(sizes * (means - mean) ** 2, axis=0) / n
        noise = within.sum(axis=0) / n  # Σ (size/n)·(within/size): noise of the bin means
        with np.errstate(divide="ignore", invalid="ignore"):
            out[:, column] = np.where(var > 0, (between - noise) / var, 0.0)
    return np.clip(out, 0.0, 1.0)


def _capability(
    limits: SpecLimits | None, mean: float | None, std: float | None
) -> tuple[float | None, float | None]:
    if limits is None or mean is None or std is None:
        return None, None
    return limits.capability(mean, std)


# --- Monte Carlo ---------------------------------------------------------------------------------


def truncated_at_limits(spec: ToleranceSpec) -> ToleranceSpec:
    """``spec`` with every normal input truncated at its specification limits.

    The truncation bounds are the limits intersected with the input's physical bounds; the
    process mean and σ are kept (the truncated distribution's own mean and standard
    deviation follow from them: :attr:`jointplay.tolerance.spec.Tolerance.mean`, ``.std``).
    Uniform and triangular inputs are returned as they are: they never leave the limits.

    Raises:
        ConfigError: a normal input whose process mean (centre + shift) lies outside its
            limits, which a truncation at the limits would pile onto one limit; sample it
            untruncated (``truncate=False``) or bring the shift inside the limits.
    """
    inputs = []
    for item in spec.inputs:
        tolerance = item.tolerance
        if tolerance.distribution != "normal":
            inputs.append(item)
            continue
        low = max(tolerance.bounds[0], tolerance.lower)
        high = min(tolerance.bounds[1], tolerance.upper)
        if not low <= tolerance.mode <= high:
            raise ConfigError(
                f"{item.name}: the process mean {tolerance.mode:g} lies outside the limits "
                f"[{tolerance.lower:g}, {tolerance.upper:g}], so the normal cannot be "
                "truncated at them; bring the shift inside the limits or sample untruncated"
            )
        inputs.append(replace(item, tolerance=replace(tolerance, bounds=(low, high))))
    return replace(spec, inputs=tuple(inputs))


def distribution_note(spec: ToleranceSpec, truncate: bool) -> str:
    """One sentence on how the inputs of ``spec`` were sampled (for reports and JSON)."""
    kinds = sorted({item.tolerance.distribution for item in spec.inputs})
    text = f"inputs sampled from {', '.join(kinds)} distributions over their limits"
    if "normal" in kinds:
        text += (
            "; normal inputs truncated at their specification limits (no sample outside them)"
            if truncate
            else "; normal inputs untruncated (±3σ at the limits: about 0.27 % of the samples "
            "of each lie outside them)"
        )
    return text


@dataclass(frozen=True)
class MonteCarlo:
    """Monte Carlo: seeded samples of the specification evaluated by the model.

    Attributes:
        samples: number of samples n (>= 1).
        seed: non-negative integer seed: the same specification, samples, seed and sampling
            give the same samples on every backend (:mod:`jointplay.tolerance.sampling`).
        sampling: ``"random"`` (independent draws) or ``"lhs"`` (Latin hypercube).
        truncate: draw normal inputs from the normal truncated at their specification limits
            (default; :func:`truncated_at_limits`), else from the untruncated normal.
    """

    name: ClassVar[str] = "monte-carlo"

    samples: int = 1000
    seed: int = 0
    sampling: SamplingMethod = "random"
    truncate: bool = True

    def __post_init__(self) -> None:
        check_settings(self.samples, self.seed, self.sampling)
        if not isinstance(self.truncate, bool):
            raise ConfigError(f"MonteCarlo: truncate must be True or False, got {self.truncate!r}")

    def run(
        self,
        model: ResponseModel,
        spec: ToleranceSpec,
        *,
        limits: Mapping[str, SpecLimits] | None = None,
        backend: Backend | None = None,
        progress: bool = False,
    ) -> MethodResult:
        """Evaluate the samples and summarise every response.

        The nominal point is evaluated first (in-process); the samples then run on
        ``backend``. Failed samples are excluded from the statistics and listed in
        ``failures``; an interrupted run summarises the samples that finished.

        Args:
            model: the response model; its inputs must be ``spec``'s.
            spec: the toleranced inputs.
            limits: specification limits per response name (SI).
            backend: where the points run (default: local processes).
            progress: show a progress bar on stderr.
        """
        n, seed, sampling = self.samples, self.seed, self.sampling
        limits = _limits_for(limits, model.response_names)
        drawn = truncated_at_limits(spec) if self.truncate else spec
        samples = sample(drawn, n, seed, method=sampling)
        nominal_run = _evaluate(model, spec, spec.nominal[None, :], Backend("serial"), False, "")
        nominal = _nominal_or_raise(nominal_run, 0, "nominal")
        result = _evaluate(model, spec, samples.values, backend, progress, "Monte Carlo samples")
        roles = ("sample",) * n
        ok = result.status == OK
        x_ok = samples.values[ok]
        sobol = _sobol_matrix(x_ok, result.values[ok])
        summaries = {}
        for j, name in enumerate(model.response_names):
            y = result.values[ok, j]
            lim = limits.get(name)
            if len(y) == 0:
                summaries[name] = ResponseSummary(
                    name, model.units[name], float(nominal[j]), 0, limits=lim
                )
                continue
            mean = float(y.mean())
            std = float(y.std(ddof=1)) if len(y) > 1 else 0.0
            contributions, r_squared = regression_contributions(x_ok, y, spec.names)
            first_order = dict(zip(spec.names, map(float, sobol[j]), strict=True))
            basis = "src"
            if r_squared is not None and r_squared < MIN_LINEAR_R_SQUARED:
                contributions, basis = _shares(sobol[j], spec.names), "sobol"
            cp, cpk = _capability(lim, mean, std)
            summaries[name] = ResponseSummary(
                name=name,
                unit=model.units[name],
                nominal=float(nominal[j]),
                n_ok=len(y),
                mean=mean,
                std=std,
                minimum=float(y.min()),
                maximum=float(y.max()),
                percentiles={f"p{p:g}": float(np.percentile(y, p)) for p in PERCENTILES},
                contributions=contributions,
                contribution_basis=basis,
                r_squared=r_squared,
                sobol_first_order=first_order,
                limits=lim,
                out_of_spec_percent=None if lim is None else 100.0 * float(lim.outside(y).mean()),
                cp=cp,
                cpk=cpk,
            )
        return MethodResult(
            method="monte-carlo",
            input_names=spec.names,
            response_names=tuple(model.response_names),
            units=dict(model.units),
            x=samples.values,
            roles=roles,
            run=result,
            nominal=nominal,
            summaries=summaries,
            failures=_failures(samples.values, roles, result, spec.names),
            settings={
                "samples": n,
                "seed": int(seed),
                "sampling": sampling,
                "truncated_at_limits": bool(self.truncate),
            },
        )


# --- sensitivities and RSS -----------------------------------------------------------------------


def _fd_points(centre: FloatArray, steps: FloatArray) -> FloatArray:
    """2k points: centre ± steps[i] along input i (rows 2i: +, 2i + 1: −)."""
    k = len(centre)
    points = np.repeat(centre[None, :], 2 * k, axis=0)
    for i in range(k):
        points[2 * i, i] += steps[i]
        points[2 * i + 1, i] -= steps[i]
    return points


def _fd_gradient(values: FloatArray, steps: FloatArray, ok: NDArray[np.bool_]) -> FloatArray:
    """(r, k) central differences from the 2k rows of :func:`_fd_points`."""
    k = len(steps)
    gradient = np.zeros((values.shape[1], k))
    for i in range(k):
        if steps[i] == 0.0:
            continue
        if not (ok[2 * i] and ok[2 * i + 1]):
            gradient[:, i] = np.nan
            continue
        gradient[:, i] = (values[2 * i] - values[2 * i + 1]) / (2.0 * steps[i])
    return gradient


#: RSS warns when, along some input, the curvature term |f₊ + f₋ − 2f₀| exceeds the slope
#: term |f₊ − f₋| over the finite-difference step: the linearisation does not describe the
#: response there (a kink, as for a deviation that is zero at the nominal point).
NONLINEARITY_LIMIT = 1.0


def _nonlinearity(values: FloatArray, centre: FloatArray, ok: NDArray[np.bool_]) -> FloatArray:
    """(r,) largest ratio |f₊ + f₋ − 2f₀| / |f₊ − f₋| over the inputs (rows of :func:`_fd_points`)."""
    worst = np.zeros(values.shape[1])
    for i in range(values.shape[0] // 2):
        if not (ok[2 * i] and ok[2 * i + 1]):
            continue
        plus, minus = values[2 * i], values[2 * i + 1]
        curvature = np.abs(plus + minus - 2.0 * centre)
        slope = np.abs(plus - minus)
        scale = 1e-12 * np.maximum(np.abs(centre), 1e-300)
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = np.where(curvature > scale, curvature / np.maximum(slope, scale), 0.0)
        worst = np.maximum(worst, ratio)
    return worst


def _check_step(fd_step: float) -> None:
    if not (math.isfinite(fd_step) and 0 < fd_step <= 1):
        raise ConfigError(
            f"finite-difference step must be in (0, 1] (a fraction of each half-width), got {fd_step}"
        )


@dataclass(frozen=True)
class Rss:
    """Root-sum-square stack from sensitivities at the input means.

    Attributes:
        fd_step: central-difference step as a fraction of each input's half-width, in (0, 1]
            (the default 0.5 takes the secant over the central half of the band, robust
            against the small numerical noise of simulated responses).
        sensitivity: ``"finite-difference"`` or ``"analytic"`` (the model's ``jacobian``).
    """

    name: ClassVar[str] = "rss"

    fd_step: float = 0.5
    sensitivity: Sensitivity = "finite-difference"

    def __post_init__(self) -> None:
        _check_step(self.fd_step)
        if self.sensitivity not in ("finite-difference", "analytic"):
            raise ConfigError(
                f"Rss: sensitivity must be finite-difference or analytic, got {self.sensitivity!r}"
            )

    def run(
        self,
        model: ResponseModel,
        spec: ToleranceSpec,
        *,
        limits: Mapping[str, SpecLimits] | None = None,
        backend: Backend | None = None,
        progress: bool = False,
    ) -> MethodResult:
        """Linearise every response at the input means and stack the input spreads.

        A finite-difference point that fails makes that input's sensitivity NaN (and the
        response's σ NaN); the point is listed in ``failures``.

        Args:
            model: the response model; its inputs must be ``spec``'s.
            spec: the toleranced inputs.
            limits: specification limits per response name (SI).
            backend: where the points run (default: local processes).
            progress: show a progress bar on stderr.

        Raises:
            ConfigError: analytic sensitivities requested from a model without a Jacobian,
                or the nominal or centre point cannot be evaluated.
        """
        fd_step, sensitivity = self.fd_step, self.sensitivity
        if sensitivity == "analytic" and not isinstance(model, DifferentiableModel):
            raise ConfigError(
                f"{type(model).__name__} has no analytic Jacobian; use finite-difference sensitivities"
            )
        limits = _limits_for(limits, model.response_names)
        centre = spec.mean
        half = (spec.upper - spec.lower) / 2.0
        steps = fd_step * half
        points = [spec.nominal[None, :], centre[None, :]]
        roles = ["nominal", "centre"]
        if sensitivity == "finite-difference":
            points.append(_fd_points(centre, steps))
            roles += ["fd"] * (2 * len(centre))
        x = np.concatenate(points, axis=0)
        result = _evaluate(model, spec, x, backend, progress, "RSS points")
        nominal = _nominal_or_raise(result, 0, "nominal")
        at_centre = _nominal_or_raise(result, 1, "centre (input means)")
        nonlinearity = np.zeros(len(model.response_names))
        if isinstance(model, DifferentiableModel) and sensitivity == "analytic":
            gradient = np.asarray(model.jacobian(centre), dtype=float)
        else:
            fd_ok = result.status[2:] == OK
            gradient = _fd_gradient(result.values[2:], steps, fd_ok)
            nonlinearity = _nonlinearity(result.values[2:], at_centre, fd_ok)
        sigma = spec.std
        summaries = {}
        for j, name in enumerate(model.response_names):
            a = gradient[j]
            std = float(np.sqrt(np.sum((a * sigma) ** 2)))
            lim = limits.get(name)
            cp, cpk = _capability(lim, float(at_centre[j]), std)
            summaries[name] = ResponseSummary(
                name=name,
                unit=model.units[name],
                nominal=float(nominal[j]),
                n_ok=int(np.sum(result.status == OK)),
                mean=float(at_centre[j]),
                std=std,
                half_range=float(np.sqrt(np.sum((a * half) ** 2))),
                sensitivities={n: float(v) for n, v in zip(spec.names, a, strict=True)},
                contributions=_shares((a * sigma) ** 2, spec.names),
                contribution_basis="sensitivities",
                limits=lim,
                out_of_spec_percent=None
                if lim is None
                else 100.0 * lim.normal_fraction_outside(float(at_centre[j]), std),
                cp=cp,
                cpk=cpk,
                note=None
                if nonlinearity[j] <= NONLINEARITY_LIMIT
                else (
                    "kinked or strongly nonlinear at the input means (curvature/slope ratio "
                    f"{nonlinearity[j]:.3g} over the finite-difference step): RSS does not describe "
                    "this response; use Monte Carlo"
                ),
            )
        return MethodResult(
            method="rss",
            input_names=spec.names,
            response_names=tuple(model.response_names),
            units=dict(model.units),
            x=x,
            roles=tuple(roles),
            run=result,
            nominal=nominal,
            summaries=summaries,
            failures=_failures(x, roles, result, spec.names),
            settings={
                "sensitivity": sensitivity,
                "fd_step": fd_step,
                "linearised_at": "input means",
            },
        )


# --- worst case ----------------------------------------------------------------------------------


@dataclass(frozen=True)
class WorstCase:
    """Extremes of every response over the corners of the input limits.

    Attributes:
        corners: ``"all"`` (2^k corners), ``"sensitivity"`` (the corners the signs of the
            finite-difference sensitivities at the centre point to) or ``"auto"`` (all for
            k ≤ 10 inputs).
        fd_step: finite-difference step for ``"sensitivity"``, a fraction of each half-width
            in (0, 1].
    """

    name: ClassVar[str] = "worst-case"

    corners: Corners = "auto"
    fd_step: float = 0.5

    def __post_init__(self) -> None:
        if self.corners not in ("auto", "all", "sensitivity"):
            raise ConfigError(
                f"WorstCase: corners must be auto, all or sensitivity, got {self.corners!r}"
            )
        _check_step(self.fd_step)

    def run(
        self,
        model: ResponseModel,
        spec: ToleranceSpec,
        *,
        limits: Mapping[str, SpecLimits] | None = None,
        backend: Backend | None = None,
        progress: bool = False,
    ) -> MethodResult:
        """Evaluate the corners and report the lowest and highest response of each.

        Args:
            model: the response model; its inputs must be ``spec``'s.
            spec: the toleranced inputs.
            limits: specification limits per response name (SI).
            backend: where the points run (default: local processes).
            progress: show a progress bar on stderr.

        Raises:
            ConfigError: too many inputs for all corners, or failed points leave the
                sensitivity signs unknown.
        """
        corners, fd_step = self.corners, self.fd_step
        limits = _limits_for(limits, model.response_names)
        k = len(spec)
        mode = (
            corners
            if corners != "auto"
            else ("all" if k <= MAX_ALL_CORNER_INPUTS else "sensitivity")
        )
        if mode == "all" and k > 20:
            raise ConfigError(f"2^{k} corners are too many; use corners='sensitivity'")
        lower, upper = spec.lower, spec.upper
        if mode == "all":
            levels = np.array(list(itertools.product((0, 1), repeat=k)), dtype=bool)
            corner_x = np.where(levels, upper, lower)
            x = np.concatenate([spec.nominal[None, :], corner_x], axis=0)
            roles = ("nominal",) + ("corner",) * len(corner_x)
            result = _evaluate(model, spec, x, backend, progress, "worst-case corners")
            nominal = _nominal_or_raise(result, 0, "nominal")
            values, ok = result.values[1:], result.status[1:] == OK
            effects = np.zeros((len(model.response_names), k))
            for i in range(k):
                hi, lo = ok & levels[:, i], ok & ~levels[:, i]
                if hi.any() and lo.any():
                    effects[:, i] = values[hi].mean(axis=0) - values[lo].mean(axis=0)
            width = upper - lower
            slopes = np.divide(effects, width, out=np.zeros_like(effects), where=width > 0)
            candidates = np.arange(len(corner_x))
            weights = np.abs(effects)
        else:
            centre = spec.centre
            steps = fd_step * (upper - lower) / 2.0
            first = np.concatenate([spec.nominal[None, :], _fd_points(centre, steps)], axis=0)
            first_run = _evaluate(model, spec, first, backend, progress, "sensitivities")
            nominal = _nominal_or_raise(first_run, 0, "nominal")
            slopes = _fd_gradient(first_run.values[1:], steps, first_run.status[1:] == OK)
            if np.any(np.isnan(slopes)):
                raise ConfigError(
                    "worst case: some finite-difference points failed, so the sensitivity signs are "
                    "unknown; use corners='all'"
                )
            corner_rows = []
            for a in slopes:
                corner_rows.append(np.where(a > 0, upper, np.where(a < 0, lower, centre)))
                corner_rows.append(np.where(a > 0, lower, np.where(a < 0, upper, centre)))
            corner_x = np.unique(np.array(corner_rows), axis=0)
            second = _evaluate(model, spec, corner_x, backend, progress, "worst-case corners")
            x = np.concatenate([first, corner_x], axis=0)
            roles = ("nominal",) + ("fd",) * (len(first) - 1) + ("corner",) * len(corner_x)
            result = _merge(first_run, second)
            values, ok = second.values, second.status == OK
            candidates = np.arange(len(corner_x))
            weights = np.abs(slopes) * (upper - lower) / 2.0
        summaries = {}
        for j, name in enumerate(model.response_names):
            lim = limits.get(name)
            good = candidates[ok]
            if len(good) == 0:
                summaries[name] = ResponseSummary(
                    name, model.units[name], float(nominal[j]), 0, limits=lim
                )
                continue
            column = values[good, j]
            low_i, high_i = good[int(np.argmin(column))], good[int(np.argmax(column))]
            summaries[name] = ResponseSummary(
                name=name,
                unit=model.units[name],
                nominal=float(nominal[j]),
                n_ok=len(good),
                minimum=float(values[low_i, j]),
                maximum=float(values[high_i, j]),
                half_range=float((values[high_i, j] - values[low_i, j]) / 2.0),
                low_corner=dict(zip(spec.names, map(float, corner_x[low_i]), strict=True)),
                high_corner=dict(zip(spec.names, map(float, corner_x[high_i]), strict=True)),
                sensitivities={n: float(v) for n, v in zip(spec.names, slopes[j], strict=True)},
                contributions=_shares(weights[j], spec.names),
                contribution_basis="main effects" if mode == "all" else "sensitivities",
                limits=lim,
                out_of_spec_percent=None
                if lim is None
                else 100.0 * float(lim.outside(values[good, j]).mean()),
            )
        return MethodResult(
            method="worst-case",
            input_names=spec.names,
            response_names=tuple(model.response_names),
            units=dict(model.units),
            x=x,
            roles=roles,
            run=result,
            nominal=nominal,
            summaries=summaries,
            failures=_failures(x, roles, result, spec.names),
            settings={
                "corners": mode,
                "evaluated_corners": len(corner_x),
                **({"fd_step": fd_step} if mode == "sensitivity" else {}),
            },
        )


def _merge(first: RunResult, second: RunResult) -> RunResult:
    """The two runs of the same model, one after the other (checks included)."""
    return RunResult(
        values=np.concatenate([first.values, second.values]),
        status=np.concatenate([first.status, second.status]),
        errors=first.errors + second.errors,
        interrupted=first.interrupted or second.interrupted,
        backend=second.backend,
        workers=max(first.workers, second.workers),
        chunk_size=second.chunk_size,
        wall_time=first.wall_time + second.wall_time,
        check_names=first.check_names,
        checks=None
        if first.checks is None or second.checks is None
        else np.concatenate([first.checks, second.checks]),
    )


#: Any tolerance analysis method.
ToleranceMethod = WorstCase | Rss | MonteCarlo

#: The tolerance analysis methods by name (as the CLI and summaries write them).
TOLERANCE_METHODS: Mapping[str, type[ToleranceMethod]] = types.MappingProxyType(
    {"worst-case": WorstCase, "rss": Rss, "monte-carlo": MonteCarlo}
)


def get_method(method: str | ToleranceMethod, /, **options: Any) -> ToleranceMethod:
    """A tolerance method from a registry name plus options, or an instance.

    Names are case-insensitive; ``_`` and spaces count as ``-``. Options are the method's
    fields (``samples``, ``seed``, ``sampling``; ``fd_step``, ``sensitivity``; ``corners``,
    ``fd_step``). Given an instance and options, returns a copy with those options replaced.

    Examples:
        >>> get_method("monte-carlo", samples=200, seed=3)
        MonteCarlo(samples=200, seed=3, sampling='random')

    Raises:
        ConfigError: unknown name (the message lists the known ones), unknown option (the
            message lists the method's) or an invalid value.
    """
    if isinstance(method, str):
        key = method.strip().lower().replace("_", "-").replace(" ", "-")
        if key not in TOLERANCE_METHODS:
            raise ConfigError(
                f"unknown tolerance method {method!r}; known: {', '.join(TOLERANCE_METHODS)}"
            )
        kind: type[ToleranceMethod] = TOLERANCE_METHODS[key]
    elif isinstance(method, WorstCase | Rss | MonteCarlo):
        kind = type(method)
    else:
        raise ConfigError(
            f"a tolerance method is a name ({', '.join(TOLERANCE_METHODS)}) or a WorstCase, "
            f"Rss or MonteCarlo instance, got {type(method).__name__}"
        )
    known = [f.name for f in fields(kind)]
    unknown = sorted(set(options) - set(known))
    if unknown:
        raise ConfigError(f"{kind.__name__}: unknown option(s) {unknown}; its options are {known}")
    if isinstance(method, str):
        return kind(**options)
    return replace(method, **options) if options else method
