"""The lane source compiled for the CPU, and the batch drivers over lanes.

:data:`explicit_lane` and :data:`implicit_lane` are the lanes' one loop
(:func:`jointplay._kernels.lanes.source.lane`) with DOPRI5's and Radau IIA's steps, compiled by
``numba.njit(cache=True, error_model="numpy")`` (so a division by zero gives inf/NaN, as in
the rest of the kernels), the steps inlined into the loop; the drivers allocate each lane's work arrays and run the lanes
serially or on Numba's threads (``prange``). Lanes are independent: a lane's result does not
depend on the other lanes or on the thread that runs it.
"""

from __future__ import annotations

from typing import Any

import numba
import numpy as np
from numba.core import cgutils, types
from numba.extending import intrinsic
from numba.np.arrayobj import make_array, populate_array

from jointplay._kernels import sustained
from jointplay._kernels.ids import N_TRACE_COUNTS
from jointplay._kernels.lanes.build import LANES, build, closed, lane_for, rebound
from jointplay._kernels.lanes.projection import N_WORK, project_lapack
from jointplay._kernels.lanes.source import LY_N, LY_NC, LY_NIDEAL, LY_NQ, LY_SIZE

#: The lanes' steps and the loop's helpers are inlined into the loop (Numba's IR inlining):
#: called as functions, they made an explicit lane 7-14 % dearer (64 conventional lanes).
_INLINE = numba.njit(cache=True, error_model="numpy", inline="always")
_PLAIN = numba.njit(cache=True, error_model="numpy")
#: The single engine's hooks: the projection with LAPACK's solve
#: (:func:`~jointplay._kernels.lanes.projection.project_lapack`) and the sustained-contact
#: mode's (:mod:`jointplay._kernels.sustained`, with its own functions), so that the lanes
#: keep its bits.
_HOOKS = {"project": project_lapack, **sustained.HOOKS}
#: Every function of the source, compiled for the CPU, by name.
compiled = build(_PLAIN, hooks=_HOOKS, extras={"np": np}, own=sustained.OWN, decorate_steps=_INLINE)
#: The explicit lane (the loop with DOPRI5's steps), compiled for the CPU.
explicit_lane = compiled["explicit_lane"]
#: The explicit lane with the running reductions (``source.RUNNING``: a separate compilation,
#: so that :data:`explicit_lane` has none of their code), run when the lanes' ``rpar`` carry
#: the running tail (:func:`jointplay._kernels.lanes.build.running_layout`).
compiled_running = build(
    _PLAIN,
    hooks=_HOOKS,
    extras={"np": np, "RUNNING": True},
    only=closed(("explicit_lane", "implicit_lane"), {**sustained.OWN, **sustained.HOOKS}),
    own=sustained.OWN,
    tag="running",
    decorate_steps=_INLINE,
)
#: The implicit lane (the loop with :mod:`jointplay._kernels.lanes.source_radau`'s steps).
implicit_lane = compiled["implicit_lane"]
#: The lanes that record their trajectory and every counter (``source.RECORD``): the single
#: engine's integrations (:data:`traced`), the batch lanes' loop and steps.
compiled_traced = build(
    _PLAIN,
    hooks=_HOOKS,
    extras={"np": np, "RECORD": True},
    only=closed(tuple(LANES), {**sustained.OWN, **sustained.HOOKS}),
    own=sustained.OWN,
    tag="traced",
    decorate_steps=_INLINE,
)

__all__ = [
    "DRIVERS",
    "compiled",
    "explicit_lane",
    "explicit_lanes",
    "explicit_lanes_parallel",
    "explicit_lanes_running",
    "explicit_lanes_running_parallel",
    "implicit_lane",
    "implicit_lanes",
    "implicit_lanes_parallel",
    "traced",
]


def _borrowed(typingctx: Any, value: Any) -> Any:
    """``borrowed(value)``: the array ``value`` (or each array of the tuple ``value``: a
    method's work) without its memory-info pointer, a view the lane borrows for the length of
    the call. Numba counts the references of every array it passes or assigns (an atomic
    increment and decrement each time); on a borrowed array the count is a null check. The
    lane passes its work arrays to its steps and equations dozens of times a step: counted,
    they made an explicit lane 5-13 % dearer once its steps were functions of their own. The
    owner must outlive the borrowing: Numba frees a variable after its last use, so the caller
    uses every owner after the call (:func:`_alive`)."""

    def view(context: Any, builder: Any, kind: Any, array: Any) -> Any:
        source = make_array(kind)(context, builder, value=array)
        out = make_array(kind)(context, builder)
        populate_array(out, data=source.data, shape=source.shape, strides=source.strides,
                       itemsize=source.itemsize, meminfo=None)  # fmt: skip
        return out._getvalue()

    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        kind = signature.args[0]
        if not isinstance(kind, types.BaseTuple):
            return view(context, builder, kind, args[0])
        members: Any = kind  # a tuple type iterates over its members' types
        items = cgutils.unpack_tuple(builder, args[0], len(members))
        views = [view(context, builder, t, v) for t, v in zip(members, items, strict=True)]
        return context.make_tuple(builder, kind, views)

    return value(value), codegen


borrowed: Any = intrinsic(_borrowed)


@numba.njit(cache=True, error_model="numpy")
def _alive(*owners):
    """Nothing: a use of ``owners`` after the call that borrowed them."""
    return


@numba.njit(cache=True, error_model="numpy")
def _work(lay, n_q):
    """The loop's work arrays (``source.lane``'s contract): ``mask``, ``vec`` (9, S), the
    quantities at two ends (2, Q), the refinement's ``samples``, the penetrations (2, nc),
    the contact records (3, 7 nc), the constrained right-hand side's ``phi_q``, ``schur``,
    ``lam`` and the projection's ``scratch``."""
    nc = max(lay[LY_NC], 1)
    rows = 2 * lay[LY_NIDEAL] + 1
    return (
        np.empty(n_q, dtype=np.int64), np.empty((9, lay[LY_SIZE])), np.empty((2, n_q)),
        np.empty((9, n_q)), np.empty((2, nc)), np.empty((3, 7 * nc)),
        np.empty((rows, lay[LY_N])), np.empty((rows, rows)), np.empty(rows), np.zeros(N_WORK),
    )  # fmt: skip


def _traced(ipar, rpar, lay, y0, t_end, max_step, rtol, atol, max_steps, interrupt):
    """One integration by the traced lane ``method_lane`` with ``method_work`` (:data:`traced`)."""
    mask, vec, q, samples, pen, records, phi_q, schur, lam, scratch = _work(lay, lay[LY_NQ])
    counts = np.zeros(N_TRACE_COUNTS, dtype=np.int64)
    code, _, times, states = method_lane(  # type: ignore[name-defined]  # noqa: F821
        ipar, rpar, lay, y0, t_end, t_end, max_step, rtol, atol, max_steps, interrupt,
        np.empty(lay[LY_NQ]), np.empty(2 * (lay[LY_N] // 3) + 4 * lay[LY_NC]), counts, mask,
        vec, q, samples, pen, records, phi_q, schur, lam, scratch,
        method_work(lay),  # type: ignore[name-defined]  # noqa: F821
    )  # fmt: skip
    return code, times.copy(), states.copy(), counts, scratch


def _one(
    ipar, rpar, lay, y0, t_settle, t_end, max_step, rtol, atol, max_steps, interrupt,
    peaks, stats, status, t_reached, counts, lane,
):  # fmt: skip
    """Lane ``lane`` (:func:`_drivers`' ``method_lane`` with ``method_work``), every array
    borrowed (:func:`borrowed`): the caller's, and the work arrays allocated here and kept
    alive until the lane returns."""
    mask, vec, q, samples, pen, records, phi_q, schur, lam, scratch = _work(lay, peaks.shape[1])
    ws = method_work(lay)  # type: ignore[name-defined]  # noqa: F821 (the drivers' namespace)
    b = borrowed
    code, t = method_lane(  # type: ignore[name-defined]  # noqa: F821
        b(ipar), b(rpar[lane]), b(lay), b(y0[lane]), t_settle[lane], t_end[lane],
        max_step[lane], rtol, b(atol), max_steps, b(interrupt), b(peaks[lane]),
        b(stats[lane]), b(counts[lane]), b(mask), b(vec), b(q), b(samples), b(pen),
        b(records), b(phi_q), b(schur), b(lam), b(scratch),
        b(ws),
    )  # fmt: skip
    # the owners of the borrowed work arrays: alive until here (Numba frees a variable after
    # its last use, which would otherwise be the borrowing, before the lane runs)
    _alive(mask, vec, q, samples, pen, records, phi_q, schur, lam, scratch, ws)
    status[lane] = code
    t_reached[lane] = t


def _lanes(
    ipar, rpar, lay, y0, t_settle, t_end, max_step, rtol, atol, max_steps, interrupt,
    peaks, stats, status, t_reached, counts,
):  # fmt: skip
    """Every lane, one after the other (arguments: :func:`jointplay._kernels.batch.run_batch`,
    plus ``lay`` of :func:`jointplay._kernels.lanes.build.lane_layout`; outputs in place)."""
    for lane in range(y0.shape[0]):
        _one(
            ipar, rpar, lay, y0, t_settle, t_end, max_step, rtol, atol, max_steps, interrupt,
            peaks, stats, status, t_reached, counts, lane,
        )  # fmt: skip


def _lanes_parallel(
    ipar, rpar, lay, y0, t_settle, t_end, max_step, rtol, atol, max_steps, interrupt,
    peaks, stats, status, t_reached, counts,
):  # fmt: skip
    """:func:`_lanes` on Numba's threads (``prange`` over lanes)."""
    for lane in numba.prange(y0.shape[0]):
        _one(
            ipar, rpar, lay, y0, t_settle, t_end, max_step, rtol, atol, max_steps, interrupt,
            peaks, stats, status, t_reached, counts, lane,
        )  # fmt: skip


def _drivers(lane: Any, work: Any, tag: str) -> tuple[Any, Any]:
    """The serial and the threaded drivers of :func:`_lanes` and :func:`_lanes_parallel` over
    the compiled lane ``lane`` with its method's work arrays ``work``: the functions compiled
    in a namespace of their own (as :func:`~jointplay._kernels.lanes.build.build` does),
    ``tag`` keeping their cache entries apart, so that each pair links its own lane and no
    other."""
    namespace = {"np": np, "numba": numba, "_work": _work, "borrowed": borrowed,
                 "_alive": _alive, "method_lane": lane, "method_work": work}  # fmt: skip
    for function, parallel in ((_one, False), (_lanes, False), (_lanes_parallel, True)):
        namespace[function.__name__] = numba.njit(
            cache=True, error_model="numpy", parallel=parallel
        )(rebound(function, namespace, function.__qualname__ + tag))
    return namespace["_lanes"], namespace["_lanes_parallel"]


def _driver_table(name: str, tag: str) -> dict[Any, Any]:
    """The drivers of lane ``name`` by ``(running, parallel)``: over the lane and over its
    compilation with the running reductions, with the work allocator of its record."""
    work = compiled[LANES[name]["work"]]
    serial, threaded = _drivers(compiled[name], work, tag)
    serial_running, threaded_running = _drivers(compiled_running[name], work, f"{tag}_running")
    return {
        (False, False): serial, (False, True): threaded,
        (True, False): serial_running, (True, True): threaded_running,
    }  # fmt: skip


#: The single engine's integration by each integrator (its name), a lane that records:
#: ``traced[name](ipar, rpar, lay, y0, t_end, max_step, rtol, atol, max_steps, interrupt) ->
#: (status, times, states, counts, work)`` — from t = 0 to ``t_end``, no window; every
#: accepted step's end (the first row the start), the counters (``K_*``, ``N_TRACE_COUNTS``)
#: and the projection's statistics (``W_*``).
_TRACED_NAMES = {"np": np, "_work": _work, "N_TRACE_COUNTS": N_TRACE_COUNTS, "LY_N": LY_N,
                 "LY_NC": LY_NC, "LY_NQ": LY_NQ}  # fmt: skip
traced = {
    record["integrator"]["name"]: numba.njit(cache=True, error_model="numpy", nogil=True)(
        rebound(
            _traced,
            {
                **_TRACED_NAMES,
                "method_lane": compiled_traced[lane],
                "method_work": compiled[record["work"]],
            },
            f"_traced_{record['integrator']['name']}",
        )
    )
    for lane, record in LANES.items()
}

#: The batch drivers of each method by ``(running, parallel)``, over the lane of the integrator
#: that the CPU's batch engine has for it (its record names ``"lanes-explicit"`` or
#: ``"batch-implicit"``).
DRIVERS = {
    "explicit": _driver_table(lane_for("lanes-explicit"), ""),
    "implicit": _driver_table(lane_for("batch-implicit"), "_implicit"),
}
#: Every lane of each method, serially and on Numba's threads (and with the running
#: reductions).
explicit_lanes, explicit_lanes_parallel = (
    DRIVERS["explicit"][False, False],
    DRIVERS["explicit"][False, True],
)
explicit_lanes_running = DRIVERS["explicit"][True, False]
explicit_lanes_running_parallel = DRIVERS["explicit"][True, True]
implicit_lanes, implicit_lanes_parallel = (
    DRIVERS["implicit"][False, False],
    DRIVERS["implicit"][False, True],
)
