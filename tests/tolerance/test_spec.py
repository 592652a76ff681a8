"""Tolerance specifications: the paper's stack, distributions and their validation."""

from __future__ import annotations

import math

import numpy as np
import pytest

from jointplay.errors import ConfigError, StandardsError
from jointplay.model.mechanism import Mechanism
from jointplay.tolerance.spec import (
    JointTolerance,
    LinkTolerance,
    QuantityTolerance,
    Tolerance,
    ToleranceSpec,
)

MM, UM = 1e-3, 1e-6


def test_paper_preset_carries_class_c_and_h8_g7(paper_fourbar: Mechanism) -> None:
    spec = ToleranceSpec.from_mechanism(paper_fourbar)
    assert spec.names == (
        "length_crank",
        "length_coupler",
        "length_rocker",
        "length_ground",
        "clearance_O2",
        "clearance_A",
        "clearance_B",
        "clearance_O4",
    )
    half = (spec.upper - spec.lower) / 2
    # ISO 2768-1 c: ±0.8 mm for 30-120 mm (crank), ±1.2 mm for 120-400 mm; the paper's ±4.4 mm
    # stack is their sum.
    np.testing.assert_allclose(half[:4] / MM, [0.8, 1.2, 1.2, 1.2], rtol=1e-12)
    assert half[:4].sum() / MM == pytest.approx(4.4)
    # Ø10 H8/g7: radial clearance 2.5 ... 21 µm; nominal = mid-range.
    np.testing.assert_allclose(spec.lower[4:] / UM, 2.5, rtol=1e-9)
    np.testing.assert_allclose(spec.upper[4:] / UM, 21.0, rtol=1e-9)
    np.testing.assert_allclose(spec.nominal[4:] / UM, 11.75, rtol=1e-9)
    assert spec["clearance_A"].journal_radius == pytest.approx(5 * MM)  # type: ignore[union-attr]
    assert spec["clearance_A"].fit == "H8/g7"  # type: ignore[union-attr]
    assert spec["length_crank"].source == "ISO 2768-1 c"


@pytest.mark.parametrize(
    ("distribution", "std_over_h"),
    [("uniform", 1 / math.sqrt(3)), ("triangular", 1 / math.sqrt(6)), ("normal", 1 / 3)],
)
def test_distribution_moments(distribution: str, std_over_h: float) -> None:
    t = Tolerance((1.0, 3.0), distribution)  # type: ignore[arg-type]
    assert t.mean == pytest.approx(2.0)
    assert t.std == pytest.approx(std_over_h, rel=1e-12)
    assert t.ppf(0.5) == pytest.approx(2.0)
    u = np.linspace(0.001, 0.999, 999)
    values = t.ppf(u)
    assert np.all(np.diff(values) > 0), "the inverse CDF must increase"
    if distribution != "normal":
        assert values.min() >= 1.0 and values.max() <= 3.0


def test_process_shift_and_cpk_set_mean_and_sigma() -> None:
    shifted = Tolerance((-1.0, 1.0), "normal", shift=0.25, cpk=1.5)
    # Cpk = min(USL - mu, mu - LSL) / (3 sigma) = (1 - 0.25) / (3 sigma) = 1.5
    assert shifted.mean == pytest.approx(0.25)
    assert shifted.std == pytest.approx(0.75 / 4.5)
    assert Tolerance((-1.0, 1.0), "uniform", shift=0.1).ppf(0.0) == pytest.approx(-0.9)


def test_truncated_normal_moments_match_a_large_sample() -> None:
    # A clearance range near zero: the normal is truncated at 0 (physical bound).
    t = Tolerance((0.0, 2.0), "normal", shift=-0.9, bounds=(0.0, math.inf))
    values = t.ppf((np.arange(200_000) + 0.5) / 200_000)
    assert values.min() >= 0.0
    # Midpoint quadrature of the inverse CDF: accurate to ~1e-4 relative here.
    assert values.mean() == pytest.approx(t.mean, rel=1e-3)
    assert values.std() == pytest.approx(t.std, rel=1e-3)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"limits": (2.0, 1.0)}, "lower <= upper"),
        ({"limits": (0.0, 1.0), "distribution": "cauchy"}, "distribution must be one of"),
        ({"limits": (0.0, 1.0), "distribution": "uniform", "cpk": 1.33}, "cpk applies"),
        ({"limits": (0.0, 1.0), "cpk": 1.0, "shift": 0.6}, "shift"),
        ({"limits": (0.0, 1.0), "distribution": "uniform", "bounds": (0.2, 5.0)}, "bounds"),
    ],
)
def test_tolerance_validation_names_the_problem(kwargs: dict, message: str) -> None:
    with pytest.raises(ConfigError, match=message):
        Tolerance(**kwargs)


def test_interference_fits_are_refused() -> None:
    with pytest.raises(ConfigError, match="interference fit"):
        JointTolerance.from_fit("A", "H7/s6", 0.010)
    with pytest.raises(StandardsError):
        JointTolerance.from_fit("A", "H8/q7", 0.010)


def test_duplicate_inputs_are_refused() -> None:
    t = LinkTolerance.from_deviations("crank", 0.1, -1e-4, 1e-4)
    with pytest.raises(ConfigError, match="given twice"):
        ToleranceSpec((t, t))
    with pytest.raises(ConfigError, match="letters, digits"):
        QuantityTolerance("a-b", 0.0, Tolerance((0.0, 1.0)))


def test_with_distribution_and_only(paper_fourbar: Mechanism) -> None:
    spec = ToleranceSpec.from_mechanism(paper_fourbar).with_distribution("triangular")
    assert {t.tolerance.distribution for t in spec.inputs} == {"triangular"}
    assert spec.only("clearance").names == (
        "clearance_O2",
        "clearance_A",
        "clearance_B",
        "clearance_O4",
    )
    described = spec.describe()["length_crank"]
    assert described["limits"] == pytest.approx([0.1072, 0.1088])
    assert described["distribution"] == "triangular"


@pytest.mark.parametrize(
    ("alpha", "beta"),
    [
        (-3.0, 3.0),
        (-1.0, 2.0),
        (-np.inf, np.inf),
        (0.5, 4.0),
        (-6.0, -1.0),
        (-2.0, np.inf),
        (5.0, 9.0),
    ],
)
def test_truncated_normal_in_closed_form_equals_scipy_truncnorm(alpha: float, beta: float) -> None:
    from scipy.stats import truncnorm

    from jointplay.tolerance.spec import _truncated_normal_moments, _truncated_normal_ppf

    reference = truncnorm(alpha, beta, loc=2.0, scale=0.5)
    u = np.linspace(1e-6, 1.0 - 1e-6, 2001)
    lower, upper = 2.0 + 0.5 * alpha, 2.0 + 0.5 * beta
    assert _truncated_normal_ppf(u, 2.0, 0.5, lower, upper) == pytest.approx(
        reference.ppf(u), rel=1e-12, abs=1e-12
    )
    mean, std = _truncated_normal_moments(alpha, beta)
    assert 2.0 + 0.5 * mean == pytest.approx(reference.mean(), rel=1e-13)
    assert 0.5 * std == pytest.approx(reference.std(), rel=1e-12)
