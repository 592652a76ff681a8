"""Independent tasks on any backend, failures as data: :func:`run_tasks`.

::

    run_tasks(function, items, backend=None, *, shared=None, sizes=None, progress=False,
              description="tasks", on_done=None) -> TaskRun

calls ``function(shared, item)`` for every item and returns, in item order, each result or
the failure (``"ErrorType: message"``) with a status per item (:data:`STATUS`). Where a task
runs never changes what it computes.

For the process and Dask backends the function must be a module-level function and the
shared object and items picklable by reference: a custom class has to live in an importable
module (not in ``__main__`` of a notebook); use the local backend otherwise.

Ctrl-C stops the run gracefully: pending tasks are cancelled, finished ones are kept and the
others are marked ``not run`` (status 2); :attr:`TaskRun.interrupted` says it happened.
"""

from __future__ import annotations

import time
import types
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any, Generic, TypeVar

import numpy as np
from numpy.typing import NDArray

from jointplay.errors import ConfigError
from jointplay.execution import progress as _progress
from jointplay.execution.backends import Backend
from jointplay.execution.executors import executor

__all__ = ["FAILED", "NOT_RUN", "OK", "STATUS", "TaskRun", "run_tasks"]

T = TypeVar("T")
R = TypeVar("R")

#: Status codes and their names (the ``status`` column of ``samples.parquet``).
STATUS: Mapping[int, str] = types.MappingProxyType({0: "ok", 1: "failed", 2: "not run"})
OK, FAILED, NOT_RUN = 0, 1, 2


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


class _Sink(Generic[R]):
    """What the executor's tasks give, in item order (:class:`~.executors.TaskSink`)."""

    def __init__(
        self,
        n: int,
        weights: list[int],
        advance: Callable[[int], None],
        on_done: Callable[[int, R], None] | None,
    ) -> None:
        self.results: list[R | None] = [None] * n
        self.status = np.full(n, NOT_RUN, dtype=np.int8)
        self.errors = ["not run (interrupted)"] * n
        self._weights, self._advance, self._on_done = weights, advance, on_done

    def store(self, index: int, outcome: tuple[bool, Any]) -> None:
        succeeded, value = outcome
        if succeeded:
            self.results[index], self.status[index], self.errors[index] = value, OK, ""
            if self._on_done is not None:
                self._on_done(index, value)
        else:
            self.status[index], self.errors[index] = FAILED, str(value)

    def keep_partial(self, index: int, partial: Any) -> None:
        self.results[index] = partial

    def advance(self, index: int) -> None:
        self._advance(self._weights[index])


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
            this process; the gpu backend runs tasks in this process).
        shared: read-only data every task needs (e.g. a response model); ``None`` if none.
        sizes: work per item for the progress bar (e.g. samples per block; default 1 each).
        progress: show a progress bar on stderr.
        description: label of the progress bar.
        on_done: called in this process as ``on_done(index, result)`` for every item that
            succeeds, in the order they finish.

    Returns:
        A :class:`TaskRun` with the results, status and error of every item.
    """
    items = list(items)
    n = len(items)
    weights = [1] * n if sizes is None else [int(size) for size in sizes]
    if len(weights) != n:
        raise ConfigError(f"sizes: one per item, got {len(weights)} for {n} items")
    runner = executor(backend or Backend()).for_tasks(n)
    wall = time.perf_counter()
    interrupted = False
    with _progress.bar(progress, sum(weights), description) as advance:
        sink: _Sink[R] = _Sink(n, weights, advance, on_done)
        try:
            runner.run_tasks(function, shared, items, sink)
        except KeyboardInterrupt:
            interrupted = bool(np.any(sink.status == NOT_RUN))  # False: all had finished already
    return TaskRun(
        results=tuple(sink.results),
        status=sink.status,
        errors=tuple(sink.errors),
        interrupted=interrupted,
        backend=runner.kind,
        workers=runner.workers,
        wall_time=time.perf_counter() - wall,
    )
