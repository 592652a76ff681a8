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
  and ``t_end``; ``min_step = 10·spacing(t)``; ``max_steps`` accepted steps without reaching
  ``t_end`` stop the lane with ``STATUS_TOO_MANY_STEPS``, a non-finite state or ẏ after a step
  with ``STATUS_NON_FINITE``.
- Error norm: RMS over the first 2·n_coordinates components of err_i / (atol_i +
  rtol·max(|y_i|, |y_new,i|)) (the work integrals and the impact memory v0 excluded).
- Explicit: DOPRI5 of Hairer, Nørsett & Wanner (*Solving ODEs I*, §II.5, Table 5.2), FSAL,
  exactly as :func:`jointplay._kernels.lanes.source.explicit_lane`: a step attempt below
  ``min_step`` stops the lane (``STATUS_STEP_TOO_SMALL``); a rejected step is retried with
  ``h·max(0.2, 0.9·err^(−1/5))``; an accepted one proposes ``h·clamp(0.9·err^(−1/5), 0.2,
  10)`` (10 when err = 0), at most h when the step had an error rejection.
- Implicit: Radau IIA 5 as :mod:`jointplay._kernels.lanes.source_radau` (SciPy's algorithm: a fresh step is
  clamped to [min_step, max_step] and a retried one below min_step stops the lane; simplified
  Newton on the eigen-transformed real and complex systems, at most 6 iterations, the step
  halved when it fails; the embedded error estimate, re-estimated after a rejection; the
  predictive controller with safety 0.9·13/(12 + iterations), growth at most 10, none after
  a failure (RADAU5's ``hold_after_failure``)). Unlike the Numba kernel, the Jacobian is
  ``jax.jacfwd`` of the right-hand side (all S columns), recomputed and factorised at every
  attempt (one real and one complex S×S LU per lane), and Newton starts from zero rather than
  from the last step's collocation polynomial.
- Contact onset: on a step that passed the error test, θ = ``step_check``; θ < 1 with
  min_step ≤ θh < h retries the step with θh (a rejection that does not limit growth), at
  most 64 times per step (then the step is accepted). After an accepted step, ``after_step``
  (v0, projection), then ẏ at the resulting state (the next step's first stage).

**Peaks and statistics over [t_settle, t_end]**: the PEAK RULE of
:mod:`jointplay._kernels.batch` (its constants ``REFINE_MARGIN``, ``REFINE_POINTS`` and, for
the explicit method, the dense output ``DENSE`` are imported from the backends' shared
:mod:`jointplay._kernels.lanes.contract`, so both backends apply one rule). The window opens at t_settle (a step lands there; at t = 0 when t_settle is
0) with the quantities there; each later accepted step adds its end point (state after
``after_step``) to the running peaks, the trapezoidal sums of ω and ω² and the largest
penetrations, and, when a triggering quantity's end values come within ``REFINE_MARGIN`` of
its running peak, evaluates every quantity at ``REFINE_POINTS`` of the step on the method's
dense output (explicit: SciPy's DOPRI5 interpolant; implicit: the collocation polynomial)
and raises each peak to the clipped parabolic vertex through its largest sample. A lane that
does not succeed returns NaN peaks and statistics.

Counters: ``n_rhs`` counts the integrator's evaluations of ẏ (1 at t = 0, 6 per explicit
attempt, 1 after an accepted step whose state ``after_step`` changed; for Radau, 3 per Newton
iteration, 1 per error estimate after a rejection and 1 per accepted step, the Jacobian's
forward passes not counted); the evaluations of the peak rule are not counted.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import jax
import jax.numpy as jnp
import jax.scipy.linalg as jsl
import numpy as np
from jax import lax

from jointplay._kernels.ids import (
    EPS,
    STATUS_NON_FINITE,
    STATUS_RUNNING,
    STATUS_STEP_TOO_SMALL,
    STATUS_SUCCESS,
    STATUS_TOO_MANY_STEPS,
)
from jointplay._kernels.jax.eom import PRISMATIC, JaxModel
from jointplay._kernels.lanes.contract import DENSE, REFINE_MARGIN, REFINE_POINTS

#: Consecutive contact-onset retries of one step after which it is accepted (radau's).
MAX_CHECK_REJECTIONS = 64

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
#: DP_A as a 7 × 7 table (row i: the coefficients of stage i, zero-padded).
DP_TABLE = np.array([[*row, *([0.0] * (7 - len(row)))] for row in DP_A])
#: Error coefficients e_i = b_i − b̂_i (k2 has none).
DP_E = (71 / 57600, 0.0, -71 / 16695, 71 / 1920, -17253 / 339200, 22 / 525, -1 / 40)

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

Lane = dict[str, Any]


def _combination(coefficients: Any, vectors: Any) -> Any:
    """Σ coefficients[j] · vectors[j], left to right, terms with a zero coefficient left out."""
    terms = [float(a) * v for a, v in zip(coefficients, vectors, strict=False) if a != 0.0]
    return sum(terms[1:], terms[0])


def _rms(x: Any, scale: Any) -> Any:
    v = x / scale
    return jnp.sqrt(jnp.sum(v * v)) / jnp.sqrt(float(x.shape[-1]))


def _all_finite(x: Any) -> Any:
    return jnp.all(jnp.isfinite(x))


def _triggers(model: JaxModel) -> np.ndarray:
    """Which quantities may trigger a refinement (PEAK RULE; batch._triggers): all but ω and α
    of the driven body and of bodies held to the ground by an ideal prismatic joint."""
    layout = model.layout
    nb = layout.nb
    mask = np.ones(layout.n_peaks, dtype=bool)
    for b in range(nb):
        held = any(
            layout.active[j] and kind == PRISMATIC and a < 0 and bb == b
            for j, (kind, a, bb) in enumerate(layout.joints)
        )
        if b == layout.crank or held:
            mask[b] = mask[nb + b] = False
    return mask


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
        self.P = layout.n_peaks
        self.triggers = _triggers(model)

    # ---- peaks and statistics ------------------------------------------------------------
    def _window(
        self, c: Lane, t: Any, h: Any, t_new: Any, q_b: Any, pen_b: Any, t_settle: Any
    ) -> dict[str, Any]:
        """The running peaks, sums and penetrations after an accepted step whose end has the
        quantities ``q_b`` and penetrations ``pen_b`` (``c["q"]``: those at its start), and
        whether the step is to be refined (PEAK RULE; :meth:`refine` does it)."""
        q_a = c["q"]
        inside = t >= t_settle  # the window was open at the step's start
        opening = ~inside & (t_new >= t_settle)  # the step lands on t_settle
        w_a, w_b = q_a[: self.nb], q_b[: self.nb]
        s1 = c["s1"] + 0.5 * h * (w_a + w_b)
        s2 = c["s2"] + 0.5 * h * (w_a * w_a + w_b * w_b)
        pen = jnp.maximum(c["pen"], pen_b)
        peaks = jnp.maximum(c["peaks"], jnp.abs(q_b))
        high = jnp.maximum(jnp.abs(q_a), jnp.abs(q_b))
        wants = jnp.any(self.triggers & (peaks > 0.0) & (high >= (1.0 - REFINE_MARGIN) * peaks))
        zeros = jnp.zeros_like(c["s1"])
        return {
            "peaks": jnp.where(inside, peaks, jnp.where(opening, jnp.abs(q_b), c["peaks"])),
            "pen": jnp.where(inside, pen, jnp.where(opening, pen_b, c["pen"])),
            "s1": jnp.where(inside, s1, zeros),
            "s2": jnp.where(inside, s2, zeros),
            "wants": inside & wants,
        }

    def dense(self, data: dict[str, Any], theta: Any) -> Any:
        """The state at θ of the step described by ``data`` (the method's dense output)."""
        y, h = data["y"], data["h"]
        if self.method == "explicit":  # SciPy's RK45 interpolant (batch.DENSE)
            t2 = theta * theta
            powers = (theta, t2, t2 * theta, t2 * theta * theta)
            weights = [
                DENSE[j, 0] * powers[0] + DENSE[j, 1] * powers[1] + DENSE[j, 2] * powers[2]
                + DENSE[j, 3] * powers[3]
                for j in range(7)
            ]  # fmt: skip
            k = data["k"]
            return y + h * sum((k[j] * weights[j] for j in range(1, 7)), k[0] * weights[0])
        return y + data["poly"] @ jnp.stack([theta, theta**2, theta**3])  # collocation

    def refine(self, data: dict[str, Any], p: Any, peaks: Any) -> Any:
        """``peaks`` raised by the refinement of one accepted step (PEAK RULE): every quantity
        at ``REFINE_POINTS`` of the dense output, and per quantity the clipped parabolic vertex
        through the largest of the samples |Q| at θ = 0, REFINE_POINTS, 1 and its neighbours
        (:func:`jointplay._kernels.batch._refine_peaks`)."""
        thetas = jnp.asarray(REFINE_POINTS)
        states = jax.vmap(lambda theta: self.dense(data, theta))(thetas)
        times = data["t"] + thetas * data["h"]
        _, q_mid, _ = jax.vmap(self.model.outputs, in_axes=(0, 0, None))(times, states, p)
        samples = jnp.abs(jnp.concatenate([data["q_a"][None], q_mid, data["q_b"][None]]))
        last = samples.shape[0] - 1
        m = jnp.argmax(samples, axis=0)  # the first largest, as the Numba loop
        best = jnp.take_along_axis(samples, m[None], axis=0)[0]
        low = jnp.take_along_axis(samples, jnp.clip(m - 1, 0, last)[None], axis=0)[0]
        up = jnp.take_along_axis(samples, jnp.clip(m + 1, 0, last)[None], axis=0)[0]
        curvature = low - 2.0 * best + up
        vertex = (m > 0) & (m < last) & (curvature < 0.0)
        offset = jnp.clip(0.5 * (low - up) / jnp.where(vertex, curvature, -1.0), -0.5, 0.5)
        best = jnp.where(vertex, best - 0.25 * (low - up) * offset, best)
        return jnp.maximum(peaks, best)

    # ---- one lane ---------------------------------------------------------------------------
    def init(self, p: Any, y0: Any, t_end: Any, max_step: Any) -> Lane:
        """The loop carry of one lane at t = 0 (the window opens there when t_settle is 0)."""
        zero = jnp.zeros_like(t_end)
        f0, q0, pen0 = self.model.outputs(zero, y0, p)
        finite = _all_finite(y0) & _all_finite(f0)
        carry: Lane = {
            "t": zero,
            "y": y0,
            "f": f0,
            "q": q0,
            "h": max_step / 10.0,
            "h_prop": max_step / 10.0,
            "retry": jnp.array(False),
            "failed": jnp.array(False),
            "n_check": jnp.array(0, dtype=jnp.int64),
            "status": jnp.where(finite, STATUS_RUNNING, STATUS_NON_FINITE).astype(jnp.int64),
            "n_steps": jnp.array(0, dtype=jnp.int64),
            "n_rejected": jnp.array(0, dtype=jnp.int64),
            "n_rhs": jnp.array(1, dtype=jnp.int64),
            "peaks": jnp.abs(q0),
            "pen": pen0,
            "s1": jnp.zeros(self.nb, dtype=y0.dtype),
            "s2": jnp.zeros(self.nb, dtype=y0.dtype),
            "h_old": jnp.full_like(t_end, jnp.nan),
            "err_old": jnp.full_like(t_end, jnp.nan),
        }
        if self.method == "implicit":  # the last step's collocation polynomial
            carry["poly"] = jnp.zeros((self.S, 3), dtype=y0.dtype)
            carry["y_prev"] = y0
            carry["t_prev"] = zero
            carry["has_poly"] = jnp.array(False)
        return carry

    def finish(self, c: Lane, t_settle: Any, t_end: Any) -> dict[str, Any]:
        """One lane's results from its final carry (NaN peaks and statistics on failure)."""
        span = t_end - t_settle
        mean = c["s1"] / span
        rms = jnp.sqrt(jnp.maximum(c["s2"] / span, 0.0))
        ok = c["status"] == STATUS_SUCCESS
        return {
            "peaks": jnp.where(ok, c["peaks"], jnp.nan),
            "stats": jnp.where(ok, jnp.concatenate([mean, rms, c["pen"]]), jnp.nan),
            "status": c["status"],
            "t_reached": c["t"],
            "n_steps": c["n_steps"],
            "n_rejected": c["n_rejected"],
            "n_rhs": c["n_rhs"],
        }

    def step(
        self, c: Lane, p: Any, t_settle: Any, t_end: Any, max_step: Any, rtol: Any, atol: Any,
        max_steps: Any,
    ) -> tuple[Lane, dict[str, Any]]:  # fmt: skip
        """One step attempt of one lane with its decision; the new carry, and what
        :meth:`refine` needs (with ``need``: this lane's accepted step is to be refined)."""
        if self.method == "implicit":
            rtol = jnp.maximum(rtol, 100.0 * EPS)
        attempt = self._dopri_attempt if self.method == "explicit" else self._radau_attempt
        return self._step(c, (p, t_settle, t_end, max_step, rtol, atol, max_steps), attempt)

    def _step(
        self, c: Lane, settings: tuple[Any, ...], attempt: Callable[..., Any]
    ) -> tuple[Lane, dict[str, Any]]:
        """One step attempt with its decision (accept, reject, retry shorter, stop)."""
        p, t_settle, t_end, max_step, rtol, atol, max_steps = settings
        model = self.model
        t, y = c["t"], c["y"]
        min_step = 10.0 * (jnp.nextafter(t, jnp.inf) - t)
        fresh = ~c["retry"]
        if self.method == "explicit":  # the Numba batch kernel's rule
            h = jnp.where(fresh, jnp.minimum(c["h"], max_step), c["h"])
            too_small = h < min_step
            clamped = jnp.array(False)
        else:  # the Radau kernel's rule
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
        y_acc = model.after_step(t_new, y_new, p, y)
        changed = jnp.any(y_acc != y_new)
        f_new, q_b, pen_b = model.outputs(t_new, y_acc, p)
        finite = _all_finite(y_acc) & _all_finite(f_new)
        window = self._window(c, t, h, t_new, q_b, pen_b, t_settle)
        n_steps = c["n_steps"] + 1
        status_acc = jnp.where(
            ~finite,
            STATUS_NON_FINITE,
            jnp.where(
                t_new >= t_end,
                STATUS_SUCCESS,
                jnp.where(n_steps >= max_steps, STATUS_TOO_MANY_STEPS, STATUS_RUNNING),
            ),
        )
        if self.method == "explicit":
            grow = 0.9 * jnp.where(err > 0.0, err, 1.0) ** -0.2
            factor_acc = jnp.where(err > 0.0, jnp.clip(grow, 0.2, 10.0), 10.0)
            factor_acc = jnp.where(c["failed"], jnp.minimum(factor_acc, 1.0), factor_acc)
            factor_rej = jnp.maximum(0.2, grow)
            rhs_after: Any = jnp.where(changed, 1, 0)
        else:
            predicted = _predict_factor(h, h_old, err, err_old)
            factor_acc = jnp.minimum(10.0, res["safety"] * predicted)
            factor_acc = jnp.where(c["failed"], jnp.minimum(factor_acc, 1.0), factor_acc)
            factor_rej = jnp.where(converged, jnp.maximum(0.2, res["safety"] * predicted), 0.5)
            rhs_after = 1

        def pick(accepted: Any, checked: Any, rejected: Any, stopped: Any) -> Any:
            return jnp.where(
                accept,
                accepted,
                jnp.where(check_retry, checked, jnp.where(too_small, stopped, rejected)),
            )

        out: Lane = {
            "t": jnp.where(accept, t_new, t),
            "y": jnp.where(accept, y_acc, y),
            "f": jnp.where(accept, f_new, c["f"]),
            "q": jnp.where(accept, q_b, c["q"]),
            "h": pick(h * factor_acc, h_try, h * factor_rej, h),
            "h_prop": jnp.where(accept, h * factor_acc, c["h_prop"]),
            "retry": pick(False, True, True, True),
            "failed": pick(False, c["failed"], True, c["failed"]),
            "n_check": pick(0, c["n_check"] + 1, c["n_check"], c["n_check"]),
            "status": pick(status_acc, STATUS_RUNNING, STATUS_RUNNING, STATUS_STEP_TOO_SMALL),
            "n_steps": jnp.where(accept, n_steps, c["n_steps"]),
            "n_rejected": c["n_rejected"] + jnp.where(check_retry | error_reject, 1, 0),
            "n_rhs": c["n_rhs"]
            + jnp.where(too_small, 0, res["n_rhs"])
            + jnp.where(accept, rhs_after, 0),
            # Radau's predictive controller: the proposal this step started from and its
            # error (NaN for this step only when its first attempt was clamped).
            "h_old": jnp.where(accept, c["h_prop"], h_old),
            "err_old": jnp.where(accept, err, err_old),
        }
        for key in ("peaks", "pen", "s1", "s2"):
            out[key] = jnp.where(accept, window[key], c[key])
        if self.method == "implicit":
            out["poly"] = jnp.where(accept, res["poly"], c["poly"])
            out["y_prev"] = jnp.where(accept, y, c["y_prev"])
            out["t_prev"] = jnp.where(accept, t, c["t_prev"])
            out["has_poly"] = jnp.where(accept, ~changed, c["has_poly"])
        for key in ("status", "n_check", "n_steps", "n_rejected", "n_rhs"):
            out[key] = out[key].astype(jnp.int64)
        out["retry"] = out["retry"].astype(bool)
        out["failed"] = out["failed"].astype(bool)
        request = {
            **res["dense"], "t": t, "h": h, "q_a": c["q"], "q_b": q_b,
            "need": accept & window["wants"],
        }  # fmt: skip
        return out, request

    # ---- Dormand–Prince 5(4) --------------------------------------------------------------
    def _dopri_attempt(
        self, c: Lane, p: Any, t: Any, y: Any, h: Any, rtol: Any, atol: Any
    ) -> dict[str, Any]:
        rhs = self.model.rhs
        # One rhs in a loop over the six stages, not six inlined copies: the program, and so
        # its tracing and XLA compilation, is about half as large (on one H100, 100 000
        # lanes: compilation 14 s -> 8 s, run 3.8 s -> 4.4 s). Each stage's state sums all
        # seven coefficient × stage products left to right; the zero coefficients (and the
        # stages not computed yet, zero) add exact zeros, so the rounding is the Numba
        # kernel's, which skips them. Stage 6 lands on y_new (FSAL) at the Numba kernel's t + h.
        table = jnp.asarray(DP_TABLE)
        times = jnp.asarray(DP_C)

        def stage(i: Any, k: Any) -> Any:
            row = table[i]
            total = row[0] * k[0]
            for j in range(1, 7):
                total = total + row[j] * k[j]
            return k.at[i].set(rhs(t + times[i] * h, y + h * total, p))

        k = jnp.zeros((7, y.shape[-1]), dtype=y.dtype).at[0].set(c["f"])
        k = lax.fori_loop(1, 7, stage, k)
        stages = list(k)
        y_new = y + h * _combination(DP_A[6], stages)  # DP_A[6] are the weights b_i
        err_vec = h * _combination(DP_E, stages)
        m = 2 * self.n
        scale = atol[:m] + rtol * jnp.maximum(jnp.abs(y[:m]), jnp.abs(y_new[:m]))
        err = _rms(err_vec[:m], scale)
        return {
            "y_new": y_new,
            "err": err,
            "converged": jnp.array(True),
            "dense": {"y": y, "k": k},
            "n_rhs": 6,
        }

    # ---- Radau IIA 5 ------------------------------------------------------------------------
    def _radau_attempt(
        self, c: Lane, p: Any, t: Any, y: Any, h: Any, rtol: Any, atol: Any
    ) -> dict[str, Any]:
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
            rate = jnp.where(
                has_old, dw_norm / jnp.where(has_old, s["dw_norm_old"], 1.0), s["rate"]
            )
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
                (dw_norm == 0.0)
                | (has_old & (safe_rate / (1.0 - safe_rate) * dw_norm < newton_tol))
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

        # Newton starts from the last step's collocation polynomial (SciPy; radau._extrapolate)
        # unless after_step changed the state.
        x = (t + ch - c["t_prev"]) / jnp.where(c["has_poly"], t - c["t_prev"], 1.0)
        powers = jnp.stack([x, x * x, x * x * x])  # (3 powers, 3 stages)
        z0 = (c["poly"] @ powers).T + c["y_prev"] - y
        z0 = jnp.where(c["has_poly"], z0, 0.0)
        start = {
            "k": jnp.array(0, dtype=jnp.int64),
            "w": jnp.asarray(RADAU_TI) @ z0,
            "z": z0,
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
        err = err_first = _rms(error[:m], scale)
        # After a rejection, SciPy re-estimates a large error with one more evaluation.
        again = c["failed"] & (err_first > 1.0)
        f_err = rhs(t, y + error, p)
        error2 = jsl.lu_solve(lu_real, f_err + ze)
        err = jnp.where(again, _rms(error2[:m], scale), err)
        safety = 0.9 * (2 * NEWTON_MAXITER + 1) / (2 * NEWTON_MAXITER + n_iter)
        q = z.T @ jnp.asarray(RADAU_P)  # (S, 3) collocation polynomial

        return {
            "y_new": y_new,
            "err": err,
            "converged": s["converged"],
            "dense": {"y": y, "poly": q},
            "n_rhs": 3 * n_iter + jnp.where(c["failed"] & (err_first > 1.0), 1, 0),
            "safety": safety,
            "poly": q,
        }


def _predict_factor(h: Any, h_old: Any, err: Any, err_old: Any) -> Any:
    """The predictive (Gustafsson) step factor ([HW96] §IV.8, (8.25); common.predict_factor)."""
    plain = jnp.isnan(err_old) | jnp.isnan(h_old) | (err == 0.0)
    safe_err = jnp.where(err == 0.0, 1.0, err)
    multiplier = jnp.where(
        plain,
        1.0,
        h / jnp.where(plain, 1.0, h_old) * (jnp.where(plain, 1.0, err_old) / safe_err) ** 0.25,
    )
    return jnp.where(err == 0.0, jnp.inf, jnp.minimum(1.0, multiplier) * safe_err**-0.25)


#: Lanes refined together, as a fraction of the batch: the accepted steps to be refined are
#: gathered, this many at a time, so an iteration where few lanes refine costs little.
REFINE_SHARE = 4


def _refine_some(
    integrator: _LaneIntegrator, need: Any, request: dict[str, Any], rpar: Any, peaks: Any
) -> Any:
    """``peaks`` (lanes, P) after :meth:`_LaneIntegrator.refine` of the lanes in ``need``,
    gathered ``lanes // REFINE_SHARE`` at a time (none: no work)."""
    lanes = need.shape[0]
    size = max(1, -(-lanes // REFINE_SHARE))
    data = {k: v for k, v in request.items() if k != "need"}

    def body(state: tuple[Any, Any]) -> tuple[Any, Any]:
        remaining, peaks = state
        index = jnp.nonzero(remaining, size=size, fill_value=lanes)[0]
        safe = jnp.minimum(index, lanes - 1)
        sub = jax.tree_util.tree_map(lambda x: x[safe], data)
        raised = jax.vmap(integrator.refine)(sub, rpar[safe], peaks[safe])
        peaks = peaks.at[index].set(raised, mode="drop")
        return remaining.at[index].set(False, mode="drop"), peaks

    return lax.while_loop(lambda state: jnp.any(state[0]), body, (need, peaks))[1]


def batch_runner(model: JaxModel, method: str) -> Callable[..., dict[str, Any]]:
    """The function integrating a batch of lanes with ``method`` ("explicit" or "implicit"):
    ``run(rpar (n, R), y0 (n, S), t_settle (n), t_end (n), max_step (n), rtol, atol (S),
    max_steps)`` → per-lane results (peaks, stats, status, t_reached, n_steps, n_rejected,
    n_rhs). One ``lax.while_loop`` runs until every lane has stopped; each iteration is one
    step attempt of every running lane (``jax.vmap`` of :meth:`_LaneIntegrator.step`; a
    stopped lane is frozen), then the refinement of the lanes that need it."""
    if method not in ("explicit", "implicit"):
        raise ValueError(f"method must be 'explicit' or 'implicit', got {method!r}")
    integrator = _LaneIntegrator(model, method)

    def run(
        rpar: Any, y0: Any, t_settle: Any, t_end: Any, max_step: Any, rtol: Any, atol: Any,
        max_steps: Any,
    ) -> dict[str, Any]:  # fmt: skip
        carry = jax.vmap(integrator.init)(rpar, y0, t_end, max_step)
        step = jax.vmap(integrator.step, in_axes=(0, 0, 0, 0, 0, None, None, None))

        def body(c: Lane) -> Lane:
            running = c["status"] == STATUS_RUNNING
            new, request = step(c, rpar, t_settle, t_end, max_step, rtol, atol, max_steps)
            new["peaks"] = _refine_some(
                integrator, request["need"] & running, request, rpar, new["peaks"]
            )

            def freeze(fresh: Any, old: Any) -> Any:
                mask = running.reshape(running.shape + (1,) * (fresh.ndim - 1))
                return jnp.where(mask, fresh, old)

            return jax.tree_util.tree_map(freeze, new, c)

        carry = lax.while_loop(lambda c: jnp.any(c["status"] == STATUS_RUNNING), body, carry)
        return jax.vmap(integrator.finish)(carry, t_settle, t_end)

    return run
