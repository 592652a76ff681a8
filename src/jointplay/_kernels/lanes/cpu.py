"""The lane source compiled for the CPU, and the batch drivers over lanes.

:data:`explicit_lane` is :func:`jointplay._kernels.lanes.source.explicit_lane` compiled by
``numba.njit(cache=True, error_model="numpy")`` (so a division by zero gives inf/NaN, as in
the rest of the kernels); the drivers allocate each lane's work arrays and run the lanes
serially or on Numba's threads (``prange``). Lanes are independent: a lane's result does not
depend on the other lanes or on the thread that runs it.
"""

from __future__ import annotations

import types
from typing import Any

import numba
import numpy as np

from jointplay._kernels.lanes.build import build, closed
from jointplay._kernels.lanes.projection import N_WORK, project_lapack
from jointplay._kernels.lanes.source import LY_N, LY_NC, LY_NIDEAL, LY_SIZE

#: Every function of the source, compiled for the CPU, by name; the projection hook is the
#: single engine's (:func:`~jointplay._kernels.lanes.projection.project_lapack`, LAPACK's
#: solve), so that the lanes keep its bits.
compiled = build(
    numba.njit(cache=True, error_model="numpy"),
    hooks={"project": project_lapack},
    extras={"np": np},
)
#: The explicit lane, compiled for the CPU.
explicit_lane = compiled["explicit_lane"]
#: The explicit lane with the running reductions (``source.RUNNING``: a separate compilation,
#: so that :data:`explicit_lane` has none of their code), run when the lanes' ``rpar`` carry
#: the running tail (:func:`jointplay._kernels.lanes.build.running_layout`).
compiled_running = build(
    numba.njit(cache=True, error_model="numpy"),
    hooks={"project": project_lapack},
    extras={"np": np, "RUNNING": True},
    only=closed(("explicit_lane",)),
    tag="running",
)
explicit_lane_running = compiled_running["explicit_lane"]
#: The implicit lane (:mod:`jointplay._kernels.lanes.source_radau`), compiled for the CPU.
implicit_lane = compiled["implicit_lane"]

__all__ = [
    "EXPLICIT_DRIVERS",
    "compiled",
    "explicit_lane",
    "explicit_lanes",
    "explicit_lanes_parallel",
    "explicit_lanes_running",
    "explicit_lanes_running_parallel",
    "implicit_lane",
    "implicit_lanes",
    "implicit_lanes_parallel",
]


@numba.njit(cache=True, error_model="numpy")
def _work(lay, n_q):
    """The work arrays both lanes take (their contract: the source's ``explicit_lane`` and
    ``implicit_lane``): ``mask``, the quantities at two ends (2, Q), the refinement's
    ``samples``, the penetrations (2, nc), the contact records (3, 7 nc), the constrained
    right-hand side's ``phi_q``, ``schur``, ``lam`` and the projection's ``scratch``."""
    nc = max(lay[LY_NC], 1)
    rows = 2 * lay[LY_NIDEAL] + 1
    return (
        np.empty(n_q, dtype=np.int64), np.empty((2, n_q)), np.empty((9, n_q)),
        np.empty((2, nc)), np.empty((3, 7 * nc)), np.empty((rows, lay[LY_N])),
        np.empty((rows, rows)), np.empty(rows), np.zeros(N_WORK),
    )  # fmt: skip


def _one(
    ipar, rpar, lay, y0, t_settle, t_end, max_step, rtol, atol, max_steps, interrupt,
    peaks, stats, status, t_reached, counts, lane,
):  # fmt: skip
    """Lane ``lane`` of the explicit method (:func:`_explicit_drivers`' ``explicit_lane``)."""
    size = y0.shape[1]
    mask, q, samples, pen, records, phi_q, schur, lam, scratch = _work(lay, peaks.shape[1])
    k = np.empty((7, size))
    work = np.empty((6, size))
    code, t = explicit_lane(
        ipar, rpar[lane], lay, y0[lane], t_settle[lane], t_end[lane], max_step[lane], rtol,
        atol, max_steps, interrupt, peaks[lane], stats[lane], counts[lane], mask, k,
        work[0], work[1], work[2], work[3], work[4], work[5], q[0], q[1], samples, pen[0],
        records[0], records[1], records[2], phi_q, schur, lam, scratch,
    )  # fmt: skip
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


def _explicit_drivers(lane: Any, tag: str) -> tuple[Any, Any]:
    """The serial and the threaded drivers of :func:`_lanes` and :func:`_lanes_parallel` over
    the compiled explicit lane ``lane``: the functions compiled in a namespace of their own
    (as :func:`~jointplay._kernels.lanes.build.build` does), ``tag`` keeping their cache
    entries apart, so that each pair links its own lane and no other."""
    namespace = {"np": np, "numba": numba, "_work": _work, "explicit_lane": lane}
    for function, parallel in ((_one, False), (_lanes, False), (_lanes_parallel, True)):
        copy = types.FunctionType(function.__code__, namespace, function.__name__)
        copy.__module__ = function.__module__
        copy.__qualname__ = function.__qualname__ + tag
        copy.__doc__ = function.__doc__
        namespace[function.__name__] = numba.njit(
            cache=True, error_model="numpy", parallel=parallel
        )(copy)
    return namespace["_lanes"], namespace["_lanes_parallel"]


#: Every lane of the explicit method, serially and on Numba's threads.
explicit_lanes, explicit_lanes_parallel = _explicit_drivers(explicit_lane, "")
#: The same with the running reductions (:data:`explicit_lane_running`).
explicit_lanes_running, explicit_lanes_running_parallel = _explicit_drivers(
    explicit_lane_running, "_running"
)
#: The explicit drivers by ``(running, parallel)``.
EXPLICIT_DRIVERS = {
    (False, False): explicit_lanes,
    (False, True): explicit_lanes_parallel,
    (True, False): explicit_lanes_running,
    (True, True): explicit_lanes_running_parallel,
}


@numba.njit(cache=True, error_model="numpy")
def _one_implicit(
    ipar, rpar, lay, y0, t_settle, t_end, max_step, rtol, atol, max_steps, interrupt,
    peaks, stats, status, t_reached, counts, lane,
):  # fmt: skip
    size = lay[LY_SIZE]
    n = lay[LY_N]
    mask, q, samples, pen, records, phi_q, schur, lam, scratch = _work(lay, peaks.shape[1])
    vec = np.empty((16, size))
    small = np.empty((3, n))
    stages = np.empty((5, 3, size))
    jac = np.empty((size - n, 2 * n))
    mats = np.empty((3, n, n))
    pivots = np.empty((2, n), dtype=np.int64)
    code, t = implicit_lane(
        ipar, rpar[lane], lay, y0[lane], t_settle[lane], t_end[lane], max_step[lane], rtol,
        atol, max_steps, interrupt, peaks[lane], stats[lane], counts[lane], mask,
        vec[0], vec[1], vec[2], vec[3], vec[4], vec[5], vec[6], vec[7], vec[8], vec[9],
        vec[10], vec[11], vec[12], vec[13], vec[14], vec[15], small[0], small[1], small[2],
        stages[0], stages[1], stages[2], stages[3], stages[4], jac, mats[0], pivots[0],
        mats[1], mats[2], pivots[1], q[0], q[1], samples, pen[0], pen[1],
        records[0], records[1], records[2], phi_q, schur, lam, scratch,
    )  # fmt: skip
    status[lane] = code
    t_reached[lane] = t


@numba.njit(cache=True, error_model="numpy")
def implicit_lanes(
    ipar, rpar, lay, y0, t_settle, t_end, max_step, rtol, atol, max_steps, interrupt,
    peaks, stats, status, t_reached, counts,
):  # fmt: skip
    """Every lane of the implicit method on the single source, one after the other
    (arguments and outputs: :func:`explicit_lanes`; not in the sustained-contact mode:
    :func:`jointplay._kernels.lanes.build.lanes_refusal`)."""
    for lane in range(y0.shape[0]):
        _one_implicit(
            ipar, rpar, lay, y0, t_settle, t_end, max_step, rtol, atol, max_steps, interrupt,
            peaks, stats, status, t_reached, counts, lane,
        )  # fmt: skip


@numba.njit(cache=True, error_model="numpy", parallel=True)
def implicit_lanes_parallel(
    ipar, rpar, lay, y0, t_settle, t_end, max_step, rtol, atol, max_steps, interrupt,
    peaks, stats, status, t_reached, counts,
):  # fmt: skip
    """:func:`implicit_lanes` on Numba's threads (``prange`` over lanes)."""
    for lane in numba.prange(y0.shape[0]):
        _one_implicit(
            ipar, rpar, lay, y0, t_settle, t_end, max_step, rtol, atol, max_steps, interrupt,
            peaks, stats, status, t_reached, counts, lane,
        )  # fmt: skip
