"""Independent tasks in-process, on local processes or on Dask: one backend for every study.

Two entry points:

* :func:`~jointplay.execution.tasks.run_tasks` — the generic runner::

      run_tasks(function, items, backend=None, *, shared=None, sizes=None, progress=False,
                description="tasks", on_done=None) -> TaskRun

  calls ``function(shared, item)`` for every item and returns, in item order, each result or
  the failure (``"ErrorType: message"``) with a status per item (:data:`STATUS`). The
  tolerance methods use it through :func:`run`; the paper study runs its simulations with it.
* :func:`run` — a response model over an (n, k) matrix of samples: the samples are cut into
  blocks of ``model.chunk_size`` rows (fixed by n and the chunk size alone, never by the
  backend), each block is one task, and the blocks are put back in sample order, the
  per-sample checks of a :class:`~jointplay.tolerance.responses.CheckedModel` with them. The
  same model and samples therefore give bit-identical results on every backend (on the same
  kind of machine).

Where the blocks run is a :class:`~jointplay.execution.backends.Backend` of the execution
room (:mod:`jointplay.execution`): ``"local"`` (``"serial"`` is the same), ``"processes"``
(default), ``"dask"`` or ``"gpu"``. A run with a single task stays in-process, and so does
one whose model says its samples are too cheap to pay for starting workers
(``seconds_per_sample``, see :func:`run`). A batch-engine model
(:class:`~jointplay.tolerance.responses.DynamicResponses`) runs its blocks from this process
and spreads each block's samples itself on the backend (:func:`_placed`).

A progress bar (on stderr) shows the work done, rate and time left. Ctrl-C stops the run
gracefully: pending tasks are cancelled, finished ones are kept and the others are marked
``not run`` (status 2); :attr:`RunResult.interrupted` says it happened.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from jointplay.errors import ConfigError
from jointplay.execution.backends import BACKENDS, Backend
from jointplay.execution.executors import WORKER_START_S, executor
from jointplay.execution.interrupts import interrupts_noted
from jointplay.execution.tasks import FAILED, NOT_RUN, OK, STATUS, TaskRun, run_tasks
from jointplay.tolerance.responses import CheckedModel, Evaluation, ResponseModel

__all__ = [
    "BACKENDS",
    "FAILED",
    "NOT_RUN",
    "OK",
    "STATUS",
    "WORKER_START_S",
    "Backend",
    "RunResult",
    "TaskRun",
    "prepare",
    "run",
    "run_tasks",
    "start_batch_workers",
]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class RunResult:
    """Responses of all samples and how the run went.

    Attributes:
        values: (n, r) responses, SI; NaN where a sample failed or did not run.
        status: (n,) int8 codes of :data:`STATUS` (0 ok, 1 failed, 2 not run).
        errors: n messages (``""`` where the sample succeeded).
        interrupted: the run was stopped (Ctrl-C) before every sample finished.
        backend: backend kind actually used (``"local"`` for runs kept in this process).
        workers: number of workers used.
        chunk_size: samples per task.
        wall_time: elapsed time, s.
        check_names: names of the model's per-sample checks (``()`` for a model without).
        checks: (n, c) the checks, dimensionless, in sample order; NaN where a sample failed
            or did not run; ``None`` for a model without checks.
    """

    values: FloatArray
    status: NDArray[np.int8]
    errors: tuple[str, ...]
    interrupted: bool
    backend: str
    workers: int
    chunk_size: int
    wall_time: float
    check_names: tuple[str, ...] = ()
    checks: FloatArray | None = None

    @property
    def n_ok(self) -> int:
        return int(np.sum(self.status == OK))

    @property
    def n_failed(self) -> int:
        return int(np.sum(self.status == FAILED))

    @property
    def n_not_run(self) -> int:
        return int(np.sum(self.status == NOT_RUN))

    def describe(self) -> dict[str, Any]:
        """JSON-ready execution record (varies between runs: kept apart from the results)."""
        return {
            "backend": self.backend,
            "workers": self.workers,
            "chunk_size": self.chunk_size,
            "wall_time_s": self.wall_time,
            "interrupted": self.interrupted,
        }


def _evaluate_block(model: ResponseModel, x: FloatArray) -> Evaluation:
    """The task of :func:`run`: one block of samples through the model."""
    return model.evaluate(x)


# --- response models over samples ----------------------------------------------------------------


def run(
    model: ResponseModel,
    x: FloatArray,
    *,
    backend: Backend | None = None,
    progress: bool = False,
    description: str = "samples",
    on_samples: Callable[[int], None] | None = None,
) -> RunResult:
    """Evaluate ``model`` on every row of ``x`` (n, k) with ``backend``.

    The rows are cut into blocks of ``backend.chunk_size`` (default ``model.chunk_size``)
    rows, one :func:`run_tasks` task per block with the model as the shared object. A block
    whose evaluation raises marks all its samples failed with that message.

    Args:
        model: a response model (see :class:`jointplay.tolerance.responses.ResponseModel`).
        x: input samples, SI, columns in ``model.input_names`` order.
        backend: where to run (default: local processes).
        progress: show a progress bar on stderr.
        description: label of the progress bar.
        on_samples: called with the number of samples of each block as it succeeds (a
            caller's own progress bar).

    Returns:
        The responses (and a :class:`~jointplay.tolerance.responses.CheckedModel`'s checks)
        in sample order, with status and error message per sample.
    """
    backend = backend or Backend()
    x = np.ascontiguousarray(np.asarray(x, dtype=float))
    if x.ndim != 2 or x.shape[1] != len(model.input_names):
        raise ConfigError(f"samples must have shape (n, {len(model.input_names)}), got {x.shape}")
    n = len(x)
    model, backend = _placed(model, backend, n)
    chunk = int(backend.chunk_size or model.chunk_size)
    starts = list(range(0, n, chunk))
    blocks = [x[start : start + chunk] for start in starts]
    tasks = run_tasks(
        _evaluate_block,
        blocks,
        backend,
        shared=model,
        sizes=[len(block) for block in blocks],
        progress=progress,
        description=description,
        on_done=None if on_samples is None else (lambda i, _: on_samples(len(blocks[i]))),
    )
    # the tasks are over: an interrupt while their results are put together is noted and
    # makes the run interrupted, and those results are kept
    with interrupts_noted() as noted:
        values = np.full((n, len(model.response_names)), np.nan)
        check_names = tuple(model.check_names) if isinstance(model, CheckedModel) else ()
        checks = np.full((n, len(check_names)), np.nan)
        status = np.full(n, NOT_RUN, dtype=np.int8)
        errors = ["not run (interrupted)"] * n
        for start, block, code, error, evaluation in zip(
            starts, blocks, tasks.status, tasks.errors, tasks.results, strict=True
        ):
            stop = start + len(block)
            if evaluation is not None:  # finished, or partly (an interrupted block)
                values[start:stop] = evaluation.values
                status[start:stop] = np.where(evaluation.ok, OK, FAILED)
                if evaluation.finished is not None:
                    status[start:stop][~evaluation.finished] = NOT_RUN
                errors[start:stop] = evaluation.errors
                if check_names and evaluation.checks is not None:
                    checks[start:stop] = evaluation.checks
            elif code == FAILED:
                status[start:stop] = FAILED
                errors[start:stop] = [error] * len(block)
        checks[status != OK] = np.nan
    lanes = _lanes_backend(model)  # a batch model spreads its blocks itself
    return RunResult(
        values=values,
        status=status,
        errors=tuple(errors),
        interrupted=tasks.interrupted or bool(noted),
        backend=tasks.backend if lanes is None else lanes.kind,
        workers=tasks.workers if lanes is None else executor(lanes).lane_workers(),
        chunk_size=chunk,
        wall_time=tasks.wall_time,
        check_names=check_names,
        checks=checks if check_names else None,
    )


def prepare(model: ResponseModel, backend: Backend | None, n: int) -> None:
    """Start what a run of ``n`` samples of ``model`` on ``backend`` will need, ahead of it:
    the batch engine's worker processes (their start-up then overlaps the caller's own
    preparations). Nothing for other models or backends."""
    model, _ = _placed(model, backend or Backend(), n)
    lanes = _lanes_backend(model)
    if lanes is not None:
        executor(lanes).prepare()


def start_batch_workers(backend: Backend, n: int, seconds_per_sample: float) -> None:
    """Start the batch engine's worker processes that a run of ``n`` samples costing
    ``seconds_per_sample`` each will use on ``backend`` (what :func:`prepare` starts), before
    the model exists: the command line calls it first, so that the workers' start-up overlaps
    its own imports and set-up. Nothing unless the run will use local processes."""
    executor(executor(backend).affordable(n, seconds_per_sample)).prepare()


def _lanes_backend(model: ResponseModel) -> Backend | None:
    """Where a batch-engine model spreads the lanes of its blocks (``None``: another model)."""
    lanes = getattr(model, "backend", None)
    return lanes if isinstance(lanes, Backend) else None


def _placed(model: ResponseModel, backend: Backend, n: int) -> tuple[ResponseModel, Backend]:
    """The model and backend a run of ``n`` samples really uses.

    A batch-engine model (one with a ``backend`` field,
    :class:`~jointplay.tolerance.responses.DynamicResponses`) runs its blocks from this process
    and spreads each block's lanes itself on ``backend``: on threads here (``"local"``), on
    this process's pool of workers, kept from block to block so that each worker starts and
    loads the compiled kernels once (``"processes"``), on the Dask cluster or on the GPU; its
    blocks are large (:meth:`~jointplay.execution.executors.Executor.block`).

    A model that states its cost (``seconds_per_sample``) gets only the workers that the
    work pays for (:meth:`~jointplay.execution.executors.Executor.affordable`), so more
    cores never make a cheap (e.g. vectorised kinematic) study slower.
    """
    lanes = _lanes_backend(model)
    if backend.on_device and lanes is None:
        raise ConfigError(
            f"the {backend.kind} backend runs the batch engine only: use dynamic responses"
        )
    placed = executor(backend).affordable(n, getattr(model, "seconds_per_sample", None))
    if lanes is None:
        return model, placed
    model = dataclasses.replace(
        model,  # type: ignore[type-var]
        backend=dataclasses.replace(placed, chunk_size=None),
    )
    block = executor(placed).block(model.chunk_size)
    return model, Backend("local", chunk_size=block)
