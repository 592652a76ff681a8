"""Dask clusters: the one connection, waiting for finished work, a cluster that goes away.

:func:`connect` is the only place that opens a client of a cluster; :func:`client` keeps one
per scheduler for the process (a study runs many blocks: one connection, not one per block).
``distributed`` is imported only when a cluster is used.
"""

from __future__ import annotations

import atexit
import math
import time
from collections.abc import Iterator
from typing import Any

from jointplay.errors import ConfigError, JointplayError

__all__ = [
    "DASK_NO_WORKERS_S",
    "DASK_POLL_S",
    "DASK_WORKER_CHECK_S",
    "ClusterLost",
    "check_workers",
    "client",
    "close_clients",
    "cluster_threads",
    "completed",
    "connect",
    "result",
    "workers",
]

#: How long work waits for a Dask cluster that has no worker (at the start, or once its
#: workers have died) before it gives up on what is not finished, s.
DASK_NO_WORKERS_S = 30.0
#: How often a run on Dask looks for finished tasks, s.
DASK_POLL_S = 0.05
#: How often a run on Dask waiting for its tasks asks the scheduler whether it still has a
#: worker, s (one round trip to the scheduler).
DASK_WORKER_CHECK_S = 1.0

#: When each cluster (by scheduler address) was first seen without a worker; absent while it
#: has one. Kept across the blocks of a run, so that once a cluster has lost its workers for
#: :data:`DASK_NO_WORKERS_S` every later block gives up at once instead of waiting that long
#: again (a study of 20 000 samples waited 30 s per block of 128, for hours).
_NO_WORKERS_SINCE: dict[str, float] = {}


class ClusterLost(JointplayError):
    """The Dask cluster cannot finish: no workers left (:data:`DASK_NO_WORKERS_S`), or a
    task killed its workers (Dask's own retries spent)."""


def connect(address: str) -> Any:
    """A new client of the cluster at ``address`` that has at least one worker.

    Raises:
        ConfigError: no scheduler answers there, or no worker joined within
            :data:`DASK_NO_WORKERS_S`.
    """
    if not address:
        raise ConfigError("the dask backend needs the scheduler's address (scheduler=...)")
    try:
        from distributed import Client
    except ImportError:  # pragma: no cover - distributed is a dependency
        raise ConfigError("the dask backend needs the 'distributed' package") from None
    try:
        opened = Client(address, timeout=30, set_as_default=False)
    except (OSError, TimeoutError, ValueError) as exc:
        raise ConfigError(f"cannot connect to the Dask scheduler at {address!r}: {exc}") from None
    try:
        opened.wait_for_workers(1, timeout=DASK_NO_WORKERS_S)
    except TimeoutError:
        opened.close()
        raise ConfigError(
            f"the Dask cluster at {address!r} has no workers (none joined within "
            f"{DASK_NO_WORKERS_S:g} s); start some (dask worker {address})"
        ) from None
    return opened


#: Clients of the Dask clusters this process has used, by scheduler address.
_CLIENTS: dict[str, Any] = {}


def client(address: str | None) -> Any:
    """The client of the cluster at ``address`` kept for the process (:func:`connect` once)."""
    kept = _CLIENTS.get(address or "")
    if kept is not None and kept.status == "running":
        return kept
    kept = connect(address or "")
    if not _CLIENTS:
        atexit.register(close_clients)
    _CLIENTS[address or ""] = kept
    return kept


def close_clients() -> None:
    """Close the clients :func:`client` kept."""
    while _CLIENTS:
        _CLIENTS.popitem()[1].close()


def cluster_threads(address: str | None) -> int:
    """The threads of every worker of the Dask cluster at ``address``: how many tasks it
    runs at once (at least 1, while its workers are still joining)."""
    info = client(address).scheduler_info(n_workers=-1)
    return max(1, sum(int(w.get("nthreads", 1)) for w in info.get("workers", {}).values()))


def workers(connected: Any) -> int:
    """The workers of the cluster of the client ``connected`` (at least 1)."""
    return max(1, len(connected.scheduler_info(n_workers=-1).get("workers", {})))


def check_workers(connected: Any, address: str) -> None:
    """Note whether the cluster of ``connected`` has a worker now.

    Raises:
        ClusterLost: it has had none for :data:`DASK_NO_WORKERS_S` (counted from when this
            process first saw it without one, across the blocks of a run).
    """
    now = time.monotonic()
    if connected.scheduler_info(n_workers=-1).get("workers"):
        _NO_WORKERS_SINCE.pop(address, None)
        return
    since = _NO_WORKERS_SINCE.setdefault(address, now)
    if now - since >= DASK_NO_WORKERS_S:
        raise ClusterLost(
            f"the Dask cluster at {address} has had no worker for {DASK_NO_WORKERS_S:g} s; "
            f"start workers (dask worker {address})"
        )


def result(future: Any, address: str, connected: Any = None) -> Any:
    """The result of a finished Dask ``future``. A result held by a worker that has since
    died is computed again, which needs a worker: without ``connected`` (the client) this
    waits at most :data:`DASK_NO_WORKERS_S`; with it, for as long as the cluster has a
    worker, and until it has had none for that long (:func:`check_workers`).

    Raises:
        ClusterLost: it did not come in that time.
    """
    waited = 0.0
    while True:
        try:
            return future.result(timeout=DASK_WORKER_CHECK_S)
        except TimeoutError:
            waited += DASK_WORKER_CHECK_S
        try:
            if connected is not None:
                check_workers(connected, address)
            elif waited >= DASK_NO_WORKERS_S:
                raise ClusterLost(f"no worker for {DASK_NO_WORKERS_S:g} s")
        except ClusterLost:
            raise ClusterLost(
                f"the Dask cluster at {address} lost a finished result with its worker and had "
                f"no worker to compute it again within {DASK_NO_WORKERS_S:g} s"
            ) from None


def completed(connected: Any, futures: list[Any], address: str) -> Iterator[Any]:
    """The Dask ``futures`` as they finish (failed ones too: look at their ``status``).

    Dask itself moves the tasks of a worker that dies to the others (and gives up on a task
    that killed three workers: its status is ``"error"``, ``KilledWorker``); this stops
    waiting when the cluster has had no worker for :data:`DASK_NO_WORKERS_S`, asking the
    scheduler every :data:`DASK_WORKER_CHECK_S` while no task finishes (at once where the
    cluster was already seen without one: :func:`check_workers`).

    Raises:
        ClusterLost: the cluster at ``address`` has had no worker for that long (the futures
            not yielded did not finish).
    """
    pending = set(futures)
    checked = -math.inf if address in _NO_WORKERS_SINCE else time.monotonic()
    while pending:
        done = [future for future in futures if future in pending and future.done()]
        pending.difference_update(done)
        yield from done
        if done:  # tasks finish: the cluster has a worker
            checked = time.monotonic()
            _NO_WORKERS_SINCE.pop(address, None)
            continue
        if time.monotonic() - checked >= DASK_WORKER_CHECK_S:
            check_workers(connected, address)
            checked = time.monotonic()
            continue
        time.sleep(DASK_POLL_S)
