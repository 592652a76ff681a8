"""The lane source compiled by numba-cuda: one GPU thread per lane (imported by
:mod:`jointplay._kernels.lanes.cuda` only, once it has checked that numba-cuda and a GPU, or
the simulator, are there).

Each thread runs the lanes' loop (:func:`jointplay._kernels.lanes.source.lane`) with the
explicit or the implicit method's steps for its lane, with
every work array in its own local memory (``cuda.local.array``, sizes fixed at compile time:
``MAX_*`` of :mod:`jointplay._kernels.lanes.limits`), and writes its peaks, statistics, status,
time reached and counters into the output arrays' rows; nothing is shared between threads.
The kernel is cached on disk by numba-cuda (``cache=True``, beside this file's
``__pycache__``).

The interrupt flags (:func:`_interrupt_pending`) are host memory that the host writes while
the kernel runs, so every step reads them with ``ld.volatile.global.u8`` (inline PTX marked
as having side effects and clobbering memory): the compiler may neither hoist it out of the
step loop nor reuse an earlier value, and the load is not served from a cache. A plain load
of memory the kernel never writes may be hoisted: in a small loop that only polls, NVVM
moved the plain ``ld.global.u8`` before the loop (``compile_ptx`` for sm_90); in this
kernel's PTX both the plain and the volatile load sit inside the step loop (its one back
edge jumps above the load), but only the volatile one is guaranteed to stay there. On the
simulator the device functions run as Python over NumPy arrays, so a plain read is always
fresh and is used there.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numba import cuda

from jointplay._kernels.lanes.build import build
from jointplay._kernels.lanes.limits import (
    MAX_CLEAR,
    MAX_COORDS,
    MAX_Q,
    MAX_ROWS,
    MAX_STATE,
    simulated,
)
from jointplay._kernels.lanes.source_radau import N_RADAU_SCALARS


def _volatile_byte() -> Any:
    """``read_flag(flags, j)``: ``flags[j]`` (uint8) loaded by ``ld.volatile.global.u8``,
    which the compiler neither hoists out of a loop nor merges with an earlier load."""
    from llvmlite import ir
    from numba import types
    from numba.cuda import cgutils  # type: ignore[attr-defined]
    from numba.cuda.extending import intrinsic

    @intrinsic
    def read_flag(typingctx: Any, flags: Any, index: Any) -> Any:
        def codegen(context: Any, builder: Any, sig: Any, args: Any) -> Any:
            array_type = sig.args[0]
            array = context.make_array(array_type)(context, builder, value=args[0])
            pointer = cgutils.get_item_pointer(
                context, builder, array_type, array, [args[1]], wraparound=False
            )
            load = ir.InlineAsm(
                ir.FunctionType(ir.IntType(16), [pointer.type]),
                "ld.volatile.global.u8 $0, [$1];",
                "=h,l,~{memory}",
                side_effect=True,
            )
            return builder.trunc(builder.call(load, [pointer]), ir.IntType(8))

        return types.uint8(flags, index), codegen

    return read_flag


def _plain_byte(flags, j):
    """``flags[j]``: the simulator's read (Python over the host's NumPy array)."""
    return flags[j]


def _interrupt_pending(flags):
    """The GPU's :func:`jointplay._kernels.lanes.source.interrupt_pending`: the same test,
    every byte read by ``read_flag`` (volatile: the host writes ``flags`` during the launch)."""
    for j in range(flags.shape[0]):
        code = read_flag(flags, j)  # type: ignore[name-defined]  # noqa: F821 (build's namespace)
        if code == 0:
            return False
        if code == SIGINT or code == SIGTERM:  # type: ignore[name-defined]  # noqa: F821, SIM109
            return True
    return False


_GPU = build(
    cuda.jit(device=True),
    hooks={"interrupt_pending": _interrupt_pending},
    extras={
        "read_flag": cuda.jit(device=True)(_plain_byte) if simulated() else _volatile_byte(),
        "RUNNING": True,  # the running reductions when a lane's rpar carries their tail
    },
)
_explicit_lane = _GPU["explicit_lane"]
_implicit_lane = _GPU["implicit_lane"]
_RECORD = 7 * MAX_CLEAR
_SAMPLES = 9
#: The loop's vectors (``source.lane``: three states, two f, the refinement's and the window
#: opening's state and f) and Radau IIA's (``source_radau.radau_start``).
_VECTORS = 9
_RADAU_VECTORS = 8
#: Columns of the Jacobian block the Newton systems read: positions and velocities.
_JAC_COLUMNS = 2 * MAX_COORDS


@cuda.jit(cache=True)
def explicit_kernel(
    ipar, rpar, lay, y0, t_settle, t_end, max_step, rtol, atol, max_steps, interrupt,
    peaks, stats, status, t_reached, counts,
):  # fmt: skip
    """Lane ``cuda.grid(1)`` of the explicit method, DOPRI5 (arguments and outputs:
    :func:`jointplay._kernels.lanes.cpu.explicit_lanes`)."""
    lane: int = cuda.grid(1)  # type: ignore[call-arg]
    if lane >= y0.shape[0]:
        return
    mask = cuda.local.array(MAX_Q, np.int64)
    vec = cuda.local.array((_VECTORS, MAX_STATE), np.float64)
    q = cuda.local.array((2, MAX_Q), np.float64)
    samples = cuda.local.array((_SAMPLES, MAX_Q), np.float64)
    pen = cuda.local.array((2, MAX_CLEAR), np.float64)
    records = cuda.local.array((3, _RECORD), np.float64)
    phi_q = cuda.local.array((MAX_ROWS, MAX_STATE), np.float64)
    schur = cuda.local.array((MAX_ROWS, MAX_ROWS), np.float64)
    lam = cuda.local.array(MAX_ROWS, np.float64)
    scratch = cuda.local.array(3, np.float64)
    work = cuda.local.array((9, MAX_STATE), np.float64)  # source.DOPRI_STATE
    code, t = _explicit_lane(
        ipar, rpar[lane], lay, y0[lane], t_settle[lane], t_end[lane], max_step[lane], rtol,
        atol, max_steps, interrupt, peaks[lane], stats[lane], counts[lane], mask, vec, q,
        samples, pen, records, phi_q, schur, lam, scratch, work,
    )  # fmt: skip
    status[lane] = code
    t_reached[lane] = t


@cuda.jit(cache=True)
def implicit_kernel(
    ipar, rpar, lay, y0, t_settle, t_end, max_step, rtol, atol, max_steps, interrupt,
    peaks, stats, status, t_reached, counts,
):  # fmt: skip
    """Lane ``cuda.grid(1)`` of the implicit method, Radau IIA (arguments and outputs:
    :func:`jointplay._kernels.lanes.cpu.implicit_lanes`): its Newton matrices and their LU
    factors (MAX_COORDS²) in the thread's local memory, like every other work array."""
    lane: int = cuda.grid(1)  # type: ignore[call-arg]
    if lane >= y0.shape[0]:
        return
    mask = cuda.local.array(MAX_Q, np.int64)
    vec = cuda.local.array((_VECTORS, MAX_STATE), np.float64)
    q = cuda.local.array((2, MAX_Q), np.float64)
    samples = cuda.local.array((_SAMPLES, MAX_Q), np.float64)
    pen = cuda.local.array((2, MAX_CLEAR), np.float64)
    records = cuda.local.array((3, _RECORD), np.float64)
    phi_q = cuda.local.array((MAX_ROWS, MAX_STATE), np.float64)
    schur = cuda.local.array((MAX_ROWS, MAX_ROWS), np.float64)
    lam = cuda.local.array(MAX_ROWS, np.float64)
    scratch = cuda.local.array(3, np.float64)
    scalars = cuda.local.array(N_RADAU_SCALARS, np.float64)
    v = cuda.local.array((_RADAU_VECTORS, MAX_STATE), np.float64)
    small = cuda.local.array((3, MAX_COORDS), np.float64)
    stages = cuda.local.array((5, 3, MAX_STATE), np.float64)
    jac = cuda.local.array((MAX_STATE, _JAC_COLUMNS), np.float64)
    mats = cuda.local.array((3, MAX_COORDS, MAX_COORDS), np.float64)
    pivots = cuda.local.array((2, MAX_COORDS), np.int64)
    work = (
        scalars, v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7], small[0], small[1], small[2],
        stages[0], stages[1], stages[2], stages[3], stages[4], jac, mats[0], pivots[0],
        mats[1], mats[2], pivots[1],
    )  # fmt: skip
    code, t = _implicit_lane(
        ipar, rpar[lane], lay, y0[lane], t_settle[lane], t_end[lane], max_step[lane], rtol,
        atol, max_steps, interrupt, peaks[lane], stats[lane], counts[lane], mask, vec, q,
        samples, pen, records, phi_q, schur, lam, scratch, work,
    )  # fmt: skip
    status[lane] = code
    t_reached[lane] = t
