"""The two functions a worker process of the batch engine is started with.

Standard library only: the parent pickles them by reference, so importing this module must
not pull in NumPy, Numba or the kernels — the parent starts its workers before it has
imported any of those (:mod:`jointplay.dynamics.workers`), and each worker imports the
kernels itself, in parallel with the parent.
"""

from __future__ import annotations

import signal

__all__ = ["worker_init", "worker_ready"]


def worker_init() -> None:
    """Initializer of a worker process of the batch engine: Ctrl-C is left to the parent."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)


def worker_ready() -> bool:
    """A task sent to a new worker so that it starts and imports the compiled kernels while
    the parent prepares the batch."""
    import jointplay._kernels.batch  # noqa: F401

    return True
