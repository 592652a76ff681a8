"""The executors: what each backend does with a run's tasks, one class per backend.

An executor owns the pools, clients and interrupts of its backend; the engines own the
numerics. Two kinds of work come to it:

* independent **tasks** (:meth:`Executor.run_tasks`, behind
  :func:`jointplay.execution.tasks.run_tasks`): ``function(shared, item)`` per item, a
  failure is data (``"ErrorType: message"``);
* an engine's **chunks of lanes** (:meth:`Executor.run_lanes`, the batch engine's samples):
  :class:`LaneWork` says how a chunk runs in a worker, in this process and on a device.

:func:`executor` is the only place that turns a :class:`~jointplay.execution.backends.Backend`
into behaviour: a new backend is a name in :mod:`jointplay.execution.backends` and a class
here. NumPy, Numba, Dask and JAX are imported only when they are used.
"""

from __future__ import annotations

import concurrent.futures as cf
import dataclasses
import math
import multiprocessing
import os
import signal
from collections.abc import Callable, Iterable
from contextlib import AbstractContextManager, nullcontext
from dataclasses import dataclass
from typing import Any, ClassVar, Protocol

from jointplay._kernels.workers import die_with_parent
from jointplay.errors import ConfigError, PartialInterrupt, caused_by_interrupt
from jointplay.execution import dask as _dask
from jointplay.execution import pool as _pool
from jointplay.execution.backends import Backend, BackendKind
from jointplay.execution.interrupts import interrupts_gated, interrupts_noted, interrupts_watched

__all__ = [
    "CHUNK_BUDGET_S",
    "DEFAULT_CHUNK",
    "GPU_CHUNK",
    "GPU_CHUNKS",
    "LOCAL_CHUNK",
    "WORKER_START_S",
    "Executor",
    "LaneWork",
    "Lanes",
    "TaskSink",
    "executor",
    "gpu_chunk",
]

#: Lanes per chunk on the process and Dask backends when none is given: large enough that a
#: chunk's fixed costs (a task's pickling and dispatch, ~1 ms) are small, small enough to
#: balance the workers and that an interrupt, which drops the chunks in flight, costs at most
#: ~1.5 s of work per worker (32 lanes of an implicit RM-set sample at ~45 ms each; an
#: explicit sample takes ~15 ms).
DEFAULT_CHUNK = 32
#: Lanes per chunk in this process (the compiled loop spreads a chunk over the threads).
LOCAL_CHUNK = 4096
#: The largest chunk on the GPU backend (JAX batches; throughput falls above ~200 000 lanes);
#: also the samples per block of a study there.
GPU_CHUNK = 200_000
#: The chunk sizes the GPU backend chooses among (:func:`gpu_chunk`): powers of 4 from 1024
#: up to :data:`GPU_CHUNK`. Each size is one compiled program (a JAX compilation the first
#: time: 7-27 s cold on an H100, 0.5-2 s from the persistent cache), so the set is small.
GPU_CHUNKS = tuple(1024 * 4**k for k in range(8) if 1024 * 4**k <= GPU_CHUNK)
#: Seconds of work that one chunk on the GPU backend may take: one XLA call cannot be
#: interrupted, so an interrupt loses at most about this much.
CHUNK_BUDGET_S = 2.0
#: What starting one worker process costs here (import, loading compiled code), s: a run
#: starts only as many workers as its estimated work pays for.
WORKER_START_S = 3.0


@dataclass(frozen=True)
class LaneWork:
    """An engine's chunks of independent lanes, as an executor runs them.

    Attributes:
        task: ``task(shared, chunk)``, a module-level function (pickled by reference) that a
            worker process or a Dask worker runs on one thread.
        shared: what every chunk needs (sent with each task: small).
        here: ``here(chunk, parallel, interrupt)`` in this process: ``parallel`` spreads the
            chunk over the threads; ``interrupt`` is the flag array of
            :func:`~jointplay.execution.interrupts.interrupts_watched` (or ``None``).
        stopped: whether an output of ``here`` was cut short by an interrupt.
        device: ``device(chunk, chunk_size, timings)`` on the accelerator (JAX), or ``None``
            where the engine has no device kernel: one uninterruptible call that runs the
            chunk's lanes in compiled chunks of ``chunk_size`` and puts the seconds spent
            running them (compilation left out) in ``timings["run_s"]`` and the lanes that
            ran then, padding included, in ``timings["lanes"]``. On the device a
            chunk and its output are tuples of arrays with the lanes along the first axis.
    """

    task: Callable[[Any, Any], Any]
    shared: Any
    here: Callable[[Any, bool, Any], Any]
    stopped: Callable[[Any], bool]
    device: Callable[[Any, int, dict[str, float]], Any] | None = None
    #: ``device``'s interface on the numba-cuda kernel (the ``"cuda"`` backend), or ``None``;
    #: it takes an ``interrupt`` keyword too (the flag array of
    #: :func:`~jointplay.execution.interrupts.interrupts_watched`, or ``None``), so that an
    #: interrupt stops the chunk in flight (:class:`Cuda`).
    cuda: Callable[..., Any] | None = None


@dataclass(frozen=True)
class Lanes:
    """One run of an engine's lanes on an executor (:meth:`Executor.run_lanes`).

    Attributes:
        work: how a chunk runs (:class:`LaneWork`).
        chunks: the chunks, in order (consumed once).
        slots: chunks at once (:meth:`Executor.lane_slots`).
        chunk: lanes per chunk (:meth:`Executor.lane_chunk`).
        done: ``done(k, output)``, called in this process as chunk ``k`` finishes.
    """

    work: LaneWork
    chunks: Iterable[Any]
    slots: int
    chunk: int
    done: Callable[[int, Any], None]


class TaskSink(Protocol):
    """Where an executor puts what its tasks give (:func:`~jointplay.execution.tasks.run_tasks`)."""

    def store(self, index: int, outcome: tuple[bool, Any]) -> None:
        """``(True, result)`` or ``(False, "ErrorType: message")`` of item ``index``."""

    def keep_partial(self, index: int, partial: Any) -> None:
        """What item ``index`` finished before an interrupt stopped it."""

    def advance(self, index: int) -> None:
        """Item ``index`` is done (the progress bar)."""


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


def attempt(function: Callable[[Any, Any], Any], shared: Any, item: Any) -> tuple[bool, Any]:
    """``(True, function(shared, item))``, or ``(False, "ErrorType: message")`` if it raised."""
    try:
        return True, function(shared, item)
    except Exception as exc:  # failure is data: the caller counts it, the run goes on
        if caused_by_interrupt(exc):  # Ctrl-C inside compiled code arrives as Numba's SystemError
            raise KeyboardInterrupt from exc
        return False, f"{type(exc).__name__}: {exc}"


def _attempt_in_worker(function: Callable[[Any, Any], Any], item: Any) -> tuple[bool, Any]:
    return attempt(function, _WORKER_SHARED, item)


def _attempt_on_dask(
    function: Callable[[Any, Any], Any], shared: Any, index: int, item: Any
) -> tuple[int, tuple[bool, Any]]:
    return index, attempt(function, shared, item)


def _stop_workers(pool_executor: cf.ProcessPoolExecutor) -> None:
    """Terminate the pool's workers so an interrupted run returns at once.

    The queued futures are left to the pool (its ``shutdown(cancel_futures=True)`` cancels
    them in its manager thread): one cancelled from this thread before the workers end stays
    in the pool's pending items, and CPython 3.11's manager thread, marking them broken
    (``terminate_broken``), raised ``InvalidStateError`` on it and died before ending the other
    workers, so the command hung at exit waiting for them."""
    terminate = getattr(pool_executor, "terminate_workers", None)  # Python >= 3.14
    if terminate is not None:
        terminate()
        return
    for process in list(getattr(pool_executor, "_processes", {}).values()):
        process.terminate()


def _store_outcome(sink: TaskSink, index: int, outcome: tuple[bool, Any]) -> None:
    """Item ``index``'s outcome into ``sink``, and the item counted done."""
    sink.store(index, outcome)
    sink.advance(index)


def _kept(keep: Callable[..., None], *args: Any) -> None:
    """``keep(*args)`` with SIGINT and SIGTERM noted meanwhile, and raised once it returns: a
    finished result is kept whole or not at all."""
    with interrupts_noted() as noted:
        keep(*args)
    if noted:
        raise KeyboardInterrupt(f"signal {noted[0]}")


def _keep_as_completed(
    futures: dict[cf.Future[Any], int], keep: Callable[[cf.Future[Any], int], None]
) -> None:
    """``keep(future, k)`` for every future as it completes, none lost to an interrupt.

    SIGINT and SIGTERM arriving while a result is kept are noted and raised once it is kept;
    one arriving while waiting raises at once, after keeping what the workers had finished
    by then (a chunk done but not yet received would otherwise be lost with the pool)."""
    pending = dict(futures)
    try:
        for future in cf.as_completed(futures):
            _kept(keep, future, pending.pop(future))
    except KeyboardInterrupt:
        with interrupts_noted():
            for future in [f for f in pending if f.done() and not f.cancelled()]:
                if future.exception() is None:
                    keep(future, pending.pop(future))
        raise


# --- the executors ---------------------------------------------------------------------------------


class Executor:
    """Runs tasks and chunks of lanes on one backend (a subclass per backend)."""

    kind: ClassVar[BackendKind]
    #: Whether the engine's device kernel runs the lanes (the engine checks it is there).
    on_device: ClassVar[bool] = False

    def __init__(self, backend: Backend) -> None:
        self.backend = backend
        #: Workers that :meth:`run_tasks` used (set as it starts them).
        self.workers = 1

    # lanes
    def lane_slots(self) -> int:
        """How many chunks of lanes run at once."""
        return 1

    def lane_chunk(self, n: int, slots: int) -> int:
        """Lanes per chunk for ``n`` lanes over ``slots`` (``chunk_size`` when given): ~4
        chunks per slot, at most :data:`DEFAULT_CHUNK`."""
        return self.backend.chunk_size or max(1, min(DEFAULT_CHUNK, math.ceil(n / (4 * slots))))

    def lane_parts(self, n: int, chunk: int) -> int:
        """Lanes per part handed to :meth:`run_lanes` (the chunk, unless the kernel cuts its own)."""
        return chunk

    def run_lanes(self, lanes: Lanes) -> None:
        """Run every chunk of ``lanes`` and call ``lanes.done(k, output)`` as chunk ``k``
        finishes.

        An interrupt (KeyboardInterrupt) goes through, the chunks done kept by ``done``.

        Raises:
            ClusterLost: the Dask cluster could not finish.
        """
        raise NotImplementedError

    def lane_workers(self) -> int:
        """Worker processes a batch of lanes keeps busy from this process (1: none)."""
        return 1

    def prepare(self) -> None:
        """Start ahead what :meth:`run_lanes` will need (nothing on most backends)."""

    # tasks
    def affordable(self, n: int, cost: float | None) -> Backend:
        """The backend a run of ``n`` tasks costing ``cost`` s each on one core is worth:
        this one, except where starting workers would cost more than they save."""
        return self.backend

    def block(self, default: int) -> int:
        """Samples per block of a study whose blocks spread their lanes here: ``default``,
        or 128 per slot where the slots are workers or a cluster's threads."""
        return self.backend.chunk_size or max(default, 128 * self.lane_slots())

    def for_tasks(self, n: int) -> Executor:
        """The executor that a run of ``n`` independent tasks really uses."""
        return self

    def run_tasks(
        self, function: Callable[[Any, Any], Any], shared: Any, items: list[Any], sink: TaskSink
    ) -> None:
        """Run ``function(shared, item)`` for every item into ``sink`` (:attr:`workers`: how
        many ran them)."""
        raise NotImplementedError


class Local(Executor):
    """In this process: tasks one after the other, lanes on the compiled loop's threads."""

    kind = "local"

    def lane_slots(self) -> int:
        import numba

        return int(numba.get_num_threads())

    def lane_chunk(self, n: int, slots: int) -> int:
        return self.backend.chunk_size or LOCAL_CHUNK

    def block(self, default: int) -> int:
        return self.backend.chunk_size or default

    def run_lanes(self, lanes: Lanes) -> None:
        work = lanes.work
        with interrupts_watched() as flags:
            for k, item in enumerate(lanes.chunks):
                output = work.here(item, lanes.slots > 1, flags)
                lanes.done(k, output)
                if work.stopped(output):
                    break

    def run_tasks(
        self, function: Callable[[Any, Any], Any], shared: Any, items: list[Any], sink: TaskSink
    ) -> None:
        for index, item in enumerate(items):
            # an interrupt after the item's lanes (a batch model's block) waits until the
            # item is kept (interrupts_gated)
            with interrupts_gated() as gate:
                try:
                    outcome = attempt(function, shared, item)
                except PartialInterrupt as stopped:  # keep what the item finished
                    sink.keep_partial(index, stopped.partial)
                    raise
                sink.store(index, outcome)
            if gate.noted:
                raise KeyboardInterrupt(f"signal {gate.noted[0]}")
            sink.advance(index)


class Processes(Executor):
    """Local worker processes (``spawn``; one compiled thread each)."""

    kind = "processes"

    def lane_slots(self) -> int:
        return self.backend.workers or os.cpu_count() or 1

    def lane_workers(self) -> int:
        return self.lane_slots()

    def prepare(self) -> None:
        _pool.start_workers(self.backend.workers)

    def affordable(self, n: int, cost: float | None) -> Backend:
        """With the default number of workers, only as many as pay for their start-up
        (:data:`WORKER_START_S` of estimated serial work each), and none (this process,
        ``"local"``) below two; workers asked for explicitly are started."""
        if cost is None or self.backend.workers is not None:
            return self.backend
        requested = os.cpu_count() or 1
        affordable = int(n * float(cost) / WORKER_START_S)
        if min(requested, affordable) < 2:
            return dataclasses.replace(self.backend, kind="local", workers=None)
        if affordable < requested:
            return dataclasses.replace(self.backend, workers=affordable)
        return self.backend

    def run_lanes(self, lanes: Lanes) -> None:
        if lanes.slots == 1:  # one worker: this process, on one thread
            Local(Backend("local")).run_lanes(lanes)
            return
        workers = _pool.pool(lanes.slots)  # kept from batch to batch: started and loaded once
        work = lanes.work
        try:
            futures: dict[cf.Future[Any], int] = {
                workers.submit(work.task, work.shared, c): k for k, c in enumerate(lanes.chunks)
            }
            _keep_as_completed(futures, lambda future, k: lanes.done(k, future.result()))
        except BaseException:
            # no future cancelled from here: _stop_workers' note
            _pool.close_pool(terminate=True)
            raise

    def for_tasks(self, n: int) -> Executor:
        workers = min(self.backend.workers or os.cpu_count() or 1, n)
        if workers <= 1:
            return Local(Backend("local"))
        return Processes(Backend("processes", workers=workers))

    def run_tasks(
        self, function: Callable[[Any, Any], Any], shared: Any, items: list[Any], sink: TaskSink
    ) -> None:
        self.workers = self.lane_slots()
        started = cf.ProcessPoolExecutor(  # the shared object goes to each worker once
            max_workers=self.workers,
            mp_context=multiprocessing.get_context("spawn"),
            initializer=_init_worker,
            initargs=(shared,),
        )
        try:
            futures = {
                started.submit(_attempt_in_worker, function, item): index
                for index, item in enumerate(items)
            }
            _keep_as_completed(
                futures, lambda future, index: _store_outcome(sink, index, future.result())
            )
        except BaseException:
            _stop_workers(started)
            raise
        finally:
            started.shutdown(wait=True, cancel_futures=True)


class Dask(Executor):
    """A Dask distributed cluster at ``backend.scheduler``."""

    kind = "dask"

    @property
    def address(self) -> str:
        return self.backend.scheduler or ""

    def lane_slots(self) -> int:  # sized by the cluster, not by this machine
        return _dask.cluster_threads(self.address)

    def run_lanes(self, lanes: Lanes) -> None:
        client = _dask.client(self.address)
        work = lanes.work
        futures: dict[Any, int] = {}
        try:
            # ``shared`` is small: it travels with each task. Scattering it gave every
            # block the same content-hashed keys, and the previous block's release could
            # delete them under the next block's tasks, which then waited for ever
            # ("computation on lost data").
            futures = {
                client.submit(work.task, work.shared, c, pure=False): k
                for k, c in enumerate(lanes.chunks)
            }
            for future in _dask.completed(client, list(futures), self.address):
                if future.status == "error":
                    raise _dask.ClusterLost(
                        f"the Dask cluster at {self.address} could not run a chunk of samples "
                        f"({type(future.exception()).__name__}: {future.exception()}); its "
                        "workers died running it"
                    )
                output = _dask.result(future, self.address, client)  # may wait: interruptible
                _kept(lanes.done, futures[future], output)
        except BaseException:
            if futures:
                client.cancel(list(futures))
            raise

    def run_tasks(
        self, function: Callable[[Any, Any], Any], shared: Any, items: list[Any], sink: TaskSink
    ) -> None:
        client = _dask.connect(self.address)
        futures: list[Any] = []
        try:
            workers = _dask.workers(client)
            # unique keys: content-hashed ones would be shared with an earlier study's data,
            # whose release could delete them under this study's tasks
            scattered = client.scatter(shared, broadcast=True, hash=False)
            futures = [
                client.submit(_attempt_on_dask, function, scattered, index, item, pure=False)
                for index, item in enumerate(items)
            ]
            where = {future.key: index for index, future in enumerate(futures)}
            try:
                for future in _dask.completed(client, futures, self.address):
                    if future.status == "error":  # KilledWorker: Dask gave up after its retries
                        error = future.exception()
                        index = where[future.key]
                        outcome: tuple[bool, Any] = (False, f"{type(error).__name__}: {error}")
                    else:
                        index, outcome = _dask.result(future, self.address, client)
                    _kept(_store_outcome, sink, index, outcome)
            except _dask.ClusterLost as lost:  # the items that finished are kept; the others failed
                for future in futures:
                    if not future.done():
                        sink.store(where[future.key], (False, f"ClusterLost: {lost}"))
                client.cancel(futures)
            self.workers = workers
        except BaseException:
            if futures:
                client.cancel(futures)
            raise
        finally:
            client.close()


def gpu_chunk(
    rate: float | None, budget: float = CHUNK_BUDGET_S, sizes: tuple[int, ...] = GPU_CHUNKS
) -> int:
    """Lanes in the next chunk on the GPU backend: the largest of ``sizes`` (ascending) that
    the measured ``rate`` (lanes/s of the chunk before; ``None`` before the first) runs in
    ``budget`` seconds, and the smallest when none does or nothing is measured yet.

    The rate of a small chunk understates a device's (a GPU runs a larger batch at more
    lanes/s), so the chunk chosen errs short of the budget, and grows chunk by chunk."""
    if rate is None or not rate > 0 or not math.isfinite(rate):
        return sizes[0]
    fitting = [size for size in sizes if size / rate <= budget]
    return max(fitting) if fitting else sizes[0]


def _lanes_of(item: Any) -> int:
    return len(item[0])


def _joined(items: list[Any]) -> Any:
    """Chunks (tuples of arrays, lanes first) as one."""
    import numpy as np

    if len(items) == 1:
        return items[0]
    return tuple(np.concatenate(columns) for columns in zip(*items, strict=True))


def _padded(item: Any, size: int) -> Any:
    """A chunk filled up to ``size`` lanes with copies of its first lane."""
    import numpy as np

    missing = size - _lanes_of(item)
    if missing <= 0:
        return item
    return tuple(np.concatenate([a, np.repeat(a[:1], missing, axis=0)]) for a in item)


def _cut(output: Any, start: int, stop: int) -> Any:
    """Lanes ``start:stop`` of a device output (a named tuple of arrays, lanes first)."""
    return type(output)(*(a[start:stop] for a in output))


class Gpu(Executor):
    """The engine's device kernel (JAX) from this process; other tasks run here.

    One call on the device cannot be interrupted, so the lanes go in chunks that take at
    most :data:`CHUNK_BUDGET_S` each (:func:`gpu_chunk`, from the rate the chunk before ran
    at; the first is the smallest of :data:`GPU_CHUNKS`): an interrupt keeps the chunks that
    finished and loses at most the one in flight. A ``chunk_size`` given is used as it is.
    Every chunk but a lone first one is padded to its size, so the compiled programs are
    those of the sizes only."""

    kind: ClassVar[BackendKind] = "gpu"
    on_device = True
    #: Whether chunks are padded to their size (one compiled program per size: JAX's).
    pads: ClassVar[bool] = True

    def sizes(self) -> tuple[int, ...]:
        """The chunk sizes this run chooses among."""
        return (self.backend.chunk_size,) if self.backend.chunk_size else GPU_CHUNKS

    def lane_chunk(self, n: int, slots: int) -> int:
        return self.sizes()[0]

    def block(self, default: int) -> int:
        return self.backend.chunk_size or GPU_CHUNK

    def run_lanes(self, lanes: Lanes) -> None:
        """Run the parts (``lanes.chunk`` lanes each, the smallest size) grouped into chunks
        of the sizes that :func:`gpu_chunk` chooses; ``done`` is called part by part."""
        import itertools
        import time

        device = self.device_of(lanes.work)
        if device is None:
            raise ConfigError(f"the {self.kind} backend runs the batch engine only")
        sizes = self.sizes()
        parts = iter(lanes.chunks)
        rate: float | None = None
        k = 0
        with self.watched(device) as flags:
            while True:
                size = gpu_chunk(rate, CHUNK_BUDGET_S, sizes)
                group = list(itertools.islice(parts, max(1, size // lanes.chunk)))
                if not group:
                    return
                item = _joined(group)
                timings: dict[str, float] = {}
                clock = time.perf_counter()
                chunk = item if k == 0 or not self.pads else _padded(item, size)
                if flags is None:
                    output = device(chunk, size, timings)
                else:
                    output = device(chunk, size, timings, interrupt=flags)
                wall = time.perf_counter() - clock
                run_s = timings.get("run_s") or wall
                ran = timings.get("lanes") or size  # a padded chunk costs its whole size
                rate = ran / run_s if run_s > 0 else None
                start = 0
                for part in group:
                    stop = start + _lanes_of(part)
                    lanes.done(k, _cut(output, start, stop))
                    start, k = stop, k + 1
                if flags is not None and lanes.work.stopped(output):
                    return  # interrupted: the context raises KeyboardInterrupt

    def watched(self, device: Callable[..., Any]) -> AbstractContextManager[Any]:
        """The interrupt flags ``device`` is given (``None``: none; the JAX kernel's calls
        cannot be interrupted, the chunks bound what an interrupt loses)."""
        return nullcontext(None)

    def for_tasks(self, n: int) -> Executor:
        return Local(Backend("local"))

    def device_of(self, work: LaneWork) -> Callable[..., Any] | None:
        """The engine's device kernel this executor runs (:attr:`LaneWork.device`: JAX)."""
        return work.device


class Cuda(Gpu):
    """:class:`Gpu` on the engine's numba-cuda kernel (:attr:`LaneWork.cuda`), one GPU thread
    per lane: the same chunks, not padded (one compiled kernel serves every size;
    experimental, issue 26). The kernel takes the interrupt flags (:meth:`watched`): an
    interrupt stops the launch in flight too, not only the chunks after it."""

    kind: ClassVar[BackendKind] = "cuda"
    pads = False

    def device_of(self, work: LaneWork) -> Callable[..., Any] | None:
        return work.cuda

    def watched(self, device: Callable[..., Any]) -> AbstractContextManager[Any]:
        """:func:`~jointplay.execution.interrupts.interrupts_watched`'s flags, which the
        kernel (:attr:`LaneWork.cuda`) takes as ``interrupt``: its threads read them during the
        launch, an interrupt stops the chunk in flight (its finished lanes kept) and the chunks
        after it are not started."""
        return interrupts_watched()


_EXECUTORS: dict[str, type[Executor]] = {
    cls.kind: cls for cls in (Local, Processes, Dask, Gpu, Cuda)
}


def executor(backend: Backend | str) -> Executor:
    """The executor of ``backend`` (a name is a :class:`Backend` of that kind)."""
    if isinstance(backend, str):
        backend = Backend(backend)  # type: ignore[arg-type]
    return _EXECUTORS[backend.kind](backend)
