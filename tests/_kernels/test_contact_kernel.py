"""The compiled contact kernels equal the readable reference laws.

Tolerance: rtol 1e-12. Kernel and reference evaluate the same expressions in the same order,
but NumPy may compute ``δ**n`` with its own vectorised (SIMD) power routine while Numba calls
the C library's ``pow``; the two may differ by a few ulp, which the product and sum of a few
terms can amplify to ~1e-15 relative. 1e-12 leaves room for that and nothing else.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from jointplay._kernels import contact as kc
from jointplay._kernels import ids
from jointplay.contact.friction import (
    FRICTION_LAWS,
    AdamsFriction,
    AmbrosioFriction,
    FrictionLaw,
    NoFriction,
)
from jointplay.contact.laws import (
    CONTACT_LAWS,
    ContactLaw,
    HertzLaw,
    HuntCrossleyTypeLaw,
    ImpactLaw,
    KelvinVoigtLaw,
    RestitutionLaw,
    step3,
)

RTOL = 1e-12
N_SAMPLES = 3000


def normal_examples(name: str) -> list[ContactLaw]:
    """A few parameter sets per law, damped and undamped, exponents 1 to 2.2."""
    cls = CONTACT_LAWS[name]
    if cls is ImpactLaw:
        return [
            ImpactLaw(stiffness=1e10, exponent=1.5, c_max=1e3, d_max=1e-5),
            ImpactLaw(stiffness=3.2e8, exponent=2.2, c_max=1e4, d_max=1e-4),
            ImpactLaw(stiffness=1e9, exponent=1.0, c_max=0.0, d_max=1e-5),
        ]
    if cls is HertzLaw:
        return [HertzLaw(stiffness=1e10), HertzLaw(stiffness=5e7, exponent=1.1)]
    if cls is KelvinVoigtLaw:
        return [KelvinVoigtLaw(stiffness=1e8, damping=632.0), KelvinVoigtLaw(1e6, 0.0)]
    if cls is RestitutionLaw:
        return [
            RestitutionLaw(penalty=1e8, restitution=0.3),
            RestitutionLaw(penalty=1e10, restitution=0.9, exponent=1.5, v_floor=1e-3),
        ]
    assert issubclass(cls, HuntCrossleyTypeLaw)
    return [
        cls(stiffness=1e10, restitution=0.5),
        cls(stiffness=6e8, restitution=0.95, exponent=1.0, v_floor=1e-3),
        cls(stiffness=1e11, restitution=1.0),
    ]


def random_inputs(seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Penetrations on a log scale (and ≤ 0), rates of both signs, v0 known and unknown."""
    rng = np.random.default_rng(seed)
    delta = 10.0 ** rng.uniform(-12.0, -3.0, N_SAMPLES)
    delta[: N_SAMPLES // 10] *= -1.0
    delta[-5:] = 0.0
    delta_dot = rng.choice([-1.0, 1.0], N_SAMPLES) * 10.0 ** rng.uniform(-7.0, 1.0, N_SAMPLES)
    v0 = rng.choice([-1.0, 0.0, 1e-6, 1e-3, 0.1, 3.0], N_SAMPLES)
    return delta, delta_dot, v0


def assert_kernel_matches(kernel_values: np.ndarray, reference: np.ndarray) -> None:
    np.testing.assert_allclose(kernel_values, reference, rtol=RTOL, atol=0.0)
    assert np.array_equal(kernel_values == 0.0, reference == 0.0)


@pytest.mark.parametrize("name", sorted(CONTACT_LAWS))
def test_normal_force_kernel_equals_reference(name: str) -> None:
    delta, delta_dot, v0 = random_inputs(seed=len(name))
    for law in normal_examples(name):
        params = law.params()
        kernel = np.array(
            [
                kc.normal_force(law.law_id, params, 0, d, r, v)
                for d, r, v in zip(delta, delta_dot, v0, strict=True)
            ]
        )
        assert_kernel_matches(kernel, law.force(delta, delta_dot, v0))


def test_normal_force_kernel_unknown_id_is_nan_not_an_exception() -> None:
    params = np.ones(4)
    assert math.isnan(kc.normal_force(99, params, 0, 1e-6, 0.1, 0.1))
    assert kc.normal_force(99, params, 0, -1e-6, 0.1, 0.1) == 0.0


def test_normal_force_kernel_tolerates_non_finite_inputs() -> None:
    law = ImpactLaw(stiffness=1e10, exponent=1.5, c_max=1e3, d_max=1e-5)
    assert kc.normal_force(law.law_id, law.params(), 0, math.nan, 0.1, 0.1) == 0.0
    assert math.isinf(kc.normal_force(law.law_id, law.params(), 0, math.inf, 0.1, 0.1))


def friction_examples(name: str) -> list[FrictionLaw]:
    cls = FRICTION_LAWS[name]
    if cls is NoFriction:
        return [NoFriction()]
    if cls is AmbrosioFriction:
        return [AmbrosioFriction(mu=0.1), AmbrosioFriction(mu=0.02, v0=0.0, v1=1e-2)]
    return [
        AdamsFriction(mu_static=0.3, mu_dynamic=0.2, v_static=1e-3, v_dynamic=1e-2),
        AdamsFriction(mu_static=0.1, mu_dynamic=0.15, v_static=0.1, v_dynamic=0.2),
    ]


@pytest.mark.parametrize("name", sorted(FRICTION_LAWS))
def test_friction_force_kernel_equals_reference(name: str) -> None:
    rng = np.random.default_rng(11)
    v_t = rng.choice([-1.0, 1.0], N_SAMPLES) * 10.0 ** rng.uniform(-6.0, 1.0, N_SAMPLES)
    v_t[:3] = 0.0
    f_n = 10.0 ** rng.uniform(-3.0, 5.0, N_SAMPLES)
    for law in friction_examples(name):
        params = law.params()
        kernel = np.array(
            [kc.friction_force(law.law_id, params, 0, v, f) for v, f in zip(v_t, f_n, strict=True)]
        )
        assert_kernel_matches(kernel, law.force(v_t, f_n))


def test_friction_kernel_unknown_id_is_nan() -> None:
    assert math.isnan(kc.friction_force(42, np.ones(4), 0, 1.0, 1.0))


def test_step3_kernel_documented_example_and_reference() -> None:
    values = [kc.step3(x, 3.0, 0.0, 4.0, 1.0) for x in (2.0, 3.0, 3.5, 4.0, 5.0)]
    assert values == [0.0, 0.0, 0.5, 1.0, 1.0]
    x = np.linspace(-1.0, 2.0, 301)
    kernel = np.array([kc.step3(value, 0.0, -0.3, 1.0, 0.2) for value in x])
    np.testing.assert_allclose(kernel, step3(x, 0.0, -0.3, 1.0, 0.2), rtol=RTOL, atol=0.0)


def test_step3_kernel_never_divides_by_zero() -> None:
    assert kc.step3(1.0, 1.0, 0.0, 1.0, 5.0) == 0.0
    assert kc.step3(1.5, 2.0, 0.0, 1.0, 5.0) == 0.0
    assert kc.step3(2.5, 2.0, 0.0, 1.0, 5.0) == 5.0


def test_layouts_match_the_parameter_arrays() -> None:
    sizes = {
        ids.LAW_IMPACT: ids.IMPACT_SIZE,
        ids.LAW_HERTZ: ids.HERTZ_SIZE,
        ids.LAW_KELVIN_VOIGT: ids.KV_SIZE,
    }
    for name in CONTACT_LAWS:
        for law in normal_examples(name):
            expected = sizes.get(law.law_id, ids.HC_SIZE)
            assert law.params().shape == (expected,)
            assert np.all(np.isfinite(law.params()))
            if ids.HC_FIRST <= law.law_id <= ids.HC_LAST:
                assert law.params()[ids.HC_CHI] == law.chi  # type: ignore[attr-defined]
    friction_sizes = {
        ids.FRICTION_NONE: ids.NONE_SIZE,
        ids.FRICTION_AMBROSIO: ids.AMBROSIO_SIZE,
        ids.FRICTION_ADAMS: ids.ADAMS_SIZE,
    }
    for name in FRICTION_LAWS:
        for friction in friction_examples(name):
            assert friction.params().shape == (friction_sizes[friction.law_id],)
