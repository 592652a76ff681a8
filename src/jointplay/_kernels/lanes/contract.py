"""What every batch kernel shares: the result type :class:`BatchKernelOutput` (one row per
lane) and the peak rule's constants.

The contract of ``run_batch`` (arguments, orders and units of the outputs, the peak rule: the
module docstring of :mod:`jointplay._kernels.batch`) is shared by the CPU engine
(:func:`jointplay._kernels.batch.run_batch`), the CUDA lanes
(:func:`jointplay._kernels.lanes.cuda.run_batch`) and the JAX backend
(:func:`jointplay._kernels.jax_batch.run_batch`, :mod:`jointplay._kernels.jax.integrate`);
what they share lives here, below all three, so that none of them imports another for it.
NumPy and the lanes' source (plain Python) only at import: no kernel is compiled.
"""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np
import numpy.typing as npt

from jointplay._kernels.ids import K_REJECTED, K_RHS, K_STEPS, STATUS_RUNNING, STATUS_SUCCESS
from jointplay._kernels.lanes import source

#: The peak rule's margin and the DOPRI5 tableau (Hairer, Nørsett & Wanner, Solving ODEs I,
#: Table II.5.2) with its dense output, as the lanes' source holds them
#: (:mod:`jointplay._kernels.lanes.source`).
REFINE_MARGIN = source.REFINE_MARGIN
#: Interior points of a refined step, as fractions of the step.
REFINE_POINTS = np.arange(1, source.N_REFINE + 1) / 8.0
#: Dense output (SciPy's ``RK45.P``, 7 × 4): y(t + θh) = y + h Σ_j k_j Σ_m P[j, m] θ^(m+1).
DENSE = np.reshape(np.array(source.DENSE), (7, 4))


#: Interrupt flags that never hold a signal: what a loop is given when nothing watches (off
#: the main thread, :func:`jointplay.execution.interrupts.interrupts_watched` yields ``None``).
NO_INTERRUPT = np.zeros(1, dtype=np.uint8)


class BatchKernelOutput(NamedTuple):
    """What a batch kernel's ``run_batch`` returns, per lane (the orders and units: the
    module docstring of :mod:`jointplay._kernels.batch`)."""

    peaks: npt.NDArray[np.float64]
    stats: npt.NDArray[np.float64]
    status: npt.NDArray[np.int64]
    t_reached: npt.NDArray[np.float64]
    n_steps: npt.NDArray[np.int64]
    n_rejected: npt.NDArray[np.int64]
    n_rhs: npt.NDArray[np.int64]


def lane_inputs(
    y0: npt.ArrayLike,
    t_settle: npt.ArrayLike,
    t_end: npt.ArrayLike,
    max_step: npt.ArrayLike,
    atol: npt.ArrayLike,
    rpar: npt.NDArray[np.float64],
    size: int,
    error: type[Exception],
) -> tuple[npt.NDArray[np.float64], ...]:
    """``run_batch``'s per-lane inputs as contiguous float64 arrays: ``(y0 (n, S), t_settle,
    t_end, max_step (n; scalars broadcast, s), atol (S))``.

    Raises:
        error: (the backend's type) a shape does not fit a state of ``size`` or ``rpar``'s
            rows.
    """
    y0_a = np.ascontiguousarray(np.atleast_2d(np.asarray(y0, dtype=np.float64)))
    lanes = y0_a.shape[0]
    settle_a, end_a, step_a = (
        np.ascontiguousarray(np.broadcast_to(np.asarray(v, dtype=np.float64), (lanes,)))
        for v in (t_settle, t_end, max_step)
    )
    atol_a = np.ascontiguousarray(np.asarray(atol, dtype=np.float64))
    if y0_a.shape[1] != size or atol_a.shape != (size,) or rpar.shape[0] != lanes:
        raise error(
            f"run_batch: y0 must be (n, {size}) and atol ({size},), rpar (n, R); got y0 "
            f"{y0_a.shape}, atol {atol_a.shape}, rpar {rpar.shape}"
        )
    return y0_a, settle_a, end_a, step_a, atol_a


def lane_outputs(lanes: int, n_peaks: int, n_stats: int) -> tuple[npt.NDArray[Any], ...]:
    """The outputs the lanes fill in place: ``(peaks (n, P), stats (n, M))`` NaN, ``status``
    ``STATUS_RUNNING``, ``t_reached`` 0 (s) and ``counts`` (n, 3: steps, rejections, rhs) 0."""
    return (
        np.full((lanes, n_peaks), np.nan),
        np.full((lanes, n_stats), np.nan),
        np.full(lanes, STATUS_RUNNING, dtype=np.int64),
        np.zeros(lanes),
        np.zeros((lanes, 3), dtype=np.int64),
    )


def finished(
    peaks: npt.NDArray[np.float64],
    stats: npt.NDArray[np.float64],
    status: npt.NDArray[np.int64],
    t_reached: npt.NDArray[np.float64],
    counts: npt.NDArray[np.int64],
) -> BatchKernelOutput:
    """The filled outputs of :func:`lane_outputs` as :class:`BatchKernelOutput`, a lane that
    did not succeed with NaN peaks and statistics."""
    failed = status != STATUS_SUCCESS
    peaks[failed] = np.nan
    stats[failed] = np.nan
    return BatchKernelOutput(
        peaks=peaks,
        stats=stats,
        status=status,
        t_reached=t_reached,
        n_steps=counts[:, K_STEPS].copy(),
        n_rejected=counts[:, K_REJECTED].copy(),
        n_rhs=counts[:, K_RHS].copy(),
    )
