"""What a sample of pass/fail outcomes shows: yields with exact intervals, verdicts, and
values at a confidence level with distribution-free bounds.

Pure functions of counts and values; no dynamics.

* **Yield interval.** ``k`` successes in ``n`` independent trials: the exact (Clopper–Pearson
  1934, *Biometrika* 26:404) two-sided interval at level 1 − α is
  ``[B(α/2; k, n − k + 1), B(1 − α/2; k + 1, n − k)]`` with ``B(q; a, b)`` the beta quantile
  (``scipy.stats.binomtest(...).proportion_ci(method="exact")`` gives the same). Its coverage
  is at least 1 − α for every true yield. Defects per million (DPM) are 10⁶ (1 − yield), their
  interval the yield's, mirrored.
* **Verdict** against a confidence level ``c`` (the share of parts that must meet a
  requirement): ``meets`` when the yield interval's lower bound is ≥ ``c``, ``fails`` when its
  upper bound is < ``c``, otherwise ``undecided``. With no failure the lower bound is
  (α/2)^(1/n): at α = 0.05 showing 99.73 % takes n ≥ ln 0.025 / ln 0.9973 = 1 365 samples.
  An undecided verdict carries the number of samples expected to decide it if the observed
  defect rate held (the smallest n at which the interval, at that rate, would leave ``c``;
  with no failure yet, the n at which zero failures would show ``c``).
* **Value at a confidence level** (e.g. the 99.73 % quantile of a peak force). The
  distribution-free one-sided upper 95 % bound of the ``q`` quantile is the order statistic
  X₍ᵣ₎ with the smallest ``r`` such that P(Binom(n, q) ≤ r − 1) ≥ 0.95 (David & Nagaraja,
  *Order Statistics*, 3rd ed., §7.2); it exists only when 1 − qⁿ ≥ 0.95, i.e. n ≥
  ln 0.05 / ln q (1 109 samples for q = 0.9973). A lower quantile is bounded from below the
  same way, mirrored. With fewer samples the value is a **model estimate**: the normal
  model mean ± z_q·s of the samples, named as such.
* **Sequential verdict** (:func:`confidence_sequence`, ``verdict(..., rule="sequential")``).
  The exact interval holds at one sample size fixed in advance; a study that looks after
  every block of samples and stops when a verdict is reached needs an interval that holds at
  every look at once. The beta-binomial mixture (Robbins 1970, *Ann. Math. Stat.* 41:1397;
  Howard, Ramdas, McAuliffe & Sekhon 2021, *Ann. Stat.* 49:1055, §3): with a prior
  Beta(a, b) on the yield, M_n(p) = B(a + k, b + n − k) / (B(a, b) pᵏ (1 − p)ⁿ⁻ᵏ) is a
  non-negative martingale of mean 1 under the true yield p, so by Ville's inequality
  P(∃ n: M_n(p) ≥ 1/α) ≤ α, and {p : M_n(p) < 1/α} is a confidence sequence: it covers the
  true yield at every n simultaneously with probability ≥ 1 − α, whenever the study looks
  and whenever it stops. ``meets`` when the sequence lies at or above ``c``, ``fails`` when
  below: each wrong verdict has probability ≤ α = 5 % over the whole study, at any stopping
  rule. The prior is a fixed function of ``c`` only, Beta(c/(2(1 − c)), 1/2) (mean yield
  ``c``), which makes the sequence tight where verdicts are decided: with no failure it shows
  99.73 % from 1 520 samples (the fixed-n exact interval: 1 365), and a defect rate 3 times
  the allowed one fails it after ~1 470 (fixed-n: 639).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike

__all__ = [
    "INTERVAL_LEVEL",
    "QuantileValue",
    "Verdict",
    "YieldEstimate",
    "clopper_pearson",
    "confidence_sequence",
    "quantile_value",
    "samples_for_order_statistic",
    "verdict",
]

#: Level of every interval this module gives (two-sided for yields, one-sided for quantiles).
INTERVAL_LEVEL = 0.95

#: Beyond this many samples a verdict is called out of reach.
_MAX_SAMPLES = 10**9

VerdictName = Literal["meets", "fails", "undecided"]

#: Which interval a verdict is decided on: the exact interval at a sample size fixed in
#: advance, or the confidence sequence valid at every look.
Rule = Literal["fixed", "sequential"]

#: The sequential rule's prior on the yield: Beta(PRIOR_SHAPE · c / (1 − c), PRIOR_SHAPE),
#: c the confidence level to show (prior mean yield c; the defect side's shape 1/2).
PRIOR_SHAPE = 0.5

#: What each rule's interval is, in words (the study's ``verdict_interval`` column).
RULE_INTERVALS: dict[str, str] = {
    "fixed": "exact (Clopper-Pearson) 95 % interval at a fixed sample size",
    "sequential": "95 % beta-binomial confidence sequence (valid at every look)",
}


def clopper_pearson(
    successes: float, trials: int, level: float = INTERVAL_LEVEL
) -> tuple[float, float]:
    """Exact two-sided interval of a binomial proportion (Clopper & Pearson 1934).

    Args:
        successes: successes k, 0 ≤ k ≤ n (a real k interpolates, for planning).
        trials: trials n ≥ 1.
        level: confidence level 1 − α of the interval.

    Returns:
        (lower, upper) bounds of the success probability.
    """
    from scipy.special import betaincinv

    if trials < 1 or not 0.0 <= successes <= trials:
        raise ValueError(f"need 0 <= successes <= trials, trials >= 1; got {successes}, {trials}")
    alpha = 1.0 - level
    lower = (
        0.0 if successes == 0 else float(betaincinv(successes, trials - successes + 1, alpha / 2))
    )
    upper = (
        1.0
        if successes == trials
        else float(betaincinv(successes + 1, trials - successes, 1.0 - alpha / 2))
    )
    return lower, upper


def _prior(confidence: float) -> tuple[float, float]:
    """The mixture's Beta(a, b) prior on the yield for showing ``confidence``."""
    return PRIOR_SHAPE * confidence / (1.0 - confidence), PRIOR_SHAPE


def _log_mixture(successes: float, trials: int, p: float, confidence: float) -> float:
    """log M_n(p) of the beta-binomial mixture (the prior of ``confidence``)."""
    from scipy.special import betaln

    a, b = _prior(confidence)
    failures = trials - successes
    out = float(betaln(a + successes, b + failures) - betaln(a, b))
    if successes:
        out -= successes * math.log(p)
    if failures:
        out -= failures * math.log1p(-p)
    return out


def confidence_sequence(
    successes: float, trials: int, confidence: float, level: float = INTERVAL_LEVEL
) -> tuple[float, float]:
    """The beta-binomial mixture confidence sequence of a yield at ``trials`` samples:
    ``{p : M_n(p) < 1/(1 − level)}`` (module docstring), which covers the true yield at
    every sample size at once with probability ≥ ``level``.

    Args:
        successes: successes k, 0 ≤ k ≤ n (a real k interpolates, for planning).
        trials: trials n ≥ 1.
        confidence: the level the yield is to be shown against, in (0, 1) (it fixes the
            prior, not the interval's coverage).
        level: coverage 1 − α of the sequence.

    Returns:
        (lower, upper) bounds of the yield at this n, fractions.
    """
    from scipy.optimize import brentq

    if trials < 1 or not 0.0 <= successes <= trials:
        raise ValueError(f"need 0 <= successes <= trials, trials >= 1; got {successes}, {trials}")
    if not 0.0 < confidence < 1.0:
        raise ValueError(f"confidence must lie in (0, 1), got {confidence}")
    bound = math.log(1.0 / (1.0 - level))
    centre = successes / trials

    def excess(p: float) -> float:
        return _log_mixture(successes, trials, p, confidence) - bound

    # log M_n is convex in p with its minimum (<= 0, a mixture never beats the best fit) at
    # the observed yield: one root on each side, or the end of [0, 1]
    tiny = 1e-300
    lower = 0.0
    if successes > 0 and excess(tiny) > 0.0:
        lower = float(brentq(excess, tiny, max(centre, tiny), xtol=1e-15, rtol=1e-13))
    upper = 1.0
    top = 1.0 - 2.0**-53
    if successes < trials and excess(top) > 0.0:
        upper = float(brentq(excess, min(centre, top), top, xtol=1e-15, rtol=1e-13))
    return lower, upper


@dataclass(frozen=True)
class YieldEstimate:
    """Failures among samples, and what they show about the share of good parts.

    Attributes:
        failures: samples that did not meet the requirement (failed simulations included).
        samples: samples judged (≥ 1).
        level: level of the intervals.
    """

    failures: int
    samples: int
    level: float = INTERVAL_LEVEL

    def __post_init__(self) -> None:
        if self.samples < 1 or not 0 <= self.failures <= self.samples:
            raise ValueError(
                f"YieldEstimate: need 0 <= failures <= samples, samples >= 1; got "
                f"{self.failures}, {self.samples}"
            )

    @property
    def value(self) -> float:
        """Observed yield (share of samples meeting the requirement), fraction."""
        return 1.0 - self.failures / self.samples

    @property
    def interval(self) -> tuple[float, float]:
        """Exact (Clopper–Pearson) interval of the yield, fractions."""
        return clopper_pearson(self.samples - self.failures, self.samples, self.level)

    @property
    def dpm(self) -> float:
        """Observed defects per million."""
        return 1e6 * self.failures / self.samples

    @property
    def dpm_interval(self) -> tuple[float, float]:
        """Interval of the defects per million (the yield's, mirrored)."""
        lower, upper = self.interval
        return 1e6 * (1.0 - upper), 1e6 * (1.0 - lower)


@dataclass(frozen=True)
class Verdict:
    """Whether a yield is shown to reach a confidence level.

    Attributes:
        name: ``"meets"``, ``"fails"`` or ``"undecided"``.
        samples_to_decide: undecided: total samples expected to decide it if the observed
            defect rate held; ``None`` when decided or out of reach (rate at the level).
    """

    name: VerdictName
    samples_to_decide: int | None = None


def interval(
    successes: float, trials: int, confidence: float, rule: Rule, level: float = INTERVAL_LEVEL
) -> tuple[float, float]:
    """The interval a verdict of ``rule`` is decided on: :func:`clopper_pearson`
    (``"fixed"``) or :func:`confidence_sequence` (``"sequential"``)."""
    if rule == "sequential":
        return confidence_sequence(successes, trials, confidence, level)
    return clopper_pearson(successes, trials, level)


def verdict(estimate: YieldEstimate, confidence: float, *, rule: Rule = "fixed") -> Verdict:
    """``meets``, ``fails`` or ``undecided``: the yield interval against ``confidence``.

    Args:
        estimate: failures among samples.
        confidence: share of parts that must meet the requirement, in (0, 1).
        rule: ``"fixed"``: the exact interval (valid for a sample size fixed in advance);
            ``"sequential"``: the confidence sequence (valid however often the study looks
            and whenever it stops; :func:`confidence_sequence`).
    """
    if not 0.0 < confidence < 1.0:
        raise ValueError(f"confidence must lie in (0, 1), got {confidence}")
    rate = estimate.failures / estimate.samples
    decided = _decides(estimate.samples, rate, confidence, estimate.level, rule)
    if decided and rate < 1.0 - confidence:
        return Verdict("meets")
    if decided:
        return Verdict("fails")
    return Verdict("undecided", _samples_to_decide(rate, confidence, estimate.level, rule))


def _decides(n: int, rate: float, confidence: float, level: float, rule: Rule = "fixed") -> bool:
    """n samples at defect rate ``rate`` (fractional failures allowed) decide the verdict:
    the interval of ``rule`` lies at or above ``confidence`` (below it for a rate above the
    allowed one). Sequential: the sequence is the interval around the observed yield where
    M_n < 1/α, so it leaves ``confidence`` exactly when M_n(confidence) ≥ 1/α."""
    if rule == "sequential":
        if rate == 1.0 - confidence:
            return False
        evidence = _log_mixture(n * (1.0 - rate), n, confidence, confidence)
        return evidence >= math.log(1.0 / (1.0 - level))
    lower, upper = interval(n * (1.0 - rate), n, confidence, rule, level)
    return lower >= confidence if rate < 1.0 - confidence else upper < confidence


def _samples_to_decide(
    rate: float, confidence: float, level: float, rule: Rule = "fixed"
) -> int | None:
    """Smallest n deciding the verdict at ``rate`` (bisection after doubling), or None."""
    if math.isclose(rate, 1.0 - confidence, rel_tol=1e-12, abs_tol=0.0):
        return None
    high = 1
    while not _decides(high, rate, confidence, level, rule):
        high *= 2
        if high > _MAX_SAMPLES:
            return None
    low = high // 2
    while high - low > 1:
        middle = (low + high) // 2
        if _decides(middle, rate, confidence, level, rule):
            high = middle
        else:
            low = middle
    return high


def samples_for_order_statistic(q: float, level: float = INTERVAL_LEVEL) -> int:
    """Fewest samples for which the largest one bounds the ``q`` quantile at ``level``:
    the smallest n with 1 − qⁿ ≥ level."""
    return math.ceil(math.log(1.0 - level) / math.log(q) - 1e-12)


@dataclass(frozen=True)
class QuantileValue:
    """A response's value at a confidence level.

    Attributes:
        value: the value, SI (±inf when the bound is a failed sample).
        basis: ``"order-statistic"`` (a distribution-free one-sided 95 % bound: ``rank``-th
            smallest of ``samples``) or ``"normal-model"`` (mean ± z·std of the samples: an
            estimate, not a bound, since too few samples bound it).
        rank: the order statistic (1-based) for ``"order-statistic"``, else ``None``.
        samples: samples used.
    """

    value: float
    basis: Literal["order-statistic", "normal-model"]
    rank: int | None
    samples: int

    def describe(self) -> str:
        """One phrase saying what the value is."""
        if self.basis == "order-statistic":
            return f"distribution-free 95 % bound (order statistic {self.rank} of {self.samples})"
        return f"normal-model estimate (mean ± z·std of {self.samples} samples; not a bound)"


def quantile_value(
    values: ArrayLike, q: float, *, upper: bool = True, level: float = INTERVAL_LEVEL
) -> QuantileValue:
    """The ``q`` quantile (``upper``) or the ``1 − q`` quantile (not ``upper``) of ``values``,
    bounded distribution-free when there are enough samples, else a normal-model estimate.

    Args:
        values: one value per sample, SI; NaN (a failed sample) counts as the worst value
            (+inf for an upper quantile, −inf for a lower one).
        q: the confidence level, in (0, 1), e.g. 0.9973.
        upper: bound the upper quantile from above (requirements ``<=``); else the lower
            quantile from below (``>=``, life).
        level: one-sided confidence of the bound.
    """
    from scipy.special import ndtri
    from scipy.stats import binom

    x = np.asarray(values, dtype=float)
    n = len(x)
    if n == 0:
        return QuantileValue(math.nan, "normal-model", None, 0)
    worst = math.inf if upper else -math.inf
    x = np.sort(np.where(np.isnan(x), worst, x))
    if not upper:
        x = -x[::-1]  # the lower quantile of x is minus the upper one of −x
    if n >= samples_for_order_statistic(q, level):
        # smallest r with P(Binom(n, q) <= r - 1) >= level
        r = int(binom.ppf(level, n, q)) + 1
        while r > 1 and binom.cdf(r - 2, n, q) >= level:
            r -= 1
        while binom.cdf(r - 1, n, q) < level:
            r += 1
        value = float(x[r - 1])
        return QuantileValue(value if upper else -value, "order-statistic", r, n)
    good = x[np.isfinite(x)]
    if len(good) < 2:
        return QuantileValue(math.nan, "normal-model", None, n)
    value = float(good.mean() + float(ndtri(q)) * good.std(ddof=1))
    return QuantileValue(value if upper else -value, "normal-model", None, n)
