"""Rare defects by cross-entropy importance sampling, on responses with an exact tail: a
linear function of independent standard normals, a·z > β|a|, has P = Φ(−β) exactly."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.stats import norm

from jointplay.errors import ConfigError
from jointplay.tolerance.rare import cross_entropy_importance_sampling

D = 8
#: a direction that is not an axis: every input contributes
A = np.linspace(1.0, 2.0, D) / np.linalg.norm(np.linspace(1.0, 2.0, D))


def _linear(p: float):
    beta = -norm.ppf(p)
    return lambda z: z @ A - beta


@pytest.mark.parametrize(("p", "repetitions"), [(1e-6, 1000), (3e-3, 400)])
def test_intervals_cover_the_exact_tail_in_93_to_97_percent(p: float, repetitions: int) -> None:
    """Seeded repetitions of a small budget (pilot stages of 500, 2 000 final samples). A
    95 % interval covers in 95 % ± 0.7 % (1 000 repetitions: one binomial σ) or ± 1.1 %
    (400); the band 93-97 % is 2.9σ and 1.8σ wide."""
    covered = 0
    for seed in range(repetitions):
        estimate = cross_entropy_importance_sampling(
            _linear(p), D, seed=seed, n_stage=500, n_final=2000
        )
        covered += estimate.interval[0] <= p <= estimate.interval[1]
    assert 0.93 <= covered / repetitions <= 0.97


def test_one_ppm_within_fifty_percent_from_at_most_20000_samples() -> None:
    """The default budget (at most 8 pilot stages of 1 000 and 10 000 final samples)."""
    for seed in range(20):
        estimate = cross_entropy_importance_sampling(_linear(1e-6), D, seed=seed)
        assert estimate.converged and estimate.samples <= 20_000
        assert estimate.relative_half_width <= 0.5
        assert estimate.dpm == pytest.approx(1.0, rel=0.25)
        # the shift finds the design point: |μ| near β = 4.75 for a linear response
        assert estimate.reliability_index == pytest.approx(-norm.ppf(1e-6), rel=0.1)


def test_failed_evaluations_count_as_defects() -> None:
    """NaN where a ≥ 0.5 on the first input (P = Φ(−0.5) = 30.9 %) and no other defect."""
    estimate = cross_entropy_importance_sampling(
        lambda z: np.where(z[:, 0] > 0.5, np.nan, -1.0), 2, seed=1, n_stage=200, n_final=4000
    )
    p = norm.sf(0.5)
    assert estimate.interval[0] <= p <= estimate.interval[1]
    assert math.isclose(estimate.probability, p, rel_tol=0.1)


def test_bad_settings_are_refused() -> None:
    with pytest.raises(ConfigError, match="rho"):
        cross_entropy_importance_sampling(_linear(1e-3), D, rho=0.7)
