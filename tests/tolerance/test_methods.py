"""Worst case, RSS and Monte Carlo against a linear stack with known answers, and the four-bar."""

from __future__ import annotations

import math

import numpy as np
import pytest

from jointplay.errors import ConfigError
from jointplay.model.mechanism import Mechanism
from jointplay.tolerance.execution import Backend
from jointplay.tolerance.methods import (
    TOLERANCE_METHODS,
    MonteCarlo,
    Rss,
    SpecLimits,
    WorstCase,
    get_method,
    regression_contributions,
    sobol_first_order,
)
from jointplay.tolerance.responses import FourBarKinematics, LinearModel
from jointplay.tolerance.spec import (
    LinkTolerance,
    QuantityTolerance,
    Tolerance,
    ToleranceSpec,
)

SERIAL = Backend("serial")

# y = 2 x1 − 3 x2 + 0.5 x3 + x4: a linear stack with known worst case and RSS.
COEFFICIENTS = (2.0, -3.0, 0.5, 1.0)
HALF_WIDTHS = (0.10, 0.20, 0.40, 0.05)
NOMINALS = (10.0, 5.0, 1.0, -2.0)


def _stack(distribution: str = "normal", k: int = 4) -> tuple[LinearModel, ToleranceSpec]:
    names = tuple(f"x{i + 1}" for i in range(k))
    inputs = tuple(
        QuantityTolerance(
            name,
            NOMINALS[i % 4],
            Tolerance(
                (NOMINALS[i % 4] - HALF_WIDTHS[i % 4], NOMINALS[i % 4] + HALF_WIDTHS[i % 4]),
                distribution,  # type: ignore[arg-type]
            ),
        )
        for i, name in enumerate(names)
    )
    model = LinearModel(names, (tuple(COEFFICIENTS[i % 4] for i in range(k)),), (7.0,))
    return model, ToleranceSpec(inputs)


def _expected(k: int = 4) -> tuple[float, float, float]:
    a = np.array([COEFFICIENTS[i % 4] for i in range(k)])
    h = np.array([HALF_WIDTHS[i % 4] for i in range(k)])
    nominal = 7.0 + float(a @ np.array([NOMINALS[i % 4] for i in range(k)]))
    return nominal, float(np.abs(a) @ h), float(np.sqrt(np.sum((a * h) ** 2)))


@pytest.mark.parametrize("corners", ["all", "sensitivity"])
def test_worst_case_of_a_linear_stack_is_the_arithmetic_sum(corners: str) -> None:
    model, spec = _stack()
    result = WorstCase(corners=corners).run(model, spec, backend=SERIAL)  # type: ignore[arg-type]
    nominal, arithmetic, _ = _expected()
    y = result.summaries["y"]
    # Exact up to rounding of a few sums of doubles.
    assert y.nominal == pytest.approx(nominal, rel=1e-14)
    assert y.maximum - y.nominal == pytest.approx(arithmetic, rel=1e-12)
    assert y.nominal - y.minimum == pytest.approx(arithmetic, rel=1e-12)
    assert y.half_range == pytest.approx(arithmetic, rel=1e-12)
    # The high corner has every input at the limit that raises y.
    assert y.high_corner == pytest.approx({"x1": 10.1, "x2": 4.8, "x3": 1.4, "x4": -1.95})
    assert y.low_corner == pytest.approx({"x1": 9.9, "x2": 5.2, "x3": 0.6, "x4": -2.05})
    np.testing.assert_allclose(list(y.sensitivities.values()), COEFFICIENTS, rtol=1e-9)
    shares = np.abs(COEFFICIENTS) * HALF_WIDTHS / arithmetic
    np.testing.assert_allclose(list(y.contributions.values()), shares, rtol=1e-9)
    assert result.settings["corners"] == corners
    assert result.settings["evaluated_corners"] == (16 if corners == "all" else 2)


def test_worst_case_switches_to_sensitivity_corners_beyond_ten_inputs() -> None:
    model, spec = _stack(k=12)
    result = WorstCase().run(model, spec, backend=SERIAL)
    _, arithmetic, _ = _expected(k=12)
    assert result.settings["corners"] == "sensitivity"
    assert result.summaries["y"].half_range == pytest.approx(arithmetic, rel=1e-12)


@pytest.mark.parametrize("sensitivity", ["finite-difference", "analytic"])
@pytest.mark.parametrize("distribution", ["uniform", "normal", "triangular"])
def test_rss_of_a_linear_stack_is_the_root_sum_of_squares(
    sensitivity: str, distribution: str
) -> None:
    model, spec = _stack(distribution)
    result = Rss(sensitivity=sensitivity).run(model, spec, backend=SERIAL)  # type: ignore[arg-type]
    _, _, root_sum = _expected()
    y = result.summaries["y"]
    sigma = spec.std
    assert y.half_range == pytest.approx(root_sum, rel=1e-12)
    assert y.std == pytest.approx(
        math.sqrt(np.sum((np.array(COEFFICIENTS) * sigma) ** 2)), rel=1e-12
    )
    if distribution == "normal":
        assert y.std == pytest.approx(root_sum / 3, rel=1e-12)  # ±3σ at the limits
    shares = (np.array(COEFFICIENTS) * sigma) ** 2 / y.std**2
    np.testing.assert_allclose(list(y.contributions.values()), shares, rtol=1e-9)
    assert y.note is None


def test_analytic_sensitivities_need_a_jacobian(paper_fourbar: Mechanism) -> None:
    spec = ToleranceSpec.from_mechanism(paper_fourbar).only("length")
    model = FourBarKinematics.from_mechanism(paper_fourbar, spec.names)
    with pytest.raises(ConfigError, match="no analytic Jacobian"):
        Rss(sensitivity="analytic").run(model, spec, backend=SERIAL)


def test_monte_carlo_std_converges_to_rss_at_the_rate_one_over_root_n() -> None:
    model, spec = _stack("uniform")
    sigma = Rss().run(model, spec, backend=SERIAL).summaries["y"].std
    assert sigma is not None
    sizes = [100, 1000, 10_000, 100_000]
    errors = []
    for n in sizes:
        stds = [
            MonteCarlo(n, seed).run(model, spec, backend=SERIAL).summaries["y"].std
            for seed in range(8)
        ]
        errors.append(float(np.sqrt(np.mean((np.array(stds) - sigma) ** 2))) / sigma)
    slope = np.polyfit(np.log(sizes), np.log(errors), 1)[0]
    # The sample standard deviation's error falls as N^(-1/2); ±0.15 allows for the spread
    # of an 8-seed estimate of the error at each size.
    assert slope == pytest.approx(-0.5, abs=0.15)
    assert errors[-1] < 0.005


def test_monte_carlo_contributions_and_capability() -> None:
    model, spec = _stack("normal")
    limits = {"y": SpecLimits(lower=-3.6, upper=-2.6)}
    result = MonteCarlo(20_000, 3).run(model, spec, limits=limits, backend=SERIAL)
    y = result.summaries["y"]
    expected = (np.array(COEFFICIENTS) * spec.std) ** 2
    expected /= expected.sum()
    # SRC² of an exactly linear response: only the sample correlations between inputs
    # (≈ 1/√n) disturb them.
    np.testing.assert_allclose(list(y.contributions.values()), expected, atol=0.01)
    assert y.r_squared == pytest.approx(1.0, abs=1e-12)
    assert y.contribution_basis == "src"
    sobol = y.sobol_first_order
    assert sobol is not None
    # The binning estimator has a bias and noise of a few 0.01 at n = 20 000.
    np.testing.assert_allclose(list(sobol.values()), expected, atol=0.03)
    assert y.most_influential == "x2"
    mean, std = y.mean, y.std
    assert mean is not None and std is not None
    assert y.cp == pytest.approx(1.0 / (6 * std))
    assert y.cpk == pytest.approx(min(-2.6 - mean, mean + 3.6) / (3 * std))
    assert y.out_of_spec_percent is not None
    counted = 100 * np.mean((result.run.values[:, 0] < -3.6) | (result.run.values[:, 0] > -2.6))
    assert y.out_of_spec_percent == pytest.approx(counted)
    assert set(y.percentiles or {}) == {"p0.135", "p2.5", "p50", "p97.5", "p99.865"}


def test_regression_and_sobol_helpers_handle_degenerate_data() -> None:
    x = np.zeros((50, 2))
    y = np.ones(50)
    assert regression_contributions(x, y, ["a", "b"]) == ({"a": 0.0, "b": 0.0}, None)
    assert sobol_first_order(x, y, ["a", "b"]) == {"a": 0.0, "b": 0.0}


def test_spec_limits_validation() -> None:
    with pytest.raises(ConfigError, match="lower limit, an upper limit or both"):
        SpecLimits()
    with pytest.raises(ConfigError, match="below upper"):
        SpecLimits(2.0, 1.0)
    one_sided = SpecLimits(upper=1.0)
    assert one_sided.capability(0.7, 0.1) == (None, pytest.approx(1.0))
    assert one_sided.normal_fraction_outside(1.0, 0.5) == pytest.approx(0.5)


def test_unknown_response_in_limits_is_refused() -> None:
    model, spec = _stack()
    with pytest.raises(ConfigError, match="unknown response"):
        MonteCarlo(10, 1).run(model, spec, limits={"z": SpecLimits(upper=1.0)}, backend=SERIAL)


def test_fourbar_monte_carlo_agrees_with_rss(paper_fourbar: Mechanism) -> None:
    spec = ToleranceSpec.from_mechanism(paper_fourbar).only("length")
    model = FourBarKinematics.from_mechanism(paper_fourbar, spec.names)
    mc = MonteCarlo(4000, 1).run(model, spec, backend=SERIAL)
    linear = Rss().run(model, spec, backend=SERIAL)
    for name in ("rocker_swing", "omega4_peak", "alpha4_peak", "transmission_angle_min"):
        # 4000 samples estimate σ to ≈ 1.1 % (1σ); the responses are nearly linear over ±1 mm.
        assert mc.summaries[name].std == pytest.approx(linear.summaries[name].std, rel=0.05)
        assert mc.summaries[name].most_influential == linear.summaries[name].most_influential
    # The paper's sensitivity claim: crank and ground lengths drive the rocker's acceleration.
    assert linear.summaries["alpha4_peak"].most_influential == "length_crank"
    # Path deviation is 0 at the nominal point, a kink: RSS says it does not apply, and Monte
    # Carlo's linear regression explains nothing, so its shares come from Sobol indices.
    assert linear.summaries["path_deviation_mid"].note is not None
    deviation = mc.summaries["path_deviation_mid"]
    assert deviation.r_squared is not None and deviation.r_squared < 0.1
    assert deviation.contribution_basis == "sobol"
    assert sum(deviation.contributions.values()) == pytest.approx(1.0)


def test_fourbar_worst_case_reports_the_corner(paper_fourbar: Mechanism) -> None:
    spec = ToleranceSpec.from_mechanism(paper_fourbar).only("length")
    model = FourBarKinematics.from_mechanism(paper_fourbar, spec.names)
    result = WorstCase().run(model, spec, backend=SERIAL)
    omega = result.summaries["omega4_peak"]
    assert omega.high_corner is not None and omega.maximum is not None
    assert omega.high_corner["length_crank"] == pytest.approx(0.1088)  # a longer crank
    # Re-evaluating the reported corner reproduces the reported extreme.
    corner = np.array([[omega.high_corner[n] for n in spec.names]])
    again = model.evaluate(corner).values[0, model.response_names.index("omega4_peak")]
    assert again == omega.maximum
    assert len(result.x) == 1 + 2**4
    assert result.roles[0] == "nominal"


def test_failed_samples_are_counted_and_reported_with_their_inputs(
    paper_fourbar: Mechanism,
) -> None:
    # A coupler of 270.5 ± 180 mm: below 116.9 mm (b + c < d + a) or above 441.9 mm
    # (|b − c| > d − a) the crank cannot turn fully — about 10 % of the samples.
    from jointplay.kinematics import fourbar
    from jointplay.model.templates import FourBarGeometry

    coupler = LinkTolerance.from_deviations("coupler", 0.2705, -0.18, 0.18, distribution="uniform")
    spec = ToleranceSpec((coupler,))
    model = FourBarKinematics.from_mechanism(paper_fourbar, spec.names)
    result = MonteCarlo(400, 2).run(model, spec, backend=SERIAL)
    failed = result.run.status == 1
    assert 10 < failed.sum() < 80
    assert len(result.failures) == int(failed.sum())
    for failure, b in zip(result.failures, result.x[failed, 0], strict=True):
        assert failure.inputs["length_coupler"] == b
        assert failure.role == "sample"
        assert failure.error.startswith("AssemblyError:")
        assert b < 0.1169 or b > 0.4419
        assert fourbar.infeasible_crank_ranges(FourBarGeometry(0.108, b, 0.2705, 0.2794))
    assert result.summaries["omega4_peak"].n_ok == int((~failed).sum())
    assert np.isnan(result.run.values[failed]).all()
    assert np.isfinite(result.run.values[~failed]).all()


def test_methods_are_registered_objects_taken_by_name_or_instance() -> None:
    assert set(TOLERANCE_METHODS) == {"worst-case", "rss", "monte-carlo"}
    assert get_method("monte-carlo", samples=200, seed=3) == MonteCarlo(samples=200, seed=3)
    assert get_method("Worst_Case") == WorstCase()
    chosen = Rss(fd_step=0.25)
    assert get_method(chosen) is chosen
    assert get_method(chosen, fd_step=0.1) == Rss(fd_step=0.1)
    for name, kind in TOLERANCE_METHODS.items():
        assert kind.name == name


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda: get_method("taguchi"), "unknown tolerance method 'taguchi'"),
        (lambda: get_method("rss", samples=10), r"Rss: unknown option\(s\) \['samples'\]"),
        (lambda: MonteCarlo(samples=0), "positive integer"),
        (lambda: Rss(fd_step=2.0), "finite-difference step"),
        (lambda: WorstCase(corners="some"), "corners must be"),  # type: ignore[arg-type]
    ],
)
def test_method_options_are_validated_at_construction(call, message: str) -> None:
    with pytest.raises(ConfigError, match=message):
        call()


# --- normal inputs truncated at their limits (the default of the Monte Carlo) --------------------


def _phi(z: float) -> float:
    """Standard normal density."""
    return math.exp(-0.5 * z * z) / math.sqrt(2.0 * math.pi)


def _cdf(z: float) -> float:
    """Standard normal distribution function."""
    return 0.5 * (1.0 + math.erf(z / math.sqrt(2.0)))


def _truncated_moments(mode: float, sigma: float, low: float, high: float) -> tuple[float, float]:
    """Mean and standard deviation of a normal(mode, sigma) truncated to [low, high], from
    the closed form (Johnson, Kotz & Balakrishnan, *Continuous Univariate Distributions*
    vol. 1, 2nd ed., §10.1, eqs. 13.134–13.135), independent of scipy."""
    a, b = (low - mode) / sigma, (high - mode) / sigma
    z = _cdf(b) - _cdf(a)
    mean = mode + sigma * (_phi(a) - _phi(b)) / z
    variance = sigma**2 * (1.0 + (a * _phi(a) - b * _phi(b)) / z - ((_phi(a) - _phi(b)) / z) ** 2)
    return mean, math.sqrt(variance)


def _one_input(shift: float = 0.0) -> tuple[LinearModel, ToleranceSpec]:
    spec = ToleranceSpec(
        (QuantityTolerance("x", 10.0, Tolerance((9.9, 10.1), "normal", shift=shift)),)
    )
    return LinearModel(("x",), ((1.0,),)), spec


@pytest.mark.parametrize("shift", [0.0, 0.04])
def test_monte_carlo_truncates_normal_inputs_at_their_limits(shift: float) -> None:
    """No sample outside the limits, and the samples' mean and σ are those of the truncated
    normal (closed form), not of the untruncated one."""
    model, spec = _one_input(shift)
    n = 20_000
    result = MonteCarlo(samples=n, seed=3).run(model, spec, backend=SERIAL)
    x = result.x[:, 0]
    assert result.settings["truncated_at_limits"] is True
    assert x.min() >= 9.9 and x.max() <= 10.1
    mean, std = _truncated_moments(10.0 + shift, 0.1 / 3.0, 9.9, 10.1)
    # Sampling error: 4 standard errors of the mean and of the standard deviation.
    assert x.mean() == pytest.approx(mean, abs=4 * std / math.sqrt(n))
    assert x.std(ddof=1) == pytest.approx(std, abs=4 * std / math.sqrt(2 * n))
    if shift == 0.0:  # ±3σ truncation narrows σ by the factor 0.9866 the docs quote
        assert std / (0.1 / 3.0) == pytest.approx(0.9866, abs=5e-5)
        assert x.std(ddof=1) < 0.1 / 3.0


def test_monte_carlo_without_truncation_keeps_the_tails() -> None:
    """truncate=False draws the plain normal: about 0.27 % of the samples beyond ±3σ."""
    model, spec = _one_input()
    n = 20_000
    result = MonteCarlo(samples=n, seed=3, truncate=False).run(model, spec, backend=SERIAL)
    x = result.x[:, 0]
    outside = int(np.sum((x < 9.9) | (x > 10.1)))
    expected = n * 2.0 * (1.0 - _cdf(3.0))  # 54
    assert result.settings["truncated_at_limits"] is False
    assert abs(outside - expected) < 4 * math.sqrt(expected)
    assert x.std(ddof=1) == pytest.approx(0.1 / 3.0, rel=4 / math.sqrt(2 * n))


def test_truncation_keeps_uniform_inputs_and_refuses_a_mean_outside_the_limits() -> None:
    from jointplay.tolerance.methods import truncated_at_limits

    uniform = ToleranceSpec((QuantityTolerance("u", 1.0, Tolerance((0.9, 1.1), "uniform")),))
    assert truncated_at_limits(uniform) == uniform
    _, shifted = _one_input(shift=0.2)  # mean 10.2, limits 9.9–10.1
    with pytest.raises(ConfigError, match=r"process mean 10\.2 lies outside the limits"):
        truncated_at_limits(shifted)
    with pytest.raises(ConfigError, match="truncate must be True or False"):
        MonteCarlo(truncate="yes")  # type: ignore[arg-type]
