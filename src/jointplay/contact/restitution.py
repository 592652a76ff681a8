"""Restitution of Hunt–Crossley-type contact laws: the exact relation and a single-impact test.

A Hunt–Crossley-type law ``F = K δ^n (1 + χ δ̇ / v0)`` dissipates energy in one impact. The
coefficient of restitution it actually produces, e_eff, follows from χ alone: integrating
``m u du/dδ = -K δ^n (1 + χ u / v0)`` from entry (δ = 0, u = v0) to exit (δ = 0,
u = -e_eff v0) gives (docs/contact-laws.md §2.3, [DERIVED])::

    g(χ) = g(-χ e_eff),    g(x) = x - ln(1 + x)

independent of n, K, the mass and v0 (it needs χ e_eff < 1). We believe this closed form is
the subject of Carvalho & Martins (2019), *Exact restitution and generalizations for the
Hunt–Crossley contact model*, Mech. Mach. Theory 139:174–194 (citation recalled, not
checked against a copy).

:func:`effective_restitution` maps χ to e_eff; :func:`chi_for_restitution` inverts it, so a
law built with that χ rebounds with exactly the coefficient you ask for (the ``restitution``
law of :mod:`jointplay.contact.laws`). :func:`single_impact` measures e_eff of *any* law by
integrating one impact of a mass on a rigid wall, e.g. for ADAMS IMPACT, whose restitution is
not an input (§1.7).

Numerics: both roots are found with Brent's method on ``λ = -ln(1 - χ e_eff)`` rather than on
e_eff or χ directly, so e_eff stays accurate when it is tiny (χ ≫ 1) and χ when it is tiny
(e → 1); ``g`` and ``λ + expm1(-λ)`` use their Taylor series near zero to avoid cancellation.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Protocol

import numpy as np
import numpy.typing as npt

from jointplay.errors import ConfigError

#: Below this χ (or 1 − e) the first-order relation χ = 3(1 − e)/2 is exact to double precision
#: (its error is O(χ²)), and Brent's method would lose the root in rounding.
_FIRST_ORDER_LIMIT = 1e-12

#: Smallest λ used as the lower end of the bracket.
_LAMBDA_MIN = 1e-100


def _g(x: float) -> float:
    """``g(x) = x - ln(1 + x)`` for x > -1, with a Taylor series for |x| < 0.01."""
    if abs(x) < 0.01:
        # x²/2 - x³/3 + x⁴/4 - ...; the first omitted term is below 1e-16 relative.
        return sum((-x) ** k / k for k in range(2, 11))
    return x - math.log1p(x)


def _h(lam: float) -> float:
    """``g(-y)`` with ``y = 1 - exp(-λ)``, i.e. ``λ + expm1(-λ)``, accurate for small λ."""
    if lam < 0.05:
        # λ²/2! - λ³/3! + ...; the first omitted term is below 1e-17 relative.
        return sum((-lam) ** k / math.factorial(k) for k in range(2, 12))
    return lam + math.expm1(-lam)


def effective_restitution(chi: float) -> float:
    """Coefficient of restitution that a Hunt–Crossley-type law with factor χ produces.

    Solves ``g(χ) = g(-χ e_eff)``, ``g(x) = x - ln(1 + x)`` (docs/contact-laws.md §2.3; see the
    module docstring for the source). Independent of exponent, stiffness, mass and impact speed.

    Args:
        chi: hysteresis damping factor χ ≥ 0 (dimensionless), as in
            ``F = K δ^n (1 + χ δ̇ / v0)``.

    Returns:
        e_eff in (0, 1]; 1 for χ = 0. Always below ``1/χ``.

    Raises:
        ConfigError: χ is negative or not finite.
    """
    from scipy.optimize import brentq  # scipy.optimize/integrate: ~0.3 s, loaded when used

    chi = float(chi)
    if not (math.isfinite(chi) and chi >= 0.0):
        raise ConfigError(f"effective_restitution: chi must be finite and >= 0, got {chi!r}")
    if chi < _FIRST_ORDER_LIMIT:
        return 1.0 - 2.0 * chi / 3.0
    target = _g(chi)
    # _h rises from 0 to infinity; _h(λ) >= λ - 1 brackets the root below target + 2.
    lam = brentq(lambda x: _h(x) - target, _LAMBDA_MIN, target + 2.0, xtol=1e-300, maxiter=500)
    return -math.expm1(-lam) / chi


def chi_for_restitution(e: float) -> float:
    """Hysteresis factor χ for which a Hunt–Crossley-type law rebounds with exactly ``e``.

    The inverse of :func:`effective_restitution` (docs/contact-laws.md §2.3), found with
    :func:`scipy.optimize.brentq`. Reference values: e = 0.9 → 0.1665, 0.5 → 1.4328,
    0.1 → 9.9982.

    Args:
        e: the wanted coefficient of restitution, in (0, 1].

    Returns:
        χ ≥ 0 (dimensionless); 0 for e = 1, and below ``1/e``.

    Raises:
        ConfigError: ``e`` is outside (0, 1].
    """
    from scipy.optimize import brentq  # scipy.optimize/integrate: ~0.3 s, loaded when used

    e = float(e)
    if not (math.isfinite(e) and 0.0 < e <= 1.0):
        raise ConfigError(
            f"chi_for_restitution: e must lie in (0, 1], got {e!r}; for a nearly plastic "
            "impact use a small positive value such as 0.01"
        )
    if 1.0 - e < _FIRST_ORDER_LIMIT:
        return 1.5 * (1.0 - e)

    def mismatch(lam: float) -> float:
        chi = -math.expm1(-lam) / e
        return _h(lam) - _g(chi)

    # χ < 1/e, so g(χ) < g(1/e) and _h(λ) >= λ - 1 puts the root below g(1/e) + 2.
    lam = brentq(mismatch, _LAMBDA_MIN, _g(1.0 / e) + 2.0, xtol=1e-300, maxiter=500)
    return -math.expm1(-lam) / e


class _NormalLaw(Protocol):
    def force(
        self,
        delta: npt.ArrayLike,
        delta_dot: npt.ArrayLike,
        v0: npt.ArrayLike | None = None,
    ) -> npt.NDArray[np.float64]: ...


@dataclass(frozen=True)
class ImpactResult:
    """One impact of a mass on a rigid wall, as measured by :func:`single_impact`.

    Attributes:
        restitution: effective coefficient of restitution, rebound speed / impact speed.
        impact_speed: approach speed at first touch, m/s.
        rebound_speed: separation speed when δ returns to 0, m/s (``nan`` if it never did).
        contact_time: time from first touch to separation, s (``nan`` if no separation).
        max_penetration: largest penetration δ, m.
        max_force: largest normal force, N (sampled on 2001 points of the dense output).
        nfev: number of force evaluations of the integrator.
        status: 0 success; 1 the mass had not left the wall by ``t_max``; -1 the integrator
            failed.
        message: a readable account of ``status``.
    """

    restitution: float
    impact_speed: float
    rebound_speed: float
    contact_time: float
    max_penetration: float
    max_force: float
    nfev: int
    status: int
    message: str


def single_impact(
    law: _NormalLaw,
    mass: float,
    impact_speed: float,
    *,
    method: str = "DOP853",
    rtol: float = 1e-11,
    atol_penetration: float = 1e-16,
    t_max: float = 1.0,
) -> ImpactResult:
    """Integrate one impact ``m δ̈ = -F(δ, δ̇)``, δ(0) = 0, δ̇(0) = v0, until δ returns to 0.

    The law's reference ``force`` is evaluated with the impact speed as ``v0``. The exit is
    located with a terminal event at δ = 0 (crossing downwards), the deepest point with an
    event at δ̇ = 0.

    For a law whose force jumps at first contact (``kelvin-voigt``) keep the explicit default
    method: an implicit one (Radau) can converge to a spurious "stuck" solution at δ ≈ 0,
    δ̇ ≈ 0 of its collocation equations across the jump, reported as ``status`` 1.

    Args:
        law: any normal contact law of :mod:`jointplay.contact.laws`.
        mass: the impacting (effective) mass, kg.
        impact_speed: approach speed v0 > 0, m/s.
        method: a :func:`scipy.integrate.solve_ivp` method, e.g. ``"DOP853"`` or ``"Radau"``.
        rtol: relative tolerance of the integrator.
        atol_penetration: absolute tolerance on δ, m; the one on δ̇ is ``rtol * impact_speed``.
        t_max: give up if the mass has not left the wall after this time, s.

    Returns:
        An :class:`ImpactResult`.

    Raises:
        ConfigError: ``mass``, ``impact_speed`` or ``t_max`` not finite and positive.
    """
    from scipy.integrate import solve_ivp  # scipy.optimize/integrate: ~0.3 s, loaded when used

    for field, value in (("mass", mass), ("impact_speed", impact_speed), ("t_max", t_max)):
        if not (math.isfinite(value) and value > 0.0):
            raise ConfigError(f"single_impact: {field} must be finite and > 0, got {value!r}")

    def force(delta: float, delta_dot: float) -> float:
        return float(law.force(delta, delta_dot, impact_speed))

    def rhs(_t: float, y: npt.NDArray[np.float64]) -> list[float]:
        return [y[1], -force(y[0], y[1]) / mass]

    def leaves_wall(_t: float, y: npt.NDArray[np.float64]) -> float:
        return float(y[0])

    def deepest(_t: float, y: npt.NDArray[np.float64]) -> float:
        return float(y[1])

    leaves_wall.terminal = True  # type: ignore[attr-defined]
    leaves_wall.direction = -1.0  # type: ignore[attr-defined]
    deepest.direction = -1.0  # type: ignore[attr-defined]

    solution = solve_ivp(
        rhs,
        (0.0, t_max),
        [0.0, impact_speed],
        method=method,
        rtol=rtol,
        atol=[atol_penetration, rtol * impact_speed],
        events=[leaves_wall, deepest],
        dense_output=True,
    )
    exits = solution.t_events[0]
    max_penetration = (
        float(solution.y_events[1][0][0])
        if len(solution.t_events[1])
        else float(np.max(solution.y[0]))
    )
    t_end = float(exits[0]) if len(exits) else float(solution.t[-1])
    if solution.sol is not None:
        samples = solution.sol(np.linspace(0.0, t_end, 2001))
        max_force = float(np.max(law.force(samples[0], samples[1], impact_speed)))
    else:
        max_force = math.nan
    if solution.status == -1:
        status, message = -1, f"integrator failed: {solution.message}"
    elif not len(exits):
        status, message = 1, f"the mass had not left the wall after t_max = {t_max} s"
    else:
        status, message = 0, "the mass left the wall"
    rebound = float(-solution.y_events[0][0][1]) if len(exits) else math.nan
    return ImpactResult(
        restitution=rebound / impact_speed,
        impact_speed=impact_speed,
        rebound_speed=rebound,
        contact_time=float(exits[0]) if len(exits) else math.nan,
        max_penetration=max_penetration,
        max_force=max_force,
        nfev=int(solution.nfev),
        status=status,
        message=message,
    )
