"""Calibration: parameters recovered from synthetic measurements with known noise, honest
intervals, identifiability warnings, and the paper's Table 7 explained."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest
from scipy import stats

from jointplay.errors import ConfigError
from jointplay.io.config import load_preset
from jointplay.study.calibration import (
    DynamicSettings,
    calibrate,
    explain_table7,
    synthetic_dataset,
    table7_dataset,
)

RPM = math.pi / 30.0
#: Noise of the synthetic rocker speeds, rad/s (about 1 % of the rocker's peak speed).
NOISE = 0.15


@pytest.fixture(scope="module")
def mechanism():
    return load_preset("paper-fourbar")


@pytest.fixture(scope="module")
def template():
    return table7_dataset("experiment_printed")


def test_recovers_crank_speed_and_phase_within_intervals(mechanism, template):
    truth = {"crank-speed": 228 * RPM, "phase": math.radians(-2.0)}
    data = synthetic_dataset(mechanism, template, truth, noise=NOISE)
    result = calibrate(mechanism, [data], ["crank-speed", "phase"])
    assert result.warnings == ()
    assert result.model == "nominal"
    for name, value in truth.items():
        estimate = result.estimate(name)
        assert estimate.ci95[0] <= value <= estimate.ci95[1], name
        assert estimate.ci95[0] <= estimate.value <= estimate.ci95[1]
    assert result.estimate("crank-speed").unit == "rad/s"
    assert result.estimate("phase").unit == "rad"
    # the fit removes the 14 % speed error of the 200 RPM start
    assert result.rms_before > 10.0
    assert result.rms_after < 2.0
    # s² estimates the noise variance (13 points, 11 degrees of freedom: loose bound)
    assert 0.3 * NOISE**2 < result.s2 < 3.0 * NOISE**2
    document = result.as_json()
    assert set(document) == {"parameters", "rms_before", "rms_after", "warnings"}
    assert set(document["parameters"]["crank-speed"]) == {"value", "stderr", "ci95", "unit"}


def test_interval_coverage_over_200_seeds(mechanism, template):
    """Over 200 noisy data sets the 95 % intervals contain the truth 180–198 times.

    For a correct 95 % interval the count is Binomial(200, 0.95): P(count < 180) ≈ 0.2 % and
    P(count > 198) ≈ 0.05 %, so the range fails a correct method well under 1 % of the time
    (and the seeds are fixed, so the test is deterministic).
    """
    assert stats.binom.cdf(179, 200, 0.95) < 0.005
    assert stats.binom.sf(198, 200, 0.95) < 0.001
    truth = {"crank-speed": 215 * RPM, "phase": math.radians(1.5)}
    exact = synthetic_dataset(mechanism, template, truth, noise=0.0)
    values = exact.values_si
    hits = {name: 0 for name in truth}
    for seed in range(200):
        rng = np.random.default_rng(seed)
        noisy = values + NOISE * rng.standard_normal(values.shape)
        data = replace(
            exact,
            measurements=replace(exact.measurements, speed=exact.from_si(noisy)),
        )
        result = calibrate(mechanism, [data], ["crank-speed", "phase"], curve_step_deg=90.0)
        for name, value in truth.items():
            low, high = result.estimate(name).ci95
            hits[name] += low <= value <= high
    for name, count in hits.items():
        assert 180 <= count <= 198, (name, count)


def test_lengths_that_trade_off_exactly_are_flagged(mechanism, template):
    """Angular speeds depend only on length ratios: scaling all four lengths changes nothing."""
    data = synthetic_dataset(mechanism, template, {"crank-speed": 220 * RPM}, noise=NOISE)
    fit = ["crank-length", "coupler-length", "rocker-length", "ground-length"]
    result = calibrate(mechanism, [data], fit)
    assert any("not identifiable" in w for w in result.warnings), result.warnings
    assert result.condition_number > 1e6


def test_too_few_points_are_flagged(mechanism, template):
    measurements = template.measurements
    few = replace(
        template,
        measurements=replace(
            measurements, crank_deg=measurements.crank_deg[:2], speed=measurements.speed[:2],
            model=None, printed_error=None,
        ),
    )  # fmt: skip
    result = calibrate(mechanism, [few], ["crank-speed", "phase"])
    assert any("degree of freedom" in w for w in result.warnings)


def test_several_files_at_different_speeds_are_fitted_jointly(mechanism, template):
    slow = replace(template, label="slow", crank_speed=150 * RPM)
    fast = replace(template, label="fast", crank_speed=300 * RPM)
    phase = math.radians(1.0)
    slow = synthetic_dataset(mechanism, slow, {"crank-speed": 160 * RPM, "phase": phase}, noise=0.1)
    fast = synthetic_dataset(mechanism, fast, {"crank-speed": 290 * RPM, "phase": phase}, noise=0.1)
    result = calibrate(mechanism, [slow, fast], ["crank-speed", "phase"])
    names = [p.name for p in result.parameters]
    assert names == ["crank-speed@slow", "crank-speed@fast", "phase"]
    for name, value in (("crank-speed@slow", 160 * RPM), ("crank-speed@fast", 290 * RPM)):
        low, high = result.estimate(name).ci95
        assert low <= value <= high, name
    assert set(result.points["dataset"]) == {"slow", "fast"}


def test_other_responses_with_their_units(mechanism, template):
    """The rocker's angular acceleration (rad/s²) fits the crank speed too (∝ ω²)."""
    accel = replace(template, quantity="alpha4", unit="rad/s^2", unit_factor=1.0)
    data = synthetic_dataset(mechanism, accel, {"crank-speed": 210 * RPM}, noise=1.0)
    result = calibrate(mechanism, [data], ["crank-speed"])
    low, high = result.estimate("crank-speed").ci95
    assert low <= 210 * RPM <= high
    assert result.points["unit"].iloc[0] == "rad/s^2"


def test_bad_parameter_and_loss_are_errors(mechanism, template):
    with pytest.raises(ConfigError, match="unknown parameter"):
        calibrate(mechanism, [template], ["speed"])
    with pytest.raises(ConfigError, match="unknown loss"):
        calibrate(mechanism, [template], ["crank-speed"], loss="l3")
    with pytest.raises(ConfigError, match="c_max"):
        calibrate(
            mechanism,
            [template],
            ["c_max"],
            settings=DynamicSettings(contact=replace(DynamicSettings().contact, law="hertz")),
        )


def test_robust_loss_resists_an_outlier(mechanism, template):
    data = synthetic_dataset(mechanism, template, {"crank-speed": 228 * RPM}, noise=0.05)
    values = data.values_si.copy()
    values[1] += 3.0  # one wild reading, 20 times the noise
    bad = replace(data, measurements=replace(data.measurements, speed=data.from_si(values)))
    plain = calibrate(mechanism, [bad], ["crank-speed"]).estimate("crank-speed").value
    robust = calibrate(mechanism, [bad], ["crank-speed"], loss="soft_l1").estimate("crank-speed")
    assert abs(robust.value - 228 * RPM) < abs(plain - 228 * RPM)


def test_table7_explained(mechanism):
    """Table 7 read as docs/paper-reading.md says: the nominal kinematics match the measurements
    best at ~228 RPM (the 1.143 factor of the comparison) and the paper's MBD column at
    ~234 RPM; neither fit reaches the printing resolution (shape errors remain), and link
    lengths within their tolerances hardly help."""
    explained = explain_table7(mechanism)
    columns = explained["columns"]
    experiment = columns["experiment_printed"]
    rpm = experiment["crank_rpm"]
    assert rpm["ci95"][0] < rpm["value"] < rpm["ci95"][1]
    assert 220 < rpm["value"] < 236
    assert experiment["rms_before"] == pytest.approx(17.02, abs=0.01)
    assert experiment["rms_after"] < experiment["rms_before"]
    mbd = columns["mbd_printed"]
    assert 226 < mbd["crank_rpm"]["value"] < 242
    for entry in columns.values():
        assert entry["residual_rms_deg_s"] > 10 * entry["rounding_sigma_deg_s"]
        assert entry["phase_deg"]["unit"] == "deg"
        # link lengths anywhere within their tolerances do not explain the rest (< 10 % less)
        assert entry["with_lengths"]["residual_rms_deg_s"] > 0.9 * entry["residual_rms_deg_s"]
    assert "experiment_printed" in explained["summary"]


def _stiffness_data(mechanism, template):
    accel = replace(template, quantity="alpha4", unit="rad/s^2")
    return synthetic_dataset(mechanism, accel, {"k": 3 * K0}, settings=DynamicSettings())


#: The paper's IMPACT stiffness (Table 3), N/m^1.5.
K0 = 1e4 * 1000**1.5


def test_contact_stiffness_recovered_on_the_clearance_model(mechanism, template):
    """A dynamic parameter on the steady cycle of the clearance model: the rocker's angular
    acceleration generated with k = 3 × the paper's IMPACT stiffness is matched again from a
    start near it (within 1 %: the data are noise-free, the step of the differences is 1 %)."""
    data = _stiffness_data(mechanism, template)
    result = calibrate(mechanism, [data], ["k"], initial={"k": 2.8 * K0}, max_nfev=15)
    assert result.model == "clearance"
    estimate = result.estimate("k")
    assert estimate.unit == "N/m^1.5"
    assert estimate.value == pytest.approx(3 * K0, rel=0.01)
    assert result.rms_after < 0.1


@pytest.mark.slow
def test_rough_clearance_response_is_flagged(mechanism, template):
    """From the paper's k the pointwise accelerations are a rough function of k (impact
    sequences change with it): the fit stops in a local minimum whose interval misses the
    truth, and says so. Measured: k = 0.92 k0 with a 95 % interval of 0.82-1.02 k0 (the data
    were made with 3 k0), RMS 33.0 -> 29.6, the 1 % and 3 % difference steps differing by
    112 %."""
    data = _stiffness_data(mechanism, template)
    result = calibrate(mechanism, [data], ["k"], max_nfev=15)
    estimate = result.estimate("k")
    assert estimate.ci95[1] < 3 * K0  # the interval is not reliable here ...
    rough = "not identifiable: the clearance model's response to k is rough here"
    assert any(w.startswith(rough) for w in result.warnings)  # ... and the result says so
    assert result.rms_after > 0.5 * result.rms_before  # no fit: far from the data's 3 k0


def test_a_parameter_without_effect_has_no_finite_error():
    """The linear algebra alone: a zero Jacobian column (no effect) and two equal columns
    (an exact trade-off) give infinite standard errors and an infinite condition number."""
    from jointplay.study.calibration import _uncertainty

    rng = np.random.default_rng(3)
    jac = rng.standard_normal((20, 3))
    residuals = rng.standard_normal(20)
    scales = np.ones(3)
    _, stderr, _, condition, dof, _ = _uncertainty(jac, residuals, scales)
    assert np.all(np.isfinite(stderr)) and condition < 10 and dof == 17
    no_effect = jac.copy()
    no_effect[:, 2] = 0.0
    _, stderr, _, condition, _, _ = _uncertainty(no_effect, residuals, scales)
    assert math.isinf(stderr[2]) and np.all(np.isfinite(stderr[:2]))
    assert math.isinf(condition)
    trade_off = jac.copy()
    trade_off[:, 1] = 2.0 * trade_off[:, 0]
    _, stderr, _, condition, _, weakest = _uncertainty(trade_off, residuals, scales)
    assert math.isinf(stderr[0]) and math.isinf(stderr[1]) and math.isfinite(stderr[2])
    assert condition > 1e12
    assert abs(weakest[2]) < 1e-6  # the weak direction involves the first two only


def test_mixed_responses_are_weighted_alike(mechanism, template):
    """Rocker speed (rad/s) and acceleration (rad/s²) fitted jointly: each data set is divided
    by the RMS of its measurements, so neither unit dominates."""
    speed = replace(template, label="speed")
    accel = replace(template, label="accel", quantity="alpha4", unit="rad/s^2")
    truth = {"crank-speed": 225 * RPM}
    speed = synthetic_dataset(mechanism, speed, truth, noise=0.0)
    accel = synthetic_dataset(mechanism, accel, truth, noise=0.0)
    result = calibrate(mechanism, [speed, accel], ["crank-speed"])
    names = [p.name for p in result.parameters]
    assert names == ["crank-speed@speed", "crank-speed@accel"]
    for name in names:
        assert result.estimate(name).value == pytest.approx(225 * RPM, rel=1e-6)
