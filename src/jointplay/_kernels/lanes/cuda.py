"""The batch engine on NVIDIA GPUs through numba-cuda: one thread per lane (experimental).

:func:`run_batch` has the batch-kernel contract of :func:`jointplay._kernels.batch.run_batch`
(arguments, :class:`~jointplay._kernels.lanes.contract.BatchKernelOutput`, a failed lane's
NaN peaks and statistics): each GPU thread runs one lane of the explicit method, or of the
implicit one (Radau IIA, :mod:`jointplay._kernels.lanes.source_radau`, its Newton matrices'
LU in the thread's local memory), compiled from the same source as the CPU lanes
(:mod:`jointplay._kernels.lanes.source`), in float64. Built and
tested on numba-cuda's CUDA simulator (``NUMBA_ENABLE_CUDASIM=1``, set before numba is
imported), where it gives the CPU lanes' results; not yet measured on a GPU.

Mechanisms with ideal joints run too; their projection onto the ideal constraints is the
GPU's own (Cholesky, :func:`~jointplay._kernels.lanes.source.project_constraints`) where the
CPU's calls LAPACK, so those lanes agree with the CPU's to round-off, not bit for bit.

An interrupt stops a launch: the ``interrupt`` flags of
:func:`~jointplay.execution.interrupts.interrupts_watched` (host memory that Python's C-level
signal handler writes at once) reach the kernel as a device view of that same memory,
zero-copy (:func:`_device_flags`: the page pinned and mapped into the GPU's address space by
``cuda.mapped``; where the driver refuses to map it, a mapped copy that a host thread
refreshes every :data:`FLAG_COPY_S`). Each thread reads them once per step, volatile
(:mod:`.cuda_kernel`), so every lane still running ends with ``STATUS_INTERRUPTED`` within
one step of the signal and finished lanes keep their results, as on the CPU.

What it does not do yet: the sustained-contact mode (the CPU's implicit lanes only), film
damping on the explicit method (the implicit one runs it;
:func:`~jointplay._kernels.lanes.build.lanes_refusal` for both), and mechanisms larger than
the per-thread arrays (:mod:`.limits`).

numba-cuda is imported by this module only, when a batch is run; without it, or without a
GPU, :func:`run_batch` raises :class:`~jointplay.errors.ConfigError` saying what to install.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Iterator
from contextlib import ExitStack, contextmanager
from typing import Any

import numpy as np
import numpy.typing as npt

from jointplay._kernels.integrators import lane_methods
from jointplay._kernels.lanes import source
from jointplay._kernels.lanes.build import (
    LANES,
    lane_for,
    lanes_refusal,
    output_widths,
    running_layout,
    source_function,
)
from jointplay._kernels.lanes.contract import (
    BatchKernelOutput,
    finished,
    lane_inputs,
    lane_outputs,
)
from jointplay._kernels.lanes.limits import (
    MAX_CLEAR,
    MAX_COORDS,
    MAX_Q,
    MAX_ROWS,
    MAX_STATE,
    simulated,
)
from jointplay.errors import ConfigError

__all__ = ["THREADS_PER_BLOCK", "available", "raise_unless_available", "run_batch", "simulated"]

#: Threads per block of a launch.
THREADS_PER_BLOCK = 128
#: Whether the interrupt flags' own page is mapped into the GPU (``False``: the fallback, a
#: mapped copy refreshed by a host thread; tests switch it to run that path).
MAP_HOST_FLAGS = True
#: How often the fallback's thread copies the flags to the mapped copy, s.
FLAG_COPY_S = 0.01
#: How often the host looks whether a launch has finished, s.
LAUNCH_POLL_S = 0.001
#: The methods of :func:`run_batch` (both outside the sustained-contact mode, the explicit one
#: without film damping: :func:`~jointplay._kernels.lanes.build.lanes_refusal`).
METHODS = lane_methods("lanes-explicit", "lanes-implicit")


def _cuda() -> Any:
    """numba-cuda's ``cuda`` module, with a GPU (or the simulator) behind it."""
    # numba-cuda <= 0.30.4 overloads np.row_stack, an alias of np.vstack that NumPy 2.5
    # removed, when it compiles its first kernel (AttributeError; seen on an H200 machine with
    # NumPy 2.5.2): give it the alias back
    alias = "row_stack"
    if not hasattr(np, alias):
        setattr(np, alias, np.vstack)
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
    interrupt: npt.NDArray[np.uint8] | None = None,
) -> BatchKernelOutput:
    """Integrate every lane on the GPU, one thread per lane (the batch contract:
    :func:`jointplay._kernels.batch.run_batch`).

    Args:
        ipar, rpar, y0, t_settle, t_end, max_step, rtol, atol, max_steps: as
            :func:`jointplay._kernels.batch.run_batch` (s, SI units).
        method: ``"explicit"`` (Dormand–Prince 5(4)) or ``"implicit"`` (Radau IIA,
            :mod:`~jointplay._kernels.lanes.source_radau`: film damping and the Reynolds
            film too; not the sustained-contact mode).
        chunk_size: unused (one launch runs every lane given); accepted for the executor's
            device interface.
        timings: if given, receives ``compile_s`` (numba-cuda's compilation or cache load,
            0 when this process had it), ``run_s`` (launch, copies included) and ``lanes``.
        interrupt: uint8 flags that stop every lane still running with
            ``STATUS_INTERRUPTED`` once they hold SIGINT or SIGTERM, read by the GPU's
            threads during the launch (:func:`_device_flags`); ``None``: not watched.

    Raises:
        ConfigError: numba-cuda or a GPU is missing, the method (or the sustained-contact
            mode, or film damping on the explicit method) is one the GPU lanes do not cover, the mechanism
            exceeds their arrays, or an input is malformed.
    """
    del chunk_size
    if method not in METHODS:
        raise ConfigError(f"the cuda batch backend's methods are {METHODS}, got {method!r}")
    ipar_a = np.ascontiguousarray(np.asarray(ipar, dtype=np.int64))
    rpar_a = np.ascontiguousarray(np.atleast_2d(np.asarray(rpar, dtype=np.float64)))
    lay = running_layout(ipar_a, rpar_a)  # one more quantity with the running responses
    size, n_q, nc = (int(lay[i]) for i in (source.LY_SIZE, source.LY_NQ, source.LY_NC))
    rows = 2 * int(lay[source.LY_NIDEAL]) + 1
    limits = [
        ("state size", size, MAX_STATE), ("quantities", n_q, MAX_Q),
        ("clearance joints", nc, MAX_CLEAR), ("constraint rows", rows, MAX_ROWS),
    ]  # fmt: skip
    for name, value, limit in limits:
        if value > limit:
            raise ConfigError(
                f"the cuda batch backend's lanes hold at most {limit} {name}, this mechanism "
                f"has {value} (raise it in jointplay._kernels.lanes.limits)"
            )
    _check_work(method, size, int(lay[source.LY_N]))
    y0_a, settle_a, end_a, step_a, atol_a = lane_inputs(
        y0, t_settle, t_end, max_step, atol, rpar_a, size, ConfigError
    )
    lanes = y0_a.shape[0]
    refusal = lanes_refusal(ipar_a, rpar_a, method)
    if refusal is not None:
        raise ConfigError(f"the cuda batch backend: {refusal}")
    n_q, n_stats = output_widths(lay, rpar_a)  # + the regimes' 3 nc, + the running slots
    peaks, stats, status, t_reached, counts = lane_outputs(lanes, n_q, n_stats)
    compile_s = run_s = 0.0
    if lanes:
        cuda = _cuda()
        clock = time.perf_counter()
        from jointplay._kernels.lanes.cuda_kernel import KERNELS

        kernel = KERNELS[method]

        compile_s = time.perf_counter() - clock
        clock = time.perf_counter()
        inputs = [cuda.to_device(a) for a in (ipar_a, rpar_a, lay, y0_a, settle_a, end_a, step_a)]
        outputs = [cuda.to_device(a) for a in (peaks, stats, status, t_reached, counts)]
        blocks = (lanes + THREADS_PER_BLOCK - 1) // THREADS_PER_BLOCK
        with _device_flags(cuda, interrupt) as flags:
            kernel[blocks, THREADS_PER_BLOCK](
                *inputs[:7], float(rtol), cuda.to_device(atol_a), int(max_steps), flags, *outputs
            )
            _finish(cuda)
        peaks, stats, status, t_reached, counts = (d.copy_to_host() for d in outputs)
        run_s = time.perf_counter() - clock
    if timings is not None:
        timings.update(compile_s=compile_s, run_s=run_s, lanes=float(lanes))
    return finished(peaks, stats, status, t_reached, counts)


def _check_work(method: str, size: int, n: int) -> None:
    """Raise a :class:`ConfigError` unless the work arrays of ``method``'s integrator for a
    state of ``size`` and ``n`` coordinates fit those its kernel allocates (its record's
    shapes at ``MAX_STATE`` and ``MAX_COORDS``: Radau IIA's Newton matrices are n × n)."""
    record = LANES[lane_for(f"lanes-{method}")]
    shapes = source_function(record["shapes"])
    for need, have in zip(
        shapes(size, n, n), shapes(MAX_STATE, MAX_COORDS, MAX_COORDS), strict=True
    ):
        if any(a > b for a, b in zip(need, have, strict=True)):
            raise ConfigError(
                f"the cuda batch backend's {method} lanes hold at most {MAX_COORDS} coordinates "
                f"and a state of {MAX_STATE} in the work arrays of "
                f"{record['integrator']['title']}, this mechanism has {n} coordinates and a "
                f"state of {size} (raise them in jointplay._kernels.lanes.limits)"
            )


@contextmanager
def _device_flags(cuda: Any, interrupt: npt.NDArray[np.uint8] | None) -> Iterator[Any]:
    """The kernel's view of ``interrupt`` while a launch runs: device memory that is the
    host's flags, so that the host's writes during the launch reach the running threads.

    - ``None``: one zero byte on the device (nothing watched).
    - On a GPU: the flags' own page (the memfd page that the signal handler writes) pinned
      and mapped into the device's address space (``cuda.mapped``: ``cuMemHostRegister``
      with ``DEVICEMAP``), read by the threads over the bus, zero-copy. If the driver refuses
      to register that memory, a mapped pinned copy (``cuda.mapped_array``) that a host
      thread refreshes from the flags every :data:`FLAG_COPY_S` while the launch runs (the
      main thread waits in :func:`_finish`, sleeping, so that thread runs).
    - On the simulator: the host array itself (the simulator's device arrays wrap NumPy
      arrays; ``cuda.to_device`` would copy it).
    """
    if interrupt is None:
        yield cuda.to_device(np.zeros(1, dtype=np.uint8))
        return
    if interrupt.dtype != np.uint8 or interrupt.ndim != 1 or not interrupt.flags.c_contiguous:
        raise ConfigError("run_batch: interrupt must be a contiguous 1-d uint8 array")
    if simulated():
        if MAP_HOST_FLAGS:
            from numba.cuda.simulator.cudadrv.devicearray import FakeCUDAArray

            yield FakeCUDAArray(interrupt)
            return
    elif MAP_HOST_FLAGS:
        from numba.cuda.cudadrv.driver import CudaAPIError

        with ExitStack() as stack:
            try:
                view = stack.enter_context(cuda.mapped(interrupt))
            except CudaAPIError:  # the driver cannot register this memory: the copy below
                view = None
            if view is not None:
                yield view
                return
    mirror = cuda.mapped_array(interrupt.shape, dtype=np.uint8)
    mirror[:] = interrupt
    stop = threading.Event()

    def refresh() -> None:
        while not stop.wait(FLAG_COPY_S):
            mirror[:] = interrupt

    copier = threading.Thread(target=refresh, name="jointplay-cuda-flags", daemon=True)
    copier.start()
    try:
        yield mirror
    finally:
        stop.set()
        copier.join()


def _finish(cuda: Any) -> None:
    """Wait for the launch, sleeping :data:`LAUNCH_POLL_S` between looks (not blocked in the
    driver), so that the fallback's thread and Python's signal handlers run meanwhile. The
    simulator's launches return when done."""
    if simulated():
        return
    done = cuda.event()
    done.record()
    while not done.query():
        time.sleep(LAUNCH_POLL_S)
