"""Yields with exact intervals, verdicts and order-statistic bounds, against exact references."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.stats import binom, binomtest

from jointplay.tolerance.confidence import (
    YieldEstimate,
    clopper_pearson,
    quantile_value,
    samples_for_order_statistic,
    verdict,
)


@pytest.mark.parametrize(("k", "n"), [(0, 1), (0, 50), (3, 50), (50, 50), (997, 1000), (1, 7)])
def test_clopper_pearson_is_scipys_exact_interval(k: int, n: int) -> None:
    expected = binomtest(k, n).proportion_ci(confidence_level=0.95, method="exact")
    # both invert the same regularised incomplete beta function: agreement to rounding
    assert clopper_pearson(k, n) == pytest.approx((expected.low, expected.high), abs=1e-12)


def test_zero_failures_bound_in_closed_form() -> None:
    """No failure in n: the lower bound of the yield is (α/2)^(1/n) exactly."""
    for n in (10, 200, 1365):
        lower, upper = YieldEstimate(0, n).interval
        assert lower == pytest.approx(0.025 ** (1 / n), rel=1e-12) and upper == 1.0


@pytest.mark.parametrize("p", [0.5, 0.9, 0.99, 0.9973])
def test_the_interval_covers_the_true_yield_at_least_95_percent(p: float) -> None:
    """Exact coverage: the binomial probability of the outcomes whose interval holds p."""
    n = 200
    coverage = sum(
        binom.pmf(k, n, p)
        for k in range(n + 1)
        if clopper_pearson(k, n)[0] <= p <= clopper_pearson(k, n)[1]
    )
    assert coverage >= 0.95


def test_dpm_is_the_yield_mirrored() -> None:
    estimate = YieldEstimate(3, 1000)
    assert estimate.value == 0.997 and estimate.dpm == pytest.approx(3000.0)
    lower, upper = estimate.interval
    assert estimate.dpm_interval == pytest.approx((1e6 * (1 - upper), 1e6 * (1 - lower)))


def test_verdicts_at_99_73_percent() -> None:
    """Zero failures show 99.73 % from 1 365 samples on (ln 0.025 / ln 0.9973 = 1 364.4)."""
    assert verdict(YieldEstimate(0, 1365), 0.9973).name == "meets"
    short = verdict(YieldEstimate(0, 1364), 0.9973)
    assert short.name == "undecided" and short.samples_to_decide == 1365
    assert verdict(YieldEstimate(0, 200), 0.9973).samples_to_decide == 1365
    assert verdict(YieldEstimate(10, 100), 0.9973).name == "fails"
    assert verdict(YieldEstimate(1, 50), 0.9973).name == "undecided"


@pytest.mark.parametrize(("failures", "n"), [(1, 50), (2, 100), (1, 1000), (5, 1000)])
def test_samples_to_decide_is_the_first_n_that_decides_at_the_observed_rate(
    failures: int, n: int
) -> None:
    rate = failures / n
    result = verdict(YieldEstimate(failures, n), 0.9973)
    assert result.name == "undecided" and result.samples_to_decide is not None
    m = result.samples_to_decide

    def bounds(total: int) -> tuple[float, float]:
        return clopper_pearson(total * (1 - rate), total)

    if rate < 1 - 0.9973:
        assert bounds(m)[0] >= 0.9973 > bounds(m - 1)[0]
    else:
        assert bounds(m)[1] < 0.9973 <= bounds(m - 1)[1]


def test_order_statistic_needs_1109_samples_at_99_73_percent() -> None:
    assert samples_for_order_statistic(0.9973) == 1109
    assert 1 - 0.9973**1109 >= 0.95 > 1 - 0.9973**1108


def test_order_statistic_rank_is_the_smallest_with_95_percent_coverage() -> None:
    n, q = 5000, 0.9973
    result = quantile_value(np.arange(n, dtype=float), q)
    assert result.basis == "order-statistic" and result.rank is not None
    r = result.rank
    assert binom.cdf(r - 1, n, q) >= 0.95 > binom.cdf(r - 2, n, q)
    assert result.value == r - 1  # the r-th smallest of 0 … n-1


def test_order_statistic_bound_covers_the_quantile() -> None:
    """400 seeded repetitions of 1 200 exponential samples: the bound of the 99.73 %
    quantile (−ln 0.0027) lies above it in at least 95 % (less 3 binomial σ = 3.3 %)."""
    rng = np.random.default_rng(7)
    truth = -math.log(1 - 0.9973)
    covered = sum(
        quantile_value(rng.exponential(size=1200), 0.9973).value >= truth for _ in range(400)
    )
    assert covered / 400 >= 0.95 - 3 * math.sqrt(0.95 * 0.05 / 400)


def test_lower_quantile_is_bounded_from_below_and_failures_count_as_worst() -> None:
    x = np.arange(2000, dtype=float)
    upper = quantile_value(x, 0.9973)
    lower = quantile_value(-x, 0.9973, upper=False)
    assert lower.value == -upper.value and lower.rank == upper.rank
    # the bound is the 2nd smallest of 2 000 (rank 1 999 mirrored): two failures reach it
    with_failures = x.copy()
    with_failures[:1] = math.nan
    assert quantile_value(with_failures, 0.9973, upper=False).value == 1.0
    with_failures[:2] = math.nan
    assert quantile_value(with_failures, 0.9973, upper=False).value == -math.inf


def test_few_samples_give_a_named_normal_model_estimate() -> None:
    rng = np.random.default_rng(1)
    x = rng.normal(10.0, 2.0, size=200)
    result = quantile_value(x, 0.9973)
    assert result.basis == "normal-model" and result.rank is None
    assert result.value == pytest.approx(x.mean() + 2.78215 * x.std(ddof=1), rel=1e-5)
    assert "not a bound" in result.describe()
