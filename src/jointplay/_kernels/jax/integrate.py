"""Batch integrators in JAX: explicit Dormand–Prince 5(4) and implicit Radau IIA (order 5).

One lane is one sample: :func:`lane_runner` returns a function of one lane's ``rpar`` row,
initial state and settings that integrates from t = 0 to ``t_end`` in one ``lax.while_loop``
and returns the lane's peaks and steady-cycle statistics; :mod:`jointplay._kernels.jax_batch`
maps it over the lanes with ``jax.vmap`` (the batched loop runs until every lane has stopped;
a stopped lane is frozen), so each lane keeps its own step size. One loop iteration is one
step *attempt*: the error test, the contact-onset check and acceptance are decided per lane
by ``jnp.where``. Nothing is saved per step: the running peaks, the trapezoidal sums and the
largest penetrations live in the loop carry.

**Step control (the batch contract, shared with the Numba backend).**

- t0 = 0; first step ``max_step/10``; h ≤ ``max_step``; steps land exactly on ``t_settle``
  and ``t_end``; a fresh step is raised to ``min_step = 10·spacing(t)`` and a retried step
  shorter than it stops the lane (``STATUS_STEP_TOO_SMALL``); ``max_steps`` accepted steps
  without reaching ``t_end`` stop it with ``STATUS_TOO_MANY_STEPS``; a non-finite state or ẏ
  after a step with ``STATUS_NON_FINITE``.
- Error norm: RMS over the first 2·n_coordinates components of err_i / (atol_i +
  rtol·max(|y_i|, |y_new,i|)) (the work integrals and the impact memory v0 excluded).
- Explicit: DOPRI5 of Hairer, Nørsett & Wanner (*Solving ODEs I*, §II.5, Table 5.2; their
  ``dopri5.f``), FSAL; new step ``h·clamp(0.9·err^(−1/5), 0.2, 10)`` (10 when err = 0),
  at most h for the step accepted after an error rejection in the same step.
- Implicit: Radau IIA 5 as :mod:`jointplay._kernels.radau` (SciPy's algorithm: simplified
  Newton on the eigen-transformed real and complex systems, at most 6 iterations, the
  embedded error estimate re-estimated after a rejection, the predictive controller with
  safety 0.9·13/(12 + iterations), growth at most 10, none after a failure (RADAU5's
  ``hold_after_failure``), the step halved when Newton fails). Different from the Numba
  kernel: the Jacobian is ``jax.jacfwd`` of the right-hand side (all S columns), recomputed
  and factorised at every attempt (two S×S LU factorisations, one real and one complex, per
  lane), and Newton starts from zero, not from the last step's collocation polynomial.
- Contact onset: on a step that passed the error test, θ = ``step_check``; θ < 1 with
  min_step ≤ θh < h retries the step with θh, at most 64 times per step (then the step is
  accepted). After an accepted step, ``after_step`` (v0, projection), then ẏ is evaluated at
  the resulting state (the next step's first stage).

**Peaks and statistics over [t_settle, t_end]** (PEAK RULE; the Numba backend computes the
same numbers). Quantities are those of :meth:`~jointplay._kernels.jax.eom.JaxModel.outputs`.

1. At every accepted step end t_new ≥ t_settle (and at t = 0 when t_settle ≤ 0): every
   quantity at the state after ``after_step``.
2. Inside every accepted step that starts at t ≥ t_settle (steps land on t_settle, so no step
   straddles it): every quantity at θ = 1/4, 1/2, 3/4 of the step, at the state of the
   method's dense output (DOPRI5: Hairer's 4th-order continuous extension ``CONTD5``;
   Radau: the collocation polynomial), with v0 of the step's start; and ω of every body
   (a state component, cheap) at θ = k/16, k = 1..15, on the same dense output.
3. Peaks: the largest |value| of all of these. Largest penetration δ of each clearance joint:
   the largest of its values at the points of 1 and 2.
4. Mean and RMS of ω of every body: trapezoidal rule over the accepted steps in the window
   (states after ``after_step``), divided by t_end − t_settle (by the window covered when a
   lane stops early; the value at t_settle for an empty window).

Counters: ``n_rhs`` counts the integrator's evaluations of ẏ (1 at t = 0, 6 per explicit
attempt, 1 after each accepted step; for Radau, 3 per Newton iteration and 1 per error
re-estimate, the Jacobian's forward passes not included); the evaluations of rule 2 are not
counted.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import jax
import jax.numpy as jnp
import jax.scipy.linalg as jsl
import numpy as np
from jax import lax

from jointplay._kernels.common import (
    STATUS_NON_FINITE,
    STATUS_RUNNING,
    STATUS_STEP_TOO_SMALL,
    STATUS_SUCCESS,
    STATUS_TOO_MANY_STEPS,
)
from jointplay._kernels.jax.eom import JaxModel

#: Consecutive contact-onset retries of one step after which it is accepted (radau's).
MAX_CHECK_REJECTIONS = 64
#: Fractions of an accepted step where every quantity is evaluated (PEAK RULE 2).
REFINE_THETAS = (0.25, 0.5, 0.75)
#: Fractions where ω is read off the dense output (PEAK RULE 2).
OMEGA_THETAS = tuple(k / 16.0 for k in range(1, 16))

# ---- Dormand–Prince 5(4), Hairer's dopri5.f ---------------------------------------------
DP_C = (0.0, 1 / 5, 3 / 10, 4 / 5, 8 / 9, 1.0, 1.0)
DP_A = (
    (),
    (1 / 5,),
    (3 / 40, 9 / 40),
    (44 / 45, -56 / 15, 32 / 9),
    (19372 / 6561, -25360 / 2187, 64448 / 6561, -212 / 729),
    (9017 / 3168, -355 / 33, 46732 / 5247, 49 / 176, -5103 / 18656),
    (35 / 384, 0.0, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84),
)
#: Error coefficients e_i = b_i − b̂_i (k2 has none).
DP_E = (71 / 57600, 0.0, -71 / 16695, 71 / 1920, -17253 / 339200, 22 / 525, -1 / 40)
#: Dense-output coefficients of CONTD5 (Hairer's d1..d7; d2 = 0).
DP_D = (
    -12715105075 / 11282082432,
    0.0,
    87487479700 / 32700410799,
    -10690763975 / 1880347072,
    701980252875 / 199316789632,
    -1453857185 / 822651844,
    69997945 / 29380423,
)

_DP_MATRIX = np.array([list(row) + [0.0] * (7 - len(row)) for row in DP_A])

# ---- Radau IIA 5, SciPy's radau.py ----------------------------------------------------------
S6 = 6**0.5
RADAU_C = np.array([(4 - S6) / 10, (4 + S6) / 10, 1.0])
RADAU_E = np.array([-13 - 7 * S6, -13 + 7 * S6, -1]) / 3
_MU = np.linalg.eigvals(
    np.array(
        [
            [(88 - 7 * S6) / 360, (296 - 169 * S6) / 1800, (-2 + 3 * S6) / 225],
            [(296 + 169 * S6) / 1800, (88 + 7 * S6) / 360, (-2 - 3 * S6) / 225],
            [(16 - S6) / 36, (16 + S6) / 36, 1 / 9],
        ]
    )
)
RADAU_T = np.array(
    [
        [0.09443876248897524, -0.14125529502095421, 0.03002919410514742],
        [0.25021312296533332, 0.20412935229379994, -0.38294211275726192],
        [1.0, 1.0, 0.0],
    ]
)
RADAU_TI = np.array(
    [
        [4.17871859155190428, 0.32768282076106237, 0.52337644549944951],
        [-4.17871859155190428, -0.32768282076106237, 0.47662355450055044],
        [0.50287263494578682, -2.57192694985560522, 0.59603920482822492],
    ]
)
RADAU_TI_REAL = RADAU_TI[0]
RADAU_TI_COMPLEX = RADAU_TI[1] + 1j * RADAU_TI[2]
MU_REAL = 3 + 3 ** (2 / 3) - 3 ** (1 / 3)
MU_COMPLEX = (3 + 0.5 * (3 ** (1 / 3) - 3 ** (2 / 3))) - 0.5j * (3 ** (5 / 6) + 3 ** (7 / 6))
RADAU_P = np.array(
    [
        [13 / 3 + 7 * S6 / 3, -23 / 3 - 22 * S6 / 3, 10 / 3 + 5 * S6],
        [13 / 3 - 7 * S6 / 3, -23 / 3 + 22 * S6 / 3, 10 / 3 - 5 * S6],
        [1 / 3, -8 / 3, 10 / 3],
    ]
)
NEWTON_MAXITER = 6
EPS = float(np.finfo(np.float64).eps)

Lane = dict[str, Any]


def _rms(x: Any, scale: Any) -> Any:
    v = x / scale
    return jnp.sqrt(jnp.sum(v * v)) / jnp.sqrt(float(x.shape[-1]))


def _all_finite(x: Any) -> Any:
    return jnp.all(jnp.isfinite(x))


class _LaneIntegrator:
    """The parts of one lane's integration that both methods share (module docstring)."""

    def __init__(self, model: JaxModel, method: str) -> None:
        self.model = model
        self.method = method
        layout = model.layout
        self.n = layout.n
        self.nb = layout.nb
        self.nc = layout.nc
        self.S = layout.n_state

    # ---- peaks and statistics ------------------------------------------------------------
    def _omega(self, y: Any) -> Any:
        n = self.n
        return jnp.stack([y[n + 3 * b + 2] for b in range(self.nb)])

    def _record_points(
        self, c: Lane, p: Any, t: Any, h: Any, t_new: Any, y_acc: Any,
        dense: Callable[[Any], Any], t_settle: Any,
    ) -> tuple[Any, Any, Any, Any, Any]:  # fmt: skip
        """ẏ at the step's end and the peaks, penetrations and trapezoidal sums after an
        accepted step (PEAK RULE)."""
        model = self.model
        end_in = t_new >= t_settle
        inside = t >= t_settle
        # The step's end (after after_step) and its interior points, in one batched call.
        thetas = jnp.asarray(REFINE_THETAS)
        times = jnp.concatenate([t + thetas * h, t_new[None]])
        states = jnp.concatenate([jax.vmap(dense)(thetas), y_acc[None]])
        ydots, vals, pens = jax.vmap(model.outputs, in_axes=(0, 0, None))(times, states, p)
        vals = jnp.abs(vals)
        peaks = jnp.where(end_in, jnp.maximum(c["peaks"], vals[-1]), c["peaks"])
        pen = jnp.where(end_in, jnp.maximum(c["pen"], pens[-1]), c["pen"])
        refined = jnp.max(vals[:-1], axis=0)
        refined_pen = jnp.max(pens[:-1], axis=0) if self.nc else pens[0]
        omegas = jax.vmap(lambda theta: self._omega(dense(theta)))(jnp.asarray(OMEGA_THETAS))
        refined = refined.at[: self.nb].set(
            jnp.maximum(refined[: self.nb], jnp.max(jnp.abs(omegas), axis=0))
        )
        peaks = jnp.where(inside, jnp.maximum(peaks, refined), peaks)
        pen = jnp.where(inside, jnp.maximum(pen, refined_pen), pen)
        w0 = self._omega(c["y"])
        w1 = self._omega(y_acc)
        s1 = jnp.where(inside, c["s1"] + 0.5 * (w0 + w1) * h, c["s1"])
        s2 = jnp.where(inside, c["s2"] + 0.5 * (w0 * w0 + w1 * w1) * h, c["s2"])
        return ydots[-1], peaks, pen, s1, s2

    # ---- one lane ---------------------------------------------------------------------------
    def __call__(
        self, p: Any, y0: Any, t_settle: Any, t_end: Any, max_step: Any, rtol: Any, atol: Any,
        max_steps: Any,
    ) -> dict[str, Any]:  # fmt: skip
        model = self.model
        zero = jnp.zeros_like(t_end)
        f0, vals0, pen0 = model.outputs(zero, y0, p)
        start_in = t_settle <= 0.0
        finite = _all_finite(y0) & _all_finite(f0)
        carry: Lane = {
            "t": zero,
            "y": y0,
            "f": f0,
            "h": max_step / 10.0,
            "h_prop": max_step / 10.0,
            "retry": jnp.array(False),
            "failed": jnp.array(False),
            "n_check": jnp.array(0, dtype=jnp.int64),
            "status": jnp.where(finite, STATUS_RUNNING, STATUS_NON_FINITE).astype(jnp.int64),
            "n_steps": jnp.array(0, dtype=jnp.int64),
            "n_rejected": jnp.array(0, dtype=jnp.int64),
            "n_rhs": jnp.array(1, dtype=jnp.int64),
            "peaks": jnp.where(start_in, jnp.abs(vals0), 0.0),
            "pen": jnp.where(start_in, pen0, -jnp.inf),
            "s1": jnp.zeros(self.nb, dtype=y0.dtype),
            "s2": jnp.zeros(self.nb, dtype=y0.dtype),
            "h_old": jnp.full_like(t_end, jnp.nan),
            "err_old": jnp.full_like(t_end, jnp.nan),
        }
        if self.method == "implicit":
            rtol = jnp.maximum(rtol, 100.0 * EPS)
        settings = (p, t_settle, t_end, max_step, rtol, atol, max_steps)
        attempt = self._dopri_attempt if self.method == "explicit" else self._radau_attempt

        def body(c: Lane) -> Lane:
            return self._step(c, settings, attempt)

        c = lax.while_loop(lambda c: c["status"] == STATUS_RUNNING, body, carry)
        span = c["t"] - t_settle
        covered = span > 0.0
        safe = jnp.where(covered, span, 1.0)
        omega_end = self._omega(c["y"])
        mean = jnp.where(covered, c["s1"] / safe, omega_end)
        rms = jnp.where(covered, jnp.sqrt(c["s2"] / safe), jnp.abs(omega_end))
        return {
            "peaks": c["peaks"],
            "stats": jnp.concatenate([mean, rms, c["pen"]]),
            "status": c["status"],
            "t_reached": c["t"],
            "n_steps": c["n_steps"],
            "n_rejected": c["n_rejected"],
            "n_rhs": c["n_rhs"],
        }

    def _step(self, c: Lane, settings: tuple[Any, ...], attempt: Callable[..., Any]) -> Lane:
        """One step attempt with its decision (accept, reject, retry shorter, stop)."""
        p, t_settle, t_end, max_step, rtol, atol, max_steps = settings
        model = self.model
        t, y = c["t"], c["y"]
        min_step = 10.0 * (jnp.nextafter(t, jnp.inf) - t)
        fresh = ~c["retry"]
        clamped = fresh & ((c["h"] > max_step) | (c["h"] < min_step))
        h = jnp.where(fresh, jnp.clip(c["h"], min_step, max_step), c["h"])
        too_small = c["retry"] & (h < min_step)
        target = jnp.where(t < t_settle, t_settle, t_end)
        t_new = jnp.minimum(t + h, target)
        h = t_new - t
        h_old = jnp.where(clamped, jnp.nan, c["h_old"])
        err_old = jnp.where(clamped, jnp.nan, c["err_old"])

        res = attempt(c, p, t, y, h, rtol, atol)
        y_new, err = res["y_new"], res["err"]
        converged = res["converged"]
        err_ok = converged & ~(err > 1.0)
        theta = model.step_check(y, y_new, p)
        h_try = h * theta
        check_retry = (
            err_ok & (theta < 1.0) & (min_step <= h_try) & (h_try < h)
            & (c["n_check"] < MAX_CHECK_REJECTIONS)
        )  # fmt: skip
        accept = err_ok & ~check_retry & ~too_small
        error_reject = ~err_ok & ~too_small

        # Accepted step: contact memory and projection, then ẏ and the quantities there.
        y_acc = model.after_step(t_new, y_new, p)
        f_new, peaks, pen, s1, s2 = self._record_points(
            c, p, t, h, t_new, y_acc, res["dense"], t_settle
        )
        finite = _all_finite(y_acc) & _all_finite(f_new)
        n_steps = c["n_steps"] + 1
        done = t_new >= t_end
        status_acc = jnp.where(
            ~finite,
            STATUS_NON_FINITE,
            jnp.where(
                done,
                STATUS_SUCCESS,
                jnp.where(n_steps >= max_steps, STATUS_TOO_MANY_STEPS, STATUS_RUNNING),
            ),
        )
        if self.method == "explicit":
            grow = jnp.where(err > 0.0, 0.9 * jnp.where(err > 0.0, err, 1.0) ** -0.2, 10.0)
            factor_acc = jnp.clip(grow, 0.2, 10.0)
            factor_acc = jnp.where(c["failed"], jnp.minimum(factor_acc, 1.0), factor_acc)
            factor_rej = jnp.clip(grow, 0.2, 10.0)
        else:
            predicted = _predict_factor(h, h_old, err, err_old)
            factor_acc = jnp.minimum(10.0, res["safety"] * predicted)
            factor_acc = jnp.where(c["failed"], jnp.minimum(factor_acc, 1.0), factor_acc)
            factor_rej = jnp.where(converged, jnp.maximum(0.2, res["safety"] * predicted), 0.5)

        def pick(accepted: Any, checked: Any, rejected: Any, stopped: Any) -> Any:
            return jnp.where(
                accept, accepted, jnp.where(check_retry, checked, jnp.where(too_small, stopped, rejected))
            )

        keep = c
        out: Lane = {
            "t": pick(t_new, t, t, t),
            "y": jnp.where(accept, y_acc, y),
            "f": jnp.where(accept, f_new, c["f"]),
            "h": pick(h * factor_acc, h_try, h * factor_rej, h),
            "h_prop": jnp.where(accept, h * factor_acc, keep["h_prop"]),
            "retry": pick(False, True, True, True),
            "failed": pick(False, keep["failed"], True, keep["failed"]),
            "n_check": pick(0, keep["n_check"] + 1, keep["n_check"], keep["n_check"]),
            "status": pick(status_acc, STATUS_RUNNING, STATUS_RUNNING, STATUS_STEP_TOO_SMALL),
            "n_steps": jnp.where(accept, n_steps, keep["n_steps"]),
            "n_rejected": keep["n_rejected"] + jnp.where(check_retry | error_reject, 1, 0),
            "n_rhs": keep["n_rhs"] + res["n_rhs"] + jnp.where(accept, 1, 0),
            "peaks": jnp.where(accept, peaks, keep["peaks"]),
            "pen": jnp.where(accept, pen, keep["pen"]),
            "s1": jnp.where(accept, s1, keep["s1"]),
            "s2": jnp.where(accept, s2, keep["s2"]),
            # Radau's predictive controller: the proposal this step started from and its
            # error (NaN for this step only when its first attempt was clamped).
            "h_old": jnp.where(accept, c["h_prop"], h_old),
            "err_old": jnp.where(accept, err, err_old),
        }
        for key in ("status", "n_check", "n_steps", "n_rejected", "n_rhs"):
            out[key] = out[key].astype(jnp.int64)
        out["retry"] = out["retry"].astype(bool)
        out["failed"] = out["failed"].astype(bool)
        return out

    # ---- Dormand–Prince 5(4) --------------------------------------------------------------
    def _dopri_attempt(self, c: Lane, p: Any, t: Any, y: Any, h: Any, rtol: Any, atol: Any) -> dict[str, Any]:
        rhs = self.model.rhs
        a = jnp.asarray(_DP_MATRIX)
        cs = jnp.asarray(DP_C)

        def stage(i: Any, k: Any) -> Any:
            return k.at[i].set(rhs(t + cs[i] * h, y + h * (a[i] @ k), p))

        k = jnp.zeros((7, self.S), dtype=y.dtype).at[0].set(c["f"])
        k = lax.fori_loop(1, 7, stage, k)
        y_new = y + h * (a[6] @ k)  # the 7th stage's state (DP_A[6] are the weights b_i)
        k7 = k[6]  # f(t + h, y_new): the FSAL stage
        err_vec = h * (jnp.asarray(DP_E) @ k)
        m = 2 * self.n
        scale = atol[:m] + rtol * jnp.maximum(jnp.abs(y[:m]), jnp.abs(y_new[:m]))
        err = _rms(err_vec[:m], scale)
        r1 = y
        r2 = y_new - y
        r3 = h * k[0] - r2
        r4 = r2 - h * k7 - r3
        r5 = h * (jnp.asarray(DP_D) @ k)

        def dense(theta: Any) -> Any:
            s = 1.0 - theta
            return r1 + theta * (r2 + s * (r3 + theta * (r4 + s * r5)))

        return {"y_new": y_new, "err": err, "converged": jnp.array(True), "dense": dense, "n_rhs": 6}

    # ---- Radau IIA 5 ------------------------------------------------------------------------
    def _radau_attempt(self, c: Lane, p: Any, t: Any, y: Any, h: Any, rtol: Any, atol: Any) -> dict[str, Any]:
        rhs = self.model.rhs
        S = self.S
        m = 2 * self.n
        f = c["f"]
        jac = jax.jacfwd(lambda yy: rhs(t, yy, p))(y)
        eye = jnp.eye(S, dtype=y.dtype)
        lu_real = jsl.lu_factor(MU_REAL / h * eye - jac)
        lu_complex = jsl.lu_factor(MU_COMPLEX / h * eye - jac.astype(jnp.complex128))
        newton_scale = atol + jnp.abs(y) * rtol
        newton_tol = jnp.maximum(10.0 * EPS / rtol, jnp.minimum(0.03, rtol**0.5))
        ch = h * RADAU_C
        ti_real = jnp.asarray(RADAU_TI_REAL)
        ti_complex = jnp.asarray(RADAU_TI_COMPLEX)
        tmat = jnp.asarray(RADAU_T)

        def newton_body(s: dict[str, Any]) -> dict[str, Any]:
            z = s["z"]
            w = s["w"]
            stages = jax.vmap(rhs, in_axes=(0, 0, None))(t + ch, y + z, p)  # (3, S)
            finite = _all_finite(stages)
            f_real = stages.T @ ti_real - MU_REAL / h * w[0]
            f_complex = stages.T @ ti_complex - MU_COMPLEX / h * (w[1] + 1j * w[2])
            dw_real = jsl.lu_solve(lu_real, f_real)
            dw_complex = jsl.lu_solve(lu_complex, f_complex)
            dw = jnp.stack([dw_real, dw_complex.real, dw_complex.imag])
            dw_norm = _rms(dw.reshape(-1), jnp.tile(newton_scale, 3))
            has_old = ~jnp.isnan(s["dw_norm_old"])
            rate = jnp.where(has_old, dw_norm / jnp.where(has_old, s["dw_norm_old"], 1.0), s["rate"])
            k = s["k"]
            safe_rate = jnp.where(rate < 1.0, rate, 0.5)
            diverging = has_old & (
                (rate >= 1.0)
                | (safe_rate ** (NEWTON_MAXITER - k) / (1.0 - safe_rate) * dw_norm > newton_tol)
            )
            stop_bad = ~finite | diverging
            w_new = w + dw
            z_new = tmat @ w_new
            converged = ~stop_bad & (
                (dw_norm == 0.0) | (has_old & (safe_rate / (1.0 - safe_rate) * dw_norm < newton_tol))
            )
            return {
                "k": k + 1,
                "w": jnp.where(stop_bad, w, w_new),
                "z": jnp.where(stop_bad, z, z_new),
                "dw_norm_old": dw_norm,
                "rate": rate,
                "converged": converged,
                "stopped": stop_bad | converged,
            }

        start = {
            "k": jnp.array(0, dtype=jnp.int64),
            "w": jnp.zeros((3, S), dtype=y.dtype),
            "z": jnp.zeros((3, S), dtype=y.dtype),
            "dw_norm_old": jnp.full_like(h, jnp.nan),
            "rate": jnp.full_like(h, jnp.nan),
            "converged": jnp.array(False),
            "stopped": jnp.array(False),
        }
        s = lax.while_loop(lambda s: ~s["stopped"] & (s["k"] < NEWTON_MAXITER), newton_body, start)
        z = s["z"]
        n_iter = s["k"]
        y_new = y + z[2]
        ze = z.T @ jnp.asarray(RADAU_E) / h
        error = jsl.lu_solve(lu_real, f + ze)
        scale = atol[:m] + rtol * jnp.maximum(jnp.abs(y[:m]), jnp.abs(y_new[:m]))
        err = _rms(error[:m], scale)
        # After a rejection, SciPy re-estimates a large error with one more evaluation.
        again = c["retry"] & (err > 1.0)
        f_err = rhs(t, y + error, p)
        error2 = jsl.lu_solve(lu_real, f_err + ze)
        err = jnp.where(again, _rms(error2[:m], scale), err)
        safety = 0.9 * (2 * NEWTON_MAXITER + 1) / (2 * NEWTON_MAXITER + n_iter)
        q = z.T @ jnp.asarray(RADAU_P)  # (S, 3) collocation polynomial

        def dense(theta: Any) -> Any:
            return y + q @ jnp.stack([theta, theta**2, theta**3])

        return {
            "y_new": y_new,
            "err": err,
            "converged": s["converged"],
            "dense": dense,
            "n_rhs": 3 * n_iter + 1,
            "safety": safety,
        }


def _predict_factor(h: Any, h_old: Any, err: Any, err_old: Any) -> Any:
    """The predictive (Gustafsson) step factor ([HW96] §IV.8, (8.25); common.predict_factor)."""
    plain = jnp.isnan(err_old) | jnp.isnan(h_old) | (err == 0.0)
    safe_err = jnp.where(err == 0.0, 1.0, err)
    multiplier = jnp.where(
        plain, 1.0, h / jnp.where(plain, 1.0, h_old) * (jnp.where(plain, 1.0, err_old) / safe_err) ** 0.25
    )
    return jnp.where(err == 0.0, jnp.inf, jnp.minimum(1.0, multiplier) * safe_err**-0.25)


def lane_runner(model: JaxModel, method: str) -> Callable[..., dict[str, Any]]:
    """The function integrating one lane with ``method`` ("explicit" or "implicit")."""
    if method not in ("explicit", "implicit"):
        raise ValueError(f"method must be 'explicit' or 'implicit', got {method!r}")
    return _LaneIntegrator(model, method)
