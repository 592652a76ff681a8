"""Sampling as parts are made: hole and pin apart, the clearance their difference."""

from __future__ import annotations

import math

import numpy as np
import pytest

from jointplay.errors import ConfigError
from jointplay.tolerance.methods import truncated_at_limits
from jointplay.tolerance.parts import Process, fit_features, model_inputs
from jointplay.tolerance.sampling import sample
from jointplay.tolerance.spec import ToleranceSpec


def test_features_sit_in_their_iso286_zones() -> None:
    """H8/f7 at Ø10 (ISO 286-2): hole 10.000/10.022 mm, pin 9.972/9.987 mm."""
    hole, pin = fit_features("A", "H8/f7", 0.010, Process())
    assert (hole.name, pin.name) == ("hole_A", "pin_A")
    assert hole.tolerance.limits == pytest.approx((0.010, 0.010022), abs=1e-12)
    assert pin.tolerance.limits == pytest.approx((0.009972, 0.009987), abs=1e-12)
    assert hole.source == "ISO 286 Ø10 H8" and pin.source == "ISO 286 Ø10 f7"


def test_model_inputs_turn_each_pair_into_the_radial_clearance() -> None:
    names = ("length_crank", "hole_A", "pin_A", "hole_B", "pin_B")
    values = np.array([[0.1, 10.02e-3, 9.98e-3, 10.01e-3, 9.99e-3]])
    out_names, x = model_inputs(names, values)
    assert out_names == ("length_crank", "clearance_A", "clearance_B")
    assert x[0] == pytest.approx([0.1, 20e-6, 10e-6], abs=1e-15)


@pytest.mark.parametrize("distribution", ["normal", "uniform"])
def test_clearance_spread_is_the_root_sum_of_squares_of_the_features(distribution: str) -> None:
    """Independent features: var(c) = (var(hole) + var(pin))/4 exactly, each feature's
    variance from its (truncated) distribution; 200 000 samples: the sample std is within
    1 % (its standard error is 0.16 %)."""
    process = Process(distribution=distribution)  # type: ignore[arg-type]
    spec = truncated_at_limits(ToleranceSpec(fit_features("A", "H8/f7", 0.010, process)))
    _, x = model_inputs(spec.names, sample(spec, 200_000, 3).values)
    expected = math.sqrt(spec.std[0] ** 2 + spec.std[1] ** 2) / 2
    assert x[:, 0].std() == pytest.approx(expected, rel=0.01)
    assert x[:, 0].min() >= 6.5e-6 - 1e-12 and x[:, 0].max() <= 25e-6 + 1e-12  # the fit's band
    if distribution == "normal":  # 2.22 µm against the worst-case band's 3.08 µm at ±3σ
        assert expected * 1e6 == pytest.approx(2.22, abs=0.05)


def test_a_process_capability_narrows_a_feature() -> None:
    """Cpk 1.33 centred: σ = half-band / (3 × 1.33)."""
    hole, pin = fit_features("A", "H8/f7", 0.010, Process(cpk={"hole": 1.33}))
    assert hole.tolerance.sigma == pytest.approx(11e-6 / (3 * 1.33), rel=1e-12)
    assert pin.tolerance.sigma == pytest.approx(7.5e-6 / 3, rel=1e-12)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"sampling": "worst"}, "sampling must be one of parts, band"),
        ({"cpk": {"bore": 1.0}}, "unknown feature 'bore'"),
        ({"cpk": {"pin": 0.0}}, "Cpk of pin must be > 0"),
        ({"distribution": "uniform", "cpk": {"pin": 1.0}}, "a Cpk needs normal features"),
        ({"sampling": "band", "cpk": {"hole": 1.0}}, "needs sampling 'parts'"),
    ],
)
def test_bad_processes_are_refused(kwargs: dict, message: str) -> None:
    with pytest.raises(ConfigError, match=message):
        Process(**kwargs)
