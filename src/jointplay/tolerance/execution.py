"""Independent tasks in-process, on local processes or on Dask: one backend for every study.

Two entry points:

* :func:`run_tasks` — the generic runner::

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

Backends (:class:`Backend`):

* ``"local"`` (``"serial"`` is the same) — in the calling process; a batch-engine model
  (:class:`~jointplay.tolerance.responses.DynamicResponses`) runs each block's samples on
  threads over the cores there;
* ``"processes"`` (default) — a :class:`concurrent.futures.ProcessPoolExecutor` with the
  ``spawn`` start method (safe with threads, the same on every OS); the shared object (e.g.
  the model) is sent to each worker once, at start-up, and each worker runs compiled code on
  one thread. A run with a single task stays in-process, and so does one whose model says its
  samples are too cheap to pay for starting workers (``seconds_per_sample``, see :func:`run`);
* ``"gpu"`` — in the calling process, a batch-engine model's blocks on JAX (the optional
  ``jointplay[gpu]`` extra), in blocks of up to 200 000 samples;
* ``"dask"`` — a Dask distributed cluster at ``scheduler`` (``distributed.Client(address)``),
  the way to scale beyond one machine; the shared object is scattered to the workers once.
  Workers need jointplay installed.

For the process and Dask backends the function must be a module-level function and the
shared object and items picklable by reference: a custom model class has to live in an
importable module (not in ``__main__`` of a notebook); use the local backend otherwise.

A rich progress bar (on stderr) shows the work done, rate and time left. Ctrl-C stops the run
gracefully: pending tasks are cancelled, finished ones are kept and the others are marked
``not run`` (status 2); :attr:`TaskRun.interrupted` and :attr:`RunResult.interrupted` say it
happened.
"""

from __future__ import annotations

import concurrent.futures as cf
import dataclasses
import math
import multiprocessing
import os
import re
import signal
import time
import types
from collections.abc import Callable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Any, Generic, Literal, TypeVar

import numpy as np
from numpy.typing import NDArray

from jointplay._kernels.workers import die_with_parent
from jointplay.errors import ConfigError, PartialInterrupt, caused_by_interrupt
from jointplay.tolerance.responses import CheckedModel, Evaluation, ResponseModel

__all__ = [
    "BACKENDS",
    "STATUS",
    "Backend",
    "RunResult",
    "TaskRun",
    "prepare",
    "run",
    "run_tasks",
    "start_batch_workers",
]

FloatArray = NDArray[np.float64]
T = TypeVar("T")
R = TypeVar("R")
BackendKind = Literal["local", "serial", "processes", "dask", "gpu"]

#: The execution backends (``"serial"`` is accepted as another name of ``"local"``).
BACKENDS: tuple[str, ...] = ("local", "processes", "dask", "gpu")
#: What starting one worker process costs here (import, loading compiled code), s: a run
#: starts only as many workers as its estimated work pays for.
WORKER_START_S = 3.0
#: Samples per block of a batch-engine model on the GPU backend.
GPU_BLOCK = 200_000

#: Sample status codes and their names (the ``status`` column of ``samples.parquet``).
STATUS: Mapping[int, str] = types.MappingProxyType({0: "ok", 1: "failed", 2: "not run"})
OK, FAILED, NOT_RUN = 0, 1, 2


#: A Dask scheduler address: optional protocol, host name or [IPv6] address, optional port
#: and path (``inproc://`` addresses carry one).
_SCHEDULER_ADDRESS = re.compile(
    r"(?:(?:tcp|tls|inproc|ucx|ws|wss)://)?(?:[A-Za-z0-9_.\-]+|\[[0-9A-Fa-f:.]+\])(?::\d{1,5})?(?:/[A-Za-z0-9_.\-/]*)?"
)


@dataclass(frozen=True)
class Backend:
    """Where the samples run.

    Attributes:
        kind: ``"local"`` (or ``"serial"``), ``"processes"``, ``"dask"`` or ``"gpu"``.
        workers: local worker processes (default: the number of CPUs); ignored by the others.
        scheduler: address of the Dask scheduler, e.g. ``"tcp://10.0.0.5:8786"`` (dask only).
        chunk_size: samples per task (default: the model's ``chunk_size``).
    """

    kind: BackendKind = "processes"
    workers: int | None = None
    scheduler: str | None = None
    chunk_size: int | None = None

    def __post_init__(self) -> None:
        if self.kind == "serial":
            object.__setattr__(self, "kind", "local")
        if self.kind not in BACKENDS:
            raise ConfigError(f"backend must be one of {', '.join(BACKENDS)}, got {self.kind!r}")
        if self.workers is not None and (
            isinstance(self.workers, bool) or not isinstance(self.workers, int) or self.workers < 1
        ):
            raise ConfigError(f"workers must be a positive integer, got {self.workers!r}")
        if self.chunk_size is not None and (
            isinstance(self.chunk_size, bool)
            or not isinstance(self.chunk_size, int)
            or self.chunk_size < 1
        ):
            raise ConfigError(f"chunk size must be a positive integer, got {self.chunk_size!r}")
        if self.kind == "dask" and not self.scheduler:
            raise ConfigError("the dask backend needs the scheduler's address")
        if self.kind == "dask" and (
            not isinstance(self.scheduler, str) or not _SCHEDULER_ADDRESS.fullmatch(self.scheduler)
        ):
            raise ConfigError(
                f"--dask-scheduler {self.scheduler!r} is not a scheduler address; write "
                "PROTOCOL://HOST:PORT, e.g. tcp://10.0.0.5:8786 (or HOST:PORT)"
            )
        if self.kind != "dask" and self.scheduler:
            raise ConfigError("a scheduler address applies to the dask backend only")

    @classmethod
    def dask(cls, scheduler: str, *, chunk_size: int | None = None) -> Backend:
        """The Dask backend at ``scheduler``."""
        return cls("dask", scheduler=scheduler, chunk_size=chunk_size)


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


# --- worker-side functions (module level: pickled by reference) --------------------------------

_WORKER_SHARED: Any = None


def _init_worker(shared: Any) -> None:
    """Process-pool initializer: keep the shared object; leave Ctrl-C to the parent and end
    with it; one compiled thread per worker (the workers are the parallelism)."""
    global _WORKER_SHARED
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    die_with_parent()
    _WORKER_SHARED = shared
    try:
        import numba

        numba.set_num_threads(1)
    except (ImportError, ValueError):  # pragma: no cover - numba is a dependency
        pass


def _attempt(function: Callable[[Any, Any], Any], shared: Any, item: Any) -> tuple[bool, Any]:
    """``(True, function(shared, item))``, or ``(False, "ErrorType: message")`` if it raised."""
    try:
        return True, function(shared, item)
    except Exception as exc:  # failure is data: the caller counts it, the run goes on
        if caused_by_interrupt(exc):  # Ctrl-C inside compiled code arrives as Numba's SystemError
            raise KeyboardInterrupt from exc
        return False, f"{type(exc).__name__}: {exc}"


def _attempt_in_worker(
    function: Callable[[Any, Any], Any], index: int, item: Any
) -> tuple[int, tuple[bool, Any]]:
    return index, _attempt(function, _WORKER_SHARED, item)


def _attempt_on_dask(
    function: Callable[[Any, Any], Any], shared: Any, index: int, item: Any
) -> tuple[int, tuple[bool, Any]]:
    return index, _attempt(function, shared, item)


def _evaluate_block(model: ResponseModel, x: FloatArray) -> Evaluation:
    """The task of :func:`run`: one block of samples through the model."""
    return model.evaluate(x)


# --- the generic runner --------------------------------------------------------------------------


@dataclass(frozen=True)
class TaskRun(Generic[R]):
    """Results of :func:`run_tasks`, in the order of the items.

    Attributes:
        results: the function's result per item; ``None`` where it failed or did not run;
            for an item that an interrupt stopped midway on the local backend, the partial
            result its function raised with (a :class:`~jointplay.errors.PartialInterrupt`),
            with status 2.
        status: (n,) int8 codes of :data:`STATUS` (0 ok, 1 failed, 2 not run).
        errors: n messages: ``""`` where the item succeeded, ``"ErrorType: message"`` where
            the function raised, ``"not run (interrupted)"`` where Ctrl-C came first.
        interrupted: the run was stopped (Ctrl-C) before every item finished.
        backend: backend kind actually used (``"local"`` for runs kept in this process).
        workers: number of workers used.
        wall_time: elapsed time, s.
    """

    results: tuple[R | None, ...]
    status: NDArray[np.int8]
    errors: tuple[str, ...]
    interrupted: bool
    backend: str
    workers: int
    wall_time: float


def run_tasks(
    function: Callable[[Any, T], R],
    items: Sequence[T],
    backend: Backend | None = None,
    *,
    shared: Any = None,
    sizes: Sequence[int] | None = None,
    progress: bool = False,
    description: str = "tasks",
    on_done: Callable[[int, R], None] | None = None,
) -> TaskRun[R]:
    """Call ``function(shared, item)`` for every item on ``backend``; failures are data.

    The tasks are independent: each gets ``shared`` (sent to every worker once: the process
    pool's initializer, Dask's broadcast ``scatter``) and its own item. A task that raises an
    :class:`Exception` is marked failed with its message and the run goes on. Ctrl-C stops
    the run: pending tasks are cancelled, finished ones kept, the others marked ``not run``.
    Where a task runs never changes what it computes, so a deterministic function gives the
    same results on every backend.

    Args:
        function: a module-level function (pickled by reference for the process and Dask
            backends) taking ``(shared, item)``.
        items: the tasks' arguments (picklable for the process and Dask backends). Submitted
            in this order: put the longest first to balance the workers.
        backend: where to run (default: local processes; one item, or one worker, runs in
            this process).
        shared: read-only data every task needs (e.g. a response model); ``None`` if none.
        sizes: work per item for the progress bar (e.g. samples per block; default 1 each).
        progress: show a progress bar on stderr.
        description: label of the progress bar.
        on_done: called in this process as ``on_done(index, result)`` for every item that
            succeeds, in the order they finish.

    Returns:
        A :class:`TaskRun` with the results, status and error of every item.
    """
    backend = backend or Backend()
    items = list(items)
    n = len(items)
    weights = [1] * n if sizes is None else [int(size) for size in sizes]
    if len(weights) != n:
        raise ConfigError(f"sizes: one per item, got {len(weights)} for {n} items")
    results: list[R | None] = [None] * n
    status = np.full(n, NOT_RUN, dtype=np.int8)
    errors = ["not run (interrupted)"] * n

    def store(index: int, outcome: tuple[bool, Any]) -> None:
        succeeded, value = outcome
        if succeeded:
            results[index], status[index], errors[index] = value, OK, ""
            if on_done is not None:
                on_done(index, value)
        else:
            status[index], errors[index] = FAILED, str(value)

    kind = "local" if backend.kind == "gpu" else backend.kind
    workers = 1
    if kind == "processes":
        workers = min(backend.workers or os.cpu_count() or 1, n)
        if workers <= 1:
            kind, workers = "local", 1
    wall = time.perf_counter()
    interrupted = False
    with _progress_bar(progress, sum(weights), description) as advance:
        try:
            if kind == "local":
                for index, item in enumerate(items):
                    try:
                        store(index, _attempt(function, shared, item))
                    except PartialInterrupt as stopped:  # keep what the item finished
                        results[index] = stopped.partial  # type: ignore[assignment]
                        raise
                    advance(weights[index])
            elif kind == "processes":
                _run_processes(function, items, shared, workers, store, weights, advance)
            else:
                workers = _run_dask(
                    function, items, shared, backend.scheduler or "", store, weights, advance
                )
        except KeyboardInterrupt:
            interrupted = bool(np.any(status == NOT_RUN))  # False: all had finished already
    return TaskRun(
        results=tuple(results),
        status=status,
        errors=tuple(errors),
        interrupted=interrupted,
        backend=kind,
        workers=workers,
        wall_time=time.perf_counter() - wall,
    )


def _run_processes(
    function: Callable[[Any, Any], Any],
    items: list[Any],
    shared: Any,
    workers: int,
    store: Callable[[int, tuple[bool, Any]], None],
    weights: list[int],
    advance: Callable[[int], None],
) -> None:
    executor = cf.ProcessPoolExecutor(
        max_workers=workers,
        mp_context=multiprocessing.get_context("spawn"),
        initializer=_init_worker,
        initargs=(shared,),
    )
    futures: list[cf.Future[tuple[int, tuple[bool, Any]]]] = []
    try:
        futures = [
            executor.submit(_attempt_in_worker, function, index, item)
            for index, item in enumerate(items)
        ]
        for future in cf.as_completed(futures):
            index, outcome = future.result()
            store(index, outcome)
            advance(weights[index])
    except BaseException:
        for future in futures:
            future.cancel()
        _stop_workers(executor)
        raise
    finally:
        executor.shutdown(wait=True, cancel_futures=True)


def _stop_workers(executor: cf.ProcessPoolExecutor) -> None:
    """Terminate the pool's workers so an interrupted run returns at once."""
    terminate = getattr(executor, "terminate_workers", None)  # Python >= 3.14
    if terminate is not None:
        terminate()
        return
    for process in list(getattr(executor, "_processes", {}).values()):
        process.terminate()


def _run_dask(
    function: Callable[[Any, Any], Any],
    items: list[Any],
    shared: Any,
    address: str,
    store: Callable[[int, tuple[bool, Any]], None],
    weights: list[int],
    advance: Callable[[int], None],
) -> int:
    try:
        from distributed import Client
    except ImportError:  # pragma: no cover - distributed is a dependency
        raise ConfigError("the dask backend needs the 'distributed' package") from None
    try:
        client = Client(address, timeout=30, set_as_default=False)
    except (OSError, TimeoutError, ValueError) as exc:
        raise ConfigError(f"cannot connect to the Dask scheduler at {address!r}: {exc}") from None
    from jointplay.dynamics.batch import (
        DASK_NO_WORKERS_S,
        ClusterLost,
        completed_on_dask,
        dask_result,
    )

    futures: list[Any] = []
    try:
        try:
            client.wait_for_workers(1, timeout=DASK_NO_WORKERS_S)
        except TimeoutError:
            raise ConfigError(
                f"the Dask cluster at {address!r} has no workers (none joined within "
                f"{DASK_NO_WORKERS_S:g} s); start some (dask worker {address})"
            ) from None
        workers = max(1, len(client.scheduler_info(n_workers=-1).get("workers", {})))
        # unique keys: content-hashed ones would be shared with an earlier study's data,
        # whose release could delete them under this study's tasks
        scattered = client.scatter(shared, broadcast=True, hash=False)
        futures = [
            client.submit(_attempt_on_dask, function, scattered, index, item, pure=False)
            for index, item in enumerate(items)
        ]
        where = {future.key: index for index, future in enumerate(futures)}
        try:
            for future in completed_on_dask(client, futures, address):
                if future.status == "error":  # KilledWorker: Dask gave up after its retries
                    error = future.exception()
                    index, outcome = where[future.key], (False, f"{type(error).__name__}: {error}")
                else:
                    index, outcome = dask_result(future, address)
                store(index, outcome)
                advance(weights[index])
        except ClusterLost as lost:  # the items that finished are kept; the others failed
            for future in futures:
                if not future.done():
                    store(where[future.key], (False, f"ClusterLost: {lost}"))
            client.cancel(futures)
        return workers
    except BaseException:
        if futures:
            client.cancel(futures)
        raise
    finally:
        client.close()


# --- response models over samples ----------------------------------------------------------------


def run(
    model: ResponseModel,
    x: FloatArray,
    *,
    backend: Backend | None = None,
    progress: bool = False,
    description: str = "samples",
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
    )
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
    engine = getattr(model, "engine", None)  # a batch model spreads its blocks itself
    return RunResult(
        values=values,
        status=status,
        errors=tuple(errors),
        interrupted=tasks.interrupted,
        backend=tasks.backend if engine is None else str(engine),
        workers=tasks.workers
        if engine != "processes"
        else int(getattr(model, "workers", None) or os.cpu_count() or 1),
        chunk_size=chunk,
        wall_time=tasks.wall_time,
        check_names=check_names,
        checks=checks if check_names else None,
    )


def prepare(model: ResponseModel, backend: Backend | None, n: int) -> None:
    """Start what a run of ``n`` samples of ``model`` on ``backend`` will need, ahead of it:
    the batch engine's worker processes (their start-up then overlaps the caller's own
    preparations). Nothing for other models or backends."""
    model, backend = _placed(model, backend or Backend(), n)
    if getattr(model, "engine", None) == "processes":
        from jointplay.dynamics.workers import start_workers

        start_workers(getattr(model, "workers", None))


def start_batch_workers(backend: Backend, n: int, seconds_per_sample: float) -> None:
    """Start the batch engine's worker processes that a run of ``n`` samples costing
    ``seconds_per_sample`` each will use on ``backend`` (what :func:`prepare` starts), before
    the model exists: the command line calls it first, so that the workers' start-up overlaps
    its own imports and set-up. Nothing unless the run will use local processes."""
    kind, workers = _affordable(backend.kind, backend.workers, n, seconds_per_sample)
    if kind == "processes":
        from jointplay.dynamics.workers import start_workers

        start_workers(workers)


def _affordable(
    kind: BackendKind, workers: int | None, n: int, cost: float | None
) -> tuple[BackendKind, int | None]:
    """``(kind, workers)`` of a run of ``n`` samples costing ``cost`` s each on one core
    (:func:`_placed`): with the default number of processes, only as many as pay for their
    start-up, and this process (``"local"``) below two."""
    if kind == "processes" and cost is not None and workers is None:
        requested = os.cpu_count() or 1
        affordable = int(n * float(cost) / WORKER_START_S)
        if min(requested, affordable) < 2:
            return "local", None
        if affordable < requested:
            return kind, affordable
    return kind, workers


def _placed(model: ResponseModel, backend: Backend, n: int) -> tuple[ResponseModel, Backend]:
    """The model and backend a run of ``n`` samples really uses.

    A batch-engine model (one with an ``engine`` field,
    :class:`~jointplay.tolerance.responses.DynamicResponses`) runs its blocks from this process
    and spreads each block's lanes itself: on threads here (``"local"``), on this process's
    pool of workers, kept from block to block so that each worker starts and loads the
    compiled kernels once (``"processes"``), on the Dask cluster or on the GPU; its blocks
    are large (:data:`GPU_BLOCK` on the GPU, 128 samples per worker process, or per thread of
    the Dask cluster).

    On the process backend with the default number of workers, a model that states its cost
    (``seconds_per_sample``) gets only as many workers as the work pays for — one per
    :data:`WORKER_START_S` of estimated serial time — and none (this process) below two, so
    more cores never make a cheap (e.g. vectorised kinematic) study slower. Workers asked
    for explicitly are started.
    """
    kind = backend.kind
    engine = getattr(model, "engine", None)
    if kind == "gpu" and engine is None:
        raise ConfigError(
            "the gpu backend runs the batch engine only: use it with --responses dynamic"
        )
    kind, workers = _affordable(
        kind, backend.workers, n, getattr(model, "seconds_per_sample", None)
    )
    if engine is None:
        return model, dataclasses.replace(backend, kind=kind, workers=workers)
    model = dataclasses.replace(
        model,  # type: ignore[type-var]
        engine=kind,
        workers=workers if kind == "processes" else None,
        scheduler=backend.scheduler if kind == "dask" else None,
    )
    if backend.chunk_size:
        block = backend.chunk_size
    elif kind == "gpu":
        block = GPU_BLOCK
    elif kind == "dask":  # sized by the cluster, not by this machine
        from jointplay.dynamics.batch import cluster_threads

        block = max(model.chunk_size, 128 * cluster_threads(backend.scheduler))
    elif kind == "processes":
        block = max(model.chunk_size, 128 * (workers or os.cpu_count() or 1))
    else:
        block = model.chunk_size
    return model, Backend("local", chunk_size=block)


@contextmanager
def _progress_bar(enabled: bool, total: int, description: str) -> Iterator[Callable[[int], None]]:
    if not enabled:
        yield lambda count: None
        return
    from rich.console import Console
    from rich.progress import (
        BarColumn,
        MofNCompleteColumn,
        Progress,
        ProgressColumn,
        Task,
        TextColumn,
        TimeElapsedColumn,
    )
    from rich.text import Text

    from jointplay.progress import eta_column

    class RateColumn(ProgressColumn):
        """Samples per second."""

        def render(self, task: Task) -> Text:
            speed = task.finished_speed or task.speed
            return Text("" if speed is None or not math.isfinite(speed) else f"{speed:,.1f}/s")

    bar = Progress(
        TextColumn("{task.description}"),
        BarColumn(),
        MofNCompleteColumn(),
        RateColumn(),
        TimeElapsedColumn(),
        TextColumn("left"),
        eta_column(),
        console=Console(stderr=True),
        transient=False,
    )
    with bar:
        task = bar.add_task(description, total=total)
        yield lambda count: bar.advance(task, count)
