"""Running a response model over many samples: in-process, on local processes, or on Dask.

The samples are cut into chunks of ``model.chunk_size`` rows (fixed by n and the chunk size
alone, never by the backend), every chunk is evaluated by ``model.evaluate`` somewhere, and
the blocks are put back in sample order. The same model and samples therefore give
bit-identical results on every backend (on the same kind of machine).

Backends (:class:`Backend`):

* ``"serial"`` — in the calling process;
* ``"processes"`` (default) — a :class:`concurrent.futures.ProcessPoolExecutor` with the
  ``spawn`` start method (safe with threads, the same on every OS); the model is sent to each
  worker once, at start-up. A run with a single chunk stays in-process;
* ``"dask"`` — a Dask distributed cluster at ``scheduler`` (``distributed.Client(address)``),
  the way to scale beyond one machine; the model is scattered to the workers once. Workers
  need jointplay installed.

For the process and Dask backends a model must be picklable by reference: a custom model
class has to live in an importable module (not in ``__main__`` of a notebook); use the
serial backend otherwise.

A rich progress bar (on stderr) shows samples done, rate and time left. Ctrl-C stops the run
gracefully: pending chunks are cancelled, finished samples are kept and the others are
marked ``not run`` (status 2); :attr:`RunResult.interrupted` says it happened.
"""

from __future__ import annotations

import concurrent.futures as cf
import math
import multiprocessing
import os
import signal
import time
import types
from collections.abc import Callable, Iterator, Mapping
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from jointplay.errors import ConfigError
from jointplay.tolerance.responses import Evaluation

__all__ = ["BACKENDS", "STATUS", "Backend", "RunResult", "run"]

FloatArray = NDArray[np.float64]
BackendKind = Literal["serial", "processes", "dask"]

#: The execution backends.
BACKENDS: tuple[str, ...] = ("serial", "processes", "dask")

#: Sample status codes and their names (the ``status`` column of ``samples.parquet``).
STATUS: Mapping[int, str] = types.MappingProxyType({0: "ok", 1: "failed", 2: "not run"})
OK, FAILED, NOT_RUN = 0, 1, 2


@dataclass(frozen=True)
class Backend:
    """Where the samples run.

    Attributes:
        kind: ``"serial"``, ``"processes"`` or ``"dask"``.
        workers: local worker processes (default: the number of CPUs); ignored by the others.
        scheduler: address of the Dask scheduler, e.g. ``"tcp://10.0.0.5:8786"`` (dask only).
        chunk_size: samples per task (default: the model's ``chunk_size``).
    """

    kind: BackendKind = "processes"
    workers: int | None = None
    scheduler: str | None = None
    chunk_size: int | None = None

    def __post_init__(self) -> None:
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
        backend: backend kind actually used (``"serial"`` for single-chunk local runs).
        workers: number of workers used.
        chunk_size: samples per task.
        wall_time: elapsed time, s.
    """

    values: FloatArray
    status: NDArray[np.int8]
    errors: tuple[str, ...]
    interrupted: bool
    backend: str
    workers: int
    chunk_size: int
    wall_time: float

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

_WORKER_MODEL: Any = None


def _init_worker(model: Any) -> None:
    """Process-pool initializer: keep the model; leave Ctrl-C to the parent."""
    global _WORKER_MODEL
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    _WORKER_MODEL = model


def _evaluate_in_worker(start: int, x: FloatArray) -> tuple[int, Evaluation]:
    return start, _WORKER_MODEL.evaluate(x)


def _evaluate_on_dask(model: Any, start: int, x: FloatArray) -> tuple[int, Evaluation]:
    return start, model.evaluate(x)


# --- the driver ----------------------------------------------------------------------------------


def run(
    model: Any,
    x: FloatArray,
    *,
    backend: Backend | None = None,
    progress: bool = False,
    description: str = "samples",
) -> RunResult:
    """Evaluate ``model`` on every row of ``x`` (n, k) with ``backend``.

    Args:
        model: a response model (see :class:`jointplay.tolerance.responses.ResponseModel`).
        x: input samples, SI, columns in ``model.input_names`` order.
        backend: where to run (default: local processes).
        progress: show a progress bar on stderr.
        description: label of the progress bar.

    Returns:
        The responses in sample order, with status and error message per sample.
    """
    backend = backend or Backend()
    x = np.ascontiguousarray(np.asarray(x, dtype=float))
    n_responses = len(model.response_names)
    if x.ndim != 2 or x.shape[1] != len(model.input_names):
        raise ConfigError(f"samples must have shape (n, {len(model.input_names)}), got {x.shape}")
    n = len(x)
    chunk = int(backend.chunk_size or model.chunk_size)
    starts = list(range(0, n, chunk))
    values = np.full((n, n_responses), np.nan)
    status = np.full(n, NOT_RUN, dtype=np.int8)
    errors = ["not run (interrupted)"] * n

    def store(start: int, block: Evaluation) -> None:
        stop = start + len(block.ok)
        values[start:stop] = block.values
        status[start:stop] = np.where(block.ok, OK, FAILED)
        errors[start:stop] = block.errors

    kind = backend.kind
    workers = 1
    if kind == "processes":
        workers = min(backend.workers or os.cpu_count() or 1, len(starts))
        if workers <= 1:
            kind, workers = "serial", 1
    wall = time.perf_counter()
    interrupted = False
    with _progress_bar(progress, n, description) as advance:
        try:
            if kind == "serial":
                for start in starts:
                    store(start, model.evaluate(x[start : start + chunk]))
                    advance(min(chunk, n - start))
            elif kind == "processes":
                _run_processes(model, x, starts, chunk, workers, store, advance)
            else:
                workers = _run_dask(
                    model, x, starts, chunk, backend.scheduler or "", store, advance
                )
        except KeyboardInterrupt:
            interrupted = True
    if interrupted and not np.any(status == NOT_RUN):
        interrupted = False  # everything had finished when the interrupt came
    return RunResult(
        values=values,
        status=status,
        errors=tuple(errors),
        interrupted=interrupted,
        backend=kind,
        workers=workers,
        chunk_size=chunk,
        wall_time=time.perf_counter() - wall,
    )


def _run_processes(
    model: Any,
    x: FloatArray,
    starts: list[int],
    chunk: int,
    workers: int,
    store: Callable[[int, Evaluation], None],
    advance: Callable[[int], None],
) -> None:
    executor = cf.ProcessPoolExecutor(
        max_workers=workers,
        mp_context=multiprocessing.get_context("spawn"),
        initializer=_init_worker,
        initargs=(model,),
    )
    futures: list[cf.Future[tuple[int, Evaluation]]] = []
    try:
        futures = [
            executor.submit(_evaluate_in_worker, start, x[start : start + chunk])
            for start in starts
        ]
        for future in cf.as_completed(futures):
            start, block = future.result()
            store(start, block)
            advance(len(block.ok))
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
    model: Any,
    x: FloatArray,
    starts: list[int],
    chunk: int,
    address: str,
    store: Callable[[int, Evaluation], None],
    advance: Callable[[int], None],
) -> int:
    try:
        from distributed import Client, as_completed
    except ImportError:  # pragma: no cover - distributed is a dependency
        raise ConfigError("the dask backend needs the 'distributed' package") from None
    try:
        client = Client(address, timeout=30, set_as_default=False)
    except (OSError, TimeoutError, ValueError) as exc:
        raise ConfigError(f"cannot connect to the Dask scheduler at {address!r}: {exc}") from None
    futures: list[Any] = []
    try:
        workers = max(1, len(client.scheduler_info(n_workers=-1).get("workers", {})))
        shared = client.scatter(model, broadcast=True)
        futures = [
            client.submit(_evaluate_on_dask, shared, start, x[start : start + chunk], pure=False)
            for start in starts
        ]
        for future in as_completed(futures, loop=client.loop):
            start, block = future.result()
            store(start, block)
            advance(len(block.ok))
        return workers
    except BaseException:
        if futures:
            client.cancel(futures)
        raise
    finally:
        client.close()


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
        TimeRemainingColumn,
    )
    from rich.text import Text

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
        TimeRemainingColumn(),
        console=Console(stderr=True),
        transient=False,
    )
    with bar:
        task = bar.add_task(description, total=total)
        yield lambda count: bar.advance(task, count)
