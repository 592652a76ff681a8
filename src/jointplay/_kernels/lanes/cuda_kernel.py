"""The lane source compiled by numba-cuda: one GPU thread per lane (imported by
:mod:`jointplay._kernels.lanes.cuda` only, once it has checked that numba-cuda and a GPU, or
the simulator, are there).

Each thread runs the lanes' loop (:func:`jointplay._kernels.lanes.source.lane`) with the
explicit or the implicit method's steps for its lane, with
every work array in its own local memory (``cuda.local.array``, sizes fixed at compile time:
``MAX_*`` of :mod:`jointplay._kernels.lanes.limits`), and writes its peaks, statistics, status,
time reached and counters into the output arrays' rows; nothing is shared between threads.
One kernel is written (:func:`lane_kernel`); each method's (:data:`KERNELS`) is a copy of it
bound to the method's lane and to the work its integrator's record declares (the shapes of
its arrays at the limits, their dtypes, the function that makes its ``ws`` of them), so a
new integrator brings its GPU kernel with its lane source module. The kernels are cached on
disk by numba-cuda (``cache=True``, beside this file's ``__pycache__``).

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

from jointplay._kernels.lanes.build import LANES, build, lane_for, rebound, source_function
from jointplay._kernels.lanes.limits import (
    MAX_CLEAR,
    MAX_COORDS,
    MAX_Q,
    MAX_ROWS,
    MAX_STATE,
    MAX_WORK_ARRAYS,
    simulated,
)


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
_RECORD = 7 * MAX_CLEAR
_SAMPLES = 9
#: The loop's vectors (``source.lane``: three states, two f, the refinement's and the window
#: opening's state and f).
_VECTORS = 9
#: What an unused slot allocates (nothing reads it: the compiler drops it).
_UNUSED = ((1,), "float64")
# The globals that each method's copy of :func:`lane_kernel` binds (:func:`_kernel`): its lane,
# the function that makes its ``ws``, the number of its arrays and the slots' shapes and
# dtypes. Placeholders here: ``lane_kernel`` itself is never compiled.
METHOD_LANE: Any = None
METHOD_ARRAYS: Any = None
N_ARRAYS = 0
SHAPE_0 = SHAPE_1 = SHAPE_2 = SHAPE_3 = SHAPE_4 = SHAPE_5 = SHAPE_6 = SHAPE_7 = _UNUSED[0]
DTYPE_0 = DTYPE_1 = DTYPE_2 = DTYPE_3 = DTYPE_4 = DTYPE_5 = DTYPE_6 = DTYPE_7 = np.float64


def lane_kernel(
    ipar, rpar, lay, y0, t_settle, t_end, max_step, rtol, atol, max_steps, interrupt,
    peaks, stats, status, t_reached, counts,
):  # fmt: skip
    """Lane ``cuda.grid(1)`` of a method (arguments and outputs: those of the CPU's drivers,
    :func:`jointplay._kernels.lanes.cpu.explicit_lanes`): the loop's work arrays and the
    method's, each in the thread's local memory, the method's as its record declares them
    (``SHAPE_k``, ``DTYPE_k``: its ``shapes`` at the limits and ``dtypes``, the first
    ``N_ARRAYS`` slots), made its ``ws`` by its ``arrays`` (``METHOD_ARRAYS``), and its lane
    (``METHOD_LANE``): the globals of each method's copy (:func:`_kernel`)."""
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
    arrays = (
        cuda.local.array(SHAPE_0, DTYPE_0), cuda.local.array(SHAPE_1, DTYPE_1),
        cuda.local.array(SHAPE_2, DTYPE_2), cuda.local.array(SHAPE_3, DTYPE_3),
        cuda.local.array(SHAPE_4, DTYPE_4), cuda.local.array(SHAPE_5, DTYPE_5),
        cuda.local.array(SHAPE_6, DTYPE_6), cuda.local.array(SHAPE_7, DTYPE_7),
    )  # fmt: skip
    work = METHOD_ARRAYS(*arrays[:N_ARRAYS])
    code, t = METHOD_LANE(
        ipar, rpar[lane], lay, y0[lane], t_settle[lane], t_end[lane], max_step[lane], rtol,
        atol, max_steps, interrupt, peaks[lane], stats[lane], counts[lane], mask, vec, q,
        samples, pen, records, phi_q, schur, lam, scratch, work,
    )  # fmt: skip
    status[lane] = code
    t_reached[lane] = t


def _kernel(lane: str) -> Any:
    """The kernel of lane ``lane``: a copy of :func:`lane_kernel` named ``<lane>_kernel`` (its
    cache files' name) whose globals are the lane's compiled loop and its record's work."""
    record = LANES[lane]
    if not {"shapes", "arrays", "dtypes"} <= set(record):
        raise ValueError(f"{lane}: its record gives no shapes, arrays and dtypes of its work")
    shapes = source_function(record["shapes"])(MAX_STATE, MAX_COORDS, MAX_COORDS)
    if len(shapes) > MAX_WORK_ARRAYS:
        raise ValueError(
            f"{lane}: {len(shapes)} work arrays, the GPU kernel has {MAX_WORK_ARRAYS} slots"
        )
    slots = [*zip(shapes, record["dtypes"], strict=True)]
    slots += [_UNUSED] * (MAX_WORK_ARRAYS - len(slots))
    method = {"METHOD_LANE": _GPU[lane], "METHOD_ARRAYS": _GPU[record["arrays"]],
              "N_ARRAYS": len(shapes)}  # fmt: skip
    for k, (shape, dtype) in enumerate(slots):
        method[f"SHAPE_{k}"], method[f"DTYPE_{k}"] = tuple(shape), getattr(np, dtype)
    return cuda.jit(cache=True)(rebound(lane_kernel, {**globals(), **method}, f"{lane}_kernel"))


#: The kernel of each batch method on the GPU, by method: the lane of the integrator that the
#: cuda backend's lanes have for it (its record's engines: ``"lanes-explicit"``,
#: ``"lanes-implicit"``).
KERNELS = {method: _kernel(lane_for(f"lanes-{method}")) for method in ("explicit", "implicit")}
