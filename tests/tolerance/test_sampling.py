"""Seeded sampling: reproducible, per-input streams, correct distributions, Latin hypercube."""

from __future__ import annotations

import math

import numpy as np
import pytest

from jointplay.errors import ConfigError
from jointplay.tolerance.sampling import sample, uniforms
from jointplay.tolerance.spec import QuantityTolerance, Tolerance, ToleranceSpec


def _spec(*items: tuple[str, str]) -> ToleranceSpec:
    return ToleranceSpec(
        tuple(
            QuantityTolerance(name, 1.0, Tolerance((0.0, 2.0), dist))  # type: ignore[arg-type]
            for name, dist in items
        )
    )


SPEC = _spec(("a", "uniform"), ("b", "normal"), ("c", "triangular"))


def test_same_seed_same_samples_other_seed_other_samples() -> None:
    first = sample(SPEC, 500, 42)
    again = sample(SPEC, 500, 42)
    other = sample(SPEC, 500, 43)
    np.testing.assert_array_equal(first.values, again.values)
    assert not np.any(first.values == other.values)
    assert first.names == ("a", "b", "c") and first.seed == 42 and first.n == 500


def test_fixed_seed_gives_fixed_numbers() -> None:
    # Golden values: they change only if the sampling scheme changes (a breaking change for
    # users who rely on reproducing published studies).
    values = sample(_spec(("a", "uniform"), ("b", "normal")), 3, 2024).values
    expected = [
        [0.3894064525011519, 1.1373071979937508],
        [1.2870491873190737, 1.280107319837643],
        [1.1138299998631354, 1.4896517650671348],
    ]
    # 1e-14: the last bits of the normal's inverse CDF may differ between SciPy builds.
    np.testing.assert_allclose(values, expected, rtol=1e-14)


def test_prefix_and_stream_independence() -> None:
    long = sample(SPEC, 1000, 7).values
    short = sample(SPEC, 100, 7).values
    np.testing.assert_array_equal(long[:100], short)
    # Adding an input leaves the other inputs' samples unchanged (common random numbers).
    wider = sample(_spec(("a", "uniform"), ("z", "normal"), ("c", "triangular")), 1000, 7).values
    np.testing.assert_array_equal(wider[:, 0], long[:, 0])
    np.testing.assert_array_equal(wider[:, 2], long[:, 2])


def test_probabilities_stay_strictly_inside_the_unit_interval() -> None:
    u = uniforms(("a", "b"), 100_000, 0)
    assert u.min() > 0.0 and u.max() < 1.0
    assert np.all(np.isfinite(sample(_spec(("b", "normal")), 100_000, 0).values))


@pytest.mark.parametrize(
    ("distribution", "std"),
    [("uniform", 1 / math.sqrt(3)), ("normal", 1 / 3), ("triangular", 1 / math.sqrt(6))],
)
def test_sample_moments_match_the_distribution(distribution: str, std: float) -> None:
    n = 40_000
    values = sample(_spec(("x", distribution)), n, 11).values[:, 0]
    # Four standard errors of the mean and of the standard deviation (≈ σ/√(2n) for these
    # light-tailed distributions): a false alarm about once in 15 000 runs.
    assert values.mean() == pytest.approx(1.0, abs=4 * std / math.sqrt(n))
    assert values.std() == pytest.approx(std, abs=4 * std / math.sqrt(2 * n))
    if distribution != "normal":
        assert values.min() >= 0.0 and values.max() <= 2.0


def test_latin_hypercube_puts_one_sample_in_every_stratum() -> None:
    n = 64
    u = uniforms(("a", "b"), n, 5, "lhs")
    for column in u.T:
        np.testing.assert_array_equal(np.sort(np.floor(column * n)), np.arange(n))
    lhs = sample(SPEC, n, 5, method="lhs")
    assert lhs.method == "lhs"
    np.testing.assert_array_equal(lhs.values, sample(SPEC, n, 5, method="lhs").values)


@pytest.mark.parametrize(
    ("n", "seed", "method", "message"),
    [
        (0, 1, "random", "positive integer"),
        (10, -1, "random", "non-negative"),
        (10, 1, "sobol", "sampling method"),
    ],
)
def test_bad_arguments(n: int, seed: int, method: str, message: str) -> None:
    with pytest.raises(ConfigError, match=message):
        sample(SPEC, n, seed, method=method)  # type: ignore[arg-type]
    with pytest.raises(ConfigError, match="no inputs"):
        sample(ToleranceSpec(()), 10, 1)
