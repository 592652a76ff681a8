"""The paired randomization test that judges a statistic over samples run at two settings
(:func:`jointplay.dynamics.irregular.paired_shifts`): exact on a case counted by hand, its
false-alarm rate at most its level on exchangeable pairs, and a bias beyond the interval
found."""

from __future__ import annotations

import math

import numpy as np
import pytest

from jointplay.dynamics.irregular import PairedShift, paired_shifts, pairs_to_judge


def test_a_constant_move_of_every_sample_is_counted_by_hand() -> None:
    """Ten samples, each moved by +1: swapping k of them moves the mean by (10 - 2k)/10. Of
    the 1 024 patterns, 2 move it by 1.0, 20 by 0.8, 90 by 0.6. At level 0.05 at most 51
    patterns may lie beyond the half-width: it is 0.6, and the observed 1.0 lies beyond.
    At level 0.001 (at most 1 beyond) the half-width is the largest move: not judged."""
    first = np.arange(10.0)
    mean, quantile = paired_shifts(first, first + 1.0, 0.05)
    assert mean.statistic == "mean" and mean.pairs == 10
    assert mean.shift == pytest.approx(1.0) and mean.half_width == pytest.approx(0.6)
    assert mean.largest == pytest.approx(1.0)
    assert mean.judged and not mean.within
    assert quantile.statistic == "p95"
    assert quantile.first == pytest.approx(np.quantile(first, 0.95))
    assert quantile.shift == pytest.approx(1.0)
    loose, _ = paired_shifts(first, first + 1.0, 0.001)
    assert loose.half_width == pytest.approx(1.0) and not loose.judged and loose.within


def test_equal_pairs_do_not_move() -> None:
    values = np.linspace(1.0, 2.0, 12)
    for s in paired_shifts(values, values.copy(), 0.05):
        assert s.shift == 0.0 and s.half_width == 0.0 and s.within and not s.judged


@pytest.mark.parametrize("level", [0.05, 0.01])
def test_exchangeable_pairs_move_beyond_the_interval_at_most_at_the_level(level: float) -> None:
    """Each sample's two values drawn from one distribution (an irregular motion's peak at
    two tolerances), 400 studies of 12 samples: the mean moves beyond its interval in at most
    the level's share (+3 binomial standard deviations; measured: the mean 0.043 at 0.05 on
    this seed, 0.053 on another; the 95th percentile conservative, 0.01)."""
    rng = np.random.default_rng(3)
    trials = 400
    beyond = np.zeros(2)
    for _ in range(trials):
        centre = rng.normal(100.0, 10.0, 12)
        first = centre + rng.normal(0.0, 5.0, 12)
        second = centre + rng.normal(0.0, 5.0, 12)
        beyond += [not s.within for s in paired_shifts(first, second, level)]
    allowed = level + 3.0 * math.sqrt(level * (1 - level) / trials)
    assert np.all(beyond / trials <= allowed), beyond / trials
    assert beyond[0] > 0  # the test does reject on chance: it is not vacuous


def test_a_bias_of_twice_the_draws_scatter_is_found() -> None:
    """16 pairs whose second value is biased by 2 draw standard deviations (sd of the change
    sqrt(2) x 5 = 7.1, bias 10): the mean moves beyond its interval at 0.05/18 (the study's
    Bonferroni level for 9 responses) in most of 100 studies (measured 91; 2.4 s of CPU)."""
    rng = np.random.default_rng(4)
    found = 0
    for _ in range(100):
        centre = rng.normal(100.0, 10.0, 16)
        first = centre + rng.normal(0.0, 5.0, 16)
        second = centre + 10.0 + rng.normal(0.0, 5.0, 16)
        mean, _ = paired_shifts(first, second, 0.05 / 18)
        found += not mean.within
    assert found >= 80


def test_pairs_to_judge_is_the_fewest_whose_largest_move_can_be_rare_enough() -> None:
    assert pairs_to_judge(0.05) == 6  # 2 / 2**6 = 0.031 <= 0.05 < 2 / 2**5
    assert pairs_to_judge(0.05 / 18) == 10
    first = np.arange(9.0)
    mean, _ = paired_shifts(first, first + 1.0, 0.05 / 18)  # 9 pairs: never beyond
    assert not mean.judged and mean.within


def test_bad_input_is_refused() -> None:
    with pytest.raises(ValueError, match="same length"):
        paired_shifts([1.0, 2.0], [1.0], 0.05)
    with pytest.raises(ValueError, match="finite"):
        paired_shifts([1.0, math.nan], [1.0, 2.0], 0.05)
    with pytest.raises(ValueError, match="level"):
        paired_shifts([1.0, 2.0], [1.0, 2.0], 1.5)


def test_the_record_is_json_ready() -> None:
    record = PairedShift("mean", 1.0, 1.5, 1.0, 0.01, 16, 2.0).as_dict()
    assert record == {
        "first": 1.0, "second": 1.5, "shift": 0.5, "half_width": 1.0, "within": True,
        "judged": True, "level": 0.01, "pairs": 16,
    }  # fmt: skip
