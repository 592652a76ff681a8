"""Per-revolution statistics and the periodicity verdict of a Poincaré section."""

from __future__ import annotations

import numpy as np
import pytest

from jointplay.dynamics.cycles import PERIODICITY_THRESHOLD, periodicity, revolution_statistics


def test_statistics_across_revolutions() -> None:
    stats = revolution_statistics({"F_A": [10.0, 12.0, 14.0]})
    assert stats["F_A"] == pytest.approx(
        {
            "mean": 12.0,
            "min": 10.0,
            "max": 14.0,
            "std": np.std([10, 12, 14]),
            "revolution_of_max": 2,
        }
    )


def test_a_repeating_section_is_periodic_with_its_period() -> None:
    fixed = np.tile([[0.2, -0.5, 0.01]], (6, 1))
    assert periodicity(fixed).period == 1
    assert periodicity(fixed).verdict == "periodic (period 1)"
    two = np.array([[0.1, 0.2], [0.6, -0.3]] * 4)
    result = periodicity(two)
    assert result.period == 2
    assert np.allclose(result.successive_distance, 0.5)


def test_a_wandering_section_is_not_periodic() -> None:
    rng = np.random.default_rng(3)
    result = periodicity(rng.uniform(-1, 1, (10, 4)))
    assert result.period is None
    assert result.verdict == "not periodic"


def test_below_threshold_noise_is_periodic_above_is_not() -> None:
    base = np.tile([[0.3, 0.3]], (6, 1))
    small = base + 0.4 * PERIODICITY_THRESHOLD * np.array([[1, -1], [-1, 1]] * 3)
    assert periodicity(small).period == 1  # differences of 0.8 threshold
    large = base + 0.6 * PERIODICITY_THRESHOLD * np.arange(6)[:, None]
    assert periodicity(large).period is None


def test_too_few_revolutions_are_undetermined() -> None:
    assert periodicity(np.zeros((2, 3))).verdict == "undetermined"


def test_a_start_up_transient_is_told_from_rattling() -> None:
    """After a short --settle the section still moves; that is not rattling."""
    from jointplay.dynamics import diagnostics as dg

    rng = np.random.default_rng(1)
    settling = np.vstack([[0.5], [0.2], *[[0.01]] * 6])  # periodic from revolution 3 on
    converging = np.array([[0.5 * 0.6**k] for k in range(8)])  # steps shrink, never equal
    rattling = rng.uniform(-1.0, 1.0, (8, 1))
    found = {}
    for name, points in {
        "settling": settling,
        "converging": converging,
        "rattle": rattling,
    }.items():
        section = periodicity(points)
        assert section.verdict == "not periodic", name
        found[name] = dg.check_periodic(
            section.verdict, section.period, len(points),
            settles_after=section.settles_after(), converging=section.converging,
        )  # fmt: skip
    assert periodicity(settling).settles_after() == 2
    assert "repeats from revolution 3 on: a start-up transient" in found["settling"].message
    assert "raise settle by 2" in found["settling"].message
    assert periodicity(converging).settles_after() is None and periodicity(converging).converging
    assert "a start-up transient still settling" in found["converging"].message
    assert not periodicity(rattling).converging and periodicity(rattling).settles_after() is None
    assert "the pins rattle differently every revolution" in found["rattle"].message
