"""Radau IIA (order 5): its numerics and its steps in the lanes' one loop (the implicit batch
lane, :func:`jointplay._kernels.lanes.source.lane` with ``radau_*``), written once for two compilers (Numba's CPU
``njit`` and numba-cuda's ``cuda.jit(device=True)``), in the subset of
:mod:`jointplay._kernels.lanes.source` (its module docstring: scalars and caller-provided
arrays, no allocation, ``math`` only); :mod:`jointplay._kernels.lanes.build` compiles these
functions into the same namespace as that module's, so that they call its equations
(:func:`rhs`, :func:`rhs_and_quantities`, :func:`contact_forces`, :func:`project`, …) by name.

The algorithm is SciPy's Radau IIA ([HW96] §IV.8: simplified Newton on the eigen-decomposed
systems, one real and one complex, started from the last step's collocation polynomial; the
embedded error estimate, re-estimated after a rejection; the predictive controller; SciPy's
initial step), the steps :func:`jointplay.integrate` runs too (in the same loop:
:mod:`jointplay._kernels.driver`), with the options that
:func:`jointplay.dynamics.simulate.simulate` runs it with: positions eliminated from the
Newton systems (``LY_SECOND`` = n, RADAU5's ``M1``: n × n matrices, the velocities kept:
``LY_KEPT`` = n), the work integrals and the contact memory passive, RADAU5's growth limit
after a failure (``hold_after_failure``), and the loop's contact hooks: the contact-onset
control and, after each accepted step, the contact memory v0 and the projection. The step's
numerics are written once, here, for any second-order structure (``m2`` positions, ``nk`` kept
components, the rest passive): the reduced Newton matrices and their LU with partial pivoting
(LAPACK's pivots, largest ``|re| + |im|``), complex numbers as pairs of floats (Numba's
complex product and CPython's quotient, :func:`cdiv`), the simplified Newton iteration in
pieces (:func:`newton_start`, :func:`stage_point`, :func:`newton_iteration`), the error
estimate and the controller's factor. The single engine, the batch lanes and the generic
``jointplay.integrate`` run these steps in the one loop (the generic with its user's f and
Jacobian in place of the mechanism's: :data:`jointplay._kernels.driver.ADAPTERS`).

The Jacobian is :func:`eom.jacobian_state`'s (:func:`lane_jacobian`): the closed form
(:func:`jacobian_clear`) when every joint is clear (the paper's mechanisms: the driver the
only constraint), fixed-step differences (:func:`jacobian_fixed`) with ideal joints and
film damping, else SciPy's finite differences as the Radau kernel takes them
(:func:`jacobian_differences`). Film
damping (each joint's ``G_FILM``) is handled: its force and power in :func:`contact_forces`, its terms in
the closed-form Jacobian (:func:`film_jacobian`), its part of the reported joint force
(:func:`film_components`), and the interpolant's rule between steps (:func:`hermite`). The
sustained-contact mode (locked joints) runs on the CPU, whose compilation fills the loop's
hooks with :mod:`jointplay._kernels.sustained`; the GPU's ``run_batch`` refuses it
(:func:`jointplay._kernels.lanes.build.lanes_refusal`).

Where the single engine records every step, the loop reduces each accepted step as it is
taken (a GPU thread cannot keep its trajectory), with the single engine's interpolant
(:func:`hermite`, on the step and the step end before it: :func:`radau_dense`) and the peak
rule of :mod:`jointplay._kernels.batch`; the window opens at ``t_settle`` inside the step
that crosses it (``LANE``: Radau does not land on it).

References:
    .. [HW96] E. Hairer, G. Wanner, *Solving Ordinary Differential Equations II*, 2nd ed.,
       Springer, 1996, §IV.8; SciPy's ``scipy/integrate/_ivp/radau.py``.
"""

from __future__ import annotations

import math

import numpy as np  # the work allocator: the CPU's

# These names are resolved in the namespace build.py makes (the source's functions and
# constants); imported here only so that a reader (and the linters) can find them.
from jointplay._kernels.ids import (
    DIFF_FLOOR,
    DIFF_STEP,
    EPS,
    G_FILM,
    G_FILM_MODEL,
    K_JAC,
    K_LU,
    K_REJ_NEWTON,
    LAW_STEP,
    NUM_JAC_DIFF_BIG,
    NUM_JAC_DIFF_REJECT,
    NUM_JAC_DIFF_SMALL,
    NUM_JAC_FACTOR_DECREASE,
    NUM_JAC_FACTOR_INCREASE,
    NUM_JAC_MAX_FACTOR,
    NUM_JAC_MIN_FACTOR,
    RATE_FLOOR,
)
from jointplay._kernels.lanes.source import (
    FILM_EPS_CAP,
    FILM_LINEAR,
    FRICTION_NONE,
    G_CLEARANCE,
    G_R_BEARING,
    G_R_JOURNAL,
    G_ROUGHNESS,
    K_REJECTED,
    K_RHS,
    K_STEPS,
    LY_DRIVER,
    LY_FRIC_ID,
    LY_FRIC_P,
    LY_GEOM,
    LY_GRAVITY,
    LY_KEPT,
    LY_LAW_ID,
    LY_LAW_P,
    LY_MASS,
    LY_N,
    LY_NC,
    LY_NIDEAL,
    LY_PFRIC,
    LY_PLAW,
    LY_SECOND,
    LY_SIZE,
    N_GEOM,
    RECORD,
    any_film,
    contact_clearance,
    contact_forces,
    driver_acceleration,
    film_share,
    friction_force,
    hold_after_failure,
    initial_step,
    joint_kinematics,
    locked,
    normal_force,
    reynolds_force,
    reynolds_matrix,
    rhs,
    rhs_and_quantities,
    rms,
)

# --- method constants (verbatim from SciPy's radau.py; a test keeps them equal) ---------------
S6 = 6.0**0.5
RC1, RC2, RC3 = (4.0 - S6) / 10.0, (4.0 + S6) / 10.0, 1.0
RE1, RE2, RE3 = (-13.0 - 7.0 * S6) / 3.0, (-13.0 + 7.0 * S6) / 3.0, -1.0 / 3.0
MU_REAL = 3.0 + 3.0 ** (2.0 / 3.0) - 3.0 ** (1.0 / 3.0)
MU_COMPLEX_RE = 3.0 + 0.5 * (3.0 ** (1.0 / 3.0) - 3.0 ** (2.0 / 3.0))
MU_COMPLEX_IM = -0.5 * (3.0 ** (5.0 / 6.0) + 3.0 ** (7.0 / 6.0))
#: T and TI of the eigen-decomposition A = T Λ T⁻¹ (row-major, 3 × 3).
RT = (
    0.09443876248897524, -0.14125529502095421, 0.03002919410514742,
    0.25021312296533332, 0.20412935229379994, -0.38294211275726192,
    1.0, 1.0, 0.0,
)  # fmt: skip
RTI = (
    4.17871859155190428, 0.32768282076106237, 0.52337644549944951,
    -4.17871859155190428, -0.32768282076106237, 0.47662355450055044,
    0.50287263494578682, -2.57192694985560522, 0.59603920482822492,
)  # fmt: skip
#: Coefficients of the collocation polynomial (row-major, 3 × 3).
RP = (
    13.0 / 3.0 + 7.0 * S6 / 3.0, -23.0 / 3.0 - 22.0 * S6 / 3.0, 10.0 / 3.0 + 5.0 * S6,
    13.0 / 3.0 - 7.0 * S6 / 3.0, -23.0 / 3.0 + 22.0 * S6 / 3.0, 10.0 / 3.0 - 5.0 * S6,
    1.0 / 3.0, -8.0 / 3.0, 10.0 / 3.0,
)  # fmt: skip
NEWTON_MAXITER = 6
#: The interpolant's rules for the velocities between steps (:func:`hermite`).
RULE_RATES = 0
RULE_CUBIC_DERIVATIVE = 1
RULE_QUINTIC = 2
R_MIN_FACTOR, R_MAX_FACTOR = 0.2, 10.0


def pmin(a, b):
    """Python's ``min(a, b)``: ``a`` unless ``b < a`` (``min(1, nan) == 1``, as in SciPy)."""
    return b if b < a else a


def pmax(a, b):
    """Python's ``max(a, b)``: ``a`` unless ``b > a``."""
    return b if b > a else a


# --- complex numbers as pairs of floats ------------------------------------------------------
def cdiv(ar, ai, br, bi):
    """(ar + i ai) / (br + i bi) by CPython's algorithm (``_Py_c_quot``), as Numba divides
    complex numbers; NaN for a zero divisor (Numba raises there; the lane never divides by a
    zero pivot: a singular factor is left to give inf/NaN)."""
    abs_br = abs(br)
    abs_bi = abs(bi)
    if abs_br >= abs_bi:
        if abs_br == 0.0:
            return math.nan, math.nan
        ratio = bi / br
        denom = br + bi * ratio
        return (ar + ai * ratio) / denom, (ai - ar * ratio) / denom
    if abs_bi >= abs_br:
        ratio = br / bi
        denom = br * ratio + bi
        return (ar * ratio + ai) / denom, (ai * ratio - ar) / denom
    return math.nan, math.nan


# --- LU with partial pivoting (every compiled integrator's) -----------------------------------
def swap_rows(a, k, p, m):
    """Interchange rows ``k`` and ``p`` of the leading ``m`` columns of ``a`` (none if equal)."""
    if p != k:
        for j in range(m):
            tmp = a[k, j]
            a[k, j] = a[p, j]
            a[p, j] = tmp


def lu_real(a, piv, m):
    """LU of the leading m × m block of ``a`` in place, P·A = L·U as LAPACK's ``?getrf``
    (the same pivots, not the same round-off), row interchanges into ``piv`` (row k was
    swapped with row ``piv[k]``). A zero pivot is left in place: the solve then gives
    inf/NaN, which the integrators take as a failed Newton iteration (kernels never raise)."""
    for k in range(m):
        p = k
        amax = abs(a[k, k])
        for i in range(k + 1, m):
            v = abs(a[i, k])
            if v > amax:
                amax = v
                p = i
        piv[k] = p
        swap_rows(a, k, p, m)
        pivot = a[k, k]
        if pivot != 0:
            for i in range(k + 1, m):
                a[i, k] = a[i, k] / pivot
            for i in range(k + 1, m):
                lik = a[i, k]
                if lik != 0:
                    for j in range(k + 1, m):
                        a[i, j] -= lik * a[k, j]


def lu_complex(re, im, piv, m):
    """:func:`lu_real` for the complex matrix ``re + i im`` (pivot: largest |re| + |im|)."""
    for k in range(m):
        p = k
        amax = abs(re[k, k]) + abs(im[k, k])
        for i in range(k + 1, m):
            v = abs(re[i, k]) + abs(im[i, k])
            if v > amax:
                amax = v
                p = i
        piv[k] = p
        swap_rows(re, k, p, m)
        swap_rows(im, k, p, m)
        pr = re[k, k]
        pi = im[k, k]
        if pr != 0.0 or pi != 0.0:
            for i in range(k + 1, m):
                re[i, k], im[i, k] = cdiv(re[i, k], im[i, k], pr, pi)
            for i in range(k + 1, m):
                lr = re[i, k]
                li = im[i, k]
                if lr != 0.0 or li != 0.0:
                    for j in range(k + 1, m):
                        ur = re[k, j]
                        ui = im[k, j]
                        re[i, j] -= lr * ur - li * ui
                        im[i, j] -= lr * ui + li * ur


def lu_solve_real(a, piv, x, m):
    """Solve from :func:`lu_real`'s factors, ``x`` (m) overwritten by the solution."""
    for k in range(m):
        p = piv[k]
        if p != k:
            tmp = x[k]
            x[k] = x[p]
            x[p] = tmp
    for i in range(m):
        s = x[i]
        for j in range(i):
            s -= a[i, j] * x[j]
        x[i] = s
    for i in range(m - 1, -1, -1):
        s = x[i]
        for j in range(i + 1, m):
            s -= a[i, j] * x[j]
        x[i] = s / a[i, i]


def lu_solve_complex(re, im, piv, xr, xi, m):
    """Solve from :func:`lu_complex`'s factors, ``xr + i xi`` (m) overwritten."""
    for k in range(m):
        p = piv[k]
        if p != k:
            tmp = xr[k]
            xr[k] = xr[p]
            xr[p] = tmp
            tmp = xi[k]
            xi[k] = xi[p]
            xi[p] = tmp
    for i in range(m):
        sr = xr[i]
        si = xi[i]
        for j in range(i):
            sr -= re[i, j] * xr[j] - im[i, j] * xi[j]
            si -= re[i, j] * xi[j] + im[i, j] * xr[j]
        xr[i] = sr
        xi[i] = si
    for i in range(m - 1, -1, -1):
        sr = xr[i]
        si = xi[i]
        for j in range(i + 1, m):
            sr -= re[i, j] * xr[j] - im[i, j] * xi[j]
            si -= re[i, j] * xi[j] + im[i, j] * xr[j]
        xr[i], xi[i] = cdiv(sr, si, re[i, i], im[i, i])


# --- the Jacobian (eom.jacobian_state, every joint clear) -------------------------------------
def law_slopes(law, rp, o_law, fric, o_fric, delta, delta_dot, v_t, v0, f_n):
    """∂F_N/∂δ, ∂F_N/∂δ̇, ∂F_T/∂v_T, ∂F_T/∂F_N (forward differences,
    relative step √eps)."""
    h = max(LAW_STEP * delta, 1e-300)
    slope_delta = (normal_force(law, rp, o_law, delta + h, delta_dot, v0) - f_n) / h
    h = LAW_STEP * max(abs(delta_dot), RATE_FLOOR)
    slope_rate = (normal_force(law, rp, o_law, delta, delta_dot + h, v0) - f_n) / h
    if fric == FRICTION_NONE:
        return slope_delta, slope_rate, 0.0, 0.0
    per_newton = friction_force(fric, rp, o_fric, v_t, 1.0)
    h = LAW_STEP * max(abs(v_t), RATE_FLOOR)
    slope_slip = (friction_force(fric, rp, o_fric, v_t + h, f_n) - per_newton * f_n) / h
    return slope_delta, slope_rate, slope_slip, per_newton


def force_column(
    jac, rp, o_mass, column, a, b, fx, fy, dfx, dfy, pax, pay, dpax, dpay, pbx, pby, dpbx, dpby
):  # fmt: skip
    """Add to column ``column`` of the Jacobian the derivative (``dfx``, ``dfy``) of a force
    (``fx``, ``fy``) on body b at the arm p_b and of its opposite on body a at p_a, with the
    arms' derivatives dp (eom's ``_add_force_column``, the same arithmetic)."""
    if b >= 0:
        jac[3 * b, column] += dfx / rp[o_mass + 3 * b]
        jac[3 * b + 1, column] += dfy / rp[o_mass + 3 * b + 1]
        moment = dpbx * fy - dpby * fx + pbx * dfy - pby * dfx
        jac[3 * b + 2, column] += moment / rp[o_mass + 3 * b + 2]
    if a >= 0:
        jac[3 * a, column] -= dfx / rp[o_mass + 3 * a]
        jac[3 * a + 1, column] -= dfy / rp[o_mass + 3 * a + 1]
        moment = dpax * fy - dpay * fx + pax * dfy - pay * dfx
        jac[3 * a + 2, column] -= moment / rp[o_mass + 3 * a + 2]


def coordinate_direction(k, sign, rx, ry, w):
    """(∂e_x, ∂e_y, ∂ė_x, ∂ė_y) along coordinate ``k`` (x, y, φ, ẋ, ẏ, ω) of one of a clearance
    joint's bodies, the journal's (``sign`` +1) or the bearing's (−1), whose centre has the
    arm (``rx``, ``ry``) and which turns at ``w``: ∂e/∂(x, y) = ±I, ∂e/∂φ = ±ẑ×r,
    ∂ė/∂φ = ∓ω r, ∂ė/∂(ẋ, ẏ) = ±I, ∂ė/∂ω = ±ẑ×r."""
    if k == 0:
        return sign, 0.0, 0.0, 0.0
    if k == 1:
        return 0.0, sign, 0.0, 0.0
    if k == 2:
        return -sign * ry, sign * rx, -sign * w * rx, -sign * w * ry
    if k == 3:
        return 0.0, 0.0, sign, 0.0
    if k == 4:
        return 0.0, 0.0, 0.0, sign
    return 0.0, 0.0, -sign * ry, sign * rx


def side_of(side, a, b, rax, ray, rbx, rby, wa, wb):
    """Side ``side`` of a clearance joint's force in the Jacobian: 0 the journal's body b, 1
    the bearing's body a; (body, the force's sign on it, its arm x, y, the body's rate)."""
    if side == 0:
        return b, 1.0, rbx, rby, wb
    return a, -1.0, rax, ray, wa


def body_column(jac, rp, o_mass, n, side, body, k, a, b, fx, fy, dfx, dfy, rax, ray, rbx, rby):
    """Add to ``jac`` the column of coordinate ``k`` (x, y, φ, ẋ, ẏ, ω) of ``body``, side
    ``side`` of a clearance joint (:func:`side_of`), for a force (``fx``, ``fy``) on the
    journal's body b at its arm r_b and its opposite on the bearing's body a at r_a whose
    derivative along that coordinate is (``dfx``, ``dfy``) (:func:`force_column`; the arm of
    the body itself turns with φ: ∂r = ẑ×r). Returns the column's index."""
    column = 3 * body + k if k < 3 else n + 3 * body + k - 3
    drbx = 0.0
    drby = 0.0
    drax = 0.0
    dray = 0.0
    if k == 2 and side == 0:
        drbx, drby = -rby, rbx
    elif k == 2:
        drax, dray = -ray, rax
    force_column(
        jac, rp, o_mass, column, a, b, fx, fy, dfx, dfy, rax, ray, drax, dray, rbx, rby, drbx, drby
    )
    return column


def film_jacobian(jac, film, rp, o_mass, n, a, b, rax, ray, rbx, rby, wa, wb, edx, edy):
    """Add one clearance joint's film damping to ``jac`` (:func:`jacobian_clear`'s rows and
    columns): f = −c_e ė on the journal's
    body b at its arm r_b, −f on the bearing's body a at r_a, power c_e |ė|² into the
    W_contact row; ė = (``edx``, ``edy``), the bodies' rates ``wa``, ``wb``."""
    fx = -film * edx
    fy = -film * edy
    for side in range(2):
        body, sign, rx, ry, w = side_of(side, a, b, rax, ray, rbx, rby, wa, wb)
        if body < 0:
            continue
        for k in range(2, 6):  # φ, ẋ, ẏ, ω of this body (ė does not depend on x, y)
            _, _, dvx, dvy = coordinate_direction(k, sign, rx, ry, w)
            column = body_column(
                jac, rp, o_mass, n, side, body, k, a, b, fx, fy, -film * dvx, -film * dvy,
                rax, ray, rbx, rby,
            )  # fmt: skip
            jac[n + 1, column] += 2.0 * film * (edx * dvx + edy * dvy)


def reynolds_position_slope(form, coef, clearance, roughness, ex, ey, edx, edy, wa, wb, i):
    """The derivative of a Reynolds film's force :func:`reynolds_force` with respect to e_x
    (``i`` 0) or e_y (1) at fixed ė and rates, (∂f_x, ∂f_y), by a central difference with the
    step ∛eps · max(|e|, c) (the closed forms lose digits to cancellation as ε nears 1: a
    forward difference's √eps step would amplify that round-off 1e3-fold)."""
    h = EPS ** (1.0 / 3.0) * pmax(math.sqrt(ex * ex + ey * ey), clearance)
    if i == 0:
        h = (ex + h) - ex
        ux, uy = reynolds_force(form, coef, clearance, roughness, ex + h, ey, edx, edy, wa, wb)
        dx, dy = reynolds_force(form, coef, clearance, roughness, ex - h, ey, edx, edy, wa, wb)
    else:
        h = (ey + h) - ey
        ux, uy = reynolds_force(form, coef, clearance, roughness, ex, ey + h, edx, edy, wa, wb)
        dx, dy = reynolds_force(form, coef, clearance, roughness, ex, ey - h, edx, edy, wa, wb)
    return (ux - dx) / (2.0 * h), (uy - dy) / (2.0 * h)


def reynolds_jacobian(jac, form, coef, clearance, roughness, rp, o_mass, n, a, b, rax, ray,
                      rbx, rby, wa, wb, ex, ey, edx, edy):  # fmt: skip
    """Add one clearance joint's Reynolds film to ``jac`` (:func:`jacobian_clear`'s rows and
    columns): F = :func:`reynolds_force` on the journal's body b at its arm r_b, −F on the
    bearing's body a at r_a, power −F·ė into the W_contact row. F = k (F_r n + F_t t) is linear
    in (ė_r, wedge) through :func:`reynolds_matrix` M, which is also its exact derivative
    there (the π-film's moving ends add nothing), so its derivatives with respect to ė, ω_a,
    ω_b are M's (ė_r = ė·n, wedge = |e| (ω_a + ω_b)/2 − ė·t); with respect to e, central
    differences (:func:`reynolds_position_slope`); chained to the bodies' coordinates and
    rates in closed form (e = r_J − r_B, ė = ṙ_J − ṙ_B with r_J = x_b + A(φ_b) s_b,
    ṙ_J = ẋ_b + ω_b ẑ × r_b; the bearing's the same with minus)."""
    fx, fy = reynolds_force(form, coef, clearance, roughness, ex, ey, edx, edy, wa, wb)
    length = math.sqrt(ex * ex + ey * ey)
    nx = 1.0
    ny = 0.0
    if length > 0.0:
        nx, ny = ex / length, ey / length
    tx, ty = -ny, nx
    rate = edx * nx + edy * ny
    wedge = 0.5 * length * (wa + wb) - (edx * tx + edy * ty)
    m_rr, m_rw, m_tr, m_tw = reynolds_matrix(
        form, min(length / clearance, FILM_EPS_CAP), rate, wedge
    )
    k = coef / math.pi * film_share(clearance, roughness, length)  # the film's share
    # ∂(F_r, F_t)/∂ė_x and /∂ė_y (rate' = n, wedge' = −t), then to the global frame
    r_x = m_rr * nx - m_rw * tx
    t_x = m_tr * nx - m_tw * tx
    r_y = m_rr * ny - m_rw * ty
    t_y = m_tr * ny - m_tw * ty
    fx_vx, fy_vx = k * (r_x * nx + t_x * tx), k * (r_x * ny + t_x * ty)
    fx_vy, fy_vy = k * (r_y * nx + t_y * tx), k * (r_y * ny + t_y * ty)
    half = 0.5 * length * k  # wedge' = |e|/2 for ω_a and ω_b alike
    fx_w, fy_w = half * (m_rw * nx + m_tw * tx), half * (m_rw * ny + m_tw * ty)
    fx_ex, fy_ex = reynolds_position_slope(
        form, coef, clearance, roughness, ex, ey, edx, edy, wa, wb, 0
    )
    fx_ey, fy_ey = reynolds_position_slope(
        form, coef, clearance, roughness, ex, ey, edx, edy, wa, wb, 1
    )
    for side in range(2):
        body, sign, rx, ry, w = side_of(side, a, b, rax, ray, rbx, rby, wa, wb)
        if body < 0:
            continue
        for k_col in range(6):  # x, y, φ, ẋ, ẏ, ω of this body
            de0, de1, dv0, dv1 = coordinate_direction(k_col, sign, rx, ry, w)
            dw = 1.0 if k_col == 5 else 0.0
            dfx = fx_ex * de0 + fx_ey * de1 + fx_vx * dv0 + fx_vy * dv1 + fx_w * dw
            dfy = fy_ex * de0 + fy_ey * de1 + fy_vx * dv0 + fy_vy * dv1 + fy_w * dw
            column = body_column(
                jac, rp, o_mass, n, side, body, k_col, a, b, fx, fy, dfx, dfy, rax, ray, rbx, rby
            )
            jac[n + 1, column] -= dfx * edx + dfy * edy + fx * dv0 + fy * dv1


def jacobian_clear(t, y, rp, ip, lay, jac, force, record):
    """Rows n … S − 1, columns 0 … 2n − 1 of ∂ẏ/∂y (the rows and columns the Newton systems
    read) into ``jac`` ((S − n) × 2n: row r of ∂ẏ/∂y is ``jac[r − n]``), for a mechanism whose
    joints are all clear (:func:`eom.jacobian_state`, the same arithmetic, film damping's
    terms included: :func:`film_jacobian`; its docstring for the derivation). ``force`` (S), ``record`` (7 nc): work."""
    n = lay[LY_N]
    nc = lay[LY_NC]
    size = lay[LY_SIZE]
    o_geom = lay[LY_GEOM]
    o_mass = lay[LY_MASS]
    plaw = lay[LY_PLAW]
    pfric = lay[LY_PFRIC]
    for r in range(size - n):
        for col in range(2 * n):
            jac[r, col] = 0.0
    power_row = n + 1  # 2n + 1 − n
    for c in range(nc):
        a, b, rax, ray, rbx, rby, length, nx, ny, wa, wb, edx, edy = joint_kinematics(
            y, rp, ip, lay, c
        )
        delta = length - contact_clearance(rp, lay, c)  # the asperities' under a Reynolds film
        delta_dot = edx * nx + edy * ny
        slide = -edx * ny + edy * nx
        r_j = rp[o_geom + N_GEOM * c + G_R_JOURNAL]
        r_b = rp[o_geom + N_GEOM * c + G_R_BEARING]
        v_t = slide + r_j * wb - r_b * wa
        film = rp[o_geom + N_GEOM * c + G_FILM]  # this joint's c_e; 0: dry
        if film > 0.0:
            form = rp[o_geom + N_GEOM * c + G_FILM_MODEL]
            if form == FILM_LINEAR:
                film_jacobian(jac, film, rp, o_mass, n, a, b, rax, ray, rbx, rby, wa, wb, edx, edy)
            else:
                reynolds_jacobian(
                    jac, int(form), film, rp[o_geom + N_GEOM * c + G_CLEARANCE],
                    rp[o_geom + N_GEOM * c + G_ROUGHNESS], rp, o_mass, n, a, b,
                    rax, ray, rbx, rby, wa, wb, length * nx, length * ny, edx, edy,
                )  # fmt: skip
        if not delta > 0.0:
            continue
        tx, ty = -ny, nx
        law = ip[lay[LY_LAW_ID] + c]
        fric = ip[lay[LY_FRIC_ID] + c]
        o_law = lay[LY_LAW_P] + plaw * c
        o_fric = lay[LY_FRIC_P] + pfric * c
        v0 = y[2 * n + 2 + c]
        f_n = normal_force(law, rp, o_law, delta, delta_dot, v0)
        f_t = 0.0
        if fric != FRICTION_NONE:
            f_t = friction_force(fric, rp, o_fric, v_t, f_n)
        n_delta, n_rate, t_slip, t_normal = law_slopes(
            law, rp, o_law, fric, o_fric, delta, delta_dot, v_t, v0, f_n
        )
        fx = -f_n * nx - f_t * tx
        fy = -f_n * ny - f_t * ty
        pbx, pby = rbx + r_j * nx, rby + r_j * ny
        pax, pay = rax + r_b * nx, ray + r_b * ny
        for side in range(2):
            body, sign, rx, ry, w = side_of(side, a, b, rax, ray, rbx, rby, wa, wb)
            if body < 0:
                continue
            for k in range(6):
                de0, de1, dv0, dv1 = coordinate_direction(k, sign, rx, ry, w)
                dw_b = 1.0 if k == 5 and side == 0 else 0.0
                dw_a = 1.0 if k == 5 and side == 1 else 0.0
                tangential = (tx * de0 + ty * de1) / length
                d_delta = nx * de0 + ny * de1
                d_rate = nx * dv0 + ny * dv1 + slide * tangential
                d_slip = tx * dv0 + ty * dv1 - delta_dot * tangential + r_j * dw_b - r_b * dw_a
                d_fn = n_delta * d_delta + n_rate * d_rate
                d_ft = t_slip * d_slip + t_normal * d_fn
                dfx = -d_fn * nx - d_ft * tx + (-f_n * tx + f_t * nx) * tangential
                dfy = -d_fn * ny - d_ft * ty + (-f_n * ty + f_t * ny) * tangential
                dpbx, dpby = r_j * tx * tangential, r_j * ty * tangential
                dpax, dpay = r_b * tx * tangential, r_b * ty * tangential
                if k == 2 and side == 0:
                    dpbx -= rby
                    dpby += rbx
                elif k == 2:
                    dpax -= ray
                    dpay += rax
                column = 3 * body + k if k < 3 else n + 3 * body + k - 3
                force_column(
                    jac, rp, o_mass, column, a, b, fx, fy, dfx, dfy,
                    pax, pay, dpax, dpay, pbx, pby, dpbx, dpby,
                )  # fmt: skip
                jac[power_row, column] += (
                    d_fn * delta_dot + f_n * d_rate + d_ft * v_t + f_t * d_slip
                )
    crank = int(rp[lay[LY_DRIVER]])
    if crank >= 0:
        k = 3 * crank + 2
        omega = y[n + k]
        for i in range(n):
            force[n + i] = rp[lay[LY_GRAVITY] + i]
        contact_forces(y, rp, ip, lay, force, record, False)
        torque = rp[o_mass + k] * driver_acceleration(t, rp, lay[LY_DRIVER]) - force[n + k]
        for column in range(2 * n):
            jac[n, column] = -omega * rp[o_mass + k] * jac[k, column]
            jac[k, column] = 0.0
        jac[n, n + k] += torque


def column_difference(f, f_col, diff, size):
    """``diff = f_col − f``; returns its largest |entry| (the first) and the scale of that
    entry, max(|f|, |f_col|) there (SciPy's ``num_jac``)."""
    for i in range(size):
        diff[i] = f_col[i] - f[i]
    imax = 0
    vmax = abs(diff[0])
    for i in range(1, size):
        v = abs(diff[i])
        if v > vmax:
            vmax = v
            imax = i
    return vmax, max(abs(f[imax]), abs(f_col[imax]))


def jacobian_differences(t, y, f, atol, factor, sign, rp, ip, lay, jac, ytmp, f_col, diff,
                         diff_new, record, phi_q, schur, lam):  # fmt: skip
    """The columns 0 … m2 + nk − 1 (``LY_SECOND``, ``LY_KEPT``: the passive ones left out) of
    ∂f/∂y by SciPy's ``num_jac`` (dense branch: forward differences with adaptive relative
    steps ``factor`` (S, kept from call to call), each in the direction of ``sign·f``, SciPy's
    f (``sign``: −1 in a lane that runs its user's time backwards); a column drowned in
    round-off retried with a 10x step; a factor capped at ``NUM_JAC_MAX_FACTOR``, where
    SciPy's grows until the Jacobian is NaN), rows m2 … S − 1 into ``jac`` as
    :func:`jacobian_clear` writes them: the Jacobian of a mechanism with ideal joints, or of
    a user's problem without one. ``ytmp``, ``f_col``, ``diff``, ``diff_new`` (S): work. Its
    evaluations of f are not counted (as SciPy's ``njev``)."""
    m2 = lay[LY_SECOND]
    size = lay[LY_SIZE]
    for i in range(size):
        ytmp[i] = y[i]
    for j in range(m2 + lay[LY_KEPT]):
        f_sign = 1.0 if sign * f[j] >= 0 else -1.0
        y_scale = f_sign * max(atol[j], abs(y[j]))
        h = (y[j] + factor[j] * y_scale) - y[j]
        while h == 0:
            factor[j] *= 10.0
            h = (y[j] + factor[j] * y_scale) - y[j]
        ytmp[j] = y[j] + h
        rhs(t, ytmp, rp, ip, lay, f_col, record, False, phi_q, schur, lam)
        ytmp[j] = y[j]
        max_diff, scale = column_difference(f, f_col, diff, size)
        if not max_diff < NUM_JAC_DIFF_REJECT * scale:
            pass
        else:
            new_factor = NUM_JAC_FACTOR_INCREASE * factor[j]
            h_new = (y[j] + new_factor * y_scale) - y[j]
            ytmp[j] = y[j] + h_new
            rhs(t, ytmp, rp, ip, lay, f_col, record, False, phi_q, schur, lam)
            ytmp[j] = y[j]
            max_diff_new, scale_new = column_difference(f, f_col, diff_new, size)
            if max_diff * scale_new < max_diff_new * scale:
                factor[j] = new_factor
                h = h_new
                for i in range(size):
                    diff[i] = diff_new[i]
                scale = scale_new
                max_diff = max_diff_new
        for i in range(m2, size):
            jac[i - m2, j] = diff[i] / h
        if max_diff < NUM_JAC_DIFF_SMALL * scale:
            factor[j] *= NUM_JAC_FACTOR_INCREASE
        elif max_diff > NUM_JAC_DIFF_BIG * scale:
            factor[j] *= NUM_JAC_FACTOR_DECREASE
        factor[j] = min(max(factor[j], NUM_JAC_MIN_FACTOR), NUM_JAC_MAX_FACTOR)


def jacobian_fixed(t, y, f, rp, ip, lay, jac, ytmp, f_col, record, phi_q, schur, lam):
    """The columns 0 … 2n − 1 of ∂ẏ/∂y by forward differences with the fixed step
    √eps·max(|y_j|, floor), rows
    n … S − 1 into ``jac``: the Jacobian of a mechanism with ideal joints and film damping.
    ``ytmp``, ``f_col`` (S): work."""
    n = lay[LY_N]
    size = lay[LY_SIZE]
    for i in range(size):
        ytmp[i] = y[i]
    for j in range(2 * n):
        h = (y[j] + DIFF_STEP * pmax(abs(y[j]), DIFF_FLOOR)) - y[j]
        ytmp[j] = y[j] + h
        rhs(t, ytmp, rp, ip, lay, f_col, record, False, phi_q, schur, lam)
        ytmp[j] = y[j]
        for i in range(n, size):
            jac[i - n, j] = (f_col[i] - f[i]) / h


def lane_jacobian(t, y, f, atol, factor, rp, ip, lay, jac, ytmp, f_col, diff, diff_new,
                  record, phi_q, schur, lam):  # fmt: skip
    """The Radau kernel's Jacobian as the single engine takes it (:func:`eom.jacobian_state`):
    the closed form (:func:`jacobian_clear`) when every joint is clear, fixed-step
    differences (:func:`jacobian_fixed`) with ideal joints and film damping, else — ideal
    joints without film, or a joint locked (the sustained-contact mode) — SciPy's
    differences (:func:`jacobian_differences`)."""
    if locked(y, rp, lay) or (lay[LY_NIDEAL] > 0 and not any_film(rp, lay)):
        jacobian_differences(t, y, f, atol, factor, 1.0, rp, ip, lay, jac, ytmp, f_col, diff,
                             diff_new, record, phi_q, schur, lam)  # fmt: skip
    elif lay[LY_NIDEAL] == 0:
        jacobian_clear(t, y, rp, ip, lay, jac, f_col, record)
    else:
        jacobian_fixed(t, y, f, rp, ip, lay, jac, ytmp, f_col, record, phi_q, schur, lam)


# --- the Newton systems ------------------------------------------------------------------------
# Written for any second-order structure: ``m2`` positions (x' = v, RADAU5's M1 option),
# ``nk`` kept components after them (velocities first, then the other active ones), passive
# components from ``m2 + nk`` to ``size``; ``jac`` holds the rows from ``m2`` on of ∂f/∂y
# (row r of ∂f/∂y is ``jac[r − m2]``), columns 0 … m2 + nk − 1. The implicit lane's:
# ``m2 = nk = n``; the single engine's: its ``n_second`` and ``n_active − n_second``.
def newton_matrix(jac, mu_over_h, a, m2, nk):
    """The kept block of ``γ/h·I − J`` (real ``mu_over_h = γ/h``) into ``a`` (nk × nk), the
    positions' columns folded in (dx = h/γ (b_x + dv)): Radau's real Newton matrix and
    RODAS4's."""
    for i in range(nk):
        for j in range(nk):
            a[i, j] = -jac[i, m2 + j]
        a[i, i] += mu_over_h
        for j in range(m2):
            a[i, j] -= jac[i, j] / mu_over_h


def factor_newton(jac, h, a_re, piv_re, c_re, c_im, piv_c, m2, nk):
    """LU factors of the reduced Newton matrices MU_REAL/h·I − J (``a_re``) and
    MU_COMPLEX/h·I − J (``c_re + i c_im``) ([HW96] §IV.8, RADAU5's M1)."""
    newton_matrix(jac, MU_REAL / h, a_re, m2, nk)
    mcr = MU_COMPLEX_RE / h
    mci = MU_COMPLEX_IM / h
    for i in range(nk):
        for j in range(nk):
            c_re[i, j] = -jac[i, m2 + j]
            c_im[i, j] = 0.0
        c_re[i, i] += mcr
        c_im[i, i] += mci
        for j in range(m2):
            qr, qi = cdiv(jac[i, j], 0.0, mcr, mci)
            c_re[i, j] -= qr
            c_im[i, j] -= qi
    lu_real(a_re, piv_re, nk)
    lu_complex(c_re, c_im, piv_c, nk)


def solve_real(a_re, piv_re, jac, mu_over_h, x, work, m2, nk, size):
    """(γ/h·I − J) x = b for a real γ/h = ``mu_over_h`` from :func:`newton_matrix`'s factors,
    ``x`` (size) b on entry, ``work`` (nk): the kept block solves
    (γ/h·I − J_KK − h/γ·J_Kx E) d_K = b_K + h/γ·J_Kx b_x, then dx = h/γ (b_x + dv) and each
    passive component h/γ (b_p + J_p x). In exact arithmetic, the full system's solution."""
    h_over_mu = 1.0 / mu_over_h
    for i in range(nk):
        s = x[m2 + i]
        for j in range(m2):
            s += h_over_mu * jac[i, j] * x[j]
        work[i] = s
    lu_solve_real(a_re, piv_re, work, nk)
    for j in range(m2):
        x[j] = h_over_mu * (x[j] + work[j])
    for i in range(nk):
        x[m2 + i] = work[i]
    for p in range(m2 + nk, size):
        s = x[p]
        for j in range(m2 + nk):
            s += jac[p - m2, j] * x[j]
        x[p] = h_over_mu * s


def solve_complex(c_re, c_im, piv_c, jac, mr, mi, xr, xi, wr, wi, m2, nk, size):
    """:func:`solve_real` for the complex γ/h = mr + i mi, ``xr + i xi``."""
    hr, hi = cdiv(1.0, 0.0, mr, mi)
    for i in range(nk):
        sr = xr[m2 + i]
        si = xi[m2 + i]
        for j in range(m2):
            ar = hr * jac[i, j]
            ai = hi * jac[i, j]
            sr += ar * xr[j] - ai * xi[j]
            si += ar * xi[j] + ai * xr[j]
        wr[i] = sr
        wi[i] = si
    lu_solve_complex(c_re, c_im, piv_c, wr, wi, nk)
    for j in range(m2):
        sr = xr[j] + wr[j]
        si = xi[j] + wi[j]
        xr[j] = hr * sr - hi * si
        xi[j] = hr * si + hi * sr
    for i in range(nk):
        xr[m2 + i] = wr[i]
        xi[m2 + i] = wi[i]
    for p in range(m2 + nk, size):
        sr = xr[p]
        si = xi[p]
        for j in range(m2 + nk):
            sr += jac[p - m2, j] * xr[j]
            si += jac[p - m2, j] * xi[j]
        xr[p] = hr * sr - hi * si
        xi[p] = hr * si + hi * sr


def stage_norm(x, scale, size):
    """SciPy's norm(x / scale) of the stages (3, S), ``scale`` broadcast on rows."""
    s = 0.0
    for i in range(3):
        for j in range(size):
            v = x[i, j] / scale[j]
            s += v * v
    return math.sqrt(s) / math.sqrt(3 * size)


def mat3(m, z, out, size):
    """``out = m @ z`` for m (9, row-major) and (3, S) stages."""
    for i in range(3):
        for j in range(size):
            out[i, j] = 0.0
        for k in range(3):
            mik = m[3 * i + k]
            for j in range(size):
                out[i, j] += mik * z[k, j]


def predict(h_abs, h_abs_old, error_norm, error_norm_old):
    """The predictive controller's step factor ([HW96] §IV.8, (8.25); SciPy's): NaN in
    ``h_abs_old`` or ``error_norm_old`` stands for SciPy's ``None`` (one-step controller)."""
    if math.isnan(error_norm_old) or math.isnan(h_abs_old) or error_norm == 0.0:
        multiplier = 1.0
    else:
        multiplier = h_abs / h_abs_old * (error_norm_old / error_norm) ** 0.25
    return pmin(1.0, multiplier) * error_norm**-0.25


def next_factor(h, h_old, error_norm, error_norm_old, safety, hold, recompute_jac):
    """The factor of the next step's size after an accepted one: the predictive controller
    ([HW96] (8.25), :func:`predict`) times the Newton safety factor, at most R_MAX_FACTOR,
    at most 1 after a failed try when ``hold`` (RADAU5: IF (REJECT) HNEW = MIN(HNEW, H)),
    and exactly 1 when it would grow less than 1.2 and the Jacobian is not recomputed
    (``recompute_jac``). Returns ``(factor, kept)``: kept, the step size and with it the LU
    factors of the Newton matrices."""
    factor = predict(h, h_old, error_norm, error_norm_old)
    factor = pmin(R_MAX_FACTOR, safety * factor)
    if hold:
        factor = pmin(factor, 1.0)
    if not recompute_jac and factor < 1.2:
        return 1.0, True
    return factor, False


# --- the collocation system (SciPy's solve_collocation_system, in pieces) ---------------------
# A Newton iteration is: the three stage points (:func:`stage_point`), f at each (the
# caller's right-hand side: the lane's :func:`rhs`, the single engine's ``fun``), then
# :func:`newton_iteration`; the loop is :func:`collocation` (the lane's) or
# ``radau._collocation`` (the single engine's), started by :func:`newton_start`.
def newton_start(t, y, h, has_sol, cq, t_old, y_old, z, w, size):
    """The Newton start ``Z`` (``z`` (3, S)) and ``W = TI Z`` (``w``): from the last step's
    collocation polynomial (``has_sol``; ``cq`` (3, S) its coefficients :func:`polynomial`,
    ``t_old``, ``y_old`` its start: Z_i = sol(t + c_i h) − y, SciPy's ``RadauDenseOutput``),
    else zero."""
    if has_sol:
        h_prev = t - t_old
        for i in range(3):
            ci = RC1 if i == 0 else (RC2 if i == 1 else RC3)
            x = (t + h * ci - t_old) / h_prev
            x2 = x * x
            x3 = x2 * x
            for j in range(size):
                z[i, j] = (cq[0, j] * x + cq[1, j] * x2 + cq[2, j] * x3) + y_old[j] - y[j]
    else:
        for i in range(3):
            for j in range(size):
                z[i, j] = 0.0
    mat3(RTI, z, w, size)


def stage_point(t, h, y, z, i, ytmp, size):
    """Stage ``i``'s state y + Z_i into ``ytmp``; returns its time t + c_i h."""
    for j in range(size):
        ytmp[j] = y[j] + z[i, j]
    return t + h * (RC1 if i == 0 else (RC2 if i == 1 else RC3))


def newton_iteration(fst, h, w, z, dw, scale, tol, k, dw_norm_old, rate, jac, a_re, piv_re,
                     c_re, c_im, piv_c, xr, xcr, xci, wk, wkr, wki, m2, nk, size):  # fmt: skip
    """Iteration ``k`` of the simplified Newton iteration, f at the stages in ``fst`` (3, S):
    the increment dW in the transformed variables (one real and one complex solve), the
    convergence test on its norm and rate, W += dW, Z = T W. ``dw_norm_old`` and ``rate``: the
    last iteration's (``rate`` NaN while undefined). Returns ``(done, converged, dw_norm,
    rate)``: ``done`` ends the iteration (converged, diverging or a non-finite stage)."""
    for i in range(3):
        for j in range(size):
            if not math.isfinite(fst[i, j]):
                return True, False, dw_norm_old, rate
    m_real = MU_REAL / h
    mcr = MU_COMPLEX_RE / h
    mci = MU_COMPLEX_IM / h
    for j in range(size):
        fr = 0.0
        fcr = 0.0
        fci = 0.0
        for i in range(3):
            fr += fst[i, j] * RTI[i]
            fcr += fst[i, j] * RTI[3 + i]
            fci += fst[i, j] * RTI[6 + i]
        xr[j] = fr - m_real * w[0, j]
        xcr[j] = fcr - (mcr * w[1, j] - mci * w[2, j])
        xci[j] = fci - (mcr * w[2, j] + mci * w[1, j])
    solve_real(a_re, piv_re, jac, m_real, xr, wk, m2, nk, size)
    solve_complex(c_re, c_im, piv_c, jac, mcr, mci, xcr, xci, wkr, wki, m2, nk, size)
    for j in range(size):
        dw[0, j] = xr[j]
        dw[1, j] = xcr[j]
        dw[2, j] = xci[j]
    dw_norm = stage_norm(dw, scale, size)
    if k > 0:
        rate = dw_norm / dw_norm_old
        if rate >= 1 or rate ** (NEWTON_MAXITER - k) / (1 - rate) * dw_norm > tol:
            return True, False, dw_norm, rate
    for i in range(3):
        for j in range(size):
            w[i, j] += dw[i, j]
    mat3(RT, w, z, size)
    if dw_norm == 0 or (k > 0 and rate / (1 - rate) * dw_norm < tol):
        return True, True, dw_norm, rate
    return False, False, dw_norm, rate


def collocation(t, y, h, has_sol, cq, t_old, y_old, scale, tol, rp, ip, lay, jac, a_re,
                piv_re, c_re, c_im, piv_c, w, z, fst, dw, ytmp, xr, xcr, xci, wk, wkr, wki,
                record, phi_q, schur, lam):  # fmt: skip
    """The lane's simplified Newton iteration of the collocation system (SciPy's
    ``solve_collocation_system``) on :func:`rhs`. Returns ``(converged, iterations, rate,
    evaluations of f)``; the stage increments Z in ``z``."""
    size = lay[LY_SIZE]
    newton_start(t, y, h, has_sol, cq, t_old, y_old, z, w, size)
    converged = False
    dw_norm = 0.0
    rate = math.nan
    k = 0
    for k in range(NEWTON_MAXITER):
        for i in range(3):
            t_i = stage_point(t, h, y, z, i, ytmp, size)
            rhs(t_i, ytmp, rp, ip, lay, fst[i], record, False, phi_q, schur, lam)
        done, converged, dw_norm, rate = newton_iteration(
            fst, h, w, z, dw, scale, tol, k, dw_norm, rate, jac, a_re, piv_re, c_re, c_im,
            piv_c, xr, xcr, xci, wk, wkr, wki, lay[LY_SECOND], lay[LY_KEPT], size,
        )  # fmt: skip
        if done:
            break
    return converged, k + 1, rate, 3 * (k + 1)


def error_estimate(z, f, h, y, y_new, atol, rtol, ze, x, work, escale, jac, a_re, piv_re,
                   m2, nk, size):  # fmt: skip
    """The embedded error estimate (MU_REAL/h·I − J)⁻¹ (f + ZE) into ``x``, ZE = Zᵀ E / h into
    ``ze``, the error scale atol + max(|y|, |y_new|)·rtol into ``escale``; returns the
    estimate's norm."""
    for j in range(size):
        ze[j] = (z[0, j] * RE1 + z[1, j] * RE2 + z[2, j] * RE3) / h
        x[j] = f[j] + ze[j]
    solve_real(a_re, piv_re, jac, MU_REAL / h, x, work, m2, nk, size)
    for j in range(size):
        escale[j] = atol[j] + max(abs(y[j]), abs(y_new[j])) * rtol
    return rms(x, escale, size)


def error_again(f_err, ze, h, x, work, escale, jac, a_re, piv_re, m2, nk, size):
    """The estimate after a rejection (SciPy's): ``f_err`` = f(t, y + error) in place of f,
    (MU_REAL/h·I − J)⁻¹ (f_err + ZE) into ``x``; returns its norm."""
    for j in range(size):
        x[j] = f_err[j] + ze[j]
    solve_real(a_re, piv_re, jac, MU_REAL / h, x, work, m2, nk, size)
    return rms(x, escale, size)


def polynomial(z, cq, size):
    """The step's collocation polynomial for the next Newton start: Q = Zᵀ P into ``cq``
    (3, S)."""
    for j in range(size):
        for kk in range(3):
            s = 0.0
            for i in range(3):
                s += z[i, j] * RP[3 * i + kk]
            cq[kk, j] = s


def touching(pen, nc):
    """Which of the ``nc`` clearance joints touch (δ > 0, ``pen``), one bit each."""
    bits = 0
    for c in range(nc):
        if pen[c] > 0.0:
            bits |= 1 << c
    return bits


def interpolation_rule(film, has_before, bits_before, bits_start, bits_end):
    """The :func:`hermite` rule of a step whose ends touch as ``bits_start``, ``bits_end``
    (:func:`touching`) and whose preceding step (if ``has_before``) started as
    ``bits_before``: :func:`jointplay.dynamics.simulate.smooth_steps`."""
    if not film:
        return RULE_RATES
    if has_before and bits_before == bits_start and bits_start == bits_end:
        return RULE_QUINTIC
    return RULE_CUBIC_DERIVATIVE


def hermite(tp, yp, t0, y0, f0, t1, y1, f1, n, size, tau, out, rule):
    """The single engine's interpolant (:func:`jointplay.dynamics.simulate._interpolate`;
    the production implicit lanes compile this one too, ``batch.lanes_hermite``) in the
    step from ``t0`` to ``t1``, ``tp``, ``yp`` the step end before it, q̈ = ``f[n:2n]``,
    with the velocities' ``rule``: the cubic Hermite of q̇ with q̈
    (``RULE_RATES``, no film), the derivative of q's cubic (``RULE_CUBIC_DERIVATIVE``), or q
    and q̇ from the quintic through q and q̇ at the three step ends (``RULE_QUINTIC``); the
    work integrals linear, the impact memory held at the step's start."""
    h = t1 - t0
    s = (tau - t0) / h
    if rule == RULE_QUINTIC:
        for i in range(n):
            s01 = (y0[i] - yp[i]) / (t0 - tp)
            s12 = (y1[i] - y0[i]) / (t1 - t0)
            f012 = (s01 - yp[n + i]) / (t0 - tp)
            f123 = (y0[n + i] - s01) / (t0 - tp)
            f234 = (s12 - y0[n + i]) / (t1 - t0)
            f345 = (y1[n + i] - s12) / (t1 - t0)
            f0123 = (f123 - f012) / (t0 - tp)
            f1234 = (f234 - f123) / (t1 - tp)
            f2345 = (f345 - f234) / (t1 - t0)
            f01234 = (f1234 - f0123) / (t1 - tp)
            f12345 = (f2345 - f1234) / (t1 - tp)
            value = (f12345 - f01234) / (t1 - tp)
            rate = 0.0
            rate = rate * (tau - t1) + value
            value = value * (tau - t1) + f01234
            rate = rate * (tau - t0) + value
            value = value * (tau - t0) + f0123
            rate = rate * (tau - t0) + value
            value = value * (tau - t0) + f012
            rate = rate * (tau - tp) + value
            value = value * (tau - tp) + yp[n + i]
            rate = rate * (tau - tp) + value
            value = value * (tau - tp) + yp[i]
            out[i] = value
            out[n + i] = rate
    else:
        h00 = 2 * s**3 - 3 * s**2 + 1
        h10 = s**3 - 2 * s**2 + s
        h01 = -2 * s**3 + 3 * s**2
        h11 = s**3 - s**2
        dh10 = 3 * s**2 - 4 * s + 1
        dh01 = -6 * s**2 + 6 * s
        dh11 = 3 * s**2 - 2 * s
        for i in range(n):
            out[i] = h00 * y0[i] + h10 * h * y0[n + i] + h01 * y1[i] + h11 * h * y1[n + i]
            if rule == RULE_CUBIC_DERIVATIVE:
                out[n + i] = dh01 * (y1[i] - y0[i]) / h + dh10 * y0[n + i] + dh11 * y1[n + i]
            else:
                out[n + i] = (
                    h00 * y0[n + i] + h10 * h * f0[n + i] + h01 * y1[n + i] + h11 * h * f1[n + i]
                )
    for i in range(2 * n, 2 * n + 2):
        out[i] = (1 - s) * y0[i] + s * y1[i]
    for i in range(2 * n + 2, size):
        out[i] = y0[i]


# --- Radau IIA's steps in the lane (the implicit method; the loop: source.lane) --------------
#: Radau IIA's slots in its scalars (``ws[0]``): the step size proposed before this step and
#: the one before it (SciPy's ``h_abs``, ``h_abs_old``; NaN: None), the last step's error
#: norm (``error_norm_old``), this step's controller's ``h_abs_old`` and ``error_norm_old``
#: (NaN after a clamp of the step size), the Newton tolerance, flags (the Jacobian is at the
#: current point, the factors are valid, the last step's polynomial starts Newton, a try of
#: this step failed the error test, any try of it failed), the passing try's Newton
#: iterations, rate, error norm and safety factor, the interpolant's touching bits at the
#: last two step ends, its rule for this step, and whether a joint has film damping.
R_H_STATE, R_H_OLD_STATE, R_ERR_OLD_STATE, R_H_OLD, R_ERR_OLD, R_NEWTON_TOL = range(6)
R_CURRENT_JAC, R_LU_VALID, R_HAS_SOL, R_REJECTED, R_FAILED = range(6, 11)
R_N_ITER, R_RATE, R_ERROR, R_SAFETY, R_BITS_OLD, R_BITS, R_RULE, R_FILM = range(11, 19)
N_RADAU_SCALARS = 19
#: Radau IIA's lane record (``source.LANE`` says what each entry is).
LANE = {
    "integrator": {
        "name": "radau", "title": "Radau IIA (order 5)", "order": 5, "explicit": False,
        "tolerance_scale": 1.0, "engines": ("single", "batch-implicit", "lanes-implicit", "jax"),
    },
    "lane": "implicit_lane", "steps": "radau", "work": "radau_work",
    "shapes": "radau_shapes", "arrays": "radau_arrays",
    "dtypes": ("float64",) * 6 + ("int64",),
    "LAND_SETTLE": False, "REGIMES": True, "RTOL_FLOOR": 100.0 * EPS,
}  # fmt: skip


def radau_shapes(size, m2, nk):
    """The shapes of Radau IIA's work arrays (:func:`radau_arrays`' arguments) for a state of
    ``size``, ``m2`` positions and ``nk`` kept components (``LY_SECOND``, ``LY_KEPT``)."""
    return ((N_RADAU_SCALARS,), (8, size), (3, nk), (5, 3, size), (size - m2, m2 + nk),
            (3, nk, nk), (2, nk))  # fmt: skip


def radau_arrays(scalars, v, small, stages, jac, mats, pivots):
    """Radau IIA's ``ws`` (:func:`radau_start`'s docstring) of its arrays, the scalars
    zeroed."""
    for j in range(scalars.shape[0]):
        scalars[j] = 0.0
    return (
        scalars, v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7],
        small[0], small[1], small[2], stages[0], stages[1], stages[2], stages[3], stages[4],
        jac, mats[0], pivots[0], mats[1], mats[2], pivots[1],
    )  # fmt: skip


def radau_work(lay):
    """Radau IIA's ``ws``; it allocates: the CPU's."""
    s = radau_shapes(lay[LY_SIZE], lay[LY_SECOND], lay[LY_KEPT])
    return radau_arrays(np.empty(s[0]), np.empty(s[1]), np.empty(s[2]), np.empty(s[3]),
                        np.empty(s[4]), np.empty(s[5]), np.empty(s[6], dtype=np.int64))  # fmt: skip


def radau_start(ws, t, y, f, t_end, max_step, rtol, atol, rp, ip, lay, pen, f_mid, record_mid,
                phi_q, schur, lam, counts):  # fmt: skip
    """Radau IIA's state at the first point: SciPy's initial step (one evaluation of f), the
    Newton tolerance and the Jacobian. ``ws``: the scalars (N_RADAU_SCALARS); ``ytmp``,
    ``scale``, ``escale``, ``xr``, ``xcr``, ``xci``, ``jfactor``, ``ze`` (S); ``wk``,
    ``wkr``, ``wki`` (nk); ``z``, ``w``, ``fst``, ``dw``, ``cq`` (3, S); ``jac``
    (S − m2, m2 + nk); ``a_re``, ``piv_re``, ``c_re``, ``c_im``, ``piv_c`` (nk, nk; nk, int)
    (m2, nk: ``LY_SECOND``, ``LY_KEPT``; a mechanism's n and n, n = 3 nb)."""
    (ms, ytmp, scale, _, xr, xcr, _, jfactor, _, _, _, _, _, _, _, _, _, jac, _, _, _, _,
     _) = ws  # fmt: skip
    bits = touching(pen, lay[LY_NC])
    ms[R_BITS_OLD] = bits
    ms[R_BITS] = bits
    ms[R_FILM] = 1.0 if any_film(rp, lay) else 0.0
    h = initial_step(t, y, t_end, max_step, f, rtol, atol, rp, ip, lay, ytmp, f_mid, scale,
                     record_mid, phi_q, schur, lam, counts)  # fmt: skip
    ms[R_H_OLD_STATE] = math.nan
    ms[R_ERR_OLD_STATE] = math.nan
    ms[R_NEWTON_TOL] = max(10.0 * EPS / rtol, min(0.03, rtol**0.5))
    for j in range(lay[LY_SIZE]):
        jfactor[j] = EPS**0.5
    lane_jacobian(t, y, f, atol, jfactor, rp, ip, lay, jac, ytmp, f_mid, xr, xcr, record_mid,
                  phi_q, schur, lam)  # fmt: skip
    if RECORD:
        counts[K_JAC] += 1
    ms[R_CURRENT_JAC] = 1.0
    ms[R_LU_VALID] = 0.0
    ms[R_HAS_SOL] = 0.0
    return h


def radau_begin(ws, t, y, f, h, max_step, min_step, rtol, atol, size):
    """A step's first try: SciPy's clamp of the proposed size (once, not its retries, which
    then run the one-step controller), the Newton scale."""
    ms, scale = ws[0], ws[2]
    ms[R_H_STATE] = h
    if h > max_step or h < min_step:
        h = max_step if h > max_step else min_step
        ms[R_H_OLD] = math.nan
        ms[R_ERR_OLD] = math.nan
    else:
        ms[R_H_OLD] = ms[R_H_OLD_STATE]
        ms[R_ERR_OLD] = ms[R_ERR_OLD_STATE]
    for j in range(size):
        scale[j] = atol[j] + abs(y[j]) * rtol
    ms[R_REJECTED] = 0.0
    ms[R_FAILED] = 0.0
    return h


def radau_land(t, h, target):
    """The try's end, cut to land on ``target``; the step is the difference (SciPy's)."""
    t_new = t + h
    if t_new - target > 0:
        t_new = target
    return t_new, t_new - t


def radau_attempt(ws, t, y, f, h, t_new, y_new, t_old, y_old, rtol, atol, rp, ip, lay,
                  record_new, qb, pen, f_mid, record_mid, phi_q, schur, lam, counts):  # fmt: skip
    """A try of Radau IIA: the simplified Newton iteration (the Jacobian refreshed once if it
    fails with an old one; else half the step), the embedded error estimate (re-estimated
    after a rejection) and its test; the end's contact records for the onset control."""
    (ms, ytmp, scale, escale, xr, xcr, xci, jfactor, ze, wk, wkr, wki, z, w, fst, dw, cq, jac,
     a_re, piv_re, c_re, c_im, piv_c) = ws  # fmt: skip
    m2 = lay[LY_SECOND]
    nk = lay[LY_KEPT]
    size = lay[LY_SIZE]
    converged = False
    n_iter = 0
    rate = math.nan
    while not converged:
        if not ms[R_LU_VALID] > 0.0:
            factor_newton(jac, h, a_re, piv_re, c_re, c_im, piv_c, m2, nk)
            ms[R_LU_VALID] = 1.0
            if RECORD:
                counts[K_LU] += 2
        converged, n_iter, rate, nfev = collocation(
            t, y, h, ms[R_HAS_SOL] > 0.0, cq, t_old, y_old, scale, ms[R_NEWTON_TOL], rp, ip,
            lay, jac, a_re, piv_re, c_re, c_im, piv_c, w, z, fst, dw, ytmp, xr, xcr, xci, wk,
            wkr, wki, record_mid, phi_q, schur, lam,
        )  # fmt: skip
        counts[K_RHS] += nfev
        if not converged:
            if ms[R_CURRENT_JAC] > 0.0:
                break
            lane_jacobian(t, y, f, atol, jfactor, rp, ip, lay, jac, ytmp, f_mid, xr, xcr,
                          record_mid, phi_q, schur, lam)  # fmt: skip
            if RECORD:
                counts[K_JAC] += 1
            ms[R_CURRENT_JAC] = 1.0
            ms[R_LU_VALID] = 0.0
    if not converged:
        ms[R_LU_VALID] = 0.0
        ms[R_FAILED] = 1.0
        counts[K_REJECTED] += 1
        if RECORD:
            counts[K_REJ_NEWTON] += 1
        return False, h * 0.5
    for j in range(size):
        y_new[j] = y[j] + z[2, j]
    error_norm = error_estimate(z, f, h, y, y_new, atol, rtol, ze, xr, wk, escale, jac, a_re,
                                piv_re, m2, nk, size)  # fmt: skip
    safety = 0.9 * (2 * NEWTON_MAXITER + 1) / (2 * NEWTON_MAXITER + n_iter)
    if ms[R_REJECTED] > 0.0 and error_norm > 1:
        for j in range(size):
            ytmp[j] = y[j] + xr[j]
        rhs(t, ytmp, rp, ip, lay, f_mid, record_mid, False, phi_q, schur, lam)
        counts[K_RHS] += 1
        error_norm = error_again(f_mid, ze, h, xr, wk, escale, jac, a_re, piv_re, m2, nk, size)
    if error_norm > 1:
        factor = predict(h, ms[R_H_OLD], error_norm, ms[R_ERR_OLD])
        ms[R_LU_VALID] = 0.0
        ms[R_REJECTED] = 1.0
        ms[R_FAILED] = 1.0
        counts[K_REJECTED] += 1
        return False, h * pmax(R_MIN_FACTOR, safety * factor)
    contact_forces(y_new, rp, ip, lay, f_mid, record_new, True)
    ms[R_N_ITER] = n_iter
    ms[R_RATE] = rate
    ms[R_ERROR] = error_norm
    ms[R_SAFETY] = safety
    return True, h


def radau_retry(ws):
    """The factors are of the old step size."""
    ws[0][R_LU_VALID] = 0.0


def radau_refresh(ws, t_new, y_new, f_new, changed, rp, ip, lay, record, qb, pen, phi_q, schur,
                  lam, counts):  # fmt: skip
    """f, the records and the quantities at the accepted end (Radau has no last stage to
    reuse)."""
    rhs_and_quantities(t_new, y_new, rp, ip, lay, f_new, record, qb, pen, phi_q, schur, lam)
    counts[K_RHS] += 1
    return True


def radau_accept(ws, t_new, y_new, f_new, h, changed, atol, rp, ip, lay, pen, f_mid,
                 record_mid, phi_q, schur, lam, counts):  # fmt: skip
    """The next step's size (the predictive controller; RADAU5's hold after a failure and
    its band where the size is kept), the Jacobian at the new point when Newton converged
    slowly, the next Newton start and the interpolant's rule for this step."""
    (ms, ytmp, _, _, xr, xcr, _, jfactor, _, _, _, _, z, _, _, _, cq, jac, _, _, _, _,
     _) = ws  # fmt: skip
    error_norm = ms[R_ERROR]
    recompute_jac = ms[R_N_ITER] > 2 and ms[R_RATE] > 1e-3
    factor, kept = next_factor(h, ms[R_H_OLD], error_norm, ms[R_ERR_OLD], ms[R_SAFETY],
                               ms[R_FAILED] > 0.0 and hold_after_failure(rp),
                               recompute_jac)  # fmt: skip
    if not kept:
        ms[R_LU_VALID] = 0.0
    if recompute_jac:
        lane_jacobian(t_new, y_new, f_new, atol, jfactor, rp, ip, lay, jac, ytmp, f_mid, xr,
                      xcr, record_mid, phi_q, schur, lam)  # fmt: skip
        if RECORD:
            counts[K_JAC] += 1
        ms[R_CURRENT_JAC] = 1.0
    else:
        ms[R_CURRENT_JAC] = 0.0
    ms[R_H_OLD_STATE] = ms[R_H_STATE]
    ms[R_ERR_OLD_STATE] = error_norm
    bits_new = touching(pen, lay[LY_NC])
    ms[R_RULE] = interpolation_rule(ms[R_FILM] > 0.0, counts[K_STEPS] >= 1, int(ms[R_BITS_OLD]),
                                    int(ms[R_BITS]), bits_new)  # fmt: skip
    ms[R_BITS_OLD] = ms[R_BITS]
    ms[R_BITS] = bits_new
    polynomial(z, cq, lay[LY_SIZE])  # the next Newton start
    ms[R_HAS_SOL] = 0.0 if changed else 1.0
    return h * factor


def radau_dense(ws, t_old, y_old, t, y, f, t_new, y_new, f_new, h, tau, theta, out, lay):
    """The interpolant between steps (:func:`hermite`, with this step's rule)."""
    hermite(t_old, y_old, t, y, f, t_new, y_new, f_new, lay[LY_N], lay[LY_SIZE], tau, out,
            int(ws[0][R_RULE]))  # fmt: skip
