"""The batch engine: many samples of one mechanism, peaks and steady-cycle statistics.

:func:`simulate_batch` integrates every sample of a :class:`BatchSamples` (link lengths,
clearances, contact-law parameters and crank speed per sample; anything absent stays
nominal) without dense output, and returns a frozen :class:`BatchResult`: per sample the peaks
of the single engine's peak quantities over the analysed revolutions, the time-mean and RMS of
every link's angular velocity, the deepest penetration of every clearance joint, the status
and, for a failed sample, what went wrong — with its inputs.

The work is split in three, each in its own module:

1. **build** (:func:`~jointplay.dynamics.batch_inputs.build_batch`,
   :mod:`jointplay.dynamics.batch_inputs`): the kernels' inputs for every sample;
2. **method** (:func:`~jointplay.dynamics.batch_method.choose_method`,
   :mod:`jointplay.dynamics.batch_method`): explicit Dormand–Prince 5(4) or Radau IIA, with
   the reason;
3. **run** (here): the lanes go to the executor of the given
   :class:`~jointplay.execution.backends.Backend` (:mod:`jointplay.execution`): ``"local"``
   (this process, compiled loop, threads over the cores), ``"processes"`` (worker processes,
   each running the compiled loop on one thread over large chunks), ``"dask"`` (the same on a
   Dask cluster), ``"gpu"`` (:mod:`jointplay._kernels.jax_batch`, the optional
   ``jointplay[gpu]`` extra) or ``"cuda"`` (:mod:`jointplay._kernels.lanes.cuda`: the explicit
   and implicit lanes of the CPU's single source on numba-cuda, one GPU thread per sample;
   experimental, not yet measured on a GPU); the results come back per sample, failures as data.

This module re-exports what the other two define, so ``jointplay.dynamics.batch`` stays the
one import path of the engine.

Lanes are independent, so neither the backend nor the chunking changes a sample's result
(bitwise on the CPU backends). The peak rule (which steps are searched between their ends,
and how) is stated in :mod:`jointplay._kernels.batch`.

Asked (``running=``, :mod:`jointplay.dynamics.batch_running`), the lanes also reduce the
running responses: the output link's speed deviation from the ideal linkage and the Archard
wear rate of every clearance joint.

What the batch engine does not do: dense output, time series, per-revolution statistics,
periodicity and the plausibility diagnostics — :func:`jointplay.dynamics.simulate.simulate`
gives those for one sample.
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from jointplay._kernels import batch as kb
from jointplay._kernels import ids
from jointplay._kernels.capabilities import engine_of, refusal
from jointplay._kernels.lanes import build as lane_build
from jointplay.dynamics.batch_inputs import BatchProblem, BatchSamples, build_batch
from jointplay.dynamics.batch_method import (
    EXPLICIT_TOLERANCE_SCALE,
    EXPLICIT_TOLERANCES,
    MethodChoice,
    choose_method,
)
from jointplay.dynamics.batch_running import RunningOutputs
from jointplay.dynamics.clearance import ClearanceJoint
from jointplay.dynamics.cycles import DEFAULT_SETTLE
from jointplay.dynamics.integrate import IntegrationStatus
from jointplay.dynamics.regimes import asperity_play
from jointplay.dynamics.simulate import SolverOptions, Start
from jointplay.dynamics.system import System, build_system
from jointplay.errors import ConfigError, PartialInterrupt, SettingError
from jointplay.execution import progress as _progress
from jointplay.execution.backends import BACKENDS, Backend, backend_kind
from jointplay.execution.dask import ClusterLost
from jointplay.execution.executors import Executor, Lanes, LaneWork, executor
from jointplay.execution.interrupts import close_gates, interrupts_gated
from jointplay.model.columns import rotating_links
from jointplay.model.mechanism import Mechanism

__all__ = [
    "BACKENDS",
    "EXPLICIT_TOLERANCE_SCALE",
    "NOT_RUN",
    "BatchInterrupted",
    "BatchProblem",
    "BatchResult",
    "BatchSamples",
    "ClusterLost",
    "MethodChoice",
    "RunningOutputs",
    "build_batch",
    "choose_method",
    "simulate_batch",
]

FloatArray = NDArray[np.float64]
#: One chunk of lanes: rpar, y0, t_settle, t_end, max_step.
Chunk = tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]
BatchMethod = Literal["auto", "explicit", "implicit"]


# --- the result ------------------------------------------------------------------------------------
#: The error of a sample that an interrupt stopped before it finished.
NOT_RUN = "not run (interrupted)"
#: The lubrication regimes whose time fractions the kernels report per clearance joint, in
#: their slot order (``full_film_<J>``, ``mixed_<J>``, ``boundary_<J>`` statistics).
REGIME_STATS = ("full_film", "mixed", "boundary")


class BatchInterrupted(PartialInterrupt):
    """SIGINT or SIGTERM stopped :func:`simulate_batch`; :attr:`result` keeps what finished.

    Attributes:
        result: the :class:`BatchResult` of every sample (also :attr:`partial`); those that
            did not finish have status ``interrupted`` and the error :data:`NOT_RUN`.
    """

    def __init__(self, result: BatchResult) -> None:
        super().__init__(result, "the batch was interrupted")
        self.result = result


@dataclass(frozen=True)
class BatchResult:
    """Per-sample peaks and steady-cycle statistics of a batch (failures as data).

    Attributes:
        samples: the inputs of every sample.
        peaks: one row per sample, one column per peak quantity (``omega3``, ``alpha3``,
            ``F_A``, ``torque``: the single engine's names, largest |value| over the analysed
            revolutions); NaN where the sample failed.
        statistics: one row per sample: ``omega{k}_mean`` and ``omega{k}_rms`` (rad/s, over
            the analysed revolutions), ``pen_{joint}`` (deepest penetration, m; negative:
            never touched) and ``full_film_{joint}``, ``mixed_{joint}``,
            ``boundary_{joint}``: the fractions of the analysed time the joint ran in each
            lubrication regime (sum 1; NaN for a dry joint; :mod:`jointplay.dynamics.regimes`).
        units: unit of every column of ``peaks`` and ``statistics``.
        ok: (n,) the sample succeeded.
        status: (n,) :class:`~jointplay.dynamics.integrate.IntegrationStatus` codes (a
            sample that could not be built: ``NON_FINITE``, with its message).
        errors: n messages (``""`` where ok).
        counters: one row per sample: ``n_steps``, ``n_rejected``, ``n_rhs``, ``t_reached``.
        method, method_reason: the integration method and why it was chosen.
        backend, workers, chunk_size: where it ran.
        build_time, wall_time: seconds spent building the kernels' inputs, and in total.
    """

    samples: BatchSamples
    peaks: pd.DataFrame
    statistics: pd.DataFrame
    units: Mapping[str, str]
    ok: NDArray[np.bool_]
    status: NDArray[np.int64]
    errors: tuple[str, ...]
    counters: pd.DataFrame
    method: str
    method_reason: str
    backend: str
    workers: int
    chunk_size: int
    build_time: float
    wall_time: float

    @property
    def n_failed(self) -> int:
        return int(np.sum(~self.ok))

    @property
    def failures(self) -> pd.DataFrame:
        """The failed samples: their inputs and what went wrong."""
        frame = self.samples.to_frame()
        frame["error"] = list(self.errors)
        return frame[~self.ok]

    def to_frame(self) -> pd.DataFrame:
        """One row per sample: inputs, peaks, statistics, status, error and counters."""
        frame = pd.concat(
            [self.samples.to_frame(), self.peaks, self.statistics, self.counters], axis=1
        )
        frame["status"] = [IntegrationStatus(int(s)).name.lower() for s in self.status]
        frame["error"] = list(self.errors)
        return frame

    def describe(self) -> dict[str, Any]:
        """JSON-ready record of how the batch ran."""
        return {
            "samples": len(self.samples),
            "failed": self.n_failed,
            "method": self.method,
            "method_reason": self.method_reason,
            "backend": self.backend,
            "workers": self.workers,
            "chunk_size": self.chunk_size,
            "build_time_s": self.build_time,
            "wall_time_s": self.wall_time,
            "steps_mean": float(self.counters["n_steps"][self.ok].mean())
            if self.ok.any()
            else None,
        }


def _names(
    mechanism: Mechanism, system: System, running: RunningOutputs | None = None
) -> tuple[list[tuple[int, str, str]], list[tuple[int, str, str]]]:
    """(kernel column, name, unit) of the reported peaks and statistics (with ``running``,
    the output link's ``omega<k>_deviation`` peak and the ``wear_rate_<joint>`` statistics,
    :mod:`jointplay.dynamics.batch_running`)."""
    flat = system.flat
    nb, nj = flat.n_bodies, len(flat.joint_names)
    links = rotating_links(mechanism)
    peaks = [(flat.body_index(name), f"omega{k}", "rad/s") for name, k in links]
    peaks += [(nb + flat.body_index(name), f"alpha{k}", "rad/s^2") for name, k in links]
    peaks += [(2 * nb + j, f"F_{name}", "N") for j, name in enumerate(flat.joint_names)]
    peaks.append((2 * nb + nj, "torque", "N*m"))
    stats = [(flat.body_index(name), f"omega{k}_mean", "rad/s") for name, k in links]
    stats += [(nb + flat.body_index(name), f"omega{k}_rms", "rad/s") for name, k in links]
    stats += [(2 * nb + c, f"pen_{j.joint}", "m") for c, j in enumerate(system.clearances)]
    nc = len(system.clearances)
    for c, j in enumerate(system.clearances):  # the kernels' time-in-regime fractions
        stats += [
            (2 * nb + nc + 3 * c + k, f"{regime}_{j.joint}", "1")
            for k, regime in enumerate(REGIME_STATS)
        ]
    if running is not None:
        peaks.append((2 * nb + nj + 1, f"omega{running.reference.link_number}_deviation", "rad/s"))
        stats += [
            (2 * nb + 4 * nc + c, f"wear_rate_{j.joint}", "m/s")
            for c, j in enumerate(system.clearances)
        ]
    return peaks, stats


_ADVICE = {
    IntegrationStatus.TOO_MANY_STEPS: "raise SolverOptions.max_steps, or look for chattering "
    "contact (a stiffer law, more damping, a larger onset tolerance)",
    IntegrationStatus.STEP_TOO_SMALL: "loosen rtol/atol, or check that the contact stiffness "
    "and damping are physically sensible (or use method='implicit')",
    IntegrationStatus.NON_FINITE: "check that the contact law's stiffness, exponent and "
    "damping are physically sensible (a value far out of range overflows)",
}


def _lane_message(code: int, t_reached: float, t_end: float, max_steps: int) -> str:
    status = IntegrationStatus(int(code))
    where = f"simulation stopped at t = {t_reached:.6g} s of {t_end:.6g} s: {status.summary}"
    if status is IntegrationStatus.TOO_MANY_STEPS:
        where += f" (max_steps = {max_steps})"
    return f"IntegrationError: {where}; {_ADVICE.get(status, '')}".rstrip("; ")


# --- the lanes on an executor -----------------------------------------------------------------------
def _chunks(n: int, size: int) -> list[NDArray[np.intp]]:
    return [np.arange(i, min(i + size, n)) for i in range(0, n, size)]


def _gpu_kernel() -> Callable[..., Any]:
    try:
        from jointplay._kernels import jax_batch
    except ImportError as exc:
        raise ConfigError(
            f"the gpu backend needs JAX: install jointplay[gpu] (pip install 'jointplay[gpu]'); "
            f"{exc}"
        ) from None
    kernel: Callable[..., Any] = jax_batch.run_batch
    return kernel


def _cuda_kernel() -> Callable[..., Any]:
    """numba-cuda's batch kernel (:mod:`jointplay._kernels.lanes.cuda`), checked usable."""
    from jointplay._kernels.lanes import cuda as lanes_cuda

    lanes_cuda.raise_unless_available()
    kernel: Callable[..., Any] = lanes_cuda.run_batch
    return kernel


def _lane_work(problem: BatchProblem, method: str) -> LaneWork:
    """How a chunk ``(rpar, y0, t_settle, t_end, max_step)`` of ``problem``'s lanes runs: the
    compiled kernels in a worker or in this process, the JAX kernel on a device."""
    constants = (problem.rtol, problem.atol, problem.max_steps, method)

    def here(chunk: Chunk, parallel: bool, interrupt: Any) -> kb.BatchKernelOutput:
        return kb.run_batch(
            problem.ipar, *chunk, *constants, parallel=parallel, interrupt=interrupt
        )

    def device(chunk: Chunk, size: int, timings: dict[str, float]) -> kb.BatchKernelOutput:
        outputs = _gpu_kernel()(problem.ipar, *chunk, *constants, chunk_size=size, timings=timings)
        return kb.BatchKernelOutput(*(np.asarray(a) for a in outputs))

    def cuda(
        chunk: Chunk, size: int, timings: dict[str, float], interrupt: Any = None
    ) -> kb.BatchKernelOutput:
        return _cuda_kernel()(
            problem.ipar, *chunk, *constants, chunk_size=size, timings=timings, interrupt=interrupt
        )

    def stopped(output: kb.BatchKernelOutput) -> bool:
        return bool(np.any(output.status == ids.STATUS_INTERRUPTED))

    return LaneWork(
        task=kb.run_chunk, shared=(problem.ipar, *constants), here=here, stopped=stopped,
        device=device, cuda=cuda,
    )  # fmt: skip


def _dispatch(
    problem: BatchProblem,
    lanes: NDArray[np.intp],
    method: str,
    runner: Executor,
    progress: bool,
) -> tuple[kb.BatchKernelOutput, int, int]:
    """Run the lanes ``lanes`` of ``problem`` on ``runner``; (outputs in lane order, workers,
    chunk size).

    Raises:
        _PartialDispatch: interrupted (SIGINT, SIGTERM); it carries the outputs, the lanes
            that did not finish marked ``STATUS_INTERRUPTED``.
    """
    columns = (problem.rpar, problem.y0, problem.t_settle, problem.t_end, problem.max_step)
    n = len(lanes)
    threads = runner.lane_slots()
    chunk = runner.lane_chunk(n, threads)
    parts = _chunks(n, runner.lane_parts(n, chunk))
    outputs: list[kb.BatchKernelOutput | None] = [None] * len(parts)

    def items() -> Iterator[Chunk]:
        for part in parts:
            rpar, y0, t_settle, t_end, max_step = (
                np.ascontiguousarray(c[lanes[part]]) for c in columns
            )
            yield rpar, y0, t_settle, t_end, max_step

    interrupted, lost = False, ""
    try:
        with _progress.bar(progress, n, "samples") as advance:

            def done(k: int, output: kb.BatchKernelOutput) -> None:
                outputs[k] = output
                advance(len(parts[k]))

            runner.run_lanes(Lanes(_lane_work(problem, method), items(), threads, chunk, done))
        close_gates()  # the lanes ended: from here an interrupt is noted (interrupts_gated)
    except KeyboardInterrupt:  # the finished chunks are kept; the others are marked below
        close_gates()
        interrupted = True
    except ClusterLost as error:
        close_gates()
        lost = f"ClusterLost: {error}"
    merged = _merged(problem, parts, outputs)
    if interrupted or lost or np.any(merged.status == ids.STATUS_INTERRUPTED):
        raise _PartialDispatch(merged, threads, chunk, lost)
    return merged, threads, chunk


class _PartialDispatch(KeyboardInterrupt):
    """A :func:`_dispatch` that did not finish: ``args`` are its outputs (lanes that did not
    finish have ``STATUS_INTERRUPTED``), workers, chunk size and why (``""``: an interrupt;
    else the message of the lost Dask cluster, the error of those lanes)."""


def _merged(
    problem: BatchProblem, parts: list[NDArray[np.intp]], outputs: list[kb.BatchKernelOutput | None]
) -> kb.BatchKernelOutput:
    """The outputs of every part in lane order; a part that did not run is ``STATUS_INTERRUPTED``."""
    n_peaks, n_stats = lane_build.output_widths(
        lane_build.running_layout(problem.ipar, problem.rpar), problem.rpar
    )

    def not_run(m: int) -> kb.BatchKernelOutput:
        return kb.BatchKernelOutput(
            peaks=np.full((m, n_peaks), np.nan),
            stats=np.full((m, n_stats), np.nan),
            status=np.full(m, ids.STATUS_INTERRUPTED, dtype=np.int64),
            t_reached=np.zeros(m),
            n_steps=np.zeros(m, dtype=np.int64),
            n_rejected=np.zeros(m, dtype=np.int64),
            n_rhs=np.zeros(m, dtype=np.int64),
        )

    def widened(output: kb.BatchKernelOutput) -> kb.BatchKernelOutput:
        """The JAX backend's stats stop at the penetrations (it runs no film): its regime
        slots NaN."""
        short = n_stats - output.stats.shape[1]
        if short <= 0:
            return output
        gap = np.full((output.stats.shape[0], short), np.nan)
        return output._replace(stats=np.hstack([output.stats, gap]))

    filled = [not_run(0)]
    filled += [
        not_run(len(p)) if o is None else widened(o) for p, o in zip(parts, outputs, strict=True)
    ]
    return kb.BatchKernelOutput(
        *(
            np.concatenate([getattr(o, name) for o in filled])
            for name in kb.BatchKernelOutput._fields
        )
    )


# --- the entry point --------------------------------------------------------------------------------
def implicit_only_options(clearances: Sequence[ClearanceJoint]) -> list[str]:
    """The settings of ``clearances`` that only the implicit lanes integrate, by their setting
    names: the sustained-contact mode (a capture speed; on the CPU backends only) and film
    damping (on the CPU backends and the ``cuda`` backend)."""
    options = []
    if any(c.capture_speed > 0 for c in clearances):
        options.append("sustained_contact")
    if any(c.film_damping > 0 for c in clearances):
        options.append("film_damping")
    if any(c.film_damping > 0 and c.film_model != "linear" for c in clearances):
        options.append("film_model")
    return options


def _check_implicit_only(options: Sequence[str], method: str, runner: Any) -> None:
    """Refuse the sustained-contact mode and film damping (``options``, setting names:
    :func:`implicit_only_options`) where the engine that ``runner``'s backend runs for
    ``method`` does not integrate them (:func:`jointplay._kernels.capabilities.refusal`:
    the explicit lanes neither, the cuda backend's implicit lanes no sustained contact, the
    JAX ``gpu`` backend neither), saying where they run."""
    message = refusal(engine_of(runner.kind, method), options, named=lambda n: f"{{{n}}}")
    if message is not None:
        raise SettingError(message)


def simulate_batch(
    mechanism: Mechanism,
    clearances: Sequence[ClearanceJoint],
    samples: BatchSamples,
    *,
    revolutions: float = 1.0,
    settle: int | None = None,
    start: Start | None = None,
    solver: SolverOptions | None = None,
    method: BatchMethod = "auto",
    backend: Backend | str = "local",
    workers: int | None = None,
    chunk_size: int | None = None,
    scheduler: str | None = None,
    progress: bool = False,
    running: RunningOutputs | None = None,
) -> BatchResult:
    """Simulate every sample of ``samples`` and return its peaks and statistics.

    Args:
        mechanism: the nominal mechanism.
        clearances: its clearance joints (nominal clearance and contact law; the samples
            replace what they give).
        samples: per-sample inputs (:class:`BatchSamples`).
        revolutions: analysed crank revolutions after ``settle`` start-up ones.
        settle: start-up revolutions left out of the peaks and statistics (>= 0; default:
            2 with the steady start, 0 with the others, whose start-up is what they show), as
            :func:`~jointplay.dynamics.simulate.simulate` and ``jointplay simulate``.
        start: initial state (default: ``Start("steady")``, the nominal motion, as
            :func:`~jointplay.dynamics.simulate.simulate`).
        solver: tolerances, largest step and step budget (as :func:`simulate`).
        method: ``"explicit"``, ``"implicit"`` or ``"auto"`` (:func:`choose_method`).
        backend: where the lanes run: a :class:`~jointplay.execution.backends.Backend`, or
            its name: ``"local"`` (threads in this process), ``"processes"``, ``"dask"``
            (give ``scheduler``), ``"gpu"`` (JAX; ``pip install 'jointplay[gpu]'``) or
            ``"cuda"`` (numba-cuda; experimental).
        workers: worker processes (``"processes"`` given by name; default one per CPU).
        chunk_size: lanes per task (default: 4096 local, ≤ 32 per process task so each
            worker gets ~4, 200 000 on the GPU). Never changes the results.
        scheduler: the Dask scheduler's address (``"dask"`` given by name).
        progress: show a progress bar on stderr.
        running: also compute the running responses (:mod:`jointplay.dynamics.batch_running`):
            the peak ``omega<k>_deviation`` of the output link's speed from the ideal
            reference (rad/s) and the statistics ``wear_rate_<joint>`` (m/s); on the CPU
            backends and ``"cuda"`` (not on the JAX ``"gpu"`` backend). ``None``: not asked,
            the lanes do nothing more.

    Raises:
        ConfigError: an argument is out of range, or the backend is not available.
        BatchInterrupted: SIGINT or SIGTERM stopped the run (a KeyboardInterrupt); its
            ``result`` holds the samples that finished, the others with status
            ``interrupted`` and the error :data:`NOT_RUN`.
    """
    wall = time.perf_counter()
    if not isinstance(samples, BatchSamples):
        raise ConfigError(f"samples must be a BatchSamples, got {type(samples).__name__}")
    if method not in ("auto", *kb.METHODS):
        raise ConfigError(f"method must be auto, explicit or implicit, got {method!r}")
    runner = executor(_where(backend, workers, chunk_size, scheduler))
    _check_implicit_only(implicit_only_options(clearances), method, runner)
    if runner.kind == "cuda":
        _cuda_kernel()  # fail early, before building
    elif runner.on_device:
        _gpu_kernel()  # fail early, before building
    if running is not None:
        refused = refusal(engine_of(runner.kind, method), ["running_responses"])
        if refused is not None:
            raise ConfigError(refused)
    start = start or Start("steady")
    if settle is None:
        settle = DEFAULT_SETTLE if start.mode == "steady" else 0
    solver = solver or SolverOptions()
    problem = build_batch(
        mechanism, clearances, samples, revolutions=revolutions, settle=settle, start=start,
        solver=solver,
    )  # fmt: skip
    system = build_system(mechanism, clearances, ramp_time=start.ramp_time, driven=start.driven)
    if running is not None:  # the running tail after every sample's packed model
        tail = running.tail(mechanism, system)
        problem = dataclasses.replace(
            problem,
            rpar=np.hstack([problem.rpar, np.broadcast_to(tail, (len(problem.rpar), len(tail)))]),
        )
    build_time = time.perf_counter() - wall
    if method == "auto":
        choice = choose_method(mechanism, clearances, samples=samples, solver=solver)
        chosen, reason = choice.method, choice.reason
    else:
        chosen, reason = method, f"{method}, as asked"
        if method == "explicit":
            reason += f" ({EXPLICIT_TOLERANCES})"
    if chosen == "explicit":
        problem = problem.scaled_tolerances(EXPLICIT_TOLERANCE_SCALE)
    n = len(samples)
    lanes = np.flatnonzero(problem.ok)
    interrupted, lost = False, ""
    # an interrupt after the lanes (the gate closed as they end) is noted, and the result goes
    # with it (BatchInterrupted) instead of being lost
    with interrupts_gated() as gate:
        try:
            output, used_workers, chunk = _dispatch(problem, lanes, chosen, runner, progress)
        except _PartialDispatch as partial:
            output, used_workers, chunk, lost = partial.args
            interrupted = not lost
        peak_names, stat_names = _names(mechanism, system, running)
        peaks = np.full((n, len(peak_names)), np.nan)
        stats = np.full((n, len(stat_names)), np.nan)
        status = np.full(n, ids.STATUS_NON_FINITE, dtype=np.int64)
        counters = np.zeros((n, 4))
        counters[:, 3] = np.nan
        peaks[lanes] = output.peaks[:, [k for k, _, _ in peak_names]]
        stats[lanes] = output.stats[:, [k for k, _, _ in stat_names]]
        pen = np.array(
            [i for i, (_, name, _) in enumerate(stat_names) if name.startswith("pen_")], dtype=int
        )
        # the kernels' δ under a Reynolds film is the asperities': the wall's is |e| − c
        stats[np.ix_(lanes, pen)] -= asperity_play(problem.rpar[lanes], problem.ipar, len(pen))
        status[lanes] = output.status
        counters[lanes] = np.column_stack(
            [output.n_steps, output.n_rejected, output.n_rhs, output.t_reached]
        )
        errors = list(problem.errors)
        for row, lane in enumerate(lanes):
            if output.status[row] == ids.STATUS_INTERRUPTED:
                errors[lane] = lost or NOT_RUN
            elif output.status[row] != ids.STATUS_SUCCESS:
                errors[lane] = _lane_message(
                    int(output.status[row]), float(output.t_reached[row]),
                    float(problem.t_end[lane]), problem.max_steps,
                )  # fmt: skip
        ok = status == ids.STATUS_SUCCESS
        units = {name: unit for _, name, unit in (*peak_names, *stat_names)}
        index = pd.RangeIndex(n, name="sample")
        result = BatchResult(
            samples=samples,
            peaks=pd.DataFrame(peaks, columns=[name for _, name, _ in peak_names], index=index),
            statistics=pd.DataFrame(
                stats, columns=[name for _, name, _ in stat_names], index=index
            ),
            units=units,
            ok=ok,
            status=status,
            errors=tuple(errors),
            counters=pd.DataFrame(
                {
                    "n_steps": counters[:, 0].astype(np.int64),
                    "n_rejected": counters[:, 1].astype(np.int64),
                    "n_rhs": counters[:, 2].astype(np.int64),
                    "t_reached": counters[:, 3],
                },
                index=index,
            ),
            method=chosen,
            method_reason=reason,
            backend=runner.kind,
            workers=used_workers,
            chunk_size=chunk,
            build_time=build_time,
            wall_time=time.perf_counter() - wall,
        )
    if interrupted or gate.noted:
        raise BatchInterrupted(result)
    return result


def _where(
    backend: Backend | str, workers: int | None, chunk_size: int | None, scheduler: str | None
) -> Backend:
    """The :class:`Backend` of :func:`simulate_batch`'s arguments (a name and its settings,
    or a Backend whose chunk size ``chunk_size`` replaces)."""
    if isinstance(backend, Backend):
        if workers is not None or scheduler is not None:
            raise ConfigError("give workers and scheduler in the Backend, not beside it")
        return (
            backend if chunk_size is None else dataclasses.replace(backend, chunk_size=chunk_size)
        )
    return Backend(
        backend_kind(backend), workers=workers, scheduler=scheduler, chunk_size=chunk_size
    )
