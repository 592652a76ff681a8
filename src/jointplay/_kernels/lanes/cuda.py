"""The batch engine on NVIDIA GPUs through numba-cuda: one thread per lane (experimental).

:func:`run_batch` has the batch-kernel contract of :func:`jointplay._kernels.batch.run_batch`
(arguments, :class:`~jointplay._kernels.batch.BatchKernelOutput`, a failed lane's NaN peaks
and statistics): each GPU thread runs one lane of the explicit method, compiled from the same
source as the CPU lanes (:mod:`jointplay._kernels.lanes.source`), in float64. Built and
tested on numba-cuda's CUDA simulator (``NUMBA_ENABLE_CUDASIM=1``, set before numba is
imported), where it gives the CPU lanes' results; not yet measured on a GPU.

Mechanisms with ideal joints run too; their projection onto the ideal constraints is the
GPU's own (Cholesky, :func:`~jointplay._kernels.lanes.source.project_constraints`) where the
CPU's calls LAPACK, so those lanes agree with the CPU's to round-off, not bit for bit.

What it does not do yet: the implicit method (Radau IIA with a per-thread LU), mechanisms
larger than the per-thread arrays (:mod:`.limits`), and an interrupt inside a launch (the
caller's chunks bound how much one interrupt loses).

numba-cuda is imported by this module only, when a batch is run; without it, or without a
GPU, :func:`run_batch` raises :class:`~jointplay.errors.ConfigError` saying what to install.
"""

from __future__ import annotations

import os
import time
from typing import Any

import numpy as np
import numpy.typing as npt

from jointplay._kernels.batch import BatchKernelOutput
from jointplay._kernels.common import STATUS_RUNNING, STATUS_SUCCESS
from jointplay._kernels.lanes import source
from jointplay._kernels.lanes.build import lane_layout
from jointplay._kernels.lanes.limits import MAX_CLEAR, MAX_Q, MAX_ROWS, MAX_STATE
from jointplay.errors import ConfigError

__all__ = ["THREADS_PER_BLOCK", "available", "raise_unless_available", "run_batch", "simulated"]

#: Threads per block of a launch.
THREADS_PER_BLOCK = 128
METHODS = ("explicit",)


def _cuda() -> Any:
    """numba-cuda's ``cuda`` module, with a GPU (or the simulator) behind it."""
    try:
        from numba import cuda
    except ImportError as exc:  # the optional extra is not installed
        raise ConfigError(
            "the cuda batch backend needs numba-cuda: pip install 'jointplay[gpu]' "
            "(numba-cuda[cu12] or [cu13] for the CUDA libraries)"
        ) from exc
    if not cuda.is_available():
        raise ConfigError(
            "the cuda batch backend found no usable NVIDIA GPU (numba.cuda.is_available() is "
            "False: no GPU, no driver or no CUDA libraries; pip install 'numba-cuda[cu12]'); "
            "NUMBA_ENABLE_CUDASIM=1 runs numba-cuda's simulator instead (slow: tests only)"
        )
    return cuda


def raise_unless_available() -> None:
    """Raise :class:`~jointplay.errors.ConfigError`, saying what is missing, unless
    numba-cuda and a GPU (or the simulator) are there."""
    _cuda()


def available() -> bool:
    """Whether :func:`run_batch` can run here (numba-cuda and a GPU or the simulator)."""
    try:
        _cuda()
    except ConfigError:
        return False
    return True


def simulated() -> bool:
    """Whether numba-cuda runs its simulator in this process (``NUMBA_ENABLE_CUDASIM=1``)."""
    return os.environ.get("NUMBA_ENABLE_CUDASIM", "0") not in ("", "0")


def run_batch(
    ipar: npt.ArrayLike,
    rpar: npt.ArrayLike,
    y0: npt.ArrayLike,
    t_settle: npt.ArrayLike,
    t_end: npt.ArrayLike,
    max_step: npt.ArrayLike,
    rtol: float,
    atol: npt.ArrayLike,
    max_steps: int,
    method: str,
    *,
    chunk_size: int | None = None,
    timings: dict[str, float] | None = None,
) -> BatchKernelOutput:
    """Integrate every lane on the GPU, one thread per lane (the batch contract:
    :func:`jointplay._kernels.batch.run_batch`).

    Args:
        ipar, rpar, y0, t_settle, t_end, max_step, rtol, atol, max_steps: as
            :func:`jointplay._kernels.batch.run_batch` (s, SI units).
        method: ``"explicit"`` (Dormand–Prince 5(4)); the implicit method is not built yet.
        chunk_size: unused (one launch runs every lane given); accepted for the executor's
            device interface.
        timings: if given, receives ``compile_s`` (numba-cuda's compilation or cache load,
            0 when this process had it), ``run_s`` (launch, copies included) and ``lanes``.

    Raises:
        ConfigError: numba-cuda or a GPU is missing, the method is one the GPU lanes do not
            cover yet, the mechanism exceeds their arrays, or an input is malformed.
    """
    del chunk_size
    if method not in METHODS:
        raise ConfigError(
            f"the cuda batch backend runs method='explicit' only so far, got {method!r} "
            "(the implicit lanes run on the CPU backends and on --backend gpu)"
        )
    ipar_a = np.ascontiguousarray(np.asarray(ipar, dtype=np.int64))
    lay = lane_layout(ipar_a)
    size, n_q, nc = (int(lay[i]) for i in (source.LY_SIZE, source.LY_NQ, source.LY_NC))
    rows = 2 * int(lay[source.LY_NIDEAL]) + 1
    for name, value, limit in (
        ("state size", size, MAX_STATE), ("quantities", n_q, MAX_Q),
        ("clearance joints", nc, MAX_CLEAR), ("constraint rows", rows, MAX_ROWS),
    ):  # fmt: skip
        if value > limit:
            raise ConfigError(
                f"the cuda batch backend's lanes hold at most {limit} {name}, this mechanism "
                f"has {value} (raise it in jointplay._kernels.lanes.limits)"
            )
    rpar_a = np.ascontiguousarray(np.atleast_2d(np.asarray(rpar, dtype=np.float64)))
    y0_a = np.ascontiguousarray(np.atleast_2d(np.asarray(y0, dtype=np.float64)))
    lanes = y0_a.shape[0]
    settle_a, end_a, step_a = (
        np.ascontiguousarray(np.broadcast_to(np.asarray(v, dtype=np.float64), (lanes,)))
        for v in (t_settle, t_end, max_step)
    )
    atol_a = np.ascontiguousarray(np.asarray(atol, dtype=np.float64))
    if y0_a.shape[1] != size or atol_a.shape != (size,) or rpar_a.shape[0] != lanes:
        raise ConfigError(
            f"run_batch: y0 must be (n, {size}) and atol ({size},), rpar (n, R); got y0 "
            f"{y0_a.shape}, atol {atol_a.shape}, rpar {rpar_a.shape}"
        )
    nb = int(lay[source.LY_N]) // 3
    peaks = np.full((lanes, n_q), np.nan)
    stats = np.full((lanes, 2 * nb + nc), np.nan)
    status = np.full(lanes, STATUS_RUNNING, dtype=np.int64)
    t_reached = np.zeros(lanes)
    counts = np.zeros((lanes, 3), dtype=np.int64)
    compile_s = run_s = 0.0
    if lanes:
        cuda = _cuda()
        clock = time.perf_counter()
        from jointplay._kernels.lanes.cuda_kernel import explicit_kernel

        compile_s = time.perf_counter() - clock
        clock = time.perf_counter()
        inputs = [cuda.to_device(a) for a in (ipar_a, rpar_a, lay, y0_a, settle_a, end_a, step_a)]
        flags = cuda.to_device(np.zeros(1, dtype=np.uint8))
        outputs = [cuda.to_device(a) for a in (peaks, stats, status, t_reached, counts)]
        blocks = (lanes + THREADS_PER_BLOCK - 1) // THREADS_PER_BLOCK
        explicit_kernel[blocks, THREADS_PER_BLOCK](
            *inputs[:7], float(rtol), cuda.to_device(atol_a), int(max_steps), flags, *outputs
        )
        peaks, stats, status, t_reached, counts = (d.copy_to_host() for d in outputs)
        run_s = time.perf_counter() - clock
    if timings is not None:
        timings.update(compile_s=compile_s, run_s=run_s, lanes=float(lanes))
    failed = status != STATUS_SUCCESS
    peaks[failed] = np.nan
    stats[failed] = np.nan
    return BatchKernelOutput(
        peaks=peaks,
        stats=stats,
        status=status,
        t_reached=t_reached,
        n_steps=counts[:, 0].copy(),
        n_rejected=counts[:, 1].copy(),
        n_rhs=counts[:, 2].copy(),
    )
