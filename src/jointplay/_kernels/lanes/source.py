"""The equations of motion, written once for every engine, the lanes' one loop and DOPRI5's
steps in it: one source for two compilers (Numba's CPU ``njit`` and numba-cuda's ``cuda.jit(device=True)``).

This is the only place where the right-hand side, the contact and friction laws, the film,
the clearance joints' kinematics, the constraint equations, the quantities and the contact
memory are written (the closed-form Jacobian and Radau IIA's steps:
:mod:`~jointplay._kernels.lanes.source_radau`). The single engine is their CPU compilation with
its own hooks (:mod:`jointplay._kernels.shared`, behind :mod:`jointplay._kernels.eom`'s
integrator hooks), the batch lanes their CPU compilation (:mod:`jointplay._kernels.lanes.cpu`),
the CUDA kernel their device compilation (:mod:`jointplay._kernels.lanes.cuda_kernel`).

Every function here is plain Python in the subset that both targets compile: scalars and
caller-provided arrays in, scalars (or small tuples of scalars) out; no allocation, no slicing
into new arrays, no NumPy calls but indexing, ``math`` for the elementary functions — but for
the trajectory of the CPU's traced lane (:data:`RECORD`, :func:`trace_start`) and each
integrator's work allocator (``LANE["work"]``: :func:`dopri_work`), which no other target
compiles (a GPU thread's work arrays are its kernel's). Calls
between the functions are resolved by name when :mod:`jointplay._kernels.lanes.build`
compiles the whole set for one target (each target gets its own namespace), so the same
source serves every target. Nothing here is decorated and nothing here is called from Python.

The model is the packed pair of :func:`jointplay._kernels.eom.pack`: ``rp`` (one lane's
``rpar`` row, float64) and ``ip`` (``ipar``, int64), read through ``lay``, an int64 array of
offsets and sizes (:func:`jointplay._kernels.lanes.build.lane_layout`, ``LY_*`` below; the
last entries of ``ipar``). The state layout and the clearance joint's kinematics and forces
are :mod:`jointplay._kernels.eom`'s module docstring's (Flores et al. 2008); the ideal joints
and the driver are constraints (Nikravesh 1988) — no matrix when every joint is clear, the
driver then the only constraint. :func:`lane` is the one loop of the batch lanes (the
contract: :mod:`jointplay._kernels.batch`'s module docstring: step control, contact-onset
control, contact memory, the peak rule, the statistics and the statuses), every method a set
of steps that :mod:`jointplay._kernels.lanes.build` binds to it: DOPRI5 of Hairer, Nørsett &
Wanner, *Solving ODEs I*, §II.5, Table 5.2 here (``dopri_*``, the explicit lane), Radau IIA
in :mod:`~jointplay._kernels.lanes.source_radau` (``radau_*``, the implicit lane). The hooks a target replaces are :func:`project`
(the projection onto the ideal constraints) and :func:`locked_accelerations` (the
sustained-contact mode, the single engine's only).

Units are SI throughout (m, rad, s, kg, N).
"""

from __future__ import annotations

import math

import numpy as np  # the traced lane's trajectory and the work allocators: the CPU's

# The shared ids, slots, statuses and counters (one home: jointplay._kernels.ids; build.py
# puts the source's upper-case globals, these included, into every target's namespace).
from jointplay._kernels.ids import (
    ADAMS_MU_DYNAMIC,
    ADAMS_MU_STATIC,
    ADAMS_V_DYNAMIC,
    ADAMS_V_STATIC,
    AMBROSIO_MU,
    AMBROSIO_V0,
    AMBROSIO_V1,
    FILM_EPS_CAP,
    FILM_LINEAR,
    FILM_SHORT_FULL,
    FRICTION_ADAMS,
    FRICTION_AMBROSIO,
    FRICTION_NONE,
    G_CLEARANCE,
    G_FILM,
    G_FILM_MODEL,
    G_R_BEARING,
    G_R_JOURNAL,
    G_ROUGHNESS,
    HC_CHI,
    HC_EXPONENT,
    HC_FIRST,
    HC_LAST,
    HC_STIFFNESS,
    HC_V_FLOOR,
    HERTZ_EXPONENT,
    HERTZ_STIFFNESS,
    IMPACT_C_MAX,
    IMPACT_D_MAX,
    IMPACT_EXPONENT,
    IMPACT_STIFFNESS,
    K_REJ_CHECK,
    K_REJECTED,
    K_RHS,
    K_STEPS,
    KV_DAMPING,
    KV_STIFFNESS,
    LAMBDA_BOUNDARY,
    LAMBDA_FULL_FILM,
    LAW_HERTZ,
    LAW_IMPACT,
    LAW_KELVIN_VOIGT,
    N_GEOM,
    N_SETTINGS,
    S_CAPTURE_MAX,
    S_ONSET_TOL,
    S_PROJ_TOL,
    S_V_MARK,
    SIGINT,
    SIGTERM,
    STATUS_INTERRUPTED,
    STATUS_NON_FINITE,
    STATUS_RUNNING,
    STATUS_STEP_TOO_SMALL,
    STATUS_SUCCESS,
    STATUS_TOO_MANY_STEPS,
)

# --- lay: offsets (into rp for floats, into ip for integers) and sizes ----------------------
LY_MASS, LY_GRAVITY, LY_JOINT_F, LY_DRIVER, LY_GEOM, LY_LAW_P, LY_FRIC_P, LY_SETTINGS = range(8)
LY_JOINT_INT, LY_ACTIVE, LY_CLEAR, LY_LAW_ID, LY_FRIC_ID = range(8, 13)
#: 3 nb, joints, clearance joints, law and friction parameter widths, ideal joints, state size,
#: quantities.
LY_N, LY_NJ, LY_NC, LY_PLAW, LY_PFRIC, LY_NIDEAL, LY_SIZE, LY_NQ = range(13, 21)
#: The implicit methods' structure of the state (``source_radau``'s Newton systems): the
#: positions with x' = v that they eliminate (m2), then the components kept in their systems
#: (nk: the velocities and the other active ones); the rest passive. A mechanism's: n and n.
LY_SECOND, LY_KEPT = 21, 22
N_LAY = 23


# --- contact laws (jointplay._kernels.contact; docs/contact-laws.md) -------------------------
def step3(x, x0, h0, x1, h1):
    """ADAMS cubic STEP: ``h0`` for x ≤ x0, ``h1`` for x ≥ x1, ``h0 + (h1 − h0) u² (3 − 2u)``
    with ``u = (x − x0)/(x1 − x0)`` in between (docs/contact-laws.md §1.1)."""
    if x <= x0:
        return h0
    if x >= x1:
        return h1
    u = (x - x0) / (x1 - x0)
    return h0 + (h1 - h0) * u * u * (3.0 - 2.0 * u)


def power(delta, exponent):
    """δ^e, as δ√δ for e = 3/2."""
    return delta * math.sqrt(delta) if exponent == 1.5 else delta**exponent


def normal_force(law_id, p, o, delta, delta_dot, v0):
    """Normal contact force magnitude F_N ≥ 0, N (0 without penetration), of law ``law_id``
    (an ``ids.LAW_*``) with its packed parameters at ``p[o:]`` (docs/contact-laws.md §1–2;
    the layouts: :mod:`jointplay._kernels.contact`).

    Args:
        delta: penetration δ, m (> 0 in contact).
        delta_dot: penetration rate δ̇, m/s (> 0 while approaching).
        v0: penetration rate at the start of the current contact event, m/s. Used by the
            Hunt–Crossley family only: ``v_eff = max(v0, v_floor)``, or
            ``max(delta_dot, v_floor)`` when ``v0 <= 0`` (not known yet).

    Returns:
        The force in N, or NaN for an unknown ``law_id``.
    """
    if not delta > 0.0:
        return 0.0
    if law_id == LAW_IMPACT:  # ADAMS IMPACT: k δ^e + STEP(δ, 0, 0, d_max, c_max) δ̇
        damping = step3(delta, 0.0, 0.0, p[o + IMPACT_D_MAX], p[o + IMPACT_C_MAX])
        force = p[o + IMPACT_STIFFNESS] * power(delta, p[o + IMPACT_EXPONENT]) + damping * delta_dot
    elif law_id == LAW_HERTZ:  # K δ^n
        force = p[o + HERTZ_STIFFNESS] * power(delta, p[o + HERTZ_EXPONENT])
    elif law_id == LAW_KELVIN_VOIGT:  # K δ + D δ̇
        force = p[o + KV_STIFFNESS] * delta + p[o + KV_DAMPING] * delta_dot
    elif HC_FIRST <= law_id <= HC_LAST:  # K δ^n (1 + χ δ̇ / v_eff)
        v_ref = v0 if v0 > 0.0 else delta_dot
        v_floor = p[o + HC_V_FLOOR]
        v_eff = v_ref if v_ref > v_floor else v_floor
        force = (
            p[o + HC_STIFFNESS]
            * power(delta, p[o + HC_EXPONENT])
            * (1.0 + p[o + HC_CHI] * delta_dot / v_eff)
        )
    else:
        return math.nan
    return force if force > 0.0 else 0.0


def friction_force(law_id, p, o, v_t, f_n):
    """Signed tangential friction force F_T, N, of friction law ``law_id`` (an
    ``ids.FRICTION_*``) with its packed parameters at ``p[o:]``: ``F_T = μ(v_T) F_N sgn(v_T)``
    in the sign convention of docs/contact-laws.md §5 (on the journal ``−F_T t``, on the
    bearing ``+F_T t``), at slip v_T (m/s, journal relative to bearing) under F_N (N); NaN for
    an unknown id."""
    if law_id == FRICTION_NONE:
        return 0.0
    sign = 1.0 if v_t > 0.0 else (-1.0 if v_t < 0.0 else 0.0)
    speed = abs(v_t)
    if law_id == FRICTION_AMBROSIO:
        v_lo = p[o + AMBROSIO_V0]
        v_hi = p[o + AMBROSIO_V1]
        if speed <= v_lo:
            correction = 0.0
        elif speed >= v_hi:
            correction = 1.0
        else:
            correction = (speed - v_lo) / (v_hi - v_lo)
        return p[o + AMBROSIO_MU] * correction * f_n * sign
    if law_id == FRICTION_ADAMS:
        mu_s = p[o + ADAMS_MU_STATIC]
        mu_d = p[o + ADAMS_MU_DYNAMIC]
        v_s = p[o + ADAMS_V_STATIC]
        v_d = p[o + ADAMS_V_DYNAMIC]
        if speed <= v_s:
            coefficient = step3(v_t, -v_s, -mu_s, v_s, mu_s)
        elif speed < v_d:
            coefficient = sign * step3(speed, v_s, mu_s, v_d, mu_d)
        else:
            coefficient = sign * mu_d
        return coefficient * f_n
    return math.nan


# --- driver (the single engine's jointplay._kernels.constraints.driver_motion) ---------------
def driver_acceleration(t, rp, o):
    """φ̈_d(t), rad/s², of the driver at ``rp[o:o + 4]`` (driven body, φ0, ω, ramp time):
    0 at constant speed, the quintic STEP5 ramp's ω/T · 30 u² (1 − u)² during the ramp."""
    omega = rp[o + 2]
    ramp = rp[o + 3]
    if ramp <= 0.0 or t >= ramp:
        return 0.0
    if t <= 0.0:
        return 0.0
    u = t / ramp
    return omega / ramp * 30.0 * u * u * (1.0 - u) ** 2


def time_enters(rp, lay):
    """Whether t enters the right-hand side (RODAS4 differences it in t): only through the
    driver's speed ramp."""
    return rp[lay[LY_DRIVER] + 3] > 0.0


# --- ideal joints and the driver (jointplay._kernels.constraints; Nikravesh 1988, ch. 4-5) -----
def rot(phi, sx, sy):
    """A(φ) (sx, sy): a body's local vector in the global frame."""
    c = math.cos(phi)
    s = math.sin(phi)
    return c * sx - s * sy, s * sx + c * sy


def point_global(y, body, sx, sy):
    """Global position of the local point (sx, sy) of ``body`` (the ground's are global)."""
    if body < 0:
        return sx, sy
    ax, ay = rot(y[3 * body + 2], sx, sy)
    return y[3 * body] + ax, y[3 * body + 1] + ay


def ideal_joint(ip, lay, j):
    """``(kind, a, b)`` of joint ``j``: kind 0 revolute, 1 prismatic, −1 not an ideal joint (a
    clearance joint's: no constraint rows); its bodies a, b (−1: the ground)."""
    o_ji = lay[LY_JOINT_INT]
    if ip[lay[LY_ACTIVE] + j] == 0:
        return -1, ip[o_ji + 3 * j + 1], ip[o_ji + 3 * j + 2]
    return ip[o_ji + 3 * j], ip[o_ji + 3 * j + 1], ip[o_ji + 3 * j + 2]


def revolute_arm(y, rp, o_jf, j, side, a, b):
    """Side ``side`` of revolute joint ``j`` (0: body ``a``, sign +1; 1: body ``b``, −1):
    ``(body, sign, ax, ay)`` with its arm A(φ) s in the global frame (0 on the ground)."""
    body = a if side == 0 else b
    sign = 1.0 if side == 0 else -1.0
    if body < 0:
        return body, sign, 0.0, 0.0
    ax, ay = rot(y[3 * body + 2], rp[o_jf + 6 * j + 2 * side], rp[o_jf + 6 * j + 2 * side + 1])
    return body, sign, ax, ay


def constraint_rows(rp, lay):
    """Rows of Φ: 2 per ideal joint, 1 for the driver unless it is off."""
    return 2 * lay[LY_NIDEAL] + (1 if rp[lay[LY_DRIVER]] >= 0 else 0)


def constraint_terms(t, y, rp, ip, lay, jac, gamma, want_gamma):
    """Φ_q (rows × 3 nb) into ``jac`` and, if ``want_gamma``, γ with Φ_q q̈ = γ (the quadratic
    velocity terms and the driver's φ̈_d) into ``gamma`` (else untouched: any 1-D array), in
    one pass over the ideal joints. Revolute: Φ = r_a + A_a s_a − r_b − A_b s_b with
    ∂(A s)/∂φ = B s = rot90(A s), γ = A_a s_a φ̇_a² − A_b s_b φ̇_b²; prismatic: φ_b − φ_a − θ0
    and n_a·d, γ2 = n·d φ̇_a² − 2 φ̇_a (B_a n')·ḋ + n·(A_b s_b φ̇_b² − A_a s_a φ̇_a²);
    driver: φ_k − φ_d."""
    n = lay[LY_N]
    o_jf = lay[LY_JOINT_F]
    for r in range(constraint_rows(rp, lay)):
        for i in range(n):
            jac[r, i] = 0.0
        if want_gamma:
            gamma[r] = 0.0
    row = 0
    for j in range(lay[LY_NJ]):
        kind, a, b = ideal_joint(ip, lay, j)
        if kind < 0:
            continue
        if kind == 0:
            for side in range(2):
                body, sign, ax, ay = revolute_arm(y, rp, o_jf, j, side, a, b)
                if body < 0:
                    continue
                jac[row, 3 * body] += sign
                jac[row + 1, 3 * body + 1] += sign
                jac[row, 3 * body + 2] += -sign * ay
                jac[row + 1, 3 * body + 2] += sign * ax
                if want_gamma:
                    w2 = y[n + 3 * body + 2] ** 2
                    gamma[row] += sign * ax * w2
                    gamma[row + 1] += sign * ay * w2
        else:
            phi_a = y[3 * a + 2] if a >= 0 else 0.0
            pax, pay = point_global(y, a, rp[o_jf + 6 * j], rp[o_jf + 6 * j + 1])
            pbx, pby = point_global(y, b, rp[o_jf + 6 * j + 2], rp[o_jf + 6 * j + 3])
            nx, ny = rot(phi_a + rp[o_jf + 6 * j + 4], 0.0, 1.0)
            dx, dy = pbx - pax, pby - pay
            sax, say, sbx, sby = 0.0, 0.0, 0.0, 0.0
            if a >= 0:
                sax, say = rot(phi_a, rp[o_jf + 6 * j], rp[o_jf + 6 * j + 1])
                jac[row, 3 * a + 2] = -1.0
                jac[row + 1, 3 * a] = -nx
                jac[row + 1, 3 * a + 1] = -ny
                jac[row + 1, 3 * a + 2] = (-ny * dx + nx * dy) - (nx * -say + ny * sax)
            if b >= 0:
                sbx, sby = rot(y[3 * b + 2], rp[o_jf + 6 * j + 2], rp[o_jf + 6 * j + 3])
                jac[row, 3 * b + 2] = 1.0
                jac[row + 1, 3 * b] = nx
                jac[row + 1, 3 * b + 1] = ny
                jac[row + 1, 3 * b + 2] = nx * -sby + ny * sbx
            if want_gamma:
                wa = y[n + 3 * a + 2] if a >= 0 else 0.0
                wb = y[n + 3 * b + 2] if b >= 0 else 0.0
                vax = (y[n + 3 * a] if a >= 0 else 0.0) - say * wa
                vay = (y[n + 3 * a + 1] if a >= 0 else 0.0) + sax * wa
                vbx = (y[n + 3 * b] if b >= 0 else 0.0) - sby * wb
                vby = (y[n + 3 * b + 1] if b >= 0 else 0.0) + sbx * wb
                ddx, ddy = vbx - vax, vby - vay
                bnx, bny = -ny, nx
                gamma[row + 1] = (
                    (nx * dx + ny * dy) * wa * wa
                    - 2.0 * wa * (bnx * ddx + bny * ddy)
                    + nx * (sbx * wb * wb - sax * wa * wa)
                    + ny * (sby * wb * wb - say * wa * wa)
                )
        row += 2
    crank = int(rp[lay[LY_DRIVER]])
    if crank >= 0:
        jac[row, 3 * crank + 2] = 1.0
    if want_gamma and rp[lay[LY_DRIVER]] >= 0:
        gamma[row] = driver_acceleration(t, rp, lay[LY_DRIVER])


def constraint_jacobian(y, rp, ip, lay, out):
    """Φ_q (rows × 3 nb) into ``out`` (:func:`constraint_terms` without γ)."""
    constraint_terms(0.0, y, rp, ip, lay, out, y, False)


def cholesky_solve(a, b, m):
    """Solve a x = b in place for the symmetric positive definite leading m × m block of
    ``a`` (its lower triangle read, overwritten by the Cholesky factor; b by x); a singular
    ``a`` gives inf/NaN."""
    for k in range(m):
        d = a[k, k]
        for p in range(k):
            d -= a[k, p] * a[k, p]
        d = math.sqrt(d)
        a[k, k] = d
        for i in range(k + 1, m):
            s = a[i, k]
            for p in range(k):
                s -= a[i, p] * a[k, p]
            a[i, k] = s / d
    for i in range(m):
        s = b[i]
        for p in range(i):
            s -= a[i, p] * b[p]
        b[i] = s / a[i, i]
    for i in range(m - 1, -1, -1):
        s = b[i]
        for p in range(i + 1, m):
            s -= a[p, i] * b[p]
        b[i] = s / a[i, i]


def constrained_accelerations(t, y, rp, ip, lay, f, phi_q, schur, lam):
    """Turn the generalised forces Q in ``f[n:2n]`` into q̈:
    (Φ_q M⁻¹ Φ_qᵀ) λ = Φ_q M⁻¹ Q − γ, q̈ = M⁻¹ (Q − Φ_qᵀ λ) (Nikravesh 1988, §6; M diagonal);
    λ (the ideal joints' rows, then the driver's) into ``lam``. Returns the motor torque
    −λ_driver (N·m). Work arrays: ``phi_q`` (rows × 3 nb), ``schur`` (rows × rows)."""
    n = lay[LY_N]
    o_mass = lay[LY_MASS]
    rows = constraint_rows(rp, lay)
    constraint_terms(t, y, rp, ip, lay, phi_q, lam, True)
    for r in range(rows):
        for p in range(rows):
            schur[r, p] = 0.0
    for r in range(rows):  # lam ← Φ_q M⁻¹ Q − γ ; schur ← Φ_q M⁻¹ Φ_qᵀ
        s = -lam[r]
        for i in range(n):
            w = phi_q[r, i] / rp[o_mass + i]
            s += w * f[n + i]
            if w != 0.0:
                for p in range(r + 1):
                    schur[r, p] += w * phi_q[p, i]
        lam[r] = s
    cholesky_solve(schur, lam, rows)
    for i in range(n):
        s = f[n + i]
        for r in range(rows):
            s -= phi_q[r, i] * lam[r]
        f[n + i] = s / rp[o_mass + i]
    return -lam[rows - 1] if rp[lay[LY_DRIVER]] >= 0 else 0.0


# --- right-hand side (jointplay._kernels.eom) ---------------------------------------------
def push(f, n, body, rx, ry, fx, fy):
    """Add the force (fx, fy) at arm (rx, ry) from the centre of mass of ``body`` to the
    generalised forces ``f[n:2n]``."""
    if body < 0:
        return
    f[n + 3 * body] += fx
    f[n + 3 * body + 1] += fy
    f[n + 3 * body + 2] += rx * fy - ry * fx


def eccentricity_rate(y, n, a, b, wa, wb, rax, ray, rbx, rby):
    """ė = v(journal centre on b) − v(bearing centre on a), v = v_com + ω ẑ × r, with the arms
    r of the two centres from their bodies' centres of mass and the bodies' rates ω
    (the ground, −1, does not move)."""
    edx = -wb * rby + wa * ray
    edy = wb * rbx - wa * rax
    if b >= 0:
        edx += y[n + 3 * b]
        edy += y[n + 3 * b + 1]
    if a >= 0:
        edx -= y[n + 3 * a]
        edy -= y[n + 3 * a + 1]
    return edx, edy


def rotation_of(y, body, last_a, ca, sa, last_b, cb, sb):
    """(cos φ, sin φ) of ``body``: the rotation of the joint before's body a or b (``last_a``
    with (``ca``, ``sa``), ``last_b`` with (``cb``, ``sb``)) when it is one of them, (1, 0)
    for the ground, else computed."""
    if body == last_a:
        return ca, sa
    if body == last_b:
        return cb, sb
    if body < 0:
        return 1.0, 0.0
    return math.cos(y[3 * body + 2]), math.sin(y[3 * body + 2])


def rotations(y, a, b, last_a, ca, sa, last_b, cb, sb):
    """(cos φ_a, sin φ_a, cos φ_b, sin φ_b) of a joint's two bodies, reusing the joint
    before's (:func:`rotation_of`)."""
    ca_new, sa_new = rotation_of(y, a, last_a, ca, sa, last_b, cb, sb)
    cb_new, sb_new = rotation_of(y, b, last_a, ca, sa, last_b, cb, sb)
    return ca_new, sa_new, cb_new, sb_new


def arm_rotated(y, body, c, s, sx, sy):
    """(x, y, r_x, r_y): the global position of the local point (sx, sy) of ``body``, whose
    rotation is (``c``, ``s``) = (cos φ, sin φ), and its arm r = A(φ) s from the centre of
    mass (the ground's points are global, arm 0)."""
    if body < 0:
        return sx, sy, 0.0, 0.0
    rx = c * sx - s * sy
    ry = s * sx + c * sy
    return y[3 * body] + rx, y[3 * body + 1] + ry, rx, ry


def arm(y, body, sx, sy):
    """(x, y, r_x, r_y) of the local point (sx, sy) of ``body`` (:func:`arm_rotated` computing the rotation)."""
    if body < 0:
        return sx, sy, 0.0, 0.0
    c = math.cos(y[3 * body + 2])
    s = math.sin(y[3 * body + 2])
    rx = c * sx - s * sy
    ry = s * sx + c * sy
    return y[3 * body] + rx, y[3 * body + 1] + ry, rx, ry


def joint_kinematics(y, rp, ip, lay, c):
    """The kinematics of clearance joint ``c`` at the state ``y`` (:func:`contact_forces`', the
    same arithmetic; docs/contact-laws.md §5): its bearing's body a and journal's body b, the
    arms (r_ax, r_ay, r_bx, r_by) of their centres from the bodies' centres of mass (m), |e|
    (m), the normal n = e/|e| ((1, 0) for a centred pin), the bodies' rates ω_a, ω_b (rad/s)
    and ė (m/s), as one tuple in that order."""
    n = lay[LY_N]
    o_ji = lay[LY_JOINT_INT]
    o_jf = lay[LY_JOINT_F]
    j = ip[lay[LY_CLEAR] + c]
    a = ip[o_ji + 3 * j + 1]
    b = ip[o_ji + 3 * j + 2]
    bx, by, rax, ray = arm(y, a, rp[o_jf + 6 * j], rp[o_jf + 6 * j + 1])
    jx, jy, rbx, rby = arm(y, b, rp[o_jf + 6 * j + 2], rp[o_jf + 6 * j + 3])
    ex = jx - bx
    ey = jy - by
    length = math.sqrt(ex * ex + ey * ey)
    if length > 0.0:
        nx, ny = ex / length, ey / length
    else:
        nx, ny = 1.0, 0.0
    wa = y[n + 3 * a + 2] if a >= 0 else 0.0
    wb = y[n + 3 * b + 2] if b >= 0 else 0.0
    edx, edy = eccentricity_rate(y, n, a, b, wa, wb, rax, ray, rbx, rby)
    return a, b, rax, ray, rbx, rby, length, nx, ny, wa, wb, edx, edy


def contact_clearance(rp, lay, c):
    """The radial play (m) at which clearance joint ``c``'s dry law starts to act: its
    clearance c, or, under a Reynolds film, c − λ_t σ (σ its ``G_ROUGHNESS``, λ_t
    :data:`LAMBDA_FULL_FILM`): the asperities' summits touch where the film thins to
    h_min = c − |e| = λ_t σ, and the dry law then carries the asperity share of the load
    beside the film (docs/contact.md, "The film-to-contact transition"). A dry joint's and the
    linear damper's contact is the bulk one, at |e| = c (the same bits as before)."""
    o = lay[LY_GEOM] + N_GEOM * c
    if rp[o + G_FILM] > 0.0 and rp[o + G_FILM_MODEL] != FILM_LINEAR:
        # a fit tighter than λ_t σ: mixed lubrication even with the pin centred, the
        # asperities' force then grows from the centre (K |e|^n along n: no jump at e = 0)
        return max(rp[o + G_CLEARANCE] - LAMBDA_FULL_FILM * rp[o + G_ROUGHNESS], 0.0)
    return rp[o + G_CLEARANCE]


def penetration_and_rate(y, rp, ip, lay, c):
    """(δ, δ̇) of clearance joint ``c`` at the state ``y``, m and m/s (:func:`contact_forces`'
    kinematics, the same arithmetic): δ = |e| − c (:func:`contact_clearance`'s play),
    δ̇ = ė·n (n = (1, 0) for a centred pin)."""
    kin = joint_kinematics(y, rp, ip, lay, c)
    length, nx, ny, edx, edy = kin[6], kin[7], kin[8], kin[11], kin[12]
    return length - contact_clearance(rp, lay, c), edx * nx + edy * ny


# --- the Reynolds films (docs/contact.md, "Reynolds films") ----------------------------------
def reynolds_matrix(form, eps, rate, wedge):
    """The short-bearing Reynolds film's force on the journal as a matrix on (ė_r, wedge):
    (m_rr, m_rw, m_tr, m_tw), with F_r = m_rr ė_r + m_rw wedge along n (radial) and
    F_t = m_tr ė_r + m_tw wedge along t = ẑ × n, per unit K = μ R L³ / c³ (N·s/m), at
    eccentricity ratio ε (< 1), radial rate ė_r = ė·n (``rate``, m/s) and wedge speed
    |e| ((ω_j + ω_b)/2 − γ̇) = |e| (ω_j + ω_b)/2 − ė·t (``wedge``, m/s).

    The pressure integrated over the length is P(θ) = μ L³ (ė_r cos θ − wedge sin θ) / h³
    with h = c(1 − ε cos θ), θ from n; F_r = −R ∫ P cos θ, F_t = −R ∫ P sin θ over the full
    film (``form`` FILM_SHORT_FULL: a constant matrix) or over where P > 0 (Gümbel's half
    film: the half θ ∈ (θ₁, θ₁ + π), θ₁ = −atan2(wedge, ė_r) − π/2, which moves with the ratio
    of squeeze to wedge; the matrix depends on that ratio only, and it is also the force's
    exact derivative with respect to (ė_r, wedge): the moving ends add nothing, P = 0 there).

    The half film's integrals, with u = 1 − ε cos θ, s = 1 − ε² and Sommerfeld's angle ψ
    (cos ψ = (cos θ − ε)/u, sin ψ = √s sin θ/u): ∫ cos²θ/u³ = s^(−5/2) [(ε² + ½) ψ + 2ε sin ψ
    + ½ sin ψ cos ψ], ∫ sin²θ/u³ = s^(−3/2) [½ ψ − ½ sin ψ cos ψ], ∫ sin θ cos θ/u³ =
    −cos²θ/(2u²), taken between θ₁ and θ₁ + π, where cos θ₁ = −wedge/ρ, sin θ₁ = −ė_r/ρ
    (ρ = |(ė_r, wedge)|) and the other end's are their opposites: no angle is formed. ψ turns
    by π − 2 atan(ε sin θ₁/√s) over the half (tan(ψ/2) = tan(θ/2) √((1 + ε)/(1 − ε)); the
    two ends' arctangents combine into one, 1 + x₁x₂ = 4k/(D₁D₂) > 0), so the matrix costs
    two square roots and one arctangent (docs/performance.md, "Lubricated default")."""
    s = 1.0 - eps * eps
    r = math.sqrt(s)
    if form == FILM_SHORT_FULL:
        squeeze = -math.pi * (1.0 + 2.0 * eps * eps) / (s * s * r)
        return squeeze, 0.0, 0.0, math.pi / (s * r)
    rho = math.sqrt(rate * rate + wedge * wedge)
    if rho > 0.0:
        cos_1 = -wedge / rho
        sin_1 = -rate / rho
    else:  # at rest: atan2(±0, ±0)'s end, θ₁ = −π/2 (or −3π/2 for ė_r = −0)
        cos_1 = 0.0
        sin_1 = -math.copysign(1.0, rate)
    u_1 = 1.0 - eps * cos_1
    u_2 = 1.0 + eps * cos_1
    turn = math.pi - 2.0 * math.atan(eps * sin_1 / r)
    rise = -2.0 * r * sin_1 / (u_1 * u_2)  # sin ψ₂ − sin ψ₁
    half = 0.5 * r * sin_1 * ((cos_1 + eps) / (u_2 * u_2) - (cos_1 - eps) / (u_1 * u_1))
    i_cc = ((eps * eps + 0.5) * turn + 2.0 * eps * rise + half) / (s * s * r)
    i_ss = (0.5 * turn - half) / (s * r)
    i_sc = 0.5 * cos_1 * cos_1 * (1.0 / (u_1 * u_1) - 1.0 / (u_2 * u_2))
    return -i_cc, i_sc, -i_sc, i_ss


def reynolds_components(form, eps, rate, wedge):
    """(F_r, F_t) of :func:`reynolds_matrix` at (ė_r, wedge), per unit K."""
    m_rr, m_rw, m_tr, m_tw = reynolds_matrix(form, eps, rate, wedge)
    return m_rr * rate + m_rw * wedge, m_tr * rate + m_tw * wedge


def film_share(clearance, roughness, length):
    """The share w of a Reynolds film's force a joint's film still carries at |e| = ``length``
    (m), with radial clearance ``clearance`` and composite roughness σ = ``roughness`` (m):
    1 in full film (λ = h_min/σ ≥ λ_t, h_min = c − |e|, λ_t = :data:`LAMBDA_FULL_FILM`), 0 in
    boundary lubrication (λ ≤ λ_b = :data:`LAMBDA_BOUNDARY`), and between them
    1 − x² (3 − 2x), x = (λ_t − λ)/(λ_t − λ_b) (C¹: the force and its Jacobian continuous at
    both ends); 1 for σ = 0 (docs/contact.md, "The film-to-contact transition")."""
    top = LAMBDA_FULL_FILM * roughness
    gap = clearance - length
    if not (roughness > 0.0 and gap < top):
        return 1.0
    x = min((top - gap) / ((LAMBDA_FULL_FILM - LAMBDA_BOUNDARY) * roughness), 1.0)
    return 1.0 - x * x * (3.0 - 2.0 * x)


def reynolds_force(form, coef, clearance, roughness, ex, ey, edx, edy, wa, wb):
    """The Reynolds film's force (N) on the journal, at its centre, of a joint with the film
    coefficient ``coef`` = C0 = π μ R L³ / c³, radial clearance ``clearance`` (m) and
    composite roughness ``roughness`` (m; the film's share :func:`film_share` of it), at
    eccentricity e = (``ex``, ``ey``) (m), ė = (``edx``, ``edy``) (m/s) and the rates ``wa``,
    ``wb`` of the bearing's and the journal's bodies (rad/s); the bearing feels its opposite
    at its centre (:func:`reynolds_components`; ε held at :data:`FILM_EPS_CAP` beyond it;
    n = (1, 0) for a centred pin, where the force does not depend on n)."""
    length = math.sqrt(ex * ex + ey * ey)
    if length > 0.0:
        nx, ny = ex / length, ey / length
    else:
        nx, ny = 1.0, 0.0
    rate = edx * nx + edy * ny
    wedge = 0.5 * length * (wa + wb) - (-edx * ny + edy * nx)
    k, f_r, f_t = reynolds_local(form, coef, clearance, roughness, length, rate, wedge)
    return k * (f_r * nx - f_t * ny), k * (f_r * ny + f_t * nx)


def reynolds_local(form, coef, clearance, roughness, length, rate, wedge):
    """:func:`reynolds_force`'s film in its joint's frame: (k, F_r, F_t), the force on the
    journal being k (F_r n + F_t t) (N; k = C0/π times the film's share :func:`film_share`,
    N·s/m; F_r, F_t :func:`reynolds_components`', m/s), at |e| = ``length`` (m),
    ė_r = ė·n = ``rate`` and the wedge speed ``wedge`` (m/s). :func:`film_components` calls it
    with the ė·n and ė·t of a joint's record: no rotation and no angle evaluated again."""
    eps = min(length / clearance, FILM_EPS_CAP)
    f_r, f_t = reynolds_components(form, eps, rate, wedge)
    return coef / math.pi * film_share(clearance, roughness, length), f_r, f_t


def contact_forces(y, rp, ip, lay, f, record, recording):
    """Add every clearance joint's contact force to ``f[n:2n]`` (
    δ = |e| − c, δ̇ = ė·n, v_T = ė·t + R_J ω_b − R_B ω_a; −F_N n − F_T t on the journal at
    r_J + R_J n, the opposite on the bearing at r_B + R_B n; under a Reynolds film δ is the
    asperity interference |e| − (c − λ_t σ), :func:`contact_clearance`); with film damping
    (the joint's ``G_FILM`` column c_e > 0), −c_e ė on the journal at its centre and +c_e ė on
    the bearing at its centre, in contact or not, first (not in the record's F_N, F_T:
    :func:`film_components`); a Reynolds film (the joint's ``G_FILM_MODEL`` not
    ``FILM_LINEAR``) instead :func:`reynolds_force` F on the journal's centre and −F on the
    bearing's, power −F·ė; when ``recording``, (F_N, F_T, δ, δ̇, v_T, e_x, e_y) of joint c
    into ``record[7c:7c + 7]``. Returns the contact power Σ (F_N δ̇ + F_T v_T + c_e |ė|²), W.
    (Only the implicit lane runs the film: the explicit one is refused it,
    :func:`jointplay._kernels.lanes.build.lanes_refusal`.)"""
    n = lay[LY_N]
    nc = lay[LY_NC]
    o_ji = lay[LY_JOINT_INT]
    o_jf = lay[LY_JOINT_F]
    o_geom = lay[LY_GEOM]
    plaw = lay[LY_PLAW]
    pfric = lay[LY_PFRIC]
    pw = 0.0
    # The rotations of the joint before's two bodies: joints listed along a chain share a body
    # with the one before (the four-bar's O2, A, B, O4: three rotations instead of six; the
    # same bits either way).
    last_a = -2
    ca = 1.0
    sa = 0.0
    last_b = -2
    cb = 1.0
    sb = 0.0
    for c in range(nc):
        film = rp[o_geom + N_GEOM * c + G_FILM]  # this joint's c_e; 0: dry
        j = ip[lay[LY_CLEAR] + c]
        a = ip[o_ji + 3 * j + 1]
        b = ip[o_ji + 3 * j + 2]
        ca, sa, cb, sb = rotations(y, a, b, last_a, ca, sa, last_b, cb, sb)
        last_a = a
        last_b = b
        # bearing centre on a, journal centre on b, and their arms from the centres of mass
        bx, by, rax, ray = arm_rotated(y, a, ca, sa, rp[o_jf + 6 * j], rp[o_jf + 6 * j + 1])
        jx, jy, rbx, rby = arm_rotated(y, b, cb, sb, rp[o_jf + 6 * j + 2], rp[o_jf + 6 * j + 3])
        ex = jx - bx
        ey = jy - by
        emag = math.sqrt(ex * ex + ey * ey)
        delta = emag - contact_clearance(rp, lay, c)  # the asperities' under a Reynolds film
        f_n = 0.0
        f_t = 0.0
        delta_dot = 0.0
        v_t = 0.0
        if film > 0.0:  # the film's force on the journal's centre, in contact or not
            wa = y[n + 3 * a + 2] if a >= 0 else 0.0
            wb = y[n + 3 * b + 2] if b >= 0 else 0.0
            fdx, fdy = eccentricity_rate(y, n, a, b, wa, wb, rax, ray, rbx, rby)
            form = rp[o_geom + N_GEOM * c + G_FILM_MODEL]
            if form == FILM_LINEAR:  # the damping −c_e ė
                push(f, n, b, rbx, rby, -film * fdx, -film * fdy)
                push(f, n, a, rax, ray, film * fdx, film * fdy)
                pw += film * (fdx * fdx + fdy * fdy)
            else:  # a Reynolds film: its power −F·ė into W_contact (the wedge's can be < 0)
                ffx, ffy = reynolds_force(
                    int(form), film, rp[o_geom + N_GEOM * c + G_CLEARANCE],
                    rp[o_geom + N_GEOM * c + G_ROUGHNESS], ex, ey, fdx, fdy, wa, wb,
                )  # fmt: skip
                push(f, n, b, rbx, rby, ffx, ffy)
                push(f, n, a, rax, ray, -ffx, -ffy)
                pw -= ffx * fdx + ffy * fdy
        if delta > 0.0 or recording:
            if emag > 0.0:
                nx, ny = ex / emag, ey / emag
            else:
                nx, ny = 1.0, 0.0
            wa = y[n + 3 * a + 2] if a >= 0 else 0.0
            wb = y[n + 3 * b + 2] if b >= 0 else 0.0
            edx, edy = eccentricity_rate(y, n, a, b, wa, wb, rax, ray, rbx, rby)
            delta_dot = edx * nx + edy * ny
            r_j = rp[o_geom + N_GEOM * c + G_R_JOURNAL]
            r_b = rp[o_geom + N_GEOM * c + G_R_BEARING]
            v_t = -edx * ny + edy * nx + r_j * wb - r_b * wa
            v0 = y[2 * n + 2 + c]
            if delta > 0.0 and v0 >= 0.0:  # v0 < 0: locked (LOCKED), F_N is a multiplier
                f_n = normal_force(
                    ip[lay[LY_LAW_ID] + c], rp, lay[LY_LAW_P] + plaw * c, delta, delta_dot, v0
                )
                fric = ip[lay[LY_FRIC_ID] + c]
                if fric != FRICTION_NONE:
                    f_t = friction_force(fric, rp, lay[LY_FRIC_P] + pfric * c, v_t, f_n)
                fx = -f_n * nx + f_t * ny
                fy = -f_n * ny - f_t * nx
                push(f, n, b, rbx + r_j * nx, rby + r_j * ny, fx, fy)
                push(f, n, a, rax + r_b * nx, ray + r_b * ny, -fx, -fy)
                pw += f_n * delta_dot + f_t * v_t
        if recording:
            record[7 * c] = f_n
            record[7 * c + 1] = f_t
            record[7 * c + 2] = delta
            record[7 * c + 3] = delta_dot
            record[7 * c + 4] = v_t
            record[7 * c + 5] = ex
            record[7 * c + 6] = ey
    return pw


def any_film(rp, lay):
    """Whether some clearance joint of the model has film damping (its ``G_FILM`` > 0)."""
    for c in range(lay[LY_NC]):  # noqa: SIM110 (the subset both compilers take: no any())
        if rp[lay[LY_GEOM] + N_GEOM * c + G_FILM] > 0.0:
            return True
    return False


def film_components(y, rp, ip, lay, record, c):
    """The film force c_e ė of clearance joint ``c`` in its contact frame, (c_e ė·n, c_e ė·t)
    (N; the journal feels minus this), from its record (:func:`contact_forces`: ė·n = δ̇,
    ė·t = v_T − R_J ω_b + R_B ω_a); for a Reynolds film (its ``G_FILM_MODEL``), minus
    :func:`reynolds_local` at that ė·n and ė·t (the record's, so the joint's kinematics are not
    evaluated again: no rotation, no angle); (0, 0) with the film off."""
    film = rp[lay[LY_GEOM] + N_GEOM * c + G_FILM]
    if not film > 0.0:
        return 0.0, 0.0
    n = lay[LY_N]
    j = ip[lay[LY_CLEAR] + c]
    a = ip[lay[LY_JOINT_INT] + 3 * j + 1]
    b = ip[lay[LY_JOINT_INT] + 3 * j + 2]
    wa = y[n + 3 * a + 2] if a >= 0 else 0.0
    wb = y[n + 3 * b + 2] if b >= 0 else 0.0
    o_geom = lay[LY_GEOM]
    slide = (
        record[7 * c + 4]
        - rp[o_geom + N_GEOM * c + G_R_JOURNAL] * wb
        + rp[o_geom + N_GEOM * c + G_R_BEARING] * wa
    )
    form = rp[o_geom + N_GEOM * c + G_FILM_MODEL]
    if form != FILM_LINEAR:  # a Reynolds film: minus its force on the journal, along n and t
        ex = record[7 * c + 5]
        ey = record[7 * c + 6]
        length = math.sqrt(ex * ex + ey * ey)
        k, f_r, f_t = reynolds_local(
            int(form), film, rp[o_geom + N_GEOM * c + G_CLEARANCE],
            rp[o_geom + N_GEOM * c + G_ROUGHNESS], length, record[7 * c + 3],
            0.5 * length * (wa + wb) - slide,
        )  # fmt: skip
        return -k * f_r, -k * f_t
    return film * record[7 * c + 3], film * slide


def locked(y, rp, lay):
    """Whether some clearance joint is locked onto its bearing's wall at ``y`` (its v0 slot
    negative, :data:`LOCKED`: the sustained-contact mode); ``False`` in one comparison with
    the mode off (the settings' ``S_CAPTURE_MAX``, the largest capture speed, is 0)."""
    if not sustained_on(rp, lay):
        return False
    base = 2 * lay[LY_N] + 2
    for c in range(lay[LY_NC]):  # noqa: SIM110 (the subset both compilers take: no any())
        if y[base + c] < 0.0:
            return True
    return False


def locked_accelerations(t, y, rp, ip, lay, f, record, recording, lam):
    """The hook of the sustained-contact mode: q̈ with the locked joints as constraints,
    (motor torque, N·m; the locked contacts' power, W). The CPU's (the single engine's and
    the CPU lanes') is :func:`jointplay._kernels.sustained.sustained_locked_accelerations`;
    the GPU lanes do not run the mode (:mod:`jointplay._kernels.capabilities` refuses it
    before a lane starts), so this default is never reached, and a lane that reached it
    would end non-finite, not wrong."""
    return math.nan, math.nan


def rhs(t, y, rp, ip, lay, f, record, recording, phi_q, schur, lam):
    """ẏ into ``f`` (state layout of :mod:`jointplay._kernels.eom`), the contact records into
    ``record`` when ``recording``, the multipliers λ into ``lam`` (ideal joints only); returns
    the motor torque τ (N·m). Every joint clear: the driver's row is the only constraint,
    λ = Q_φk − I_k φ̈_d, q̈_φk = φ̈_d, q̈ = M⁻¹ Q elsewhere (no matrix:
    the single engine's case too); else :func:`constrained_accelerations` (work
    arrays ``phi_q``, ``schur``). W_motor' = τ ω_k, W_contact' = the contact power."""
    n = lay[LY_N]
    o_mass = lay[LY_MASS]
    o_gravity = lay[LY_GRAVITY]
    o_driver = lay[LY_DRIVER]
    for i in range(n):
        f[i] = y[n + i]
        f[n + i] = rp[o_gravity + i]
    f[2 * n + 1] = contact_forces(y, rp, ip, lay, f, record, recording)
    crank = int(rp[o_driver])
    torque = 0.0
    if locked(y, rp, lay):  # the sustained-contact mode, with a joint locked
        torque, locked_power = locked_accelerations(t, y, rp, ip, lay, f, record, recording, lam)
        f[2 * n + 1] += locked_power
    elif lay[LY_NIDEAL] > 0:
        torque = constrained_accelerations(t, y, rp, ip, lay, f, phi_q, schur, lam)
    else:
        if crank >= 0:
            k = 3 * crank + 2
            multiplier = f[n + k] - rp[o_mass + k] * driver_acceleration(t, rp, o_driver)
            f[n + k] -= multiplier
            torque = -multiplier
            if lam.shape[0] > 0:
                lam[0] = multiplier
        for i in range(n):
            f[n + i] /= rp[o_mass + i]
    f[2 * n] = torque * y[n + 3 * crank + 2] if crank >= 0 else 0.0
    for i in range(2 * n + 2, lay[LY_SIZE]):
        f[i] = 0.0
    return torque


def rhs_and_quantities(t, y, rp, ip, lay, f, record, qty, pen, phi_q, schur, lam):
    """:func:`rhs` recording the contacts, then the quantities in QUANTITY ORDER into ``qty``
    (ω_b rad/s, α_b rad/s², |F_N n + F_T t| of every joint N (+ c_e ė with film damping:
    :func:`film_components`), torque N·m) and δ of every
    clearance joint into ``pen`` (m): an ideal revolute
    joint's force is |λ| of its two rows, a prismatic joint's |λ| of its normal row."""
    n = lay[LY_N]
    nb = n // 3
    nc = lay[LY_NC]
    nj = lay[LY_NJ]
    torque = rhs(t, y, rp, ip, lay, f, record, True, phi_q, schur, lam)
    for b in range(nb):
        qty[b] = y[n + 3 * b + 2]
        qty[nb + b] = f[n + 3 * b + 2]
    row = 0
    for j in range(nj):
        if ip[lay[LY_ACTIVE] + j] == 1:
            if ip[lay[LY_JOINT_INT] + 3 * j] == 0:
                qty[2 * nb + j] = math.hypot(lam[row], lam[row + 1])
            else:
                qty[2 * nb + j] = abs(lam[row + 1])
            row += 2
        else:
            for c in range(nc):
                if ip[lay[LY_CLEAR] + c] == j:
                    if rp[lay[LY_GEOM] + N_GEOM * c + G_FILM] > 0.0:  # what it transmits
                        film_n, film_t = film_components(y, rp, ip, lay, record, c)
                        qty[2 * nb + j] = math.hypot(
                            record[7 * c] + film_n, record[7 * c + 1] + film_t
                        )
                    else:
                        qty[2 * nb + j] = math.hypot(record[7 * c], record[7 * c + 1])
    qty[2 * nb + nj] = torque
    for c in range(nc):
        pen[c] = record[7 * c + 2]


def quantities(t, y, rp, ip, lay, f, record, qty, pen, phi_q, schur, lam):
    """:func:`rhs_and_quantities` for the peak search (``f``, ``record`` and the constraint
    arrays: work arrays)."""
    rhs_and_quantities(t, y, rp, ip, lay, f, record, qty, pen, phi_q, schur, lam)


# --- the hooks after a step (jointplay._kernels.eom) ---------------------------------------
def onset_fraction(old, new, tolerance):
    """The step's fraction ending at half the onset tolerance (secant) for a joint free at the
    step's start and deeper than ``tolerance`` at its end; 1 otherwise."""
    if new > tolerance:
        return (0.5 * tolerance - old) / (new - old)
    return 1.0


def onset_check(t, y, t_new, y_new, old, new, rp, lay):
    """Contact-onset control of the step ``(t, y) → (t_new, y_new)`` from its two ends'
    records (Flores & Ambrósio 2010): the smallest fraction of the step to retry, 1 for none;
    a joint locked at the step's start ``y`` (the sustained-contact mode) is not entering
    contact."""
    tolerance = rp[lay[LY_SETTINGS] + S_ONSET_TOL]
    base = 2 * lay[LY_N] + 2
    theta = 1.0
    for c in range(lay[LY_NC]):
        if old[7 * c + 2] <= 0.0 and not y[base + c] < 0.0:
            theta = min(theta, onset_fraction(old[7 * c + 2], new[7 * c + 2], tolerance))
    return theta


def release_fraction(t, y, t_new, y_new, rp, ip, lay):
    """The hook of the sustained-contact mode's release control: the step's fraction that ends
    where a locked joint's normal force turns tensile, 1 for none. The CPU's is
    :func:`jointplay._kernels.sustained.sustained_release_fraction`; the GPU lanes do not run the mode
    (the capability table refuses it), so this default is never reached."""
    return 1.0


def switch_contacts(t, y, rp, ip, lay, work, before):
    """The hook of the sustained-contact mode's capture and release after an accepted step;
    returns whether it changed the state. The CPU's is
    :func:`jointplay._kernels.sustained.sustained_switch_contacts`; the GPU lanes do not run the mode,
    so this default is never reached."""
    return False


def sustained_on(rp, lay):
    """Whether some clearance joint has the sustained-contact mode (the settings' largest
    capture speed > 0: one comparison)."""
    return rp[lay[LY_SETTINGS] + S_CAPTURE_MAX] > 0.0


def impact_rate(delta_0, rate_0, delta_1, rate_1):
    """δ̇ (m/s) at δ = 0 between the step's ends, linear in δ."""
    if delta_0 <= 0.0 and delta_1 > delta_0:
        return rate_0 + (rate_1 - rate_0) * (-delta_0 / (delta_1 - delta_0))
    return rate_1


def contact_memory(y, rp, lay, record, before):
    """Each joint's contact-event memory v0 (state slot 2n + 2 + c) from its records at the
    step's end (``record``) and start (``before``): a new event
    stores max(δ̇ at δ = 0, v_mark), an ended one 0. Returns: a slot changed."""
    n = lay[LY_N]
    v_mark = rp[lay[LY_SETTINGS] + S_V_MARK]
    changed = False
    for c in range(lay[LY_NC]):
        delta = record[7 * c + 2]
        delta_dot = record[7 * c + 3]
        slot = 2 * n + 2 + c
        if delta > 0.0 and y[slot] == 0.0:  # a new contact event begins (not locked)
            rate = impact_rate(before[7 * c + 2], before[7 * c + 3], delta, delta_dot)
            y[slot] = max(rate, v_mark)
            changed = True
        elif delta <= 0.0 and y[slot] > 0.0:
            y[slot] = 0.0
            changed = True
    return changed


def driver_angle(t, rp, o):
    """φ_d(t), rad, of the driver at ``rp[o:o + 4]``."""
    phi0 = rp[o + 1]
    omega = rp[o + 2]
    ramp = rp[o + 3]
    if ramp <= 0.0 or t >= ramp:
        shift = 0.5 * omega * ramp if ramp > 0.0 else 0.0
        return phi0 + shift + omega * (t - max(ramp, 0.0))
    if t <= 0.0:
        return phi0
    u = t / ramp
    return phi0 + omega * ramp * u**4 * (2.5 - 3.0 * u + u * u)


def driver_speed(t, rp, o):
    """φ̇_d(t), rad/s."""
    omega = rp[o + 2]
    ramp = rp[o + 3]
    if ramp <= 0.0 or t >= ramp:
        return omega
    if t <= 0.0:
        return 0.0
    u = t / ramp
    return omega * u**3 * (10.0 - 15.0 * u + 6.0 * u * u)


def project_driver(t, y, rp, lay):
    """Mass-weighted projection onto the one constraint of an all-clear mechanism,
    φ_k − φ_d(t) = 0, when it is violated beyond the projection tolerance
    (:func:`projection.project_lapack`; Hairer, Lubich & Wanner, *Geometric Numerical Integration*, §IV.4):
    with one row the Schur complement is 1/I_k, so the position step is Φ and the velocity
    step the drift φ̇_k − φ̇_d (written as :func:`projection.project_lapack`'s solve, x = Φ / (1/I_k), whose
    LAPACK division may differ in the last bit; never seen to run: φ̈_k is prescribed, so φ_k
    drifts by round-off only). Returns: the state changed."""
    o = lay[LY_DRIVER]
    crank = int(rp[o])
    if crank < 0:
        return False
    k = 3 * crank + 2
    n = lay[LY_N]
    tolerance = rp[lay[LY_SETTINGS] + S_PROJ_TOL]
    phi = y[k] - driver_angle(t, rp, o)
    if abs(phi) <= tolerance:
        return False
    inv = 1.0 / rp[lay[LY_MASS] + k]
    for _ in range(3):
        y[k] -= inv * (phi / inv)
        phi = y[k] - driver_angle(t, rp, o)
        if abs(phi) <= 1e-3 * tolerance:
            break
    drift = y[n + k] - driver_speed(t, rp, o)
    y[n + k] -= inv * (drift / inv)
    return True


def constraint_residual(t, y, rp, ip, lay, out):
    """Φ(q, t) into ``out``: m for the joint rows, rad for
    the angle rows."""
    o_jf = lay[LY_JOINT_F]
    row = 0
    for j in range(lay[LY_NJ]):
        kind, a, b = ideal_joint(ip, lay, j)
        if kind < 0:
            continue
        pax, pay = point_global(y, a, rp[o_jf + 6 * j], rp[o_jf + 6 * j + 1])
        pbx, pby = point_global(y, b, rp[o_jf + 6 * j + 2], rp[o_jf + 6 * j + 3])
        if kind == 0:
            out[row] = pax - pbx
            out[row + 1] = pay - pby
        else:
            phi_a = y[3 * a + 2] if a >= 0 else 0.0
            phi_b = y[3 * b + 2] if b >= 0 else 0.0
            out[row] = phi_b - phi_a - rp[o_jf + 6 * j + 5]
            nx, ny = rot(phi_a + rp[o_jf + 6 * j + 4], 0.0, 1.0)
            out[row + 1] = nx * (pbx - pax) + ny * (pby - pay)
        row += 2
    crank = int(rp[lay[LY_DRIVER]])
    if crank >= 0:
        out[row] = y[3 * crank + 2] - driver_angle(t, rp, lay[LY_DRIVER])


def max_abs(x, m):
    """max |x[:m]| (0 for none)."""
    largest = 0.0
    for i in range(m):
        largest = max(largest, abs(x[i]))
    return largest


def schur_solve(rp, lay, phi_q, schur, vec, rows):
    """Solve (Φ_q M⁻¹ Φ_qᵀ) x = vec in place (Cholesky: the matrix is symmetric positive
    definite for independent constraints)."""
    n = lay[LY_N]
    o_mass = lay[LY_MASS]
    for r in range(rows):
        for p in range(r + 1):
            s = 0.0
            for i in range(n):
                s += phi_q[r, i] * phi_q[p, i] / rp[o_mass + i]
            schur[r, p] = s
    cholesky_solve(schur, vec, rows)


def project_constraints(t, y, rp, ip, lay, phi_q, schur, vec):
    """Mass-weighted projection of q and q̇ onto the ideal constraints and the driver when
    they are violated beyond the projection tolerance (:func:`projection.project_lapack`: at most three
    Newton steps q ← q − M⁻¹ Φ_qᵀ (Φ_q M⁻¹ Φ_qᵀ)⁻¹ Φ, until max |Φ| ≤ 10⁻³ of the tolerance,
    then q̇ ← q̇ − M⁻¹ Φ_qᵀ (Φ_q M⁻¹ Φ_qᵀ)⁻¹ (Φ_q q̇ − ν); Hairer, Lubich & Wanner,
    *Geometric Numerical Integration*, §IV.4), solved by Cholesky where :func:`projection.project_lapack`
    calls LAPACK's LU (the same projection to round-off). ``vec`` (rows): work.
    Returns: the state changed."""
    n = lay[LY_N]
    o_mass = lay[LY_MASS]
    rows = constraint_rows(rp, lay)
    if rows == 0:
        return False
    tolerance = rp[lay[LY_SETTINGS] + S_PROJ_TOL]
    constraint_residual(t, y, rp, ip, lay, vec)
    if max_abs(vec, rows) <= tolerance:
        return False
    for _ in range(3):
        constraint_jacobian(y, rp, ip, lay, phi_q)
        schur_solve(rp, lay, phi_q, schur, vec, rows)
        for i in range(n):
            s = 0.0
            for r in range(rows):
                s += phi_q[r, i] * vec[r]
            y[i] -= s / rp[o_mass + i]
        constraint_residual(t, y, rp, ip, lay, vec)
        if max_abs(vec, rows) <= 1e-3 * tolerance:
            break
    constraint_jacobian(y, rp, ip, lay, phi_q)
    for r in range(rows):
        s = 0.0
        for i in range(n):
            s += phi_q[r, i] * y[n + i]
        vec[r] = s
    if rp[lay[LY_DRIVER]] >= 0:
        vec[rows - 1] -= driver_speed(t, rp, lay[LY_DRIVER])
    schur_solve(rp, lay, phi_q, schur, vec, rows)
    for i in range(n):
        s = 0.0
        for r in range(rows):
            s += phi_q[r, i] * vec[r]
        y[n + i] -= s / rp[o_mass + i]
    return True


def project(t, y, rp, ip, lay, scratch, phi_q, schur, lam):
    """The lane's projection hook, after each accepted step: returns whether it changed the
    state. This one is the GPU's: :func:`project_driver` for an all-clear mechanism, else
    :func:`project_constraints` (``phi_q``, ``schur``, ``lam``: work). The CPU's is
    :func:`projection.project_lapack` itself, LAPACK's solve included (:mod:`jointplay._kernels.lanes.cpu`,
    through :func:`build`'s ``hooks``), so that its lanes keep the old lane's bits."""
    if lay[LY_NIDEAL] == 0:
        return project_driver(t, y, rp, lay)
    return project_constraints(t, y, rp, ip, lay, phi_q, schur, lam)


def all_finite(x, size):
    """Whether ``x[:size]`` is all finite."""
    for j in range(size):  # noqa: SIM110 (a generator does not compile for the GPU)
        if not math.isfinite(x[j]):
            return False
    return True


def interrupt_pending(flags):
    """Whether ``flags`` holds SIGINT or SIGTERM."""
    for j in range(flags.shape[0]):
        code = flags[j]
        if code == 0:
            return False
        if code == SIGINT or code == SIGTERM:  # noqa: SIM109
            return True
    return False


# --- DOPRI5 (Hairer, Nørsett & Wanner, Solving ODEs I, §II.5, Table 5.2) ---------------------
C2, C3, C4, C5 = 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0
A21 = 1.0 / 5.0
A31, A32 = 3.0 / 40.0, 9.0 / 40.0
A41, A42, A43 = 44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0
A51, A52, A53, A54 = 19372.0 / 6561.0, -25360.0 / 2187.0, 64448.0 / 6561.0, -212.0 / 729.0
A61, A62, A63, A64, A65 = (
    9017.0 / 3168.0, -355.0 / 33.0, 46732.0 / 5247.0, 49.0 / 176.0, -5103.0 / 18656.0,
)  # fmt: skip
#: 5th-order weights (b2 = b7 = 0).
B1, B3, B4, B5, B6 = 35.0 / 384.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0, 11.0 / 84.0
#: Error weights E = b − b̂ (e2 = 0).
E1, E3, E4, E5, E6, E7 = (
    71.0 / 57600.0, -71.0 / 16695.0, 71.0 / 1920.0, -17253.0 / 339200.0, 22.0 / 525.0,
    -1.0 / 40.0,
)  # fmt: skip
#: Dense output (SciPy's ``RK45.P``, 7 × 4, row-major): y(t + θh) = y + h Σ_j k_j Σ_m P[j, m] θ^(m+1).
DENSE = (
    1.0, -8048581381.0 / 2820520608.0, 8663915743.0 / 2820520608.0,
    -12715105075.0 / 11282082432.0,
    0.0, 0.0, 0.0, 0.0,
    0.0, 131558114200.0 / 32700410799.0, -68118460800.0 / 10900136933.0,
    87487479700.0 / 32700410799.0,
    0.0, -1754552775.0 / 470086768.0, 14199869525.0 / 1410260304.0,
    -10690763975.0 / 1880347072.0,
    0.0, 127303824393.0 / 49829197408.0, -318862633887.0 / 49829197408.0,
    701980252875.0 / 199316789632.0,
    0.0, -282668133.0 / 205662961.0, 2019193451.0 / 616988883.0,
    -1453857185.0 / 822651844.0,
    0.0, 40617522.0 / 29380423.0, -110615467.0 / 29380423.0, 69997945.0 / 29380423.0,
)  # fmt: skip
SAFETY, MIN_FACTOR, MAX_FACTOR = 0.9, 0.2, 10.0
#: The peak rule (:mod:`jointplay._kernels.batch`): refinement margin, interior points θ = r/8.
REFINE_MARGIN = 0.01
N_REFINE = 7
#: Contact-onset retries of one step (:func:`jointplay._kernels.driver.run_core`'s ``step_check``).
MAX_CHECK_REJECTIONS = 64


def dopri_stage(k, y, h, stage, out, size):
    """DOPRI5's state (Table 5.2) where its stage ``stage + 1`` is evaluated (``stage`` = 1 …
    5: y + h Σ_j a_{stage+1, j} k_j, at t + c_{stage+1} h), or with ``stage`` = 6 the
    5th-order solution y + h Σ_j b_j k_j, into ``out``: every engine's DOPRI5 step."""
    if stage == 1:
        for i in range(size):
            out[i] = y[i] + h * (A21 * k[0, i])
    elif stage == 2:
        for i in range(size):
            out[i] = y[i] + h * (A31 * k[0, i] + A32 * k[1, i])
    elif stage == 3:
        for i in range(size):
            out[i] = y[i] + h * (A41 * k[0, i] + A42 * k[1, i] + A43 * k[2, i])
    elif stage == 4:
        for i in range(size):
            out[i] = y[i] + h * (A51 * k[0, i] + A52 * k[1, i] + A53 * k[2, i] + A54 * k[3, i])
    elif stage == 5:
        for i in range(size):
            out[i] = y[i] + h * (
                A61 * k[0, i] + A62 * k[1, i] + A63 * k[2, i] + A64 * k[3, i] + A65 * k[4, i]
            )
    else:
        for i in range(size):
            out[i] = y[i] + h * (
                B1 * k[0, i] + B3 * k[2, i] + B4 * k[3, i] + B5 * k[4, i] + B6 * k[5, i]
            )


def dopri_error(k, h, y, y_new, atol, rtol, m):
    """DOPRI5's error norm: the RMS over the first ``m`` components of h Σ_j e_j k_j in units
    of atol + rtol·max(|y|, |y_new|)."""
    total = 0.0
    for i in range(m):
        e = h * (
            E1 * k[0, i] + E3 * k[2, i] + E4 * k[3, i] + E5 * k[4, i] + E6 * k[5, i]
            + E7 * k[6, i]
        )  # fmt: skip
        scale = atol[i] + rtol * max(abs(y[i]), abs(y_new[i]))
        total += (e / scale) ** 2
    return math.sqrt(total / m)


def dense(y, k, h, theta, out, size):
    """DOPRI5's free interpolant at t + θh (SciPy's RK45 dense output) into ``out``."""
    t1 = theta
    t2 = theta * theta
    t3 = t2 * theta
    t4 = t3 * theta
    for i in range(size):
        s = 0.0
        for j in range(7):
            w = (
                DENSE[4 * j] * t1 + DENSE[4 * j + 1] * t2 + DENSE[4 * j + 2] * t3
                + DENSE[4 * j + 3] * t4
            )  # fmt: skip
            s += k[j, i] * w
        out[i] = y[i] + h * s


def triggers(ip, rp, lay, mask):
    """``mask[p]`` = 1 where quantity p may trigger a refinement: all but ω and α of the
    driven body and of bodies held by an ideal prismatic joint to the ground."""
    nb = lay[LY_N] // 3
    nj = lay[LY_NJ]
    o_ji = lay[LY_JOINT_INT]
    for p in range(lay[LY_NQ]):
        mask[p] = 1
    crank = int(rp[lay[LY_DRIVER]])
    for b in range(nb):
        fixed = b == crank
        for j in range(nj):
            if (
                ip[lay[LY_ACTIVE] + j] == 1
                and ip[o_ji + 3 * j] == 1
                and ip[o_ji + 3 * j + 1] < 0
                and ip[o_ji + 3 * j + 2] == b
            ):
                fixed = True
        if fixed:
            mask[b] = 0
            mask[nb + b] = 0


def wants_refinement(qa, qb, peaks, mask, n_q):
    """Whether a step whose ends have the quantities ``qa``, ``qb`` comes within the margin of
    a running peak of a triggering quantity."""
    for p in range(n_q):
        if mask[p] == 0:
            continue
        high = max(abs(qa[p]), abs(qb[p]))
        if peaks[p] > 0.0 and high >= (1.0 - REFINE_MARGIN) * peaks[p]:
            return True
    return False


def refine_start(qa, qb, samples, every, n_q):
    """The refinement's first quantity — 0 when ``every`` quantity is refined, else the
    last (the running responses' speed deviation alone) — with ``qa`` and ``qb`` (the step's
    two ends) as the first and last rows of ``samples`` from it on; returns it."""
    first = 0 if every else n_q - 1
    for p in range(first, n_q):
        samples[0, p] = qa[p]
        samples[N_REFINE + 1, p] = qb[p]
    return first


def refine_peaks(samples, peaks, first, n_q):
    """Raise ``peaks[first:n_q]`` to the parabolic vertex through the largest sample of |Q|
    at θ = 0, 1/8, …, 1 (rows of ``samples``) and its two neighbours."""
    for p in range(first, n_q):
        refine_one(samples, peaks, p)


def refine_one(samples, peaks, p):
    """:func:`refine_peaks` of quantity ``p`` alone."""
    last = N_REFINE + 1
    m = 0
    for i in range(1, last + 1):
        if abs(samples[i, p]) > abs(samples[m, p]):
            m = i
    best = abs(samples[m, p])
    if 0 < m < last:
        low = abs(samples[m - 1, p])
        high = abs(samples[m + 1, p])
        curvature = low - 2.0 * best + high
        if curvature < 0.0:
            offset = 0.5 * (low - high) / curvature
            offset = min(max(offset, -0.5), 0.5)
            best = best - 0.25 * (low - high) * offset
    if best > peaks[p]:
        peaks[p] = best


def open_window(q, pen, peaks, stats, nb, n_q, nc):
    """Start the window's running values from its first point."""
    for p in range(n_q):
        peaks[p] = abs(q[p])
    for k in range(2 * nb):
        stats[k] = 0.0
    for c in range(nc):
        stats[2 * nb + c] = pen[c]


def accumulate(qa, qb, pen, h, peaks, stats, nb, n_q, nc):
    """Add one step to the trapezoidal sums of ω and ω², the deepest penetrations and the
    end-point peaks."""
    for b in range(nb):
        stats[b] += 0.5 * h * (qa[b] + qb[b])
        stats[nb + b] += 0.5 * h * (qa[b] * qa[b] + qb[b] * qb[b])
    for c in range(nc):
        if pen[c] > stats[2 * nb + c]:
            stats[2 * nb + c] = pen[c]
    for p in range(n_q):
        if abs(qb[p]) > peaks[p]:
            peaks[p] = abs(qb[p])


def close_window(stats, nb, span):
    """Turn the trapezoidal sums into the mean and the RMS of ω."""
    for b in range(nb):
        stats[b] /= span
        stats[nb + b] = math.sqrt(max(stats[nb + b] / span, 0.0))


def regime_gap(rp, lay, pen, c):
    """The thinnest film h_min = c − |e| (m) of clearance joint ``c`` whose kernels' δ is
    ``pen[c]`` (δ = |e| − :func:`contact_clearance`)."""
    o = lay[LY_GEOM] + N_GEOM * c
    return rp[o + G_CLEARANCE] - (pen[c] + contact_clearance(rp, lay, c))


def open_regimes(rp, lay, pen, stats, nb, nc):
    """Start the time-in-regime integrals of every lubricated clearance joint (its
    ``G_FILM`` > 0; a dry joint's stay NaN) from the window's first point: per joint ``c``,
    three slots from ``2 nb + nc + 3 c``: the time in full film, the last point's h_min (m;
    the mixed share once closed) and the time in boundary lubrication."""
    for c in range(nc):
        s = 2 * nb + nc + 3 * c
        if rp[lay[LY_GEOM] + N_GEOM * c + G_FILM] > 0.0:
            stats[s] = 0.0
            stats[s + 1] = regime_gap(rp, lay, pen, c)
            stats[s + 2] = 0.0
        else:
            stats[s] = math.nan
            stats[s + 1] = math.nan
            stats[s + 2] = math.nan


def accumulate_regimes(rp, lay, pen, h, stats, nb, nc):
    """Add one step of length ``h`` (s) to the time-in-regime integrals: the step counts by
    λ = h_min / σ at its midpoint (the mean of its ends' h_min; σ the joint's
    ``G_ROUGHNESS``): full film for λ ≥ :data:`LAMBDA_FULL_FILM`, boundary below
    :data:`LAMBDA_BOUNDARY` (σ = 0: full film for h_min > 0, boundary at or in the wall), as
    :func:`jointplay.dynamics.regimes.joint_regime` counts the single engine's steps."""
    for c in range(nc):
        s = 2 * nb + nc + 3 * c
        if not rp[lay[LY_GEOM] + N_GEOM * c + G_FILM] > 0.0:
            continue
        gap = regime_gap(rp, lay, pen, c)
        mid = 0.5 * (stats[s + 1] + gap)
        sigma = rp[lay[LY_GEOM] + N_GEOM * c + G_ROUGHNESS]
        if sigma > 0.0:
            full = mid >= LAMBDA_FULL_FILM * sigma
            boundary = mid < LAMBDA_BOUNDARY * sigma
        else:
            full = mid > 0.0
            boundary = mid <= 0.0
        if full:
            stats[s] += h
        elif boundary:
            stats[s + 2] += h
        stats[s + 1] = gap


def close_regimes(stats, nb, nc, span):
    """Turn the time-in-regime integrals into the fractions of the window ``span`` (s) in
    full film, mixed and boundary lubrication (NaN: a dry joint)."""
    for c in range(nc):
        s = 2 * nb + nc + 3 * c
        if stats[s] == stats[s]:  # not NaN: a lubricated joint
            stats[s] /= span
            stats[s + 2] /= span
            stats[s + 1] = max(1.0 - stats[s] - stats[s + 2], 0.0)


# --- the running responses (asked for: lay[LY_NQ] one more than the model's quantities) ------
#: The running tail of a lane's ``rp`` (after the packed model, at :func:`running_base`):
#: the output body's index, the reference table's length N, the wear profiles' bins, then the
#: table's crank angles (rad, increasing in [0, 2π)) and ideal output speeds (rad/s), then
#: per clearance joint its bearing width (m), effective modulus E* (Pa) and the Archard
#: factor (the surface's share) k/H (1/Pa).
RUN_OUTPUT, RUN_POINTS, RUN_BINS, RUN_TABLE = 0, 1, 2, 3
RUN_JOINT = 3
#: The running slots of ``stats`` after the model's 2 nb + 4 nc, per clearance joint c: the
#: wear rate (m/s, at ``c``), the last point's F_N, F_N |v_T|, bearing and journal angle
#: (``nc + 4 c``), then one "started" flag (``5 nc``), then the bearing's and the journal's
#: worn amounts per bin (``5 nc + 1 + 2 bins c``, ``… + bins``; N·m, the Archard load ×
#: distance spread over the Hertz arc).
RUN_PREVIOUS = 4
#: Whether a compilation of the lanes holds the running reductions at all: a constant of the
#: target's namespace (:func:`jointplay._kernels.lanes.build.build`'s ``extras``), so that a
#: compilation without them has none of their code. Measured: their mere presence (never run)
#: made the explicit lane 12 % dearer (64 conventional lanes, one thread, CPU time 0.478 s
#: against 0.425 s), as the regimes' calls did (:func:`lane`'s docstring). The CPU
#: compiles the explicit lane twice (:mod:`jointplay._kernels.lanes.cpu`), the CUDA kernels
#: with them.
RUNNING = False
#: Whether a compilation of the loop records the trajectory (every accepted step's end, the
#: single engine's result: :func:`trace_add`) and keeps the counters of ``N_TRACE_COUNTS``;
#: a constant of the target's namespace as :data:`RUNNING` (the CPU's traced lane,
#: :mod:`jointplay._kernels.lanes.cpu`), so that no other compilation has its code — the
#: trace allocates, which the GPU cannot.
RECORD = False


def running_on(lay):
    """Whether the lane computes the running responses (the output speed's deviation from
    the ideal reference as one more quantity, the Archard wear profiles in ``stats``)."""
    return lay[LY_NQ] > 2 * (lay[LY_N] // 3) + lay[LY_NJ] + 1


def running_base(lay):
    """Where the running tail starts in a lane's ``rp``: just after the packed model."""
    return lay[LY_SETTINGS] + N_SETTINGS


def running_stats(lay):
    """Where the running slots start in ``stats``."""
    return 2 * (lay[LY_N] // 3) + 4 * lay[LY_NC]


def reference_speed(rp, lay, angle):
    """The ideal output speed (rad/s) at crank angle ``angle`` (rad): the tail's table,
    periodic over 2π, interpolated linearly (as ``numpy.interp(..., period=2π)``)."""
    r = running_base(lay)
    npts = int(rp[r + RUN_POINTS])
    xp = r + RUN_TABLE
    fp = xp + npts
    two_pi = 2.0 * math.pi
    x = angle - math.floor(angle / two_pi) * two_pi
    last = npts - 1
    if x < rp[xp]:
        x0, f0, x1, f1 = rp[xp + last] - two_pi, rp[fp + last], rp[xp], rp[fp]
    elif x >= rp[xp + last]:
        x0, f0, x1, f1 = rp[xp + last], rp[fp + last], rp[xp] + two_pi, rp[fp]
    else:
        lo = 0
        hi = last
        while hi - lo > 1:
            mid = (lo + hi) // 2
            if rp[xp + mid] <= x:
                lo = mid
            else:
                hi = mid
        x0, f0, x1, f1 = rp[xp + lo], rp[fp + lo], rp[xp + hi], rp[fp + hi]
    return f0 + (x - x0) * ((f1 - f0) / (x1 - x0))


def speed_deviation(y, rp, lay, qty):
    """The running quantity: ω_out − ω_ideal(θ_crank) (rad/s) into ``qty``'s last slot."""
    n = lay[LY_N]
    out = int(rp[running_base(lay) + RUN_OUTPUT])
    crank = int(rp[lay[LY_DRIVER]])
    qty[lay[LY_NQ] - 1] = y[n + 3 * out + 2] - reference_speed(rp, lay, y[3 * crank + 2])


def spread_weight(k, width, angle, half):
    """The elliptical weight of bin ``k`` (centre (k + ½) width) about ``angle``."""
    two_pi = 2.0 * math.pi
    d = (k + 0.5) * width - angle + math.pi
    d = d - math.floor(d / two_pi) * two_pi - math.pi
    r = d / half
    return math.sqrt(max(1.0 - r * r, 0.0))


def spread_wear(stats, base, bins, angle, amount, half_angle):
    """Add ``amount`` to the ``bins`` bins at ``stats[base:]`` around 2π with an elliptical
    weight of half-angle ``half_angle`` about ``angle`` (rad, in [0, 2π)), normalised, an arc
    narrower than a bin in the nearest bin (:func:`jointplay.dynamics.wear._spread`)."""
    width = 2.0 * math.pi / bins
    half = max(half_angle, width)
    reach = min(int(math.ceil(half / width)) + 1, bins // 2)  # noqa: RUF046 (both targets)
    nearest = int(math.floor(angle / width))  # noqa: RUF046
    if nearest >= bins:
        nearest -= bins
    total = 0.0
    for o in range(-reach, reach + 1):
        total += spread_weight(nearest + o, width, angle, half)
    if total <= 0.0:
        stats[base + nearest] += amount
        return
    for o in range(-reach, reach + 1):
        w = spread_weight(nearest + o, width, angle, half)
        if w > 0.0:
            k = nearest + o
            if k < 0:
                k += bins
            elif k >= bins:
                k -= bins
            stats[base + k] += (w / total) * amount


def body_angle(y, body):
    """The angle of ``body`` (rad; the ground's 0)."""
    return y[3 * body + 2] if body >= 0 else 0.0


def midpoint_angle(a0, a1):
    """The mean direction of two angles, in [0, 2π) (``angle(e^{i a0} + e^{i a1})``)."""
    two_pi = 2.0 * math.pi
    m = math.atan2(math.sin(a0) + math.sin(a1), math.cos(a0) + math.cos(a1))
    return m - math.floor(m / two_pi) * two_pi


def running_point(t_new, h, t_settle, y, rp, ip, lay, f, record, stats, phi_q, schur, lam):
    """Add the accepted point ``y`` at ``t_new`` (the step before it ``h`` s long) to the
    Archard wear profiles (:func:`jointplay.dynamics.wear.cycle_wear`'s trapezoidal rule on
    the integrator's steps, from the first step at or after ``t_settle``): F_N of the contact
    law (under a Reynolds film the asperities' only; a locked joint's, in the
    sustained-contact mode, its multiplier: :func:`rhs` records it), v_T, and the contact
    normal's direction in the bearing's and the journal's body, from :func:`contact_forces`
    (``f``, ``record``, ``phi_q``, ``schur``, ``lam``: work arrays)."""
    nc = lay[LY_NC]
    s = running_stats(lay)
    flag = s + 5 * nc
    started = stats[flag] > 0.0
    if not started and t_new < t_settle - 1e-12:
        return
    if locked(y, rp, lay):
        rhs(t_new, y, rp, ip, lay, f, record, True, phi_q, schur, lam)
    else:
        contact_forces(y, rp, ip, lay, f, record, True)
    r = running_base(lay)
    npts = int(rp[r + RUN_POINTS])
    bins = int(rp[r + RUN_BINS])
    o_ji = lay[LY_JOINT_INT]
    for c in range(nc):
        j = ip[lay[LY_CLEAR] + c]
        a = ip[o_ji + 3 * j + 1]
        b = ip[o_ji + 3 * j + 2]
        force = max(record[7 * c], 0.0)
        power = force * abs(record[7 * c + 4])
        ex = record[7 * c + 5]
        ey = record[7 * c + 6]
        psi = math.atan2(ey, ex) if (ex != 0.0 or ey != 0.0) else 0.0
        angle_a = psi - body_angle(y, a)
        angle_b = psi - body_angle(y, b)
        p = s + nc + RUN_PREVIOUS * c
        if started:
            amount = 0.5 * (stats[p + 1] + power) * h
            if amount > 0.0:
                pj = r + RUN_TABLE + 2 * npts + RUN_JOINT * c
                width = rp[pj]
                modulus = rp[pj + 1]
                o = lay[LY_GEOM] + N_GEOM * c
                r_j = rp[o + G_R_JOURNAL]
                r_b = r_j + rp[o + G_CLEARANCE]
                radius = r_j * r_b / (r_b - r_j) if r_b > r_j else 1e3
                f_mid = 0.5 * (stats[p] + force)
                half_width = math.sqrt(4.0 * (f_mid / width) * radius / (math.pi * modulus))
                base = s + 5 * nc + 1 + 2 * bins * c
                spread_wear(stats, base, bins, midpoint_angle(stats[p + 2], angle_a), amount,
                            half_width / r_b)  # fmt: skip
                spread_wear(stats, base + bins, bins, midpoint_angle(stats[p + 3], angle_b),
                            amount, half_width / r_j)  # fmt: skip
        stats[p] = force
        stats[p + 1] = power
        stats[p + 2] = angle_a
        stats[p + 3] = angle_b
    stats[flag] = 1.0


def start_running(rp, lay, stats):
    """The running slots before the first step: rates NaN, the last points, the flag and
    the profiles zero."""
    nc = lay[LY_NC]
    s = running_stats(lay)
    bins = int(rp[running_base(lay) + RUN_BINS])
    for c in range(nc):
        stats[s + c] = math.nan
    for m in range(s + nc, s + 5 * nc + 1 + 2 * bins * nc):
        stats[m] = 0.0


def close_running(rp, lay, stats, span):
    """Each joint's wear rate (m/s): the deepest wear of the bearing plus the journal over
    the window ``span`` (s), the profiles turned into depths (k/H share × amount over the
    bin's surface, R θ_bin w)."""
    nc = lay[LY_NC]
    s = running_stats(lay)
    r = running_base(lay)
    npts = int(rp[r + RUN_POINTS])
    bins = int(rp[r + RUN_BINS])
    arc = 2.0 * math.pi / bins
    for c in range(nc):
        pj = r + RUN_TABLE + 2 * npts + RUN_JOINT * c
        width = rp[pj]
        factor = rp[pj + 2]
        o = lay[LY_GEOM] + N_GEOM * c
        r_j = rp[o + G_R_JOURNAL]
        r_b = r_j + rp[o + G_CLEARANCE]
        base = s + 5 * nc + 1 + 2 * bins * c
        deepest_b = 0.0
        deepest_j = 0.0
        for k in range(bins):
            deepest_b = max(deepest_b, stats[base + k])
            deepest_j = max(deepest_j, stats[base + bins + k])
        depth_b = factor * deepest_b / (arc * r_b * width)
        depth_j = factor * deepest_j / (arc * r_j * width)
        stats[s + c] = (depth_b + depth_j) / span


def trace_start(t, y, size):
    """The trajectory's arrays (times, states; room for 64 rows), row 0 ``(t, y)``: the CPU's
    traced lane only (:data:`RECORD`)."""
    times = np.empty(64)
    states = np.empty((64, size))
    times[0] = t
    for i in range(size):
        states[0, i] = y[i]
    return times, states


def trace_add(times, states, m, t, y, size):
    """Row ``m`` of the trajectory ``(t, y)``, the arrays doubled first when full; returns
    them."""
    if m == times.shape[0]:
        grown_times = np.empty(2 * m)
        grown_states = np.empty((2 * m, size))
        for r in range(m):
            grown_times[r] = times[r]
            for i in range(size):
                grown_states[r, i] = states[r, i]
        times, states = grown_times, grown_states
    times[m] = t
    for i in range(size):
        states[m, i] = y[i]
    return times, states


def start_outputs(ip, rp, lay, mask, peaks, stats, counts):
    """A lane's outputs before its first step: the triggering quantities in ``mask``
    (:func:`triggers`), peaks and statistics NaN (a lane that fails leaves them so), counters
    zero."""
    triggers(ip, rp, lay, mask)
    for p in range(lay[LY_NQ]):
        peaks[p] = math.nan
    for m in range(2 * (lay[LY_N] // 3) + 4 * lay[LY_NC]):  # + the regimes' 3 nc
        stats[m] = math.nan
    for m in range(counts.shape[0]):
        counts[m] = 0
    if running_on(lay):
        start_running(rp, lay, stats)


def start_time(rp):
    """The time a lane starts at: 0 (a lane's times run from its start, s)."""
    return 0.0


def first_step(rp):
    """The first step's size asked for (0: none, SciPy's choice; a mechanism's), s."""
    return 0.0


def hold_after_failure(rp):
    """Whether the implicit methods' next step may not grow after a step that a failed try
    preceded (RADAU5's ``IF (REJECT) HNEW = MIN(HNEW, H)``, rodas.f's): always, for a
    mechanism (its right-hand side is only piecewise smooth)."""
    return True


def lane(
    ip, rp, lay, y0, t_settle, t_end, max_step, rtol, atol, max_steps, interrupt,
    peaks, stats, counts, mask, vec, q, samples, pen, records, phi_q, schur, lam, scratch, ws,
):  # fmt: skip
    """One lane of the batch contract (:mod:`jointplay._kernels.batch`), for every method:
    the one loop of every engine (and of the generic ``jointplay.integrate``, whose adapters
    take the place of the mechanism's hooks, :mod:`jointplay._kernels.driver`; a lane starts
    at ``start_time(rp)``, 0 for a mechanism). It owns the step budget, the interrupt, the smallest step, the
    contact-onset retry, the hooks after a step (contact memory, projection), finiteness, the
    running responses and the window's peaks and statistics; a method brings its steps, bound
    by :func:`jointplay._kernels.lanes.build.build` to the names the loop calls (a lane of
    ``explicit_lane`` binds ``step_attempt`` to :func:`dopri_attempt`, of ``implicit_lane`` to
    ``source_radau.radau_attempt``, …) with its constants: ``LAND_SETTLE`` (its steps land
    on the window's start, else the window opens inside the step that crosses it, at the
    method's interpolant), ``REGIMES`` (the time-in-regime statistics: their calls alone
    made a dry explicit step 15-17 % dearer, so a method that runs no film compiles without
    them) and ``RTOL_FLOOR``. The steps' contract (every method takes the same arguments):

    - ``step_start(ws, t, y, f, t_end, max_step, rtol, atol, rp, ip, lay, pen, f_mid,
      record_mid, phi_q, schur, lam, counts) -> h``: the method's state at the first point
      (``f`` and ``pen`` evaluated) and its first step's size;
    - ``step_begin(ws, t, y, f, h, max_step, min_step, rtol, atol, size) -> h``: a step from
      ``(t, y)`` (``f`` there) proposed ``h`` long: the size of its first try;
    - ``step_land(t, h, target) -> (t_new, h)``: the try's end, cut to land on ``target``;
    - ``step_attempt(ws, t, y, f, h, t_new, y_new, t_old, y_old, rtol, atol, rp, ip, lay,
      record_new, qb, pen, f_mid, record_mid, phi_q, schur, lam, counts) -> (passed, h)``:
      the try (rejections counted): ``y_new`` and the end's contact records ``record_new``,
      or the size to retry with;
    - ``step_retry(ws)``: the onset control shortened the step that passed;
    - ``step_refresh(ws, t_new, y_new, f_new, changed, rp, ip, lay, record, qb, pen, phi_q,
      schur, lam, counts) -> evaluated``: f, the records and the quantities at the accepted
      end after the hooks (``False``: the attempt's own, FSAL: the loop swaps the records);
    - ``step_accept(ws, t_new, y_new, f_new, h, changed, atol, rp, ip, lay, pen, f_mid,
      record_mid, phi_q, schur, lam, counts) -> h``: the accepted step into the method's
      state; the next step's proposed size;
    - ``step_dense(ws, t_old, y_old, t, y, f, t_new, y_new, f_new, h, tau, theta, out, lay)``:
      the method's interpolant at ``tau`` = t + θh into ``out``.

    Work arrays (the caller's, any contents): ``mask`` (P, int); ``vec`` (9, S): three states
    (the step's start, end and the one before), two f, the refinement's and the window
    opening's state and f; ``q`` (2, P) the quantities at a step's two ends; ``samples``
    (9, P); ``pen`` (2, nc); ``records`` (3, 7 nc); ``phi_q`` (rows × 3 nb), ``schur``
    (rows × rows), ``lam`` (rows), ``scratch``: the target's :func:`project`'s; ``ws``: the
    method's work (a tuple its steps read). The sustained-contact mode's hooks
    (``release_fraction``, ``switch_contacts``, ``locked_accelerations``) are the CPU's
    (:mod:`jointplay._kernels.sustained`); the GPU lanes refuse the mode (the capability
    table).

    Returns:
        ``(status, t_reached)``: a ``STATUS_*`` code and the last accepted time, s; compiled
        with :data:`RECORD` (the single engine's traced lane), also the trajectory
        ``(times, states)``: the start and every accepted step's end, after the hooks.
    """
    n = lay[LY_N]
    nb = n // 3
    nc = lay[LY_NC]
    size = lay[LY_SIZE]
    n_q = lay[LY_NQ]
    start_outputs(ip, rp, lay, mask, peaks, stats, counts)
    t = start_time(rp)
    if RECORD:
        times, states = trace_start(t, y0, size)
        m = 1
    if interrupt_pending(interrupt):
        if RECORD:
            return STATUS_INTERRUPTED, t, times[:m], states[:m]
        else:
            return STATUS_INTERRUPTED, t
    rtol = max(rtol, RTOL_FLOOR)
    y, y_new, y_old, f, f_new = vec[0], vec[1], vec[2], vec[3], vec[4]
    y_mid, f_mid, y_open, f_open = vec[5], vec[6], vec[7], vec[8]
    qa, qb = q[0], q[1]
    pen_open = pen[1]
    pen = pen[0]
    record, record_new, record_mid = records[0], records[1], records[2]
    for i in range(size):
        y[i] = y0[i]
    rhs_and_quantities(t, y, rp, ip, lay, f, record, qa, pen, phi_q, schur, lam)
    counts[K_RHS] += 1
    if not (all_finite(y, size) and all_finite(f, size)):
        if RECORD:
            return STATUS_NON_FINITE, t, times[:m], states[:m]
        else:
            return STATUS_NON_FINITE, t
    running = RUNNING and running_on(lay)
    if running:
        speed_deviation(y, rp, lay, qa)
        running_point(t, 0.0, t_settle, y, rp, ip, lay, f_mid, record_mid, stats, phi_q,
                      schur, lam)  # fmt: skip
    in_window = t_settle <= 0.0
    if in_window:
        open_window(qa, pen, peaks, stats, nb, n_q, nc)
        if REGIMES:
            open_regimes(rp, lay, pen, stats, nb, nc)
    h_next = step_start(ws, t, y, f, t_end, max_step, rtol, atol, rp, ip, lay, pen, f_mid,
                        record_mid, phi_q, schur, lam, counts)  # fmt: skip
    t_old = t
    status = STATUS_RUNNING
    while status == STATUS_RUNNING:
        if t >= t_end:
            status = STATUS_SUCCESS
            break
        if counts[K_STEPS] >= max_steps:
            status = STATUS_TOO_MANY_STEPS
            break
        if interrupt_pending(interrupt):
            status = STATUS_INTERRUPTED
            break
        target = t_settle if (LAND_SETTLE and t < t_settle) else t_end
        min_step = 10.0 * abs(math.nextafter(t, math.inf) - t)
        h_try = step_begin(ws, t, y, f, h_next, max_step, min_step, rtol, atol, size)
        n_check = 0
        t_new = t
        h = h_try
        while True:
            if h_try < min_step:
                status = STATUS_STEP_TOO_SMALL
                break
            t_new, h = step_land(t, h_try, target)
            passed, h_try = step_attempt(
                ws, t, y, f, h, t_new, y_new, t_old, y_old, rtol, atol, rp, ip, lay, record_new, qb,
                pen, f_mid, record_mid, phi_q, schur, lam, counts,
            )  # fmt: skip
            if not passed:
                continue
            # the contact-onset control on the two ends' records; in the
            # sustained-contact mode, the release control (the locked set is the step's)
            theta = onset_check(t, y, t_new, y_new, record, record_new, rp, lay)
            if locked(y_new, rp, lay):
                theta = min(theta, release_fraction(t, y, t_new, y_new, rp, ip, lay))
            shorter = h * theta
            if theta < 1.0 and min_step <= shorter < h and n_check < MAX_CHECK_REJECTIONS:
                h_try = shorter
                step_retry(ws)
                n_check += 1
                counts[K_REJECTED] += 1
                if RECORD:
                    counts[K_REJ_CHECK] += 1
                continue
            break
        if status != STATUS_RUNNING:
            break
        # after the step: the contact memory from the two ends' records, the sustained-contact
        # mode's capture and release, then the projection
        changed = contact_memory(y_new, rp, lay, record_new, record)
        if sustained_on(rp, lay) and switch_contacts(t_new, y_new, rp, ip, lay, scratch, record):
            changed = True
        changed = project(t_new, y_new, rp, ip, lay, scratch, phi_q, schur, lam) or changed
        if not step_refresh(ws, t_new, y_new, f_new, changed, rp, ip, lay, record, qb, pen,
                            phi_q, schur, lam, counts):  # fmt: skip
            record, record_new = record_new, record  # the end's records become the start's
            if locked(y_new, rp, lay):  # the mode's projection moved q: δ, δ̇ afresh
                for c in range(nc):
                    record[7 * c + 2], record[7 * c + 3] = penetration_and_rate(
                        y_new, rp, ip, lay, c
                    )
        if not (all_finite(y_new, size) and all_finite(f_new, size)):
            status = STATUS_NON_FINITE
            break
        if running:
            speed_deviation(y_new, rp, lay, qb)
            running_point(t_new, h, t_settle, y_new, rp, ip, lay, f_mid, record_mid, stats,
                          phi_q, schur, lam)  # fmt: skip
        h_next = step_accept(ws, t_new, y_new, f_new, h, changed, atol, rp, ip, lay, pen,
                             f_mid, record_mid, phi_q, schur, lam, counts)  # fmt: skip
        # the peaks and statistics of this step (batch's module docstring)
        t_a = t
        h_window = h
        add = in_window
        if not in_window and t_new == t_settle:  # the window opens at this step's end
            in_window = True
            for p in range(n_q):
                qa[p] = qb[p]
            open_window(qa, pen, peaks, stats, nb, n_q, nc)
            if REGIMES:
                open_regimes(rp, lay, pen, stats, nb, nc)
        elif not (LAND_SETTLE or in_window) and t_new > t_settle:  # … inside it: from there
            in_window = True
            add = True
            step_dense(ws, t_old, y_old, t, y, f, t_new, y_new, f_new, h, t_settle,
                       (t_settle - t) / h, y_open, lay)  # fmt: skip
            quantities(t_settle, y_open, rp, ip, lay, f_open, record_mid, qa, pen_open, phi_q,
                       schur, lam)  # fmt: skip
            if running:
                speed_deviation(y_open, rp, lay, qa)
            open_window(qa, pen_open, peaks, stats, nb, n_q, nc)
            if REGIMES:
                open_regimes(rp, lay, pen_open, stats, nb, nc)
            t_a = t_settle
            h_window = t_new - t_settle
        if add:
            accumulate(qa, qb, pen, h_window, peaks, stats, nb, n_q, nc)
            if REGIMES:
                accumulate_regimes(rp, lay, pen, h_window, stats, nb, nc)
            every = wants_refinement(qa, qb, peaks, mask, n_q - 1 if running else n_q)
            if every or running:  # the deviation alone is refined on every step (its own rule)
                first = refine_start(qa, qb, samples, every, n_q)
                for r in range(N_REFINE):
                    theta = (r + 1) / 8.0
                    tau = t_a + theta * h_window
                    step_dense(ws, t_old, y_old, t, y, f, t_new, y_new, f_new, h, tau, theta,
                               y_mid, lay)  # fmt: skip
                    if every:
                        quantities(tau, y_mid, rp, ip, lay, f_mid, record_mid, samples[r + 1],
                                   pen_open, phi_q, schur, lam)  # fmt: skip
                    if running:
                        speed_deviation(y_mid, rp, lay, samples[r + 1])
                refine_peaks(samples, peaks, first, n_q)
            qa, qb = qb, qa
        if RECORD:
            times, states = trace_add(times, states, m, t_new, y_new, size)
            m += 1
        t_old = t
        t = t_new
        y_old, y, y_new = y, y_new, y_old
        f, f_new = f_new, f
        counts[K_STEPS] += 1
    if status == STATUS_SUCCESS:
        close_window(stats, nb, t_end - t_settle)
        if REGIMES:
            close_regimes(stats, nb, nc, t_end - t_settle)
        if running:
            close_running(rp, lay, stats, t_end - t_settle)
    if RECORD:
        return status, t, times[:m], states[:m]
    else:
        return status, t


def rms(x, scale, size):
    """SciPy's norm(x / scale): the RMS of x_j / scale_j."""
    s = 0.0
    for j in range(size):
        v = x[j] / scale[j]
        s += v * v
    return math.sqrt(s) / math.sqrt(size)


def initial_trial(y0, f0, rtol, atol, scale, interval_length, size):
    """SciPy's ``select_initial_step`` for order 3 (Hairer, Nørsett & Wanner, *Solving ODEs
    I*, §II.4), its first half: the error scale into ``scale``, the norm ``d1`` of f0 and the
    trial step ``h0``; returns ``(h0, d1)``."""
    for j in range(size):
        scale[j] = atol[j] + abs(y0[j]) * rtol
    d0 = rms(y0, scale, size)
    d1 = rms(f0, scale, size)
    h0 = 1e-6 if (d0 < 1e-5 or d1 < 1e-5) else 0.01 * d0 / d1
    return min(h0, interval_length), d1


def initial_choice(f0, f1, diff, scale, d1, h0, interval_length, max_step, size):
    """Its second half, from ``f1``, f at the trial point ``y0 + h0 f0`` (``diff``: work):
    the first step."""
    for j in range(size):
        diff[j] = f1[j] - f0[j]
    d2 = rms(diff, scale, size) / h0
    if d1 <= 1e-15 and d2 <= 1e-15:
        h1 = max(1e-6, h0 * 1e-3)
    else:
        h1 = (0.01 / max(d1, d2)) ** (1.0 / (3 + 1))
    return min(100.0 * h0, h1, interval_length, max_step)


def initial_step(t0, y0, t_bound, max_step, f0, rtol, atol, rp, ip, lay, y1, f1, scale,
                 record, phi_q, schur, lam, counts):  # fmt: skip
    """Every method's first step: the one asked for (:func:`first_step`), else SciPy's
    choice (:func:`initial_trial`, :func:`initial_choice`), one evaluation of f, counted
    (``y1``, ``f1``, ``scale``: work)."""
    asked = first_step(rp)
    if asked > 0.0:
        return asked
    size = lay[LY_SIZE]
    interval_length = abs(t_bound - t0)
    if interval_length == 0.0:
        return 0.0
    h0, d1 = initial_trial(y0, f0, rtol, atol, scale, interval_length, size)
    for j in range(size):
        y1[j] = y0[j] + h0 * 1.0 * f0[j]
    rhs(t0 + h0 * 1.0, y1, rp, ip, lay, f1, record, False, phi_q, schur, lam)
    counts[K_RHS] += 1
    return initial_choice(f0, f1, y1, scale, d1, h0, interval_length, max_step, size)


# --- DOPRI5's steps in the lane (the explicit method; the loop: lane) ------------------------
#: DOPRI5's ``ws``, one array (9, S): the stages k_1..k_7 (rows 0-6), a stage's state (row
#: 7) and its scalars (row 8): the error norm of the try that passed, whether a try of this
#: step was rejected by the error test.
DOPRI_STATE, DOPRI_SCALARS = 7, 8
DOPRI_ERROR, DOPRI_REJECTED = 0, 1
#: DOPRI5's lane record (the one place it is declared;
#: :data:`jointplay._kernels.lanes.SOURCES` finds it): the integrator
#: (:class:`jointplay._kernels.integrators.Integrator`'s fields), the lane's name, its steps'
#: prefix, its work: the CPU's allocator (``work``), the shapes of its arrays (``shapes``, a
#: function of the state's size S and its structure m2, nk: ``LY_SECOND``, ``LY_KEPT``), their
#: dtypes and the function that makes the method's ``ws`` of them (``arrays``; a GPU thread's
#: arrays are its kernel's local arrays, :mod:`jointplay._kernels.lanes.cuda_kernel`), and the
#: loop's constants (:func:`lane`).
LANE = {
    "integrator": {
        "name": "dopri5", "title": "DOPRI5 (order 5, explicit)", "order": 5, "explicit": True,
        "tolerance_scale": 0.2, "engines": ("single", "lanes-explicit", "jax"),
    },
    "lane": "explicit_lane", "steps": "dopri", "work": "dopri_work",
    "shapes": "dopri_shapes", "arrays": "dopri_arrays", "dtypes": ("float64",),
    "LAND_SETTLE": True, "REGIMES": False, "RTOL_FLOOR": 0.0,
}  # fmt: skip


def dopri_shapes(size, m2, nk):
    """The shapes of DOPRI5's work arrays: the stages, a stage's state and the scalars (9, S)."""
    return ((9, size),)


def dopri_arrays(k):
    """DOPRI5's ``ws`` (``DOPRI_STATE``) of its array: ``k``, zeroed."""
    for i in range(k.shape[0]):
        for j in range(k.shape[1]):
            k[i, j] = 0.0
    return k


def dopri_work(lay):
    """DOPRI5's ``ws``; it allocates: the CPU's."""
    return dopri_arrays(np.empty(dopri_shapes(lay[LY_SIZE], lay[LY_SECOND], lay[LY_KEPT])[0]))


def dopri_start(ws, t, y, f, t_end, max_step, rtol, atol, rp, ip, lay, pen, f_mid, record_mid,
                phi_q, schur, lam, counts):  # fmt: skip
    """The first step: a tenth of the largest (the batch lanes'); the traced lane's (the
    single engine's), SciPy's choice (:func:`initial_step`)."""
    if RECORD:
        return initial_step(t, y, t_end, max_step, f, rtol, atol, rp, ip, lay, ws[DOPRI_STATE],
                            f_mid, ws[0], record_mid, phi_q, schur, lam, counts)  # fmt: skip
    else:
        return max_step / 10.0


def dopri_begin(ws, t, y, f, h, max_step, min_step, rtol, atol, size):
    """A step's first try: at most the largest step."""
    ws[DOPRI_SCALARS, DOPRI_REJECTED] = 0.0
    return min(h, max_step)


def dopri_land(t, h, target):
    """The try's end, cut to land on ``target`` (the window's start, then its end); the
    traced lane's step is the difference of its ends, as the single engine's was."""
    t_new = t + h
    if t_new >= target:
        return target, target - t
    if RECORD:
        return t_new, t_new - t
    else:
        return t_new, h


def dopri_attempt(ws, t, y, f, h, t_new, y_new, t_old, y_old, rtol, atol, rp, ip, lay, record_new,
                  qb, pen, f_mid, record_mid, phi_q, schur, lam, counts):  # fmt: skip
    """A try of DOPRI5 (the batch contract's "explicit"): the stages, the 5th-order solution
    and the error test on the first 2 n components (the traced lane's, the single engine's:
    on every component, and a non-finite stage fails the try); the last stage also records
    the end's contacts and quantities."""
    k = ws
    ys = ws[DOPRI_STATE]
    size = lay[LY_SIZE]
    for i in range(size):
        k[0, i] = f[i]
    dopri_stage(k, y, h, 1, ys, size)
    rhs(t + C2 * h, ys, rp, ip, lay, k[1], record_mid, False, phi_q, schur, lam)
    dopri_stage(k, y, h, 2, ys, size)
    rhs(t + C3 * h, ys, rp, ip, lay, k[2], record_mid, False, phi_q, schur, lam)
    dopri_stage(k, y, h, 3, ys, size)
    rhs(t + C4 * h, ys, rp, ip, lay, k[3], record_mid, False, phi_q, schur, lam)
    dopri_stage(k, y, h, 4, ys, size)
    rhs(t + C5 * h, ys, rp, ip, lay, k[4], record_mid, False, phi_q, schur, lam)
    dopri_stage(k, y, h, 5, ys, size)
    rhs(t + h, ys, rp, ip, lay, k[5], record_mid, False, phi_q, schur, lam)
    dopri_stage(k, y, h, 6, y_new, size)
    # the last stage also gives the contact records and the quantities at the step's end
    rhs_and_quantities(t_new, y_new, rp, ip, lay, k[6], record_new, qb, pen, phi_q, schur, lam)
    counts[K_RHS] += 6
    if RECORD:
        err = dopri_error(k, h, y, y_new, atol, rtol, size)
        if not (all_finite(y_new, size) and all_finite(k[6], size)):
            err = math.nan
        if not err <= 1.0:  # NaN fails too
            ws[DOPRI_SCALARS, DOPRI_REJECTED] = 1.0
            counts[K_REJECTED] += 1
            shrink = SAFETY * err**-0.2 if math.isfinite(err) else MIN_FACTOR
            return False, h * max(MIN_FACTOR, min(1.0, shrink))
    else:
        err = dopri_error(k, h, y, y_new, atol, rtol, 2 * lay[LY_N])
        if err > 1.0:
            ws[DOPRI_SCALARS, DOPRI_REJECTED] = 1.0
            counts[K_REJECTED] += 1
            return False, h * max(MIN_FACTOR, SAFETY * err**-0.2)
    ws[DOPRI_SCALARS, DOPRI_ERROR] = err
    return True, h


def dopri_retry(ws):
    """Nothing of DOPRI5's state depends on the step's size."""
    return


def dopri_refresh(ws, t_new, y_new, f_new, changed, rp, ip, lay, record, qb, pen, phi_q, schur,
                  lam, counts):  # fmt: skip
    """f at the accepted end: the last stage's (FSAL) unless the hooks changed the state."""
    if changed:
        rhs_and_quantities(t_new, y_new, rp, ip, lay, f_new, record, qb, pen, phi_q, schur, lam)
        counts[K_RHS] += 1
        return True
    for i in range(lay[LY_SIZE]):
        f_new[i] = ws[6, i]
    return False


def dopri_accept(ws, t_new, y_new, f_new, h, changed, atol, rp, ip, lay, pen, f_mid,
                 record_mid, phi_q, schur, lam, counts):  # fmt: skip
    """The next step's size: ``h·min(10, max(0.2, 0.9·err^(−1/5)))``, at most ``h`` after a
    rejection."""
    err = ws[DOPRI_SCALARS, DOPRI_ERROR]
    factor = MAX_FACTOR if err == 0.0 else min(MAX_FACTOR, max(MIN_FACTOR, SAFETY * err**-0.2))
    if ws[DOPRI_SCALARS, DOPRI_REJECTED] > 0.0:
        factor = min(factor, 1.0)
    return h * factor


def dopri_dense(ws, t_old, y_old, t, y, f, t_new, y_new, f_new, h, tau, theta, out, lay):
    """DOPRI5's free interpolant (:func:`dense`) at t + θh."""
    dense(y, ws, h, theta, out, lay[LY_SIZE])


# The names the loop calls for its method: build.py binds each lane's own (its source module's
# LANE record, and its steps); these, the explicit lane's, only let
# a reader and the linters find them.
LAND_SETTLE, REGIMES, RTOL_FLOOR = True, False, 0.0
step_start, step_begin, step_land, step_attempt = (
    dopri_start,
    dopri_begin,
    dopri_land,
    dopri_attempt,
)
step_retry, step_refresh, step_accept, step_dense = (
    dopri_retry,
    dopri_refresh,
    dopri_accept,
    dopri_dense,
)
