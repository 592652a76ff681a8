"""Where a dry steady revolution's time goes (issue 40, item 4).

The paper's four-bar, 21 µm in all four joints, the dry contact (``ContactModel(lubrication=
"dry")``: no film), steady start, settle 2 + ``--revolutions`` revolutions, default tolerances.
Prints the integrator's counters, the steps per number of joints in contact with their median
step, where the rejected tries fall (the accepted step that follows each, by the joints in
contact), and the cost of each piece of work from micro-timings of the compiled functions at
a state in contact (µs per call, times the counts), against the measured integration time.

Run it with a checkout's sources first on the path::

    PYTHONPATH=src python benchmarks/bench_dry_profile.py --revolutions 1
"""

from __future__ import annotations

import argparse
import os
import time
from typing import Any

import numba
import numpy as np

from jointplay._kernels import eom
from jointplay._kernels.ids import N_WORK
from jointplay._kernels.lanes.cpu import compiled as lane
from jointplay.dynamics.setup import ContactModel
from jointplay.dynamics.simulate import SimulationResult, Start, simulate
from jointplay.io.config import load_preset

JOINTS = ("O2", "A", "B", "O4")
MICRO_CALLS = 20_000
_onset_check, _contact_memory, _project, _factor_newton, _newton_iteration = (
    lane[n]
    for n in ("onset_check", "contact_memory", "project", "factor_newton", "newton_iteration")
)
PERIOD = 60.0 / 200.0  # s per crank revolution at 200 rpm


def run(revolutions: int) -> SimulationResult:
    mechanism = load_preset("paper-fourbar")
    joints = ContactModel(lubrication="dry").joints(mechanism, JOINTS)
    return simulate(mechanism, joints, revolutions=revolutions, settle=2, start=Start("steady"))


@numba.njit
def _time_rhs(t: float, y: Any, args: Any, calls: int) -> float:
    s = 0.0
    for _ in range(calls):
        s += eom.state_rhs(t, y, args)[0]
    return s


@numba.njit
def _time_jacobian(t: float, y: Any, f: Any, args: Any, out: Any, calls: int) -> None:
    for _ in range(calls):
        eom.jacobian_state(t, y, f, args, out)


@numba.njit
def _time_lu(jac: Any, h: float, a_re: Any, piv_re: Any, c_re: Any, c_im: Any, piv_c: Any,
             m2: int, nk: int, calls: int) -> None:  # fmt: skip
    for _ in range(calls):
        _factor_newton(jac, h, a_re, piv_re, c_re, c_im, piv_c, m2, nk)


@numba.njit
def _time_newton(fst: Any, h: float, w: Any, z: Any, dw: Any, scale: Any, jac: Any, lu: Any,
                 vectors: Any, m2: int, nk: int, calls: int) -> float:  # fmt: skip
    a_re, piv_re, c_re, c_im, piv_c = lu
    xr, xcr, xci = vectors
    wk, wkr, wki = np.empty(nk), np.empty(nk), np.empty(nk)
    s = 0.0
    for _ in range(calls):
        w[:] = 0.0
        s += _newton_iteration(
            fst, h, w, z, dw, scale, 1e-3, 0, 0.0, np.nan, jac, a_re, piv_re, c_re, c_im, piv_c,
            xr, xcr, xci, wk, wkr, wki, m2, nk, fst.shape[1],
        )[2]  # fmt: skip
    return s


@numba.njit
def _time_hooks(t: float, y: Any, t2: float, y2: Any, rpar: Any, ipar: Any, lay: Any,
                old: Any, new: Any, scratch: Any, calls: int) -> float:  # fmt: skip
    """The lanes' loop's work around an accepted step (``source.lane``): the contact-onset
    control on the two ends' records, the contact memory and the projection."""
    s = 0.0
    empty = y[:0].reshape((0, 0))
    for _ in range(calls):
        s += _onset_check(t, y, t2, y2, old, new, rpar, lay)
        _contact_memory(y2, rpar, lay, new, old)
        _project(t2, y2, rpar, ipar, lay, scratch, empty, empty, y[:0])
    return s


def hook_arguments(result: SimulationResult, i: int) -> tuple[Any, ...]:
    """:func:`_time_hooks`' arguments for the step from recorded state ``i`` to ``i + 1``:
    the contact records of both ends as ``eom.evaluate`` writes them (the loop's layout)."""
    rpar, ipar = result.system.kernel_args()[:2]
    ends = []
    for k in (i, i + 1):
        y = np.array(result.y[k])
        records = np.empty((len(result.system.clearances), 7))
        eom.evaluate(float(result.t[k]), y, rpar, ipar, records)
        ends.append((float(result.t[k]), y, records.reshape(-1)))
    (t, y, old), (t2, y2, new) = ends
    return t, y, t2, y2, rpar, ipar, eom.lay_of(ipar), old, new, np.zeros(N_WORK)


def micro_us(result: SimulationResult, h: float) -> dict[str, float]:
    """µs (CPU time) per call of each piece at a state in the middle of the run, best of 5
    rounds."""
    args = result.system.kernel_args()
    i = len(result.t) // 2
    y, t = np.array(result.y[i]), float(result.t[i])
    f = eom.state_rhs(t, y, args).copy()
    out = np.empty((y.size, y.size))
    eom.jacobian_state(t, y, f, args, out)
    m2 = result.system.n_coordinates
    nk = m2  # the velocities: the passive components are not factored
    lu = (np.empty((nk, nk)), np.zeros(nk, np.int64), np.empty((nk, nk)), np.empty((nk, nk)),
          np.zeros(nk, np.int64))  # fmt: skip
    _factor_newton(out[m2:], h, *lu, m2, nk)
    stages = np.tile(f, (3, 1))
    scale = 1e-10 + 1e-6 * np.abs(y)
    vectors = (np.empty(y.size), np.empty(y.size), np.empty(y.size))
    z, w, dw = np.zeros((3, y.size)), np.zeros((3, y.size)), np.zeros((3, y.size))
    newton = (stages, h, w, z, dw, scale, out[m2:], lu, vectors, m2, nk)
    calls: dict[str, tuple[Any, tuple[Any, ...]]] = {
        "rhs": (_time_rhs, (t, y, args)),
        "Newton iteration's algebra": (_time_newton, newton),
        "jacobian": (_time_jacobian, (t, y, f, args, out)),
        "LU pair": (_time_lu, (out[m2:], h, *lu, m2, nk)),
        "hooks": (_time_hooks, hook_arguments(result, i)),
    }
    timings = {}
    for name, (function, arguments) in calls.items():
        function(*arguments, 10)
        best = np.inf
        for _ in range(5):
            start = time.process_time()  # CPU time: robust to other jobs on the machine
            function(*arguments, MICRO_CALLS)
            best = min(best, (time.process_time() - start) / MICRO_CALLS * 1e6)
        timings[name] = best
    return timings


def profile(revolutions: int) -> None:
    run(1)  # loads the compiled kernels
    cpu = time.process_time()
    result = run(revolutions)
    cpu = time.process_time() - cpu
    stats = result.solver_stats
    keys = ("steps", "rejected_by_error", "rejected_by_newton", "rejected_for_contact_onset",
            "rhs_evaluations", "jacobian_evaluations", "lu_decompositions")  # fmt: skip
    total = revolutions + 2
    print(f"counters ({total} revolutions):", {k: stats[k] for k in keys})
    wall = stats["wall_s"]
    print(f"wall {wall * 1e3:.1f} ms, {wall / total * 1e3:.1f} ms per revolution; CPU time of the "
          f"whole simulate() call (post-processing included) {cpu / total * 1e3:.1f} ms per "
          f"revolution")  # fmt: skip
    attempts = stats["steps"] + stats["rejected_steps"]
    print(f"per accepted step: {stats['rhs_evaluations'] / stats['steps']:.2f} evaluations, "
          f"{stats['jacobian_evaluations'] / stats['steps']:.3f} Jacobians, "
          f"{stats['lu_decompositions'] / 2 / stats['steps']:.3f} LU pairs; "
          f"{stats['rhs_evaluations'] / attempts / 3:.2f} Newton iterations per try (upper bound)")  # fmt: skip
    t = result.t
    h = np.diff(t)
    columns = result._step_columns
    pens = np.column_stack([columns[f"pen_{j}"][1:] > 0 for j in JOINTS])
    in_contact = pens.sum(axis=1)
    for k in range(5):
        mask = in_contact == k
        if mask.any():
            print(f"{k} joints in contact at the step's end: {mask.sum()} steps, "
                  f"median h {np.median(h[mask]):.2e} s")  # fmt: skip
    drops = np.flatnonzero(h[1:] < 0.6 * h[:-1]) + 1  # a step cut after a rejected try
    print(f"steps cut below 0.6x the last (after a rejection): {drops.size}; joints in contact "
          f"there: {np.bincount(in_contact[drops], minlength=5).tolist()} (0..4); "
          f"an onset in the step before: {int(np.sum(in_contact[drops] > in_contact[drops - 1]))}")  # fmt: skip
    for j, name in enumerate(JOINTS):
        onsets = int(np.sum(pens[1:, j] & ~pens[:-1, j]))
        print(f"{name}: {pens[:, j].mean() * 100:.1f} % of the steps in contact, {onsets} onsets")
    print(f"h: median {np.median(h):.2e} s, 10 % {np.quantile(h, 0.1):.2e}, "
          f"90 % {np.quantile(h, 0.9):.2e}, max {h.max():.2e}")  # fmt: skip
    per = micro_us(result, float(np.median(h)))
    print("µs per call:", {k: round(v, 3) for k, v in per.items()})
    iterations = (stats["rhs_evaluations"] - stats["steps"]) / 3  # upper bound
    parts = {
        "rhs": stats["rhs_evaluations"] * per["rhs"],
        "Newton algebra": iterations * per["Newton iteration's algebra"],
        "jacobian": stats["jacobian_evaluations"] * per["jacobian"],
        "LU": stats["lu_decompositions"] / 2 * per["LU pair"],
        "hooks": stats["steps"] * per["hooks"],
    }
    accounted = sum(parts.values()) / 1e3
    print("CPU ms per revolution: "
          + ", ".join(f"{k} {v / total / 1e3:.1f}" for k, v in parts.items())
          + f"; the rest of simulate() (error estimates, loop, reference counting, calls, "
          f"post-processing) {(cpu * 1e3 - accounted) / total:.1f}")  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--revolutions", type=int, default=1)
    args = parser.parse_args()
    print(f"load {os.getloadavg()[0]:.1f}, {os.cpu_count()} CPUs")
    profile(args.revolutions)


if __name__ == "__main__":
    main()
