"""Normal contact force laws: invariants over every registered law, IMPACT, the registry."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from jointplay._kernels import ids
from jointplay.contact.laws import (
    CONTACT_LAWS,
    DEFAULT_V_FLOOR,
    ContactLaw,
    FloresLaw,
    GonthierLaw,
    HerbertMcWhannellLaw,
    HertzLaw,
    HuGuoLaw,
    HuntCrossleyLaw,
    HuntCrossleyTypeLaw,
    ImpactLaw,
    KelvinVoigtLaw,
    LankaraniNikraveshLaw,
    LeeWangLaw,
    RestitutionLaw,
    ZhiyingQishaoLaw,
    get_law,
    layout,
    step3,
)
from jointplay.contact.restitution import chi_for_restitution, single_impact
from jointplay.errors import ConfigError

# A steel pin of 0.1 kg hitting at 0.5 m/s; K ≈ Hertz stiffness of a pin-in-hole joint.
MASS = 0.1  # kg
SPEED = 0.5  # m/s
K_HERTZ = 1e10  # N/m^1.5
K_LINEAR = 1e8  # N/m
D_KV = 2.0 * 0.1 * math.sqrt(MASS * K_LINEAR)  # N·s/m, damping ratio ζ = 0.1

#: One damped example per registered law.
EXAMPLES: dict[str, ContactLaw] = {
    "impact": ImpactLaw(stiffness=K_HERTZ, exponent=1.5, c_max=1e3, d_max=1e-5),
    "restitution": RestitutionLaw(penalty=K_LINEAR, restitution=0.7),
    "hertz": HertzLaw(stiffness=K_HERTZ),
    "kelvin-voigt": KelvinVoigtLaw(stiffness=K_LINEAR, damping=D_KV),
    **{
        cls.name: cls(stiffness=K_HERTZ, restitution=0.7)
        for cls in (
            HuntCrossleyLaw,
            LankaraniNikraveshLaw,
            FloresLaw,
            GonthierLaw,
            HuGuoLaw,
            HerbertMcWhannellLaw,
            LeeWangLaw,
            ZhiyingQishaoLaw,
        )
    },
}

#: Laws whose force tends to 0 as δ → 0+ (all but the linear spring–dashpot).
CONTINUOUS_AT_CONTACT = sorted(set(CONTACT_LAWS) - {"kelvin-voigt"})

#: Laws that dissipate nothing.
CONSERVATIVE = {"hertz"}


def undamped(law: ContactLaw) -> ContactLaw:
    """The same law with its dissipation switched off."""
    if isinstance(law, ImpactLaw):
        return dataclasses.replace(law, c_max=0.0)
    if isinstance(law, KelvinVoigtLaw):
        return dataclasses.replace(law, damping=0.0)
    if isinstance(law, RestitutionLaw | HuntCrossleyTypeLaw):
        return dataclasses.replace(law, restitution=1.0)
    return law


def random_states(n: int = 500) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    rng = np.random.default_rng(20240611)
    delta = rng.uniform(-1e-4, 1e-4, n)
    delta_dot = rng.uniform(-2.0, 2.0, n)
    v0 = rng.choice([-1.0, 0.0, 1e-6, 0.3, 2.0], n)
    return delta, delta_dot, v0


def test_examples_cover_the_registry() -> None:
    assert set(EXAMPLES) == set(CONTACT_LAWS)
    for name, cls in CONTACT_LAWS.items():
        assert cls.name == name
        assert isinstance(EXAMPLES[name], cls)
    # law_id is the kernel's force form: its own for each law outside the Hunt–Crossley family,
    # an id from HC_FIRST to HC_LAST (one form, which family members may share) inside it
    for cls in CONTACT_LAWS.values():
        family = issubclass(cls, HuntCrossleyTypeLaw | RestitutionLaw)
        assert family == (ids.HC_FIRST <= cls.law_id <= ids.HC_LAST), cls.name
    others = [cls.law_id for cls in CONTACT_LAWS.values() if cls.law_id < ids.HC_FIRST]
    assert len(set(others)) == len(others)


@pytest.mark.parametrize("name", sorted(CONTACT_LAWS))
def test_each_law_declares_what_it_packs(name: str) -> None:
    """``params()`` is the declared ``packing``; a field packed as it is sits in its slot, and
    the stiffness the geometric refit replaces is a field of the law."""
    law = EXAMPLES[name]
    fields = {item.name for item in dataclasses.fields(law)}
    np.testing.assert_array_equal(law.params(), [getattr(law, n) for n in law.packing])
    for field in fields:
        slot = law.packed_slot(field)
        if slot is not None:
            assert law.params()[slot] == getattr(law, field)
    assert law.stiffness_name in fields and law.packed_slot(law.stiffness_name) == 0
    unpacked = fields - set(law.packing)  # packed transformed (restitution → χ), or not at all
    assert unpacked <= {"restitution"}


def test_a_layout_must_fill_every_slot() -> None:
    assert layout(2, {1: "b", 0: "a"}) == ("a", "b")
    with pytest.raises(ConfigError, match="do not fill"):
        layout(3, {0: "a", 2: "c"})


@pytest.mark.parametrize("name", sorted(CONTACT_LAWS))
def test_zero_force_without_penetration(name: str) -> None:
    law = EXAMPLES[name]
    delta = np.array([-1e-3, -1e-9, -0.0, 0.0])
    for rate in (-1.0, 0.0, 1.0):
        for v0 in (None, 0.5):
            assert np.all(law.force(delta, rate, v0) == 0.0)


@pytest.mark.parametrize("name", sorted(CONTACT_LAWS))
def test_force_is_non_negative_and_finite(name: str) -> None:
    delta, delta_dot, v0 = random_states()
    force = EXAMPLES[name].force(delta, delta_dot, v0)
    assert force.shape == delta.shape
    assert np.all(np.isfinite(force))
    assert np.all(force >= 0.0)
    assert np.all(EXAMPLES[name].force(delta, delta_dot) >= 0.0)


@pytest.mark.parametrize("name", CONTINUOUS_AT_CONTACT)
def test_force_vanishes_at_first_contact(name: str) -> None:
    """F → 0 as δ → 0+ at a fixed approach speed: no jump when contact starts."""
    law = EXAMPLES[name]
    delta = np.array([1e-6, 1e-9, 1e-12, 1e-15])
    force = law.force(delta, SPEED, SPEED)
    assert np.all(np.diff(force) < 0.0)
    assert force[-1] < 1e-6 * force[0]


def test_kelvin_voigt_jumps_by_d_v0_at_first_contact() -> None:
    law = EXAMPLES["kelvin-voigt"]
    assert isinstance(law, KelvinVoigtLaw)
    force = float(law.force(1e-18, SPEED))
    assert force == pytest.approx(law.damping * SPEED, rel=1e-9)


@pytest.mark.parametrize("name", sorted(CONTACT_LAWS))
def test_single_impact_conserves_energy_without_damping(name: str) -> None:
    """Damping off → rebound speed = impact speed (integrator rtol 1e-11, so 1e-6 is safe)."""
    result = single_impact(undamped(EXAMPLES[name]), MASS, SPEED)
    assert result.status == 0, result.message
    assert result.rebound_speed == pytest.approx(SPEED, rel=1e-6)


@pytest.mark.parametrize("name", sorted(set(CONTACT_LAWS) - CONSERVATIVE))
def test_single_impact_loses_energy_with_damping(name: str) -> None:
    result = single_impact(EXAMPLES[name], MASS, SPEED)
    assert result.status == 0, result.message
    assert 0.0 < result.restitution < 0.99
    assert result.max_penetration > 0.0
    assert result.contact_time > 0.0


@pytest.mark.parametrize(("zeta", "expected"), [(0.1, 0.744), (0.3, 0.451), (0.5, 0.298)])
def test_clamped_kelvin_voigt_restitution_matches_reference(zeta: float, expected: float) -> None:
    """docs/contact-laws.md §2.1 [DERIVED]: clamped KV e_eff, given to three digits."""
    law = KelvinVoigtLaw(stiffness=K_LINEAR, damping=2.0 * zeta * math.sqrt(MASS * K_LINEAR))
    result = single_impact(law, MASS, SPEED)
    assert result.restitution == pytest.approx(expected, abs=5e-4)


# --- IMPACT and STEP ------------------------------------------------------------------------


def test_step3_documented_example() -> None:
    """ADAMS docs: STEP((2, 3, 3.5, 4, 5), 3, 0, 4, 1) -> 0, 0, 0.5, 1, 1."""
    np.testing.assert_array_equal(step3([2, 3, 3.5, 4, 5], 3, 0, 4, 1), [0, 0, 0.5, 1, 1])


def test_step3_rejects_reversed_interval() -> None:
    with pytest.raises(ConfigError, match="x1 must be greater than x0"):
        step3(1.0, 2.0, 0.0, 2.0, 1.0)


def test_impact_matches_hand_computation() -> None:
    """k = 1e7 N/m^1.5, e = 1.5, c_max = 1e4 N·s/m, d = 1e-4 m."""
    law = ImpactLaw(stiffness=1e7, exponent=1.5, c_max=1e4, d_max=1e-4)
    # δ = 1e-5 (u = 0.1): k δ^1.5 = 0.316227766; c = 1e4 · 0.01 · 2.8 = 280 N·s/m.
    assert float(law.force(1e-5, 0.1)) == pytest.approx(1e7 * 1e-5**1.5 + 280.0 * 0.1, rel=1e-12)
    # δ = 5e-5 (u = 0.5): c = c_max / 2 = 5000 N·s/m; separating at 0.5 mm/s (3.536 − 2.5 N).
    assert float(law.force(5e-5, -5e-4)) == pytest.approx(1e7 * 5e-5**1.5 - 2.5, rel=1e-12)
    # δ = 2e-4 ≥ d: full damping; separating fast enough that max(0, ·) clamps.
    assert float(law.force(2e-4, -1.0)) == 0.0
    assert float(law.force(2e-4, 0.01)) == pytest.approx(1e7 * 2e-4**1.5 + 100.0, rel=1e-12)


def test_impact_equals_adams_definition() -> None:
    """IMPACT(x, ẋ, x1, k, e, cmax, d) of docs/contact-laws.md §1.2 with δ = x1 − x, δ̇ = −ẋ."""
    k, e, cmax, d, x1 = 100.0, 1.5, 25.0, 0.1, 1.0
    law = ImpactLaw(stiffness=k, exponent=e, c_max=cmax, d_max=d)
    rng = np.random.default_rng(7)
    x = rng.uniform(0.7, 1.2, 400)
    x_dot = rng.uniform(-3.0, 3.0, 400)
    adams = np.where(
        x < x1,
        np.maximum(
            0.0, k * np.clip(x1 - x, 0.0, None) ** e - step3(x, x1 - d, cmax, x1, 0) * x_dot
        ),
        0.0,
    )
    np.testing.assert_allclose(law.force(x1 - x, -x_dot), adams, rtol=1e-12, atol=1e-12)


# --- Hunt–Crossley family -------------------------------------------------------------------


@pytest.mark.parametrize(
    ("cls", "chi"),
    [
        (HuntCrossleyLaw, 0.3),
        (LankaraniNikraveshLaw, 0.27),
        (FloresLaw, 0.4),
        (GonthierLaw, 0.45),
        (HuGuoLaw, 0.375),
        (HerbertMcWhannellLaw, 1.2 / 3.36),
        (LeeWangLaw, 0.15),
        (ZhiyingQishaoLaw, 0.27 * math.exp(0.4)),
    ],
)
def test_hysteresis_factors_at_e_08(cls: type[HuntCrossleyTypeLaw], chi: float) -> None:
    """χ(0.8) of every model, computed by hand from docs/contact-laws.md §2.2."""
    assert cls(stiffness=1.0, restitution=0.8).chi == pytest.approx(chi, rel=1e-12)


def test_restitution_law_uses_the_exact_chi() -> None:
    law = RestitutionLaw(penalty=1e6, restitution=0.5)
    assert law.chi == chi_for_restitution(0.5)
    assert law.exponent == 1.0
    assert law.v_floor == DEFAULT_V_FLOOR


def test_hunt_crossley_impact_velocity_floor() -> None:
    """v_eff = max(v0, v_floor); while v0 is unknown (None or ≤ 0), max(δ̇, v_floor)."""
    law = LankaraniNikraveshLaw(stiffness=1e10, restitution=0.5, v_floor=1e-3)
    delta, rate = 1e-5, 0.02
    elastic = 1e10 * delta**1.5
    assert float(law.force(delta, rate, 0.5)) == pytest.approx(
        elastic * (1 + law.chi * rate / 0.5), rel=1e-14
    )
    assert float(law.force(delta, rate, 1e-6)) == pytest.approx(
        elastic * (1 + law.chi * rate / 1e-3), rel=1e-14
    )
    for unknown in (None, 0.0, -1.0):
        assert float(law.force(delta, rate, unknown)) == pytest.approx(
            elastic * (1 + law.chi), rel=1e-14
        )
    assert float(law.force(delta, 1e-5, None)) == pytest.approx(
        elastic * (1 + law.chi * 1e-5 / 1e-3), rel=1e-14
    )


def test_needs_impact_velocity_flags() -> None:
    needing = {name for name, cls in CONTACT_LAWS.items() if cls.needs_impact_velocity}
    assert needing == set(CONTACT_LAWS) - {"impact", "hertz", "kelvin-voigt"}


@pytest.mark.parametrize("name", sorted(CONTACT_LAWS))
def test_every_law_documents_itself(name: str) -> None:
    cls = CONTACT_LAWS[name]
    assert cls.citation
    assert cls.equation
    assert cls.__doc__
    params = EXAMPLES[name].params()
    assert params.dtype == np.float64
    assert np.all(np.isfinite(params))


# --- registry -------------------------------------------------------------------------------


def test_get_law_by_name_with_aliases() -> None:
    law = get_law("Lankarani_Nikravesh", K=1e10, e=0.9, n=1.0)
    assert law == LankaraniNikraveshLaw(stiffness=1e10, restitution=0.9, exponent=1.0)
    impact = get_law("impact", k=1e8, e=2.2, cmax=1e4, d=1e-4)
    assert impact == ImpactLaw(stiffness=1e8, exponent=2.2, c_max=1e4, d_max=1e-4)
    assert get_law("restitution", p=1e6, epsilon=0.5) == RestitutionLaw(1e6, 0.5)


def test_get_law_with_an_instance() -> None:
    law = EXAMPLES["flores"]
    assert get_law(law) is law
    changed = get_law(law, restitution=0.5)
    assert isinstance(changed, FloresLaw)
    assert changed.restitution == 0.5
    assert changed.stiffness == K_HERTZ


def test_unknown_law_lists_known_names() -> None:
    with pytest.raises(ConfigError, match=r"known names: .*hunt-crossley.*lankarani-nikravesh"):
        get_law("poisson", penalty=1.0)


def test_unknown_and_missing_parameters() -> None:
    with pytest.raises(ConfigError, match="unknown parameter 'damping_ratio'"):
        get_law("hertz", stiffness=1.0, damping_ratio=0.1)
    with pytest.raises(ConfigError, match="missing parameter"):
        get_law("lankarani-nikravesh", stiffness=1.0)
    with pytest.raises(ConfigError, match="given twice"):
        get_law("hertz", stiffness=1.0, K=2.0)
    with pytest.raises(ConfigError, match=r"name .* or instance"):
        get_law(3.0)  # type: ignore[arg-type]


@pytest.mark.parametrize(
    ("factory", "match"),
    [
        (lambda: ImpactLaw(stiffness=-1.0, exponent=1.5, c_max=0.0, d_max=1e-5), "stiffness"),
        (lambda: ImpactLaw(stiffness=1.0, exponent=1.5, c_max=0.0, d_max=0.0), "d_max"),
        (lambda: HertzLaw(stiffness=1.0, exponent=0.0), "exponent"),
        (lambda: KelvinVoigtLaw(stiffness=1.0, damping=-1.0), "damping"),
        (lambda: RestitutionLaw(penalty=1.0, restitution=0.0), "restitution"),
        (lambda: LankaraniNikraveshLaw(stiffness=1.0, restitution=1.2), "restitution"),
        (lambda: FloresLaw(stiffness=1.0, restitution=0.5, v_floor=0.0), "v_floor"),
        (lambda: HertzLaw(stiffness=math.nan), "finite"),
        (lambda: HertzLaw(stiffness="1e10"), "expected a number"),  # type: ignore[arg-type]
    ],
)
def test_invalid_parameters_name_class_and_field(factory: object, match: str) -> None:
    with pytest.raises(ConfigError, match=match) as info:
        factory()  # type: ignore[operator]
    assert "Law." in str(info.value)


def test_laws_are_frozen_and_hashable() -> None:
    law = HuntCrossleyLaw(stiffness=K_HERTZ, restitution=0.7)
    with pytest.raises(dataclasses.FrozenInstanceError):
        law.stiffness = 1.0  # type: ignore[misc]
    assert hash(law) == hash(dataclasses.replace(law))
