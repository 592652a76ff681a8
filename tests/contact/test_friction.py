"""Joint friction laws: ramps, odd symmetry, limits, ADAMS continuity, registry."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from jointplay.contact.friction import (
    FRICTION_LAWS,
    AdamsFriction,
    AmbrosioFriction,
    FrictionLaw,
    NoFriction,
    get_friction,
)
from jointplay.errors import ConfigError

AMBROSIO = AmbrosioFriction(mu=0.1)
ADAMS = AdamsFriction(mu_static=0.3, mu_dynamic=0.2, v_static=1e-3, v_dynamic=1e-2)
EXAMPLES: dict[str, FrictionLaw] = {"none": NoFriction(), "ambrosio": AMBROSIO, "adams": ADAMS}

speeds = st.floats(min_value=-10.0, max_value=10.0, allow_nan=False)
loads = st.floats(min_value=0.0, max_value=1e5, allow_nan=False)


def test_examples_cover_the_registry() -> None:
    assert set(EXAMPLES) == set(FRICTION_LAWS)
    ids = [cls.law_id for cls in FRICTION_LAWS.values()]
    assert len(set(ids)) == len(ids)


def test_ambrosio_defaults_and_ramp() -> None:
    """c_d = 0 up to v0 = 1e-4, linear to 1 at v1 = 1e-3 m/s, then 1 (docs/contact-laws.md §4)."""
    assert (AMBROSIO.v0, AMBROSIO.v1) == (1e-4, 1e-3)
    v = np.array([0.0, 5e-5, 1e-4, 3.25e-4, 5.5e-4, 1e-3, 0.5])
    np.testing.assert_allclose(AMBROSIO.correction(v), [0, 0, 0, 0.25, 0.5, 1, 1], atol=1e-15)
    np.testing.assert_allclose(
        AMBROSIO.force(v, 100.0), 0.1 * 100.0 * np.array([0, 0, 0, 0.25, 0.5, 1, 1]), atol=1e-13
    )


def test_ambrosio_limit_is_coulomb() -> None:
    assert float(AMBROSIO.force(3.0, 250.0)) == pytest.approx(25.0, rel=1e-15)
    assert float(AMBROSIO.force(-3.0, 250.0)) == pytest.approx(-25.0, rel=1e-15)


def test_adams_values_at_the_transitions() -> None:
    """μ passes 0 at 0, ±μ_s at ±v_s, ±μ_d from ±v_d on (docs/contact-laws.md §1.4)."""
    v = np.array([0.0, 1e-3, -1e-3, 1e-2, -1e-2, 5.0, -5.0])
    np.testing.assert_allclose(
        ADAMS.coefficient(v), [0.0, 0.3, -0.3, 0.2, -0.2, 0.2, -0.2], rtol=1e-14, atol=1e-16
    )
    # Midway through the stiction STEP: u = 3/4 → −μ_s + 2 μ_s (9/16)(3/2) = 0.20625.
    assert float(ADAMS.coefficient(5e-4)) == pytest.approx(0.20625, rel=1e-14)
    # Midway through the transition STEP: (μ_s + μ_d)/2.
    assert float(ADAMS.coefficient(5.5e-3)) == pytest.approx(0.25, rel=1e-14)


@pytest.mark.parametrize("edge", [1e-3, 1e-2])
@pytest.mark.parametrize("side", [1.0, -1.0])
def test_adams_is_continuous_at_the_transition_velocities(edge: float, side: float) -> None:
    """Left and right limits at ±v_s and ±v_d agree (STEP is C¹, so the gap is O(ε²))."""
    eps = 1e-9 * edge
    left = float(ADAMS.coefficient(side * (edge - eps)))
    right = float(ADAMS.coefficient(side * (edge + eps)))
    assert left == pytest.approx(right, abs=1e-12)


@pytest.mark.parametrize("name", sorted(FRICTION_LAWS))
@given(v=speeds, f_n=loads)
def test_friction_is_odd_and_bounded(name: str, v: float, f_n: float) -> None:
    law = EXAMPLES[name]
    forward = float(law.force(v, f_n))
    backward = float(law.force(-v, f_n))
    assert forward == pytest.approx(-backward, rel=1e-12, abs=1e-12 * f_n)
    assert forward * v >= 0.0  # the journal's friction −F_T t opposes its slip
    assert abs(forward) <= 0.3 * f_n * (1 + 1e-12)


@pytest.mark.parametrize("name", sorted(FRICTION_LAWS))
def test_zero_slip_gives_zero_friction(name: str) -> None:
    assert float(EXAMPLES[name].force(0.0, 1e4)) == 0.0


def test_none_is_zero_and_has_no_parameters() -> None:
    law = get_friction("none")
    np.testing.assert_array_equal(law.force([-1.0, 0.0, 2.0], 10.0), [0.0, 0.0, 0.0])
    assert law.params().shape == (0,)


def test_registry_and_validation() -> None:
    assert get_friction("Ambrosio", mu=0.1) == AMBROSIO
    assert get_friction("adams", mu_s=0.3, mu_d=0.2, v_s=1e-3, v_d=1e-2) == ADAMS
    assert get_friction(AMBROSIO, mu=0.05) == AmbrosioFriction(mu=0.05)
    with pytest.raises(ConfigError, match="known names: adams, ambrosio, none"):
        get_friction("coulomb", mu=0.1)
    with pytest.raises(ConfigError, match=r"AmbrosioFriction.v1 .* must be > v0"):
        AmbrosioFriction(mu=0.1, v0=1e-3, v1=1e-4)
    with pytest.raises(ConfigError, match=r"AmbrosioFriction.mu"):
        AmbrosioFriction(mu=-0.1)
    with pytest.raises(ConfigError, match=r"AdamsFriction.v_dynamic"):
        AdamsFriction(mu_static=0.3, mu_dynamic=0.2, v_static=1e-2, v_dynamic=1e-3)
    with pytest.raises(ConfigError, match="missing parameter"):
        get_friction("ambrosio")
