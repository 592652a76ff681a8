"""The lane source compiled by numba-cuda: one GPU thread per lane (imported by
:mod:`jointplay._kernels.lanes.cuda` only, once it has checked that numba-cuda and a GPU, or
the simulator, are there).

Each thread runs :func:`jointplay._kernels.lanes.source.explicit_lane` for its lane with
every work array in its own local memory (``cuda.local.array``, sizes fixed at compile time:
``MAX_*`` of :mod:`jointplay._kernels.lanes.cuda`), and writes its peaks, statistics, status,
time reached and counters into the output arrays' rows; nothing is shared between threads.
The kernel is cached on disk by numba-cuda (``cache=True``, beside this file's
``__pycache__``).
"""

from __future__ import annotations

import numpy as np
from numba import cuda

from jointplay._kernels.lanes.build import build
from jointplay._kernels.lanes.limits import MAX_CLEAR, MAX_Q, MAX_ROWS, MAX_STATE

_GPU = build(cuda.jit(device=True))
_explicit_lane = _GPU["explicit_lane"]
_RECORD = 7 * MAX_CLEAR
_SAMPLES = 9


@cuda.jit(cache=True)
def explicit_kernel(
    ipar, rpar, lay, y0, t_settle, t_end, max_step, rtol, atol, max_steps, interrupt,
    peaks, stats, status, t_reached, counts,
):  # fmt: skip
    """Lane ``cuda.grid(1)`` of the explicit method (arguments and outputs:
    :func:`jointplay._kernels.lanes.cpu.explicit_lanes`)."""
    lane: int = cuda.grid(1)  # type: ignore[call-arg]
    if lane >= y0.shape[0]:
        return
    mask = cuda.local.array(MAX_Q, np.int64)
    k = cuda.local.array((7, MAX_STATE), np.float64)
    y = cuda.local.array(MAX_STATE, np.float64)
    y_new = cuda.local.array(MAX_STATE, np.float64)
    ys = cuda.local.array(MAX_STATE, np.float64)
    y_mid = cuda.local.array(MAX_STATE, np.float64)
    f = cuda.local.array(MAX_STATE, np.float64)
    f_mid = cuda.local.array(MAX_STATE, np.float64)
    qa = cuda.local.array(MAX_Q, np.float64)
    qb = cuda.local.array(MAX_Q, np.float64)
    samples = cuda.local.array((_SAMPLES, MAX_Q), np.float64)
    pen = cuda.local.array(MAX_CLEAR, np.float64)
    record = cuda.local.array(_RECORD, np.float64)
    record_new = cuda.local.array(_RECORD, np.float64)
    record_mid = cuda.local.array(_RECORD, np.float64)
    phi_q = cuda.local.array((MAX_ROWS, MAX_STATE), np.float64)
    schur = cuda.local.array((MAX_ROWS, MAX_ROWS), np.float64)
    lam = cuda.local.array(MAX_ROWS, np.float64)
    scratch = cuda.local.array(3, np.float64)
    code, t = _explicit_lane(
        ipar, rpar[lane], lay, y0[lane], t_settle[lane], t_end[lane], max_step[lane], rtol,
        atol, max_steps, interrupt, peaks[lane], stats[lane], counts[lane], mask, k, y, y_new,
        ys, y_mid, f, f_mid, qa, qb, samples, pen, record, record_new, record_mid, phi_q,
        schur, lam, scratch,
    )  # fmt: skip
    status[lane] = code
    t_reached[lane] = t
