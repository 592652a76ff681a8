"""The worker processes of the ``"processes"`` backend for the batch engine, kept for the process.

Standard library only, so that a command can start the workers first thing: their start-up
(an interpreter and the compiled kernels, ~0.7 s each) then overlaps the command's own
imports (~1 s of NumPy, pandas, Numba) instead of following them.
"""

from __future__ import annotations

import atexit
import concurrent.futures as cf
import multiprocessing
import os
from typing import Any

from jointplay._kernels.workers import worker_init, worker_ready

__all__ = ["close_pool", "pool", "running_pool", "start_workers"]

_POOL: dict[str, Any] = {}


def pool(workers: int) -> cf.ProcessPoolExecutor:
    """The worker processes of this process's batches, started once and kept (so the start-up
    and the loading of the compiled kernels are paid once per worker, not per batch)."""
    executor = _POOL.get("executor")
    if executor is None or _POOL.get("workers") != workers:
        close_pool()
        executor = cf.ProcessPoolExecutor(
            max_workers=workers,
            mp_context=multiprocessing.get_context("spawn"),
            initializer=worker_init,
        )
        _POOL.update(executor=executor, workers=workers)
        # at exit the (idle) workers are terminated: a graceful shutdown would wait for each
        # to finish starting and to tear its interpreter down
        atexit.register(close_pool, terminate=True)
    return executor


def running_pool() -> cf.ProcessPoolExecutor | None:
    """The workers this process has started, if any (for other work once its batches are
    done, e.g. drawing a study's figures)."""
    executor: cf.ProcessPoolExecutor | None = _POOL.get("executor")
    return executor


def start_workers(workers: int | None = None) -> None:
    """Start the worker processes of the ``"processes"`` backend now (one per CPU by default),
    so that their start-up overlaps whatever this process does before its batch."""
    count = workers or os.cpu_count() or 1
    executor = pool(count)
    for _ in range(count):
        executor.submit(worker_ready)


def close_pool(terminate: bool = False) -> None:
    """Shut the workers down (``terminate``: at once, dropping what they were doing)."""
    executor = _POOL.pop("executor", None)
    _POOL.pop("workers", None)
    if executor is None:
        return
    if terminate:
        for process in list(getattr(executor, "_processes", {}).values()):
            process.terminate()
    executor.shutdown(wait=True, cancel_futures=True)
