"""The contact laws as the single engine calls them: normal force, joint friction, the ADAMS
cubic STEP and the laws' slopes for the closed-form Jacobian.

They are written once, in the lane source (:func:`jointplay._kernels.lanes.source.normal_force`,
:func:`~jointplay._kernels.lanes.source.friction_force`,
:func:`~jointplay._kernels.lanes.source_radau.law_slopes`), and compiled for the CPU
by :mod:`jointplay._kernels.shared` with the single engine's flags, so the single
engine, the batch lanes and the CUDA kernel evaluate the same lines: a law with a new force
form is a branch of ``normal_force`` there and its class in :mod:`jointplay.contact.laws`
(docs/contact-laws.md, "Adding a law"). Flat numbers in, one number out, no Python objects;
the parameters are read from a packed array at an offset (``p[o:]``). The readable reference implementations
are the frozen law objects of :mod:`jointplay.contact.laws` and
:mod:`jointplay.contact.friction`; their ``law_id`` and ``params()`` produce the integer ids
and packed ``float64`` parameter arrays (:mod:`jointplay._kernels.ids` numbers them, once). A test checks that every kernel
equals its reference.

Kernels never raise. An unknown law id gives ``nan``, which the engine's finite-state check
turns into an :class:`~jointplay.errors.IntegrationError`.

Units are SI: penetration δ in m (> 0 in contact), penetration rate δ̇ in m/s (> 0 while
approaching), forces in N, velocities in m/s.

Normal-force law ids and their packed parameters (``p[o + i]``):

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

from jointplay._kernels.shared import compiled

__all__ = ["friction_force", "law_slopes", "normal_force", "power", "step3"]

#: ``step3(x, x0, h0, x1, h1)``: the ADAMS cubic STEP (docs/contact-laws.md §1.1).
step3 = compiled["step3"]
#: ``power(delta, exponent)``: δ^e, as δ√δ for e = 3/2.
power = compiled["power"]
#: ``normal_force(law_id, p, o, delta, delta_dot, v0)``: F_N ≥ 0, N; NaN for an unknown id.
normal_force = compiled["normal_force"]
#: ``friction_force(law_id, p, o, v_t, f_n)``: the signed F_T, N; NaN for an unknown id.
friction_force = compiled["friction_force"]
#: ``law_slopes(law, p, o_law, fric, o_fric, delta, delta_dot, v_t, v0, f_n)``: ∂F_N/∂δ,
#: ∂F_N/∂δ̇, ∂F_T/∂v_T, ∂F_T/∂F_N by forward differences (relative step ``ids.LAW_STEP``).
law_slopes = compiled["law_slopes"]
