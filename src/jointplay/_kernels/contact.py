"""Compiled contact kernels: normal force, joint friction and the ADAMS cubic STEP.

Flat numbers in, one number out, no Python objects. The readable reference implementations
are the frozen law objects of :mod:`jointplay.contact.laws` and
:mod:`jointplay.contact.friction`; their ``law_id`` and ``params()`` produce the integer ids
and packed ``float64`` parameter arrays defined here, once. A test checks that every kernel
equals its reference.

Kernels never raise. An unknown law id gives ``nan``, which the engine's finite-state check
turns into an :class:`~jointplay.errors.IntegrationError`.

Units are SI: penetration δ in m (> 0 in contact), penetration rate δ̇ in m/s (> 0 while
approaching), forces in N, velocities in m/s.

Normal-force law ids and their packed parameters (``params[i]``):

==============================  ====  ===================================================
law                             id    packed parameters
==============================  ====  ===================================================
``LAW_IMPACT``                  0     stiffness k (N/m^e), exponent e, c_max (N·s/m),
                                      d_max (m)
``LAW_HERTZ``                   1     stiffness K (N/m^n), exponent n
``LAW_KELVIN_VOIGT``            2     stiffness K (N/m), damping D (N·s/m)
``LAW_RESTITUTION`` …           3–11  stiffness K or penalty p (N/m^n), exponent n,
``LAW_ZHIYING_QISHAO``                hysteresis factor χ, v_floor (m/s)
==============================  ====  ===================================================

Ids 3 to 11 are the Hunt–Crossley family ``F = K δ^n (1 + χ δ̇ / v_eff)``; they differ only
in how χ follows from the coefficient of restitution, which is done in Python, so they share
one packed layout.

Friction law ids: ``FRICTION_NONE`` 0 (no parameters), ``FRICTION_AMBROSIO`` 1 (μ, v0, v1 in
m/s), ``FRICTION_ADAMS`` 2 (μ_s, μ_d, v_s, v_d in m/s).
"""

from __future__ import annotations

import math

import numba
import numpy as np
import numpy.typing as npt

# --- normal-force law ids -------------------------------------------------------------------
LAW_IMPACT = 0
LAW_HERTZ = 1
LAW_KELVIN_VOIGT = 2
LAW_RESTITUTION = 3
LAW_HUNT_CROSSLEY = 4
LAW_LANKARANI_NIKRAVESH = 5
LAW_FLORES = 6
LAW_GONTHIER = 7
LAW_HU_GUO = 8
LAW_HERBERT_MCWHANNELL = 9
LAW_LEE_WANG = 10
LAW_ZHIYING_QISHAO = 11
#: First and last id of the Hunt–Crossley family (shared layout ``HC_*``).
HC_FIRST = LAW_RESTITUTION
HC_LAST = LAW_ZHIYING_QISHAO

# --- packed layouts of the normal-force laws --------------------------------------------------
IMPACT_STIFFNESS = 0
IMPACT_EXPONENT = 1
IMPACT_C_MAX = 2
IMPACT_D_MAX = 3
IMPACT_SIZE = 4

HERTZ_STIFFNESS = 0
HERTZ_EXPONENT = 1
HERTZ_SIZE = 2

KV_STIFFNESS = 0
KV_DAMPING = 1
KV_SIZE = 2

HC_STIFFNESS = 0
HC_EXPONENT = 1
HC_CHI = 2
HC_V_FLOOR = 3
HC_SIZE = 4

# --- friction law ids and layouts -------------------------------------------------------------
FRICTION_NONE = 0
FRICTION_AMBROSIO = 1
FRICTION_ADAMS = 2

NONE_SIZE = 0

AMBROSIO_MU = 0
AMBROSIO_V0 = 1
AMBROSIO_V1 = 2
AMBROSIO_SIZE = 3

ADAMS_MU_STATIC = 0
ADAMS_MU_DYNAMIC = 1
ADAMS_V_STATIC = 2
ADAMS_V_DYNAMIC = 3
ADAMS_SIZE = 4


@numba.njit(cache=True)
def step3(x: float, x0: float, h0: float, x1: float, h1: float) -> float:
    """ADAMS cubic STEP: ``h0`` for x ≤ x0, ``h1`` for x ≥ x1, a C¹ cubic in between.

    ``h0 + (h1 - h0) u² (3 - 2u)`` with ``u = (x - x0)/(x1 - x0)``
    (docs/contact-laws.md §1.1). Never divides by zero: with ``x1 <= x0`` every ``x`` falls in
    one of the two constant branches.
    """
    if x <= x0:
        return h0
    if x >= x1:
        return h1
    u = (x - x0) / (x1 - x0)
    return h0 + (h1 - h0) * u * u * (3.0 - 2.0 * u)


@numba.njit(cache=True, inline="always")
def power(delta: float, exponent: float) -> float:
    """δ^e, as δ√δ for the Hertzian e = 3/2 of every paper law (to round-off: ≤ 1 ulp from
    the power function, and measured a third of the right-hand side's time faster)."""
    return delta * math.sqrt(delta) if exponent == 1.5 else delta**exponent


@numba.njit(cache=True)
def normal_force(
    law_id: int, params: npt.NDArray[np.float64], delta: float, delta_dot: float, v0: float
) -> float:
    """Normal contact force magnitude, N (≥ 0; 0 without penetration).

    Args:
        law_id: one of the ``LAW_*`` ids.
        params: packed parameters in the layout of ``law_id`` (module docstring).
        delta: penetration δ, m (> 0 in contact).
        delta_dot: penetration rate δ̇, m/s (> 0 while approaching).
        v0: penetration rate at the start of the current contact event, m/s. Used by the
            Hunt–Crossley family only: ``v_eff = max(v0, v_floor)``, or
            ``max(delta_dot, v_floor)`` when ``v0 <= 0`` (not known yet).

    Returns:
        The force in N, or ``nan`` for an unknown ``law_id``.
    """
    if not delta > 0.0:
        return 0.0
    if law_id == LAW_IMPACT:
        damping = step3(delta, 0.0, 0.0, params[IMPACT_D_MAX], params[IMPACT_C_MAX])
        force = (
            params[IMPACT_STIFFNESS] * power(delta, params[IMPACT_EXPONENT]) + damping * delta_dot
        )
    elif law_id == LAW_HERTZ:
        force = params[HERTZ_STIFFNESS] * power(delta, params[HERTZ_EXPONENT])
    elif law_id == LAW_KELVIN_VOIGT:
        force = params[KV_STIFFNESS] * delta + params[KV_DAMPING] * delta_dot
    elif HC_FIRST <= law_id <= HC_LAST:
        v_ref = v0 if v0 > 0.0 else delta_dot
        v_floor = params[HC_V_FLOOR]
        v_eff = v_ref if v_ref > v_floor else v_floor
        force = (
            params[HC_STIFFNESS]
            * power(delta, params[HC_EXPONENT])
            * (1.0 + params[HC_CHI] * delta_dot / v_eff)
        )
    else:
        return math.nan
    return force if force > 0.0 else 0.0


@numba.njit(cache=True)
def friction_force(law_id: int, params: npt.NDArray[np.float64], v_t: float, f_n: float) -> float:
    """Signed tangential friction force F_T, N.

    ``F_T = μ(v_T) F_N sgn(v_T)`` in the sign convention of docs/contact-laws.md §5: the
    friction force on the journal is ``-F_T t``, on the bearing ``+F_T t``.

    Args:
        law_id: one of the ``FRICTION_*`` ids.
        params: packed parameters in the layout of ``law_id`` (module docstring).
        v_t: tangential slip velocity v_T of the journal relative to the bearing, m/s.
        f_n: normal force F_N, N.

    Returns:
        F_T in N, or ``nan`` for an unknown ``law_id``.
    """
    if law_id == FRICTION_NONE:
        return 0.0
    sign = 1.0 if v_t > 0.0 else (-1.0 if v_t < 0.0 else 0.0)
    speed = abs(v_t)
    if law_id == FRICTION_AMBROSIO:
        v_lo = params[AMBROSIO_V0]
        v_hi = params[AMBROSIO_V1]
        if speed <= v_lo:
            correction = 0.0
        elif speed >= v_hi:
            correction = 1.0
        else:
            correction = (speed - v_lo) / (v_hi - v_lo)
        return params[AMBROSIO_MU] * correction * f_n * sign
    if law_id == FRICTION_ADAMS:
        mu_s = params[ADAMS_MU_STATIC]
        mu_d = params[ADAMS_MU_DYNAMIC]
        v_s = params[ADAMS_V_STATIC]
        v_d = params[ADAMS_V_DYNAMIC]
        if speed <= v_s:
            coefficient = step3(v_t, -v_s, -mu_s, v_s, mu_s)
        elif speed < v_d:
            coefficient = sign * step3(speed, v_s, mu_s, v_d, mu_d)
        else:
            coefficient = sign * mu_d
        return coefficient * f_n
    return math.nan
