"""The Weibull fit with right-censoring and the empirical quantiles, against closed forms."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.stats import weibull_min

from jointplay.errors import ConfigError
from jointplay.study.weibull import (
    _Data,
    empirical_quantile,
    fit_weibull,
    median_ranks,
)

SHAPE, SCALE, CENSOR = 2.0, 1000.0, 1000.0


def _censored_sample(rng, n=50):
    lives = SCALE * rng.weibull(SHAPE, n)
    censored = lives > CENSOR
    return np.minimum(lives, CENSOR), censored


def test_shape_and_scale_are_recovered_within_their_90_percent_intervals():
    """100 seeded repetitions of 50 lives from Weibull(β 2, η 1000 h) censored at 1000 h
    (37 % censored): each likelihood-ratio interval covers the truth in >= 88 of 100 (the
    issue's bar; measured 94 and 89), and B10's too (measured 94)."""
    rng = np.random.default_rng(1)
    b10 = SCALE * (-math.log(0.9)) ** (1 / SHAPE)
    shape = scale = quantile = 0
    for _ in range(100):
        lives, censored = _censored_sample(rng)
        fit = fit_weibull(lives, censored)
        assert fit is not None
        shape += fit.shape_interval[0] <= SHAPE <= fit.shape_interval[1]
        scale += fit.scale_interval[0] <= SCALE <= fit.scale_interval[1]
        low, high = fit.quantile_interval(0.10)
        quantile += low <= b10 <= high
    assert shape >= 88
    assert scale >= 88
    assert quantile >= 88


def test_the_fit_is_scipys_maximum_and_its_likelihood_scipys():
    rng = np.random.default_rng(7)
    lives, censored = _censored_sample(rng, 40)
    fit = fit_weibull(lives, censored)
    assert fit is not None
    # the closed-form log-likelihood of the profiles is SciPy's logpdf + logsf
    scipy_ll = (
        weibull_min.logpdf(lives[~censored], 1.7, scale=900.0).sum()
        + weibull_min.logsf(lives[censored], 1.7, scale=900.0).sum()
    )
    assert _Data.of(tuple(lives), tuple(censored)).loglik(1.7, 900.0) == pytest.approx(scipy_ll)
    # the estimate is a maximum: every neighbour is less likely
    data = _Data.of(tuple(lives), tuple(censored))
    for db, de in ((0.02, 0), (-0.02, 0), (0, 5.0), (0, -5.0)):
        assert data.loglik(fit.shape + db, fit.scale + de) < fit.loglik
    # at an interval's end the likelihood ratio is chi2(1, 90 %) = 2.706
    for end in fit.shape_interval:
        ratio = 2 * (fit.loglik - data.loglik(end, data.scale_at(end)))
        assert ratio == pytest.approx(2.7055, abs=1e-3)
    assert fit.shape_interval[0] < fit.shape < fit.shape_interval[1]
    assert fit.quantile_interval(0.1)[0] < fit.quantile(0.1) < fit.quantile_interval(0.1)[1]


def test_no_fit_from_fewer_than_two_failures():
    assert fit_weibull([5.0, 10.0, 10.0], [False, True, True]) is None
    assert fit_weibull([10.0, 10.0], [True, True]) is None
    with pytest.raises(ConfigError, match="finite and > 0"):
        fit_weibull([0.0, 1.0, 2.0], [False, False, False])


def test_empirical_quantile_interval_is_the_exact_binomial_one():
    """n = 100, p = 0.10: the estimate is the 10th smallest; the ranks of the interval's
    ends from Binom(100, 0.1), 5 % beyond each."""
    from scipy.stats import binom

    lives = np.arange(1.0, 101.0)
    q = empirical_quantile(lives, np.zeros(100, bool), 0.10)
    assert q.value == 10.0
    low, high = q.ranks
    assert (q.low, q.high) == (float(low), float(high))
    coverage = binom.cdf(high - 1, 100, 0.1) - binom.cdf(low - 1, 100, 0.1)
    assert coverage >= 0.90
    # equal tails: each end is the innermost that leaves at most 5 % beyond it
    assert binom.cdf(low - 1, 100, 0.1) <= 0.05 < binom.cdf(low, 100, 0.1)
    assert binom.sf(high - 1, 100, 0.1) <= 0.05 < binom.sf(high - 2, 100, 0.1)


def test_an_empirical_end_beyond_the_censoring_is_unbounded():
    lives = np.array([1.0, 2.0, 5.0, 5.0, 5.0])
    q = empirical_quantile(lives, np.array([False, False, True, True, True]), 0.5)
    assert math.isinf(q.value)
    assert math.isinf(q.high)


def test_median_ranks_of_failures_among_all_units():
    failures, positions = median_ranks([3.0, 1.0, 9.0, 9.0], [False, False, True, True])
    assert failures.tolist() == [1.0, 3.0]
    assert positions == pytest.approx([0.7 / 4.4, 1.7 / 4.4])
