"""Statistics of irregular running: intervals on synthetic series with known answers.

The coverage checks draw many series from processes whose answers are known (independent
normals; a stationary AR(1) with coefficient 0.5, whose revolutions are correlated) and count
how often the interval holds the true value; each interval must hold it about as often as its
confidence level says (the mean's batch-means interval) or at least that often (the
distribution-free order-statistic bounds).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.stats import norm

from jointplay.dynamics.irregular import (
    MIN_REVOLUTIONS,
    Estimate,
    agrees,
    batch_means,
    describe,
    maximum_interval,
    peak_distribution,
    peak_distributions,
    quantile_interval,
    replicate_distribution,
    revolutions_for_quantile,
)

SEEDS = 600


def _ar1(rng: np.random.Generator, n: int, phi: float) -> np.ndarray:
    """A stationary AR(1) series of unit innovations (variance 1 / (1 - phi**2))."""
    noise = rng.standard_normal(n)
    x = np.empty(n)
    x[0] = noise[0] / math.sqrt(1.0 - phi**2)
    for i in range(1, n):
        x[i] = phi * x[i - 1] + noise[i]
    return x


@pytest.mark.parametrize(("phi", "n"), [(0.0, 100), (0.5, 400)])
def test_the_mean_interval_covers_at_its_confidence(phi: float, n: int) -> None:
    rng = np.random.default_rng(11)
    hits = sum(batch_means(_ar1(rng, n, phi) + 5.0)[0].contains(5.0) for _ in range(SEEDS))
    # Binomial spread of the count at 600 seeds is ±0.009; batch means of 20 under-state an
    # AR(1)'s long-run variance a little (measured 0.93 at phi = 0.5).
    assert 0.91 <= hits / SEEDS <= 0.98


def test_an_iid_interval_is_narrower_than_a_correlated_one() -> None:
    """Correlation between revolutions must widen the mean's interval (a plain standard error
    would not): an AR(1) of coefficient 0.8 has a long-run variance 25x its innovations'."""
    rng = np.random.default_rng(5)
    iid = rng.standard_normal(400) * (1 / math.sqrt(1 - 0.8**2))
    correlated = _ar1(rng, 400, 0.8)
    wide = batch_means(correlated)
    narrow = batch_means(iid)
    assert wide[2] > 3.0 and narrow[2] < 2.0  # the variance inflation
    assert wide[0].high - wide[0].low > 2.0 * (narrow[0].high - narrow[0].low)


@pytest.mark.parametrize(("phi", "n"), [(0.0, 200), (0.5, 400)])
def test_the_quantile_interval_covers_at_least_its_confidence(phi: float, n: int) -> None:
    sd = 1.0 / math.sqrt(1.0 - phi**2)
    truth = norm.ppf(0.95) * sd
    rng = np.random.default_rng(7)
    found = [peak_distribution(_ar1(rng, n, phi)).quantile for _ in range(SEEDS)]
    coverage = sum(e.contains(truth) for e in found) / SEEDS
    assert 0.94 <= coverage <= 1.0  # distribution-free, conservative: 0.98-0.99 measured
    assert sum(e.bounded for e in found) >= 0.95 * SEEDS  # a noisy inflation can unbound one
    assert np.median([e.high - e.low for e in found]) < sd  # not trivially wide


def test_the_quantile_of_too_few_revolutions_is_unbounded_above() -> None:
    """Below 72 independent revolutions no order statistic bounds the 95th percentile from
    above at 95 % confidence: the interval says so rather than stop at the sample's largest."""
    assert revolutions_for_quantile() == 72
    x = np.arange(71.0)
    assert quantile_interval(x).high == math.inf
    assert quantile_interval(np.arange(72.0)).high == 71.0  # the largest of 72
    # Correlation costs revolutions: inflation 2 needs twice as many.
    assert revolutions_for_quantile(inflation=2.0) == 144
    assert quantile_interval(np.arange(100.0), inflation=2.0).high == math.inf


def test_the_quantile_interval_of_independent_values_is_the_binomial_one() -> None:
    """For 100 independent values and B ~ Binomial(100, 0.95): P(B <= 89) = 0.0115 <= 0.025
    < P(B <= 90) = 0.0282, so l - 1 = 89; P(B <= 98) = 0.963 < 0.975 <= P(B <= 99) = 0.994,
    so u - 1 = 99."""
    x = np.arange(1.0, 101.0)  # x_(j) = j
    found = quantile_interval(x)
    assert (found.low, found.high) == (90.0, 100.0)
    assert found.value == pytest.approx(np.quantile(x, 0.95))


def test_a_repeat_runs_largest_falls_below_the_lower_end_rarely() -> None:
    """The maximum's prediction interval: a repeat's largest below its lower end at most
    2.5 % of the time, above this run's largest half of the time (no upper end)."""
    rng = np.random.default_rng(3)
    below = above = 0
    for _ in range(SEEDS):
        found = maximum_interval(rng.standard_normal(40))
        again = rng.standard_normal(40).max()
        below += again < found.low
        above += again > found.value
    assert below / SEEDS <= 0.035
    assert 0.42 <= above / SEEDS <= 0.58
    assert found.high == math.inf


def test_the_maximum_lower_end_is_the_exchangeable_rank() -> None:
    """For k = 10: C(j + 9, 10) / C(20, 10) = 0.0163 at j = 6 and 0.0433 at j = 7; 1/2 at
    j = 10 (a repeat's largest below this one's half of the time)."""
    assert math.comb(15, 10) / math.comb(20, 10) <= 0.025 < math.comb(16, 10) / math.comb(20, 10)
    assert math.comb(19, 10) / math.comb(20, 10) == 0.5
    assert maximum_interval(np.arange(1.0, 11.0)).low == 6.0


def test_two_draws_of_one_distribution_agree_at_the_confidence_level() -> None:
    """``agrees`` tests "one distribution" at the intervals' level: two independent samples of
        one AR(1) process agree about 95 % of the time (the mean; the distribution-free quantile
        at least that), and a shift of 0.7 (five standard errors of the difference of the means:
    long-run standard deviation 1 / (1 - 0.3) over sqrt(200), times sqrt(2)) is seen almost
    always."""
    rng = np.random.default_rng(2)
    same = {"mean": 0, "quantile": 0}
    shifted = 0
    for _ in range(SEEDS // 2):
        a = peak_distribution(_ar1(rng, 200, 0.3))
        b = peak_distribution(_ar1(rng, 200, 0.3))
        for name, ok in agrees(a, b).items():
            same[name] += ok
        shifted += agrees(a, peak_distribution(_ar1(rng, 200, 0.3) + 0.7))["mean"]
    assert 0.91 <= same["mean"] / (SEEDS // 2) <= 0.99
    assert same["quantile"] / (SEEDS // 2) >= 0.94
    assert shifted / (SEEDS // 2) <= 0.05


def test_an_unbounded_side_agrees_with_anything() -> None:
    x = np.arange(20.0)
    short = peak_distribution(x)  # 20 revolutions: the 95th percentile is unbounded above
    assert short.quantile.high == math.inf
    assert agrees(short, peak_distribution(x + 1e6))["quantile"] is True
    bounded = peak_distribution(np.random.default_rng(4).permutation(100) - 1e6)
    assert bounded.quantile.bounded
    assert agrees(short, bounded)["quantile"] is False  # the bounded side faces it


def test_too_few_revolutions_have_no_statistics() -> None:
    assert peak_distributions({"F_A": [1.0] * (MIN_REVOLUTIONS - 1)}) == {}
    with pytest.raises(ValueError, match="at least 10 revolutions"):
        peak_distribution([1.0] * 9)
    with pytest.raises(ValueError, match="finite"):
        peak_distribution([1.0] * 9 + [math.nan])


def test_an_unbounded_end_is_null_in_json() -> None:
    assert Estimate(1.0, 0.5, math.inf).as_dict() == {"value": 1.0, "low": 0.5, "high": None}


def _dwelling_run(rng: np.random.Generator, n: int) -> np.ndarray:
    """A run that dwells in one of two states for its whole length (calm, mean 0, with
    probability 0.7; rough, mean 2), plus independent unit noise: ensemble mean 0.6."""
    return (2.0 if rng.random() < 0.3 else 0.0) + rng.standard_normal(n)


def test_one_dwelling_trajectory_misses_the_ensemble_mean_and_replicates_do_not() -> None:
    """The dry four-bar's trouble in miniature: one trajectory's interval is honest about its
    own revolutions but covers the mean over the states rarely; an ensemble of 12 independent
    runs (each a batch) covers it at about its confidence."""
    rng = np.random.default_rng(8)
    single = replicated = 0
    for _ in range(SEEDS // 2):
        single += peak_distribution(_dwelling_run(rng, 360)).mean.contains(0.6)
        runs = [_dwelling_run(rng, 30) for _ in range(12)]
        replicated += replicate_distribution(runs).mean.contains(0.6)
    assert single / (SEEDS // 2) < 0.05  # measured 0
    assert 0.88 <= replicated / (SEEDS // 2) <= 0.99


def test_replicates_of_independent_values_are_one_sample() -> None:
    """Without dwelling, twelve runs of 30 are a sample of 360: the inflation is about 1 and
    the mean's interval about that of the pooled values."""
    rng = np.random.default_rng(9)
    runs = [rng.standard_normal(30) for _ in range(12)]
    found = replicate_distribution(runs)
    pooled = peak_distribution(np.concatenate(runs))
    assert found.revolutions == 360 and found.batches == 12
    assert found.inflation < 2.0
    assert found.mean.value == pytest.approx(pooled.mean.value)
    width = found.mean.high - found.mean.low
    assert 0.6 < width / (pooled.mean.high - pooled.mean.low) < 1.6
    assert found.quantile.bounded


def test_an_ensemble_needs_enough_equal_runs() -> None:
    with pytest.raises(ValueError, match="at least 5 runs"):
        replicate_distribution([[1.0, 2.0]] * 4)
    with pytest.raises(ValueError, match="of the same number"):
        replicate_distribution([[1.0, 2.0]] * 4 + [[1.0]])


def test_the_line_says_each_statistic_with_its_interval_and_unit() -> None:
    rng = np.random.default_rng(6)
    line = describe("F_O2", peak_distribution(100.0 + 5.0 * rng.standard_normal(100)))
    assert line.startswith("F_O2 over 100 revolutions: mean ")
    assert " N, 95th percentile " in line and "max " in line and "a repeat run's max: above" in line
    wide = describe("alpha4", peak_distribution(8000.0 + 3000.0 * rng.standard_normal(12)))
    assert "e+0" not in wide.split("95th")[0] and "rad/s²" in wide  # ± 1234, not ± 1.2e+03
