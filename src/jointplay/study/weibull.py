"""Life data with right-censoring: the Weibull fit with likelihood-ratio intervals, and the
empirical quantiles (B1, B10, B50) with exact order-statistic intervals.

**Weibull fit.** The two-parameter Weibull ``F(t) = 1 − exp(−(t/η)^β)`` (shape β, scale η,
location 0) is fitted by maximum likelihood to failures and right-censored lives with SciPy:
``scipy.stats.weibull_min.fit(scipy.stats.CensoredData(...), floc=0)``; the log-likelihood
is ``weibull_min.logpdf`` of the failures plus ``weibull_min.logsf`` of the censored lives
(evaluated in closed form inside the profiles, the same numbers: tests/study/test_weibull.py). The intervals are **likelihood-ratio (profile-likelihood) intervals** (Meeker &
Escobar, *Statistical Methods for Reliability Data*, Wiley 1998, §8.3): the values θ of a
quantity (β, η, or a quantile t_p) whose profile log-likelihood ``ℓ_p(θ) = max ℓ`` over the
other parameter stays within ``χ²₁(level)/2`` of the maximum (1.353 at 90 %). Each profile is
maximised with :func:`scipy.optimize.minimize_scalar` (over ln β, η in closed form for a
fixed β), and the interval's ends are the roots of ``2(ℓ̂ − ℓ_p(θ)) − χ²₁(level)`` found by
:func:`scipy.optimize.brentq`. They are not symmetric, follow the likelihood's shape with few
failures, and are the intervals Meeker & Escobar recommend over the Wald (normal) ones.
The band on the probability plot is the pointwise likelihood-ratio interval of the
quantiles t_p.

**Empirical quantiles.** The p quantile's estimate is the order statistic ``X₍⌈np⌉₎``; its
exact distribution-free two-sided interval ``[X₍l₎, X₍u₎]`` takes ``l`` and ``u`` from the
binomial: ``P(l ≤ Binom(n, p) ≤ u − 1) ≥ level`` (David & Nagaraja, *Order Statistics*, 3rd
ed., §7.1). Every life here is censored at one time (the hours simulated, after every
failure), so the order statistics below it are observed; an end at a censored life is only
known to lie beyond the censoring time (``inf`` here).

**Plotting positions.** Median ranks (Benard's approximation ``(i − 0.3)/(n + 0.4)``) over
all n mechanisms: exact with censoring at one time after every failure (the ranks of the
failures are then known; no Johnson adjustment is needed).

All times are in any one unit (the callers use seconds, SI).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from jointplay.errors import ConfigError

__all__ = [
    "INTERVAL_LEVEL",
    "EmpiricalQuantile",
    "WeibullFit",
    "empirical_quantile",
    "fit_weibull",
    "median_ranks",
]

FloatArray = NDArray[np.float64]

#: Level of the two-sided intervals of this module.
INTERVAL_LEVEL = 0.90


@dataclass(frozen=True)
class EmpiricalQuantile:
    """The ``p`` quantile of the lives with its exact order-statistic interval.

    Attributes:
        p: the probability (0.10 for B10).
        value: the order statistic ``X₍⌈np⌉₎`` (``inf``: censored, beyond the censoring time).
        low, high: the interval's ends (``0``: too few samples to bound it from below;
            ``inf``: beyond the censoring time or too few samples).
        level: two-sided confidence of the interval.
        ranks: the order statistics (l, u) of the interval, 1-based (may lie outside 1..n).
    """

    p: float
    value: float
    low: float
    high: float
    level: float
    ranks: tuple[int, int]

    def describe(self) -> dict[str, Any]:
        return {
            "p": self.p,
            "value": _finite(self.value),
            "low": _finite(self.low),
            "high": _finite(self.high),
            "level": self.level,
            "ranks": list(self.ranks),
            "method": "order statistic with the exact binomial interval (David & Nagaraja §7.1)",
        }


def empirical_quantile(
    lives: ArrayLike, censored: ArrayLike, p: float, level: float = INTERVAL_LEVEL
) -> EmpiricalQuantile:
    """The ``p`` quantile of ``lives`` (censored lives count as beyond every failure).

    Args:
        lives: one life per unit (any time unit).
        censored: per unit, the life is a censoring time (the unit had not failed).
        p: the probability, in (0, 1).
        level: two-sided confidence.
    """
    from scipy.stats import binom

    if not 0.0 < p < 1.0:
        raise ConfigError(f"quantile probability must lie in (0, 1), got {p!r}")
    t = np.asarray(lives, dtype=float)
    c = np.asarray(censored, dtype=bool)
    n = len(t)
    if n == 0:
        return EmpiricalQuantile(p, math.nan, math.nan, math.nan, level, (0, 0))
    ordered = np.sort(np.where(c, np.inf, t))
    alpha = 1.0 - level

    def at(rank: int) -> float:
        if rank < 1:
            return 0.0
        if rank > n:
            return math.inf
        return float(ordered[rank - 1])

    # l: the largest rank with P(B <= l - 1) <= alpha/2; u: the smallest with P(B >= u) <=
    # alpha/2; then P(l <= B <= u - 1) >= level (B ~ Binom(n, p))
    low_rank = int(binom.ppf(alpha / 2, n, p))
    while low_rank > 0 and binom.cdf(low_rank - 1, n, p) > alpha / 2:
        low_rank -= 1
    while binom.cdf(low_rank, n, p) <= alpha / 2:
        low_rank += 1
    high_rank = int(binom.ppf(1.0 - alpha / 2, n, p)) + 1
    while binom.sf(high_rank - 1, n, p) <= alpha / 2:
        high_rank -= 1
    while binom.sf(high_rank - 1, n, p) > alpha / 2:
        high_rank += 1
    return EmpiricalQuantile(
        p, at(math.ceil(n * p - 1e-12)), at(low_rank), at(high_rank), level, (low_rank, high_rank)
    )


def median_ranks(lives: ArrayLike, censored: ArrayLike) -> tuple[FloatArray, FloatArray]:
    """The failures in order and their plotting positions ``(i − 0.3)/(n + 0.4)`` among all
    ``n`` units (Benard's median ranks; exact when every censoring follows every failure)."""
    t = np.asarray(lives, dtype=float)
    c = np.asarray(censored, dtype=bool)
    failures = np.sort(t[~c])
    ranks = np.arange(1, len(failures) + 1, dtype=float)
    return failures, np.asarray((ranks - 0.3) / (len(t) + 0.4), dtype=np.float64)


@dataclass(frozen=True)
class WeibullFit:
    """A two-parameter Weibull fitted to right-censored lives, with likelihood-ratio
    intervals.

    Attributes:
        shape: β (dimensionless).
        scale: η (the lives' unit).
        shape_interval, scale_interval: their likelihood-ratio intervals (``inf``: not
            bounded by the data).
        failures, censored: how many lives of each kind.
        level: two-sided confidence of the intervals.
        loglik: the maximum log-likelihood.
        lives, is_censored: the data (kept for the quantiles' intervals).
    """

    shape: float
    scale: float
    shape_interval: tuple[float, float]
    scale_interval: tuple[float, float]
    failures: int
    censored: int
    level: float
    loglik: float
    lives: tuple[float, ...]
    is_censored: tuple[bool, ...]

    def quantile(self, p: float) -> float:
        """The ``p`` quantile ``t_p = η (−ln(1 − p))^(1/β)`` (B10: p = 0.10)."""
        return float(self.scale * (-math.log1p(-p)) ** (1.0 / self.shape))

    def quantile_interval(self, p: float) -> tuple[float, float]:
        """The likelihood-ratio interval of the ``p`` quantile."""
        w = -math.log1p(-p)
        data = _Data.of(self.lives, self.is_censored)

        def profile(t_p: float) -> float:
            # η = t_p / w^(1/β): the likelihood over β at that quantile
            return data.profile(lambda beta: t_p / w ** (1.0 / beta), self.shape)

        return _interval(profile, self.quantile(p), self.loglik, self.level)

    def cdf(self, t: ArrayLike) -> FloatArray:
        from scipy.stats import weibull_min

        return np.asarray(weibull_min.cdf(t, self.shape, scale=self.scale), dtype=float)

    def describe(self, unit: float = 1.0, name: str = "") -> dict[str, Any]:
        """JSON-ready; times divided by ``unit`` (3600: hours), named ``scale{name}``."""
        b10 = self.quantile(0.10)
        b10_interval = self.quantile_interval(0.10)
        return {
            "shape": self.shape,
            "shape_interval": [_finite(v) for v in self.shape_interval],
            f"scale{name}": self.scale / unit,
            f"scale_interval{name}": [_finite(v / unit) for v in self.scale_interval],
            f"B10{name}": b10 / unit,
            f"B10_interval{name}": [_finite(v / unit) for v in b10_interval],
            "failures": self.failures,
            "censored": self.censored,
            "level": self.level,
            "loglik": self.loglik,
            "method": (
                "maximum likelihood with right-censoring (scipy.stats.weibull_min.fit on "
                "scipy.stats.CensoredData, floc=0); likelihood-ratio (profile-likelihood) "
                "intervals, Meeker & Escobar 1998 §8.3"
            ),
        }


def fit_weibull(
    lives: ArrayLike, censored: ArrayLike, level: float = INTERVAL_LEVEL
) -> WeibullFit | None:
    """Fit a two-parameter Weibull to ``lives`` (right-censored where ``censored``).

    Returns:
        The fit, or ``None`` with fewer than two distinct failures (no fit is possible:
        the caller reports a bound instead).

    Raises:
        ConfigError: a life is not finite and > 0, or ``level`` is not in (0, 1).
    """
    from scipy.stats import CensoredData, weibull_min

    if not 0.0 < level < 1.0:
        raise ConfigError(f"interval level must lie in (0, 1), got {level!r}")
    t = np.asarray(lives, dtype=float)
    c = np.asarray(censored, dtype=bool)
    if len(t) != len(c):
        raise ConfigError("fit_weibull: lives and censored differ in length")
    if len(t) and not (np.all(np.isfinite(t)) and np.all(t > 0)):
        raise ConfigError("fit_weibull: every life must be finite and > 0")
    failed = t[~c]
    if len(np.unique(failed)) < 2:
        return None
    data = CensoredData.right_censored(t, c)
    shape, _, scale = weibull_min.fit(data, floc=0)
    fitted = _Data.of(tuple(map(float, t)), tuple(map(bool, c)))
    # SciPy's optimum, polished on the profile (β; η in closed form) to the same likelihood
    beta = fitted.best_shape(float(shape))
    if fitted.loglik(beta, fitted.scale_at(beta)) < fitted.loglik(float(shape), float(scale)):
        beta = float(shape)
    eta = fitted.scale_at(beta)
    best = fitted.loglik(beta, eta)
    shape_interval = _interval(lambda b: fitted.loglik(b, fitted.scale_at(b)), beta, best, level)
    scale_interval = _interval(lambda e: fitted.profile(lambda _: e, beta), eta, best, level)
    return WeibullFit(
        beta,
        eta,
        shape_interval,
        scale_interval,
        int((~c).sum()),
        int(c.sum()),
        level,
        best,
        tuple(map(float, t)),
        tuple(map(bool, c)),
    )


@dataclass(frozen=True)
class _Data:
    failures: FloatArray
    censored: FloatArray

    @classmethod
    def of(cls, lives: tuple[float, ...], censored: tuple[bool, ...]) -> _Data:
        t = np.asarray(lives, dtype=float)
        c = np.asarray(censored, dtype=bool)
        return cls(t[~c], t[c])

    def loglik(self, beta: float, eta: float) -> float:
        """The Weibull log-likelihood: ``Σ ln f(tᵢ)`` over the failures plus ``Σ ln S(tⱼ)``
        over the censored lives, in closed form (``r ln β − rβ ln η + (β − 1) Σ ln tᵢ −
        Σ (t/η)^β`` over every life; the same numbers as SciPy's ``weibull_min.logpdf`` and
        ``logsf``, checked in the tests, at a tenth of the cost inside the profiles)."""
        if not (beta > 0 and eta > 0 and math.isfinite(beta) and math.isfinite(eta)):
            return -math.inf
        r = len(self.failures)
        with np.errstate(over="ignore"):
            value = (
                r * (math.log(beta) - beta * math.log(eta))
                + (beta - 1.0) * float(self.log_failures)
                - float(np.sum((self.failures / eta) ** beta))
                - float(np.sum((self.censored / eta) ** beta))
            )
        return value if math.isfinite(value) else -math.inf

    @property
    def log_failures(self) -> float:
        return float(np.sum(np.log(self.failures)))

    def scale_at(self, beta: float) -> float:
        """η maximising the likelihood at shape β: ``(Σ tᵢ^β / r)^(1/β)`` (r failures)."""
        every = np.concatenate([self.failures, self.censored])
        top = float(every.max())
        # scaled by the largest life: no overflow for large β
        return top * float(np.sum((every / top) ** beta) / len(self.failures)) ** (1.0 / beta)

    def best_shape(self, guess: float) -> float:
        from scipy.optimize import minimize_scalar

        found = minimize_scalar(
            lambda u: -self.loglik(math.exp(u), self.scale_at(math.exp(u))),
            bounds=(math.log(guess) - 3.0, math.log(guess) + 3.0),
            method="bounded",
            options={"xatol": 1e-10},
        )
        return float(math.exp(found.x))

    def profile(self, eta_of: Callable[[float], float], guess: float) -> float:
        """``max over β`` of the log-likelihood at ``η = eta_of(β)``."""
        from scipy.optimize import minimize_scalar

        found = minimize_scalar(
            lambda u: -self.loglik(math.exp(u), eta_of(math.exp(u))),
            bounds=(math.log(guess) - 4.0, math.log(guess) + 4.0),
            method="bounded",
            options={"xatol": 1e-9},
        )
        return -float(found.fun)


def _interval(
    profile: Callable[[float], float],
    estimate: float,
    best: float,
    level: float,
) -> tuple[float, float]:
    """The likelihood-ratio interval of a positive quantity: where ``2(best − profile(θ))``
    crosses ``χ²₁(level)`` below and above ``estimate`` (0 / inf where it never does within
    a factor e¹² of it)."""
    from scipy.optimize import brentq
    from scipy.stats import chi2

    cut = float(chi2.ppf(level, 1))

    def excess(u: float) -> float:
        value = profile(math.exp(u))
        return (2.0 * (best - value) if math.isfinite(value) else math.inf) - cut

    centre = math.log(estimate)
    ends = []
    for direction in (-1.0, 1.0):
        step = 0.05
        inside = centre
        end = math.nan
        while step < 12.0:
            outside = centre + direction * step
            if excess(outside) > 0:
                end = math.exp(
                    brentq(excess, min(inside, outside), max(inside, outside), xtol=1e-10)
                )
                break
            inside = outside
            step *= 2.0
        if math.isnan(end):
            end = 0.0 if direction < 0 else math.inf
        ends.append(end)
    return ends[0], ends[1]


def _finite(value: float) -> float | None:
    return None if not math.isfinite(value) else float(value)
