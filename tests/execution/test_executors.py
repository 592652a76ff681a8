"""The execution room: one list of backend names, one executor per name, the choices it makes."""

from __future__ import annotations

from typing import Any, NamedTuple

import pytest

from jointplay.errors import ConfigError
from jointplay.execution import ALIASES, BACKENDS, Backend, backend_kind
from jointplay.execution.executors import _EXECUTORS, GPU_CHUNKS, Executor, executor, gpu_chunk


def test_every_backend_name_has_one_executor_and_no_more() -> None:
    assert set(_EXECUTORS) == set(BACKENDS)
    for name in BACKENDS:
        assert _EXECUTORS[name].kind == name


def test_an_alias_names_its_backend_and_an_unknown_name_is_refused() -> None:
    for alias, kind in ALIASES.items():
        assert backend_kind(alias) == kind
        assert Backend(alias).kind == kind  # type: ignore[arg-type]
    with pytest.raises(ConfigError, match="backend must be one of local, processes"):
        Backend("threads")  # type: ignore[arg-type]


def test_tasks_that_cannot_use_workers_run_in_this_process() -> None:
    assert executor(Backend("processes", workers=4)).for_tasks(1).kind == "local"
    assert executor(Backend("processes", workers=1)).for_tasks(10).kind == "local"
    assert executor(Backend("gpu")).for_tasks(10).kind == "local"
    two = executor(Backend("processes", workers=8)).for_tasks(2)
    assert two.kind == "processes" and two.lane_slots() == 2


def test_lane_chunks_follow_the_backend_and_a_given_chunk_size_wins() -> None:
    processes = executor(Backend("processes", workers=3))
    assert processes.lane_chunk(1000, 3) == 32  # the default chunk caps ~4 per slot
    assert processes.lane_chunk(12, 3) == 1
    assert executor(Backend("processes", workers=3, chunk_size=7)).lane_chunk(1000, 3) == 7
    gpu = executor(Backend("gpu"))
    assert gpu.on_device and gpu.lane_chunk(10, 1) == GPU_CHUNKS[0]  # the parts it groups
    assert executor(Backend("gpu", chunk_size=7)).lane_chunk(10, 1) == 7


def test_the_gpu_chunk_is_the_largest_size_that_fits_the_budget() -> None:
    """The rule: the largest size the measured rate runs within the budget; the smallest
    before anything is measured or when none fits."""
    sizes = (1024, 4096, 16384, 65536)
    assert gpu_chunk(None, 2.0, sizes) == 1024
    assert gpu_chunk(0.0, 2.0, sizes) == 1024
    assert gpu_chunk(100.0, 2.0, sizes) == 1024  # 10 s even for the smallest: the smallest
    assert gpu_chunk(22_000.0, 2.0, sizes) == 16384  # 0.74 s; 65536 would take 3 s
    assert gpu_chunk(32_768.0, 2.0, sizes) == 65536  # exactly the budget
    assert gpu_chunk(32_767.0, 2.0, sizes) == 16384
    assert gpu_chunk(1e9, 2.0, sizes) == 65536  # never above the largest
    assert gpu_chunk(22_000.0, 0.5, sizes) == 4096
    assert GPU_CHUNKS == (1024, 4096, 16384, 65536)  # powers of 4 up to GPU_CHUNK


def test_the_gpu_executor_sizes_each_chunk_from_the_rate_of_the_one_before(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """A fake device that runs 4 lanes/s: with a 2 s budget and sizes 2, 8, 32 the first
    chunk is the smallest, then 8 lanes (2 s), padded to its size when short; every part
    comes back in order with its own lanes."""
    import numpy as np

    from jointplay.execution import executors as ex
    from jointplay.execution.executors import Lanes, LaneWork

    class Out(NamedTuple):
        lanes: np.ndarray

    calls: list[tuple[int, int]] = []

    def device(chunk, size, timings):
        calls.append((len(chunk[0]), size))
        timings["run_s"] = len(chunk[0]) / 4.0
        return Out(chunk[0].copy())

    work = LaneWork(task=print, shared=None, here=print, stopped=lambda o: False, device=device)
    parts = [(np.arange(i, min(i + 2, 13)),) for i in range(0, 13, 2)]  # 13 lanes in 7 parts
    got: dict[int, np.ndarray] = {}
    monkeypatch.setattr(ex, "GPU_CHUNKS", (2, 8, 32))
    runner = executor(Backend("gpu"))
    runner.run_lanes(Lanes(work, parts, 1, 2, lambda k, o: got.__setitem__(k, o.lanes)))
    assert calls == [(2, 2), (8, 8), (8, 8)]  # the last 3 lanes padded to 8
    assert sorted(got) == list(range(7))
    np.testing.assert_array_equal(np.concatenate([got[k] for k in range(7)]), np.arange(13))


def test_the_gpu_executor_refuses_an_engine_without_a_device_kernel() -> None:
    from jointplay.execution.executors import Lanes, LaneWork

    work = LaneWork(task=print, shared=None, here=lambda *a: None, stopped=lambda o: False)
    with pytest.raises(ConfigError, match="gpu backend runs the batch engine only"):
        executor(Backend("gpu")).run_lanes(Lanes(work, [()], 1, 1, lambda k, o: None))


def test_an_executor_is_chosen_from_the_backend_alone() -> None:
    chosen = executor(Backend("local", chunk_size=5))
    assert isinstance(chosen, Executor) and chosen.kind == "local"
    assert chosen.block(64) == 5 and executor(Backend("local")).block(64) == 64


def test_the_cuda_executor_runs_the_engines_numba_cuda_kernel_and_nothing_else(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """``cuda`` is the gpu executor's chunking on :attr:`LaneWork.cuda`: the JAX kernel
    (``device``) is never called, and an engine without a numba-cuda kernel is refused."""
    import numpy as np

    from jointplay.execution.executors import Lanes, LaneWork

    class Out(NamedTuple):
        lanes: np.ndarray

    def jax(chunk, size, timings):
        raise AssertionError("the cuda backend called the JAX kernel")

    def cuda(chunk, size, timings, interrupt=None):
        timings["run_s"] = 1e-3
        return Out(chunk[0].copy())

    runner = executor(Backend("cuda"))
    assert runner.on_device and runner.for_tasks(10).kind == "local"
    work = LaneWork(print, None, print, lambda o: False, device=jax, cuda=cuda)
    got: dict[int, np.ndarray] = {}
    runner.run_lanes(Lanes(work, [(np.arange(3),)], 1, 3, lambda k, o: got.__setitem__(k, o.lanes)))
    np.testing.assert_array_equal(got[0], np.arange(3))
    calls: list[int] = []

    def counted(chunk, size, timings, interrupt=None):
        calls.append(len(chunk[0]))
        return cuda(chunk, size, timings)

    from jointplay.execution import executors as ex

    monkeypatch.setattr(ex, "GPU_CHUNKS", (2, 8, 32))
    parts = [(np.arange(i, min(i + 2, 7)),) for i in range(0, 7, 2)]  # 7 lanes in 4 parts
    runner.run_lanes(Lanes(LaneWork(print, None, print, lambda o: False, cuda=counted), parts,
                           1, 2, lambda k, o: got.__setitem__(k, o.lanes)))  # fmt: skip
    assert calls == [2, 5]  # 2, then the other 5 unpadded (gpu pads them to 32)
    jax_only = LaneWork(print, None, print, lambda o: False, device=jax)
    with pytest.raises(ConfigError, match="cuda backend runs the batch engine only"):
        runner.run_lanes(Lanes(jax_only, [()], 1, 1, lambda k, o: None))


def test_the_cuda_executor_lends_a_kernel_that_takes_them_the_interrupt_flags() -> None:
    """A kernel with an ``interrupt`` keyword gets the flags of ``interrupts_watched``; a
    SIGINT during its launch is in them at once (the kernel ends its lanes interrupted), the
    chunk's lanes are kept, the next chunk is not started and KeyboardInterrupt reaches the
    caller."""
    import os
    import signal

    import numpy as np

    from jointplay.execution.executors import Lanes, LaneWork

    class Out(NamedTuple):
        status: np.ndarray

    seen: list[int] = []

    def cuda(chunk, size, timings, interrupt=None):
        assert interrupt is not None and interrupt.dtype == np.uint8 and interrupt[0] == 0
        os.kill(os.getpid(), signal.SIGINT)  # Ctrl-C while the launch runs
        seen.append(int(interrupt[0]))  # written by the C-level handler, before Python's
        return Out(np.where(chunk[0] == 0, 0, -4))  # lane 0 finished, the others stopped

    got: dict[int, np.ndarray] = {}
    work = LaneWork(print, None, print, lambda o: bool((o.status == -4).any()), cuda=cuda)
    parts = [(np.arange(3),), (np.arange(3, 6),)]
    runner = executor(Backend("cuda", chunk_size=3))
    with pytest.raises(KeyboardInterrupt):
        runner.run_lanes(Lanes(work, parts, 1, 3, lambda k, o: got.__setitem__(k, o.status)))
    assert seen == [signal.SIGINT]  # one launch: the second chunk never started
    np.testing.assert_array_equal(got[0], [0, -4, -4])
    assert list(got) == [0]


class _InterruptOnFirstResult:
    """A task sink that is interrupted (Ctrl-C) when the first result arrives."""

    def store(self, index: int, outcome: tuple[bool, Any]) -> None:
        raise KeyboardInterrupt

    def keep_partial(self, index: int, partial: Any) -> None:
        pass

    def advance(self, index: int) -> None:
        pass


def test_an_interrupt_with_tasks_queued_ends_the_pool_cleanly() -> None:
    """Ctrl-C while tasks are still queued behind the workers: the pool's workers end and its
    manager thread does not fail. Cancelling the queued futures before terminating the
    workers (as before) made CPython 3.11's manager thread raise ``InvalidStateError`` on a
    cancelled future (``terminate_broken``) and die before ending the other workers, and the
    command hung at exit waiting for them (a CI run of tests/cli/test_interrupts.py)."""
    import concurrent.futures as cf
    import multiprocessing
    import operator
    import threading
    import time

    from jointplay.execution.backends import Backend
    from jointplay.execution.executors import Processes

    failures: list[BaseException | None] = []
    cancelled_here: list[object] = []
    cancel = cf.Future.cancel

    def recorded(future: cf.Future[Any]) -> bool:
        if threading.current_thread() is threading.main_thread():
            cancelled_here.append(future)
        return cancel(future)

    others = set(multiprocessing.active_children())  # another test's kept pool, say
    previous = threading.excepthook
    threading.excepthook = lambda hook: failures.append(hook.exc_value)
    cf.Future.cancel = recorded  # type: ignore[method-assign]
    try:
        with pytest.raises(KeyboardInterrupt):
            Processes(Backend("processes", workers=2)).run_tasks(
                operator.call, time.sleep, [0.05] + [2.0] * 9, _InterruptOnFirstResult()
            )
        deadline = time.monotonic() + 10.0
        while set(multiprocessing.active_children()) - others and time.monotonic() < deadline:
            time.sleep(0.05)
    finally:
        threading.excepthook = previous
        cf.Future.cancel = cancel  # type: ignore[method-assign]
    assert cancelled_here == []  # the race's precondition, which a run seldom hits
    assert failures == []
    assert set(multiprocessing.active_children()) - others == set()


def _double_after_interrupt(closing: bool, item: int) -> int:
    """A task that is sent Ctrl-C as item 0 ends; with ``closing``, after its compiled part
    (the gate closed, as a batch's lanes close it as they end)."""
    import os
    import signal

    from jointplay.execution.interrupts import close_gates

    if item == 0:
        if closing:
            close_gates()
        os.kill(os.getpid(), signal.SIGINT)
    return 2 * item


@pytest.mark.parametrize("closing", [True, False], ids=["after-the-lanes", "before-them"])
def test_an_interrupt_after_a_tasks_lanes_waits_until_the_task_is_kept(closing: bool) -> None:
    """Ctrl-C after a block's lanes ended (in the Python that puts its result together, where
    a signal used to lose the block: CI saw "0 of 40000 points finished") is held until the
    block is kept, then stops the run; before that point it stops the task at once, as ever."""
    from jointplay.execution.tasks import NOT_RUN, OK, run_tasks

    run = run_tasks(_double_after_interrupt, [0, 1, 2], Backend("local"), shared=closing)
    assert run.interrupted
    assert list(run.status) == ([OK] if closing else [NOT_RUN]) + [NOT_RUN, NOT_RUN]
    assert run.results == ((0,) if closing else (None,)) + (None, None)


def test_a_gate_opened_inside_a_closed_one_lets_an_interrupt_act() -> None:
    """A second batch in the same task (its own gate, open) is interrupted at once, though
    the task's gate closed when the first batch's lanes ended; its gate closed, it notes."""
    import os
    import signal

    from jointplay.execution.interrupts import close_gates, interrupts_gated

    with interrupts_gated() as task:
        close_gates()  # the first batch's lanes ended
        with interrupts_gated() as second, pytest.raises(KeyboardInterrupt):
            os.kill(os.getpid(), signal.SIGINT)  # during the second batch's lanes
        assert not second.noted and not task.noted
        with interrupts_gated() as third:
            close_gates()
            os.kill(os.getpid(), signal.SIGINT)
        assert third.noted == [signal.SIGINT] and not task.noted


def test_an_interrupt_while_a_chunk_is_kept_stops_the_run_once_it_is_kept() -> None:
    """Ctrl-C while the ``processes`` backend hands a finished chunk to ``done`` (the Python
    that keeps it): the chunk is kept, then the run stops; the chunks the workers had finished
    by then are kept too, each with its own output. Before, the signal raised inside
    ``done`` and the finished chunk was lost."""
    import operator
    import os
    import signal

    from jointplay.execution.executors import Lanes, LaneWork, Processes

    got: dict[int, int] = {}

    def done(k: int, output: int) -> None:
        if not got:
            os.kill(os.getpid(), signal.SIGINT)
        got[k] = output

    work = LaneWork(operator.mul, 2, print, bool)  # a chunk c's output: 2·c
    chunks = [10, 11, 12, 13]
    with pytest.raises(KeyboardInterrupt):
        Processes(Backend("processes", workers=2)).run_lanes(Lanes(work, chunks, 2, 1, done))
    assert got, "the chunk being kept was lost"
    assert all(output == 2 * chunks[k] for k, output in got.items())
