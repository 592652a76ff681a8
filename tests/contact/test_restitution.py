"""Exact restitution of Hunt–Crossley-type laws (docs/contact-laws.md §2.3) and single impacts."""

from __future__ import annotations

import math

import numpy as np
import pytest

from jointplay.contact.laws import (
    CONTACT_LAWS,
    HuntCrossleyTypeLaw,
    ImpactLaw,
    LankaraniNikraveshLaw,
    RestitutionLaw,
)
from jointplay.contact.restitution import (
    chi_for_restitution,
    effective_restitution,
    single_impact,
)
from jointplay.errors import ConfigError

#: §2.3 table: the χ that reproduces e exactly, given to four decimals.
CHI_TABLE = {
    0.95: 0.0789,
    0.9: 0.1665,
    0.8: 0.3731,
    0.7: 0.6348,
    0.6: 0.9749,
    0.5: 1.4328,
    0.4: 2.0825,
    0.3: 3.0871,
    0.2: 4.9192,
    0.1: 9.9982,
}

#: Tolerance of a simulated impact against the exact relation. The integrator runs at
#: rtol 1e-11 (errors ~1e-9 in practice); 1e-3 is the brief's acceptance level.
IMPACT_TOLERANCE = 1e-3

HC_TYPE_LAWS = sorted(
    name for name, cls in CONTACT_LAWS.items() if issubclass(cls, HuntCrossleyTypeLaw)
)


def g(x: float) -> float:
    return x - math.log1p(x)


@pytest.mark.parametrize(("e", "chi"), sorted(CHI_TABLE.items()))
def test_chi_for_restitution_matches_the_table(e: float, chi: float) -> None:
    assert chi_for_restitution(e) == pytest.approx(chi, abs=5e-5)


@pytest.mark.parametrize("e", [1e-6, 0.01, 0.1, 0.37, 0.5, 0.8, 0.99, 0.999999, 1.0 - 1e-13, 1.0])
def test_round_trip(e: float) -> None:
    chi = chi_for_restitution(e)
    assert effective_restitution(chi) == pytest.approx(e, rel=1e-12)
    assert chi * e <= 1.0  # < 1 exactly; equal by rounding when e is tiny (χ → 1/e)


@pytest.mark.parametrize("chi", [1e-9, 0.05, 0.5, 1.0, 3.0, 25.0])
def test_effective_restitution_solves_the_relation(chi: float) -> None:
    """g(χ) = g(−χ e_eff), checked directly where g is well conditioned.

    For small χ, g cancels (x − ln(1+x) ≈ x²/2); for large χ, χ e_eff → 1 where g(−x) has a
    logarithmic singularity, so rounding χ e_eff alone moves g by more than 1e-10.
    """
    e_eff = effective_restitution(chi)
    assert 0.0 < e_eff < min(1.0, 1.0 / chi)
    if 1e-3 < chi <= 3.0:
        assert g(-chi * e_eff) == pytest.approx(g(chi), rel=1e-10)


def test_limits() -> None:
    assert effective_restitution(0.0) == 1.0
    assert chi_for_restitution(1.0) == 0.0
    assert effective_restitution(1e6) == pytest.approx(1e-6, rel=1e-9)
    # Small damping: χ ≈ 3(1 − e²)/[2(1 + e³)] → 1.5 (1 − e) (§2.3).
    e = 0.999
    assert chi_for_restitution(e) == pytest.approx(3 * (1 - e**2) / (2 * (1 + e**3)), rel=1e-5)
    chis = [chi_for_restitution(e) for e in np.linspace(0.05, 1.0, 40)]
    assert np.all(np.diff(chis) < 0.0)


@pytest.mark.parametrize("bad", [-0.1, math.nan, math.inf])
def test_effective_restitution_rejects_bad_chi(bad: float) -> None:
    with pytest.raises(ConfigError, match="chi must be finite and >= 0"):
        effective_restitution(bad)


@pytest.mark.parametrize("bad", [0.0, -0.5, 1.01, math.nan])
def test_chi_for_restitution_rejects_bad_e(bad: float) -> None:
    with pytest.raises(ConfigError, match=r"e must lie in \(0, 1\]"):
        chi_for_restitution(bad)


@pytest.mark.parametrize("exponent", [1.0, 1.5])
@pytest.mark.parametrize("name", HC_TYPE_LAWS)
def test_hunt_crossley_type_impact_matches_exact_relation(name: str, exponent: float) -> None:
    """Single impact of every Hunt–Crossley-type law: e_eff = effective_restitution(χ)."""
    cls = CONTACT_LAWS[name]
    assert issubclass(cls, HuntCrossleyTypeLaw)
    for e in (0.3, 0.9):
        law = cls(stiffness=1e10 if exponent == 1.5 else 1e8, restitution=e, exponent=exponent)
        result = single_impact(law, 0.1, 0.5)
        assert result.status == 0, result.message
        assert result.restitution == pytest.approx(
            effective_restitution(law.chi), abs=IMPACT_TOLERANCE
        )


@pytest.mark.parametrize(("mass", "speed"), [(0.02, 0.3), (1.5, 2.0)])
@pytest.mark.parametrize("exponent", [1.0, 1.5])
def test_restitution_law_rebounds_with_the_specified_coefficient(
    mass: float, speed: float, exponent: float
) -> None:
    penalty = 1e8 if exponent == 1.0 else 1e10
    for epsilon in (0.1, 0.3, 0.5, 0.7, 0.9, 0.95):
        law = RestitutionLaw(penalty=penalty, restitution=epsilon, exponent=exponent)
        result = single_impact(law, mass, speed)
        assert result.status == 0, result.message
        assert result.restitution == pytest.approx(epsilon, abs=IMPACT_TOLERANCE)


def test_single_impact_is_method_independent() -> None:
    """DOP853 and Radau agree (both at rtol 1e-11) on a continuous law."""
    law = LankaraniNikraveshLaw(stiffness=1e10, restitution=0.5)
    explicit = single_impact(law, 0.1, 0.5)
    implicit = single_impact(law, 0.1, 0.5, method="Radau")
    assert implicit.restitution == pytest.approx(explicit.restitution, abs=1e-7)
    assert implicit.contact_time == pytest.approx(explicit.contact_time, rel=1e-6)


def test_single_impact_hertz_peak_matches_closed_form() -> None:
    """Undamped Hertz: δ_max = (5 m v² / (4 K))^(2/5) (energy balance)."""
    law = LankaraniNikraveshLaw(stiffness=1e10, restitution=1.0)
    result = single_impact(law, 0.1, 0.5)
    expected = (5 * 0.1 * 0.5**2 / (4 * 1e10)) ** 0.4
    assert result.max_penetration == pytest.approx(expected, rel=1e-8)
    assert result.max_force == pytest.approx(1e10 * expected**1.5, rel=1e-4)


def test_impact_restitution_falls_with_damping() -> None:
    """IMPACT's restitution is not an input (§1.7); it falls as c_max grows."""
    values = [
        single_impact(
            ImpactLaw(stiffness=1e10, exponent=1.5, c_max=c_max, d_max=1e-5), 0.1, 0.5
        ).restitution
        for c_max in (0.0, 1e2, 1e3, 1e4)
    ]
    assert values[0] == pytest.approx(1.0, abs=1e-6)
    assert np.all(np.diff(values) < 0.0)


def test_single_impact_reports_no_separation() -> None:
    law = LankaraniNikraveshLaw(stiffness=1.0, restitution=0.9)
    result = single_impact(law, 1.0, 0.1, t_max=1e-3)
    assert result.status == 1
    assert math.isnan(result.restitution)
    assert "t_max" in result.message


def test_single_impact_validates_its_arguments() -> None:
    law = LankaraniNikraveshLaw(stiffness=1e10, restitution=0.9)
    with pytest.raises(ConfigError, match="mass"):
        single_impact(law, 0.0, 0.5)
    with pytest.raises(ConfigError, match="impact_speed"):
        single_impact(law, 1.0, -0.5)
