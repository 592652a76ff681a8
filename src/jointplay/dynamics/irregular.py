"""Statistics of irregular (chaotic) running: per-revolution peak distributions with intervals.

A dry clearance joint can rattle chaotically: the once-per-revolution Poincaré section never
repeats (:func:`jointplay.dynamics.cycles.periodicity`) and two runs that differ only in the
integrator's tolerances part ways after a fraction of a revolution. Each per-revolution peak
is then a draw from a distribution, and so is the largest peak over the analysed revolutions:
tightening the tolerances moves it by as much as the revolutions differ from one another
(the dry paper four-bar's F_O2 peak over one revolution goes from 84.9 to 112.4 N as rtol goes
from 1e-6 to 1e-10). What is reproducible is the distribution of the per-revolution peaks.
This module estimates, from the peaks of ``n`` analysed revolutions:

- the **mean** per-revolution peak, with a batch-means confidence interval (the revolutions
  are split into ``b = floor(sqrt(n))`` batches of equal size; the variance of the batch means
  gives the long-run variance of the series, which a correlated series needs; Student's t
  with ``b - 1`` degrees of freedom): Schmeiser, "Batch size effects in the analysis of
  simulation output", Operations Research 30 (1982) 556-568; Law & Kelton, Simulation
  Modeling and Analysis, §9.5.3;
- the **95th percentile** of the per-revolution peak (linear interpolation between order
  statistics, Hyndman & Fan 1996 definition 7, NumPy's default), with the distribution-free
  order-statistic (binomial) confidence interval [x_(l), x_(u)] (Conover, Practical
  Nonparametric Statistics, 3rd ed., §3.2), computed for the *effective* number of
  independent revolutions ``n / inflation`` (the batch-means variance of the series over its
  plain variance, at least 1) so that correlation between revolutions widens it; its upper
  end is unbounded (``inf``) when even the largest peak is not far enough in the tail — for
  the 95th percentile at 95 % confidence, below 72 effective revolutions
  (:func:`revolutions_for_quantile`);
- the **largest** per-revolution peak over the ``n`` revolutions, which is what a single run
  reports as "the peak". Its interval is a distribution-free prediction interval for the
  largest peak of a repeat run of as many revolutions (exchangeability of the 2n peaks: the
  repeat's largest lies below this run's j-th smallest with probability
  C(j + n - 1, n) / C(2n, n)); its upper end is always unbounded, since a repeat's largest
  exceeds this run's largest half of the time. The maximum is a draw: it does not converge
  under tighter tolerances, and no number of revolutions makes it converge without a model of
  the tail.

The contract asked for (docs/performance.md, "Accuracy of irregular (chaotic) running"): the
mean and the 95th percentile converge — tightening the tolerances ×100 moves each by less
than its interval (:func:`agrees`: the difference within its own interval); the largest peak
does not. Measured on the dry paper four-bar, it holds for some quantities (F_O4, omega4) and
not for others (F_O2, F_A): the motion dwells in one of two states for hundreds of
revolutions and the tolerances decide which, so the intervals here — the sampling uncertainty
of one run's revolutions — do not cover that. An ensemble of runs from perturbed starts, the
runs as batches (:func:`replicate_distribution`, :mod:`jointplay.dynamics.ensemble`), samples
the states; its F_O2 and F_A statistics meet the contract.

All functions are pure and unit-free: the values keep the unit of the quantity (N, rad/s, …).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

FloatArray = NDArray[np.float64]

#: Confidence level of every interval.
CONFIDENCE = 0.95

#: The high quantile reported (the 95th percentile).
QUANTILE = 0.95

#: Fewest analysed revolutions with statistics (three batches of three).
MIN_REVOLUTIONS = 10

#: The statistics :func:`agrees` judges: the ones that converge.
CONVERGING = ("mean", "quantile")


@dataclass(frozen=True)
class Estimate:
    """A statistic with its interval, in the unit of the quantity.

    Attributes:
        value: the estimate.
        low: lower end of the interval (``-inf``: unbounded below).
        high: upper end of the interval (``inf``: unbounded above).
    """

    value: float
    low: float
    high: float

    def contains(self, value: float) -> bool:
        """Whether ``value`` lies inside the closed interval."""
        return bool(self.low <= value <= self.high)

    @property
    def bounded(self) -> bool:
        """Whether both ends are finite."""
        return math.isfinite(self.low) and math.isfinite(self.high)

    def as_dict(self) -> dict[str, float | None]:
        """JSON-ready: ``value``, ``low``, ``high`` (``None`` for an unbounded end)."""
        return {
            "value": self.value,
            "low": self.low if math.isfinite(self.low) else None,
            "high": self.high if math.isfinite(self.high) else None,
        }


@dataclass(frozen=True)
class PeakDistribution:
    """The distribution of one quantity's per-revolution peak over the analysed revolutions.

    Attributes:
        revolutions: analysed revolutions (the sample size n).
        mean: the mean peak, batch-means interval.
        quantile: the :data:`QUANTILE` quantile of the peak, order-statistic interval.
        maximum: the largest peak of the n revolutions, prediction interval for a repeat
            run's largest (unbounded above).
        batches: the number of batches of the batch-means estimate.
        inflation: the batch-means variance of the series over its plain variance (at least
            1): how much correlation between revolutions widens the intervals.
        confidence: the confidence level of the intervals.
        probability: the quantile's probability (0.95: the 95th percentile).
    """

    revolutions: int
    mean: Estimate
    quantile: Estimate
    maximum: Estimate
    batches: int
    inflation: float
    confidence: float = CONFIDENCE
    probability: float = QUANTILE

    @property
    def effective_revolutions(self) -> float:
        """The number of independent revolutions the sample is worth: n / inflation."""
        return self.revolutions / self.inflation

    def as_dict(self) -> dict[str, Any]:
        """JSON-ready: the three estimates and how they were taken."""
        return {
            "revolutions": self.revolutions,
            "mean": self.mean.as_dict(),
            f"percentile_{100 * self.probability:g}": self.quantile.as_dict(),
            "max": self.maximum.as_dict(),
            "confidence": self.confidence,
            "batches": self.batches,
            "variance_inflation": self.inflation,
            "effective_revolutions": self.effective_revolutions,
        }


def batch_means(values: ArrayLike, confidence: float = CONFIDENCE) -> tuple[Estimate, int, float]:
    """The mean of a (possibly correlated) series with its batch-means confidence interval.

    The last ``b * m`` values, ``b = floor(sqrt(n))`` batches of ``m = n // b`` each (the
    earliest ``n - b m`` values, nearest the start-up, sit out of the batches but not of the
    mean), give the long-run variance ``m * var(batch means)``; the interval is the mean ±
    t_{b-1} sqrt(long-run variance / n) (Schmeiser 1982; Law & Kelton §9.5.3).

    Args:
        values: the series (at least :data:`MIN_REVOLUTIONS` values).
        confidence: the two-sided confidence level.

    Returns:
        The estimate, the number of batches, and the variance inflation: the long-run
        variance over the plain sample variance, at least 1.
    """
    from scipy.stats import t as student

    x = _series(values)
    n = x.size
    b = math.isqrt(n)
    m = n // b
    batches = x[n - b * m :].reshape(b, m).mean(axis=1)
    long_run = m * float(batches.var(ddof=1))
    plain = float(x.var(ddof=1))
    half = float(student.ppf(0.5 + confidence / 2, b - 1)) * math.sqrt(long_run / n)
    mean = float(x.mean())
    inflation = max(1.0, long_run / plain) if plain > 0 else 1.0
    return Estimate(mean, mean - half, mean + half), b, inflation


def quantile_interval(
    values: ArrayLike,
    probability: float = QUANTILE,
    confidence: float = CONFIDENCE,
    inflation: float = 1.0,
) -> Estimate:
    """The ``probability`` quantile of a series with its order-statistic confidence interval.

    For ``k`` independent values, [x_(l), x_(u)] covers the quantile with probability at least
    ``confidence`` when P(B <= l - 1) <= α/2 and P(B >= u) <= α/2 for B ~ Binomial(k,
    probability), α = 1 - confidence (Conover §3.2). A correlated series of ``n`` values is
    worth ``k = floor(n / inflation)`` independent ones; the ranks found for ``k`` are scaled
    back to ``n`` outwards.

    Args:
        values: the series (at least :data:`MIN_REVOLUTIONS` values).
        probability: the quantile's probability, in (0, 1).
        confidence: the two-sided confidence level.
        inflation: variance inflation of the series (:func:`batch_means`), at least 1.

    Returns:
        The quantile (Hyndman & Fan definition 7) and its interval; an end is infinite where
        no order statistic of the sample reaches that far.
    """
    from scipy.stats import binom

    x = np.sort(_series(values))
    n = x.size
    k = max(1, math.floor(n / max(inflation, 1.0)))
    alpha = 1.0 - confidence
    below = binom.cdf(np.arange(k + 1), k, probability)
    # lower rank l (1-based): the largest with P(B <= l - 1) <= alpha / 2.
    fits = np.flatnonzero(below <= alpha / 2)
    low = -math.inf
    if fits.size:
        rank = math.floor((int(fits[-1]) + 1) * n / k)
        low = float(x[rank - 1]) if rank >= 1 else -math.inf
    # upper rank u: the smallest with P(B >= u) <= alpha / 2, i.e. P(B <= u - 1) >= 1 - alpha/2.
    upper = int(np.flatnonzero(below >= 1 - alpha / 2)[0]) + 1
    high = math.inf
    if upper <= k:
        rank = math.ceil(upper * n / k)
        high = float(x[rank - 1]) if rank <= n else math.inf
    return Estimate(float(np.quantile(x, probability)), low, high)


def maximum_interval(
    values: ArrayLike, confidence: float = CONFIDENCE, inflation: float = 1.0
) -> Estimate:
    """The largest value of a series with a prediction interval for a repeat's largest.

    For two independent samples of ``k`` exchangeable values, the repeat's largest lies below
    the first sample's j-th smallest with probability C(j + k - 1, k) / C(2k, k); the lower
    end is the largest j-th smallest with that probability at most α/2 (α = 1 - confidence),
    for ``k = floor(n / inflation)`` and its rank scaled back to ``n``. The upper end is
    unbounded: a repeat's largest exceeds this one's with probability 1/2.

    Args:
        values: the series (at least :data:`MIN_REVOLUTIONS` values).
        confidence: the confidence level of the lower end (one-sided α/2, as the others').
        inflation: variance inflation of the series (:func:`batch_means`), at least 1.
    """
    x = np.sort(_series(values))
    n = x.size
    k = max(1, math.floor(n / max(inflation, 1.0)))
    alpha = 1.0 - confidence
    total = math.comb(2 * k, k)
    fits = [j for j in range(1, k + 1) if math.comb(j + k - 1, k) / total <= alpha / 2]
    low = -math.inf
    if fits:
        rank = math.floor(fits[-1] * n / k)
        low = float(x[rank - 1]) if rank >= 1 else -math.inf
    return Estimate(float(x[-1]), low, math.inf)


def peak_distribution(
    values: ArrayLike, probability: float = QUANTILE, confidence: float = CONFIDENCE
) -> PeakDistribution:
    """The mean, the ``probability`` quantile and the largest of one quantity's
    per-revolution peaks, each with its interval (see the module docstring).

    Args:
        values: the quantity's peak in each analysed revolution (at least
            :data:`MIN_REVOLUTIONS`).
        probability: the quantile's probability.
        confidence: the intervals' confidence level.

    Raises:
        ValueError: fewer than :data:`MIN_REVOLUTIONS` values, or a value that is not finite.
    """
    mean, batches, inflation = batch_means(values, confidence)
    return _distribution(values, mean, batches, inflation, probability, confidence)


def peak_distributions(
    per_revolution: Mapping[str, Sequence[float]],
    probability: float = QUANTILE,
    confidence: float = CONFIDENCE,
) -> dict[str, PeakDistribution]:
    """:func:`peak_distribution` of every quantity; empty with fewer than
    :data:`MIN_REVOLUTIONS` revolutions (or a partial last one dropped: only whole ones
    count, pass them)."""
    return {
        name: peak_distribution(values, probability, confidence)
        for name, values in per_revolution.items()
        if len(values) >= MIN_REVOLUTIONS
    }


#: Fewest independent runs of an ensemble (:func:`replicate_distribution`).
MIN_RUNS = 5


def replicate_distribution(
    runs: Sequence[ArrayLike], probability: float = QUANTILE, confidence: float = CONFIDENCE
) -> PeakDistribution:
    """The distribution of one quantity's per-revolution peak over an ensemble of independent
    runs (each a batch: the method of independent replications, Law & Kelton §9.4.1).

    One trajectory of a motion that dwells in one of several states for hundreds of
    revolutions gives statistics of the state it happens to dwell in; an ensemble of runs from
    perturbed starts samples the states. The mean is the mean of the runs' means, its interval
    Student's t with ``M - 1`` degrees of freedom over the ``M`` run means (exact for
    independent runs however long each dwells); the variance inflation is ``N`` × the variance
    of the run means over the variance of all the ``M N`` peaks (at least 1), which sets the
    effective sample of the 95th percentile's and the max's intervals as in
    :func:`peak_distribution`.

    Args:
        runs: each run's peak in each of its ``N`` analysed revolutions (at least
            :data:`MIN_RUNS` runs of equal length).
        probability: the quantile's probability.
        confidence: the intervals' confidence level.

    Raises:
        ValueError: fewer than :data:`MIN_RUNS` runs, runs of unequal length, or a value that
            is not finite.
    """
    from scipy.stats import t as student

    lengths = {int(np.size(run)) for run in runs}
    if len(runs) < MIN_RUNS or len(lengths) != 1 or 0 in lengths:
        raise ValueError(
            f"an ensemble needs at least {MIN_RUNS} runs of the same number (> 0) of "
            f"revolutions, got {len(runs)} run(s) of {sorted(lengths)} revolution(s)"
        )
    x = np.array([np.asarray(run, dtype=float).ravel() for run in runs])
    if not np.all(np.isfinite(x)):
        raise ValueError("the per-revolution peaks must be finite numbers")
    m, n = x.shape
    means = x.mean(axis=1)
    pooled = x.ravel()
    mean = float(means.mean())
    half = float(student.ppf(0.5 + confidence / 2, m - 1)) * float(means.std(ddof=1)) / m**0.5
    plain = float(pooled.var(ddof=1)) if pooled.size > 1 else 0.0
    inflation = max(1.0, n * float(means.var(ddof=1)) / plain) if plain > 0 else 1.0
    if pooled.size < MIN_REVOLUTIONS:
        raise ValueError(
            f"the statistics of irregular running need at least {MIN_REVOLUTIONS} revolutions, "
            f"got {pooled.size}"
        )
    estimate = Estimate(mean, mean - half, mean + half)
    return _distribution(pooled, estimate, m, inflation, probability, confidence)


def _distribution(
    values: ArrayLike,
    mean: Estimate,
    batches: int,
    inflation: float,
    probability: float,
    confidence: float,
) -> PeakDistribution:
    """The distribution of ``values`` given its mean's estimate, the number of batches behind
    it and the variance inflation that sets the percentile's and the max's effective sample."""
    return PeakDistribution(
        revolutions=int(np.size(values)),
        mean=mean,
        quantile=quantile_interval(values, probability, confidence, inflation),
        maximum=maximum_interval(values, confidence, inflation),
        batches=batches,
        inflation=inflation,
        confidence=confidence,
        probability=probability,
    )


def agrees(
    first: PeakDistribution, second: PeakDistribution, statistics: Sequence[str] = CONVERGING
) -> dict[str, bool]:
    """For each of ``statistics`` (``"mean"``, ``"quantile"``, ``"maximum"``): whether the
    two runs agree — the difference of their estimates lies within its own interval.

    The interval of the difference of two independent estimates is taken as the root sum of
    squares of their half-widths on the sides that face each other (the upper half-width of
    the smaller estimate, the lower of the larger: the order-statistic intervals are not
    symmetric); an unbounded side agrees with anything. At the estimates' confidence this is
    a two-sided test of "the two runs draw from one distribution" at that level.
    """
    out = {}
    for name in statistics:
        a, b = getattr(first, name), getattr(second, name)
        low, high = (a, b) if a.value <= b.value else (b, a)
        allowed = math.hypot(low.high - low.value, high.value - high.low)
        out[name] = bool(high.value - low.value <= allowed)
    return out


def revolutions_for_quantile(
    probability: float = QUANTILE, confidence: float = CONFIDENCE, inflation: float = 1.0
) -> int:
    """The fewest revolutions whose order-statistic interval of the ``probability`` quantile
    is bounded above: the smallest k with 1 - probability**k >= 1 - α/2, times the variance
    inflation (72 for the 95th percentile at 95 % confidence and independent revolutions)."""
    alpha = 1.0 - confidence
    k = math.ceil(math.log(alpha / 2) / math.log(probability))
    return max(MIN_REVOLUTIONS, math.ceil(k * max(inflation, 1.0)))


#: Pairs whose swaps :func:`paired_shifts` enumerates (2**16 = 65 536 patterns); beyond,
#: as many patterns drawn at random (seed 0, the identity among them).
MAX_ENUMERATED_PAIRS = 16


@dataclass(frozen=True)
class PairedShift:
    """How far a statistic over paired samples moved between two settings, against the
    randomization interval of that move (:func:`paired_shifts`), in the unit of the values.

    Attributes:
        statistic: ``"mean"`` or ``"p95"`` (the :data:`QUANTILE` quantile).
        first: the statistic over the samples at the first setting (e.g. the default
            tolerances).
        second: the same statistic over the same samples at the second setting.
        half_width: the interval of the move: under the hypothesis that the setting changes
            nothing but the draw (each sample's two values exchangeable) the move exceeds it
            with probability at most ``level``.
        level: that probability (the per-statistic false-alarm rate).
        pairs: the samples behind the statistic.
        largest: the largest |move| any swap pattern gives; where the half-width reaches it,
            no move can lie beyond: the statistic cannot be judged by these pairs at this
            level (:attr:`judged`).
    """

    statistic: str
    first: float
    second: float
    half_width: float
    level: float
    pairs: int
    largest: float

    @property
    def shift(self) -> float:
        """``second - first``."""
        return self.second - self.first

    @property
    def within(self) -> bool:
        """Whether the move lies within its interval: the statistic converged."""
        return bool(abs(self.shift) <= self.half_width)

    @property
    def judged(self) -> bool:
        """Whether the test can reject at all: some swap pattern moves the statistic beyond
        the half-width (with few pairs, or a quantile set by the largest one or two values,
        the largest move is shared by more than ``level`` of the patterns)."""
        return bool(self.half_width < self.largest)

    def as_dict(self) -> dict[str, Any]:
        """JSON-ready: the two values, the shift, its interval, whether it lies within."""
        return {
            "first": self.first,
            "second": self.second,
            "shift": self.shift,
            "half_width": self.half_width,
            "within": self.within,
            "judged": self.judged,
            "level": self.level,
            "pairs": self.pairs,
        }


def pairs_to_judge(level: float) -> int:
    """The fewest pairs whose randomization test can reject at ``level``: the two patterns
    that give the largest move (a swap pattern and its complement move the statistic by the
    same amount, opposite signs) must be at most ``level`` of the 2**n patterns."""
    return max(1, math.ceil(math.log2(2.0 / level)))


def paired_shifts(
    first: ArrayLike, second: ArrayLike, level: float, probability: float = QUANTILE
) -> tuple[PairedShift, PairedShift]:
    """The move of the mean and of the ``probability`` quantile of paired samples between two
    settings, each with its randomization interval at ``level``.

    ``first[i]`` and ``second[i]`` are the same sample (the same inputs) at the two settings.
    Under the hypothesis that the second setting changes nothing but the draw — a converged
    sample gives the same value, an irregular (chaotic) one another draw of its distribution —
    each sample's two values are exchangeable, so swapping them in any subset of the samples
    gives a move as likely as the one observed (a paired randomization test: Fisher 1935;
    Good, Permutation Tests, 2nd ed., §3.1). All 2**n swap patterns are enumerated (n <=
    :data:`MAX_ENUMERATED_PAIRS`; else as many drawn). The interval's half-width is the
    ``1 - level`` point of the patterns' |move|: the observed move exceeds it with probability
    at most ``level`` under the hypothesis, whatever the distribution — the test's
    false-alarm rate. A bias of the second setting larger than about the half-width is found;
    a smaller one is not resolved by n samples.

    Args:
        first: (n,) the values at the first setting.
        second: (n,) the values of the same samples at the second setting.
        level: the per-statistic false-alarm rate, in (0, 1) (Bonferroni: the family's rate
            over the number of statistics judged).
        probability: the quantile's probability (Hyndman & Fan definition 7).

    Returns:
        The mean's and the quantile's :class:`PairedShift`.

    Raises:
        ValueError: the two differ in length, fewer than two pairs, a value that is not
            finite, or a level outside (0, 1).
    """
    a = np.asarray(first, dtype=float).ravel()
    b = np.asarray(second, dtype=float).ravel()
    if a.shape != b.shape or a.size < 2:
        raise ValueError(
            f"paired samples need two arrays of the same length >= 2, got {a.size} and {b.size}"
        )
    if not (np.all(np.isfinite(a)) and np.all(np.isfinite(b))):
        raise ValueError("the paired values must be finite numbers")
    if not 0.0 < level < 1.0:
        raise ValueError(f"the level must be in (0, 1), got {level!r}")
    n = a.size
    if n <= MAX_ENUMERATED_PAIRS:
        swap = ((np.arange(2**n)[:, None] >> np.arange(n)) & 1).astype(bool)
    else:
        swap = np.random.default_rng(0).random((2**MAX_ENUMERATED_PAIRS, n)) < 0.5
        swap[0] = False  # the observed pattern is one of them
    one, two = np.where(swap, b, a), np.where(swap, a, b)
    quantile = f"p{100 * probability:g}"
    # row 0 is the observed pattern (no swap): its statistics are the reported ones, so the
    # observed move is exactly one of the patterns' moves
    statistics = {
        "mean": (one.mean(axis=1), two.mean(axis=1)),
        quantile: (np.quantile(one, probability, axis=1), np.quantile(two, probability, axis=1)),
    }
    out = []
    for name, (at_first, at_second) in statistics.items():
        size = np.sort(np.abs(at_second - at_first))
        beyond = math.floor(level * size.size)  # at most this many patterns exceed the width
        half_width = float(size[size.size - beyond - 1])
        first_value, second_value = float(at_first[0]), float(at_second[0])
        out.append(
            PairedShift(name, first_value, second_value, half_width, level, n, float(size[-1]))
        )
    return out[0], out[1]


#: The unit of each peak quantity, by prefix (SI, as summary.json).
UNITS = (("omega", "rad/s"), ("alpha", "rad/s²"), ("F_", "N"), ("torque", "N·m"))

#: What summary.json says the statistics are.
MEANING = (
    "the motion is irregular (its once-per-revolution Poincare section does not repeat), so "
    "each revolution's peak is a draw and so is the largest over the analysed revolutions "
    "('peaks'): it moves by as much as the revolutions differ when the tolerances change. "
    "What is reproducible is the distribution of the per-revolution peak over the whole "
    "analysed revolutions: its mean (batch-means interval), its 95th percentile "
    "(order-statistic interval on the effective number of independent revolutions) and its "
    "max (the 'peaks' value; low: a repeat run's max lies above it with 97.5 % probability; "
    "no high: a repeat's max exceeds this one half of the time). Intervals are "
    "95 %; null: unbounded. The intervals are the sampling uncertainty of this run's "
    "revolutions only: a chaotic motion can dwell in one state for hundreds of revolutions, "
    "and which state can change with the tolerances (the dry paper four-bar's F_O2 mean is "
    "97 N at rtol 1e-7 and 1e-10, 108-119 N at 1e-8 and 1e-6). See docs/performance.md, "
    "'Accuracy of irregular (chaotic) running'"
)

#: The caveat the terminal prints under the statistics.
CAVEAT = (
    "the intervals are the sampling uncertainty of this run's revolutions only: a chaotic "
    "motion can dwell in one state for hundreds of revolutions, and which state can change "
    "with the tolerances; an ensemble of runs from perturbed starts samples the states "
    '(--ensemble 12; docs/performance.md, "Accuracy of irregular (chaotic) running")'
)


def unit_of(name: str) -> str:
    """The SI unit of a peak quantity (``""`` where unknown)."""
    return next((unit for prefix, unit in UNITS if name.startswith(prefix)), "")


def irregular_summary(
    distributions: Mapping[str, PeakDistribution], revolutions: int
) -> dict[str, Any]:
    """The ``irregular`` of summary.json for a motion that is not periodic.

    Args:
        distributions: each quantity's per-revolution peak distribution (empty: too few
            revolutions).
        revolutions: the whole analysed revolutions.
    """
    needed = max(
        [revolutions_for_quantile(d.probability, d.confidence, d.inflation)
         for d in distributions.values()] or [revolutions_for_quantile()]
    )  # fmt: skip
    return {
        "motion": "irregular",
        "revolutions": revolutions,
        "meaning": MEANING,
        "statistics": {name: d.as_dict() for name, d in distributions.items()},
        "revolutions_for_bounded_percentile": needed,
        **(
            {}
            if distributions
            else {
                "note": (
                    f"no statistics: {revolutions} whole analysed revolution(s), fewer than "
                    f"{MIN_REVOLUTIONS}; analyse at least {needed} revolutions"
                )
            }
        ),
    }


def describe(name: str, found: PeakDistribution) -> str:
    """One line: ``F_O2 over 100 revolutions: mean 108 ± 3.4 N, 95th percentile 137 N
    (128–150 N), max 149 N (a draw; a repeat run's max: above 130 N)``, intervals at the
    distribution's confidence."""
    unit = unit_of(name)
    unit = f" {unit}" if unit else ""
    mean, quantile, largest = found.mean, found.quantile, found.maximum
    half = 0.5 * (mean.high - mean.low)
    spread = f"{half:.0f}" if half >= 100 else f"{half:.2g}"  # 897, not 9e+02
    return (
        f"{name} over {found.revolutions} revolutions: mean {mean.value:.4g} ± {spread}{unit}, "
        f"{100 * found.probability:g}th percentile {quantile.value:.4g}{unit} "
        f"({_interval(quantile, unit)}), max {largest.value:.4g}{unit} (a draw; a repeat "
        f"run's max: {_interval(largest, unit)})"
    )


def _interval(found: Estimate, unit: str) -> str:
    """``101–110 N``, ``above 101 N`` (unbounded above) or ``below 110 N``."""
    if math.isfinite(found.low) and math.isfinite(found.high):
        return f"{found.low:.4g}–{found.high:.4g}{unit}"
    if math.isfinite(found.low):
        return f"above {found.low:.4g}{unit}"
    if math.isfinite(found.high):
        return f"below {found.high:.4g}{unit}"
    return "unbounded"


def _series(values: ArrayLike) -> FloatArray:
    x = np.asarray(values, dtype=float).ravel()
    if x.size < MIN_REVOLUTIONS:
        raise ValueError(
            f"the statistics of irregular running need at least {MIN_REVOLUTIONS} revolutions, "
            f"got {x.size}"
        )
    if not np.all(np.isfinite(x)):
        raise ValueError("the per-revolution peaks must be finite numbers")
    return x
