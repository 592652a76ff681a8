"""The two functions a worker process of the batch engine is started with.

Standard library only: the parent pickles them by reference, so importing this module must
not pull in NumPy, Numba or the kernels — the parent starts its workers before it has
imported any of those (:mod:`jointplay.execution.pool`), and each worker imports the
kernels itself, in parallel with the parent.
"""

from __future__ import annotations

import os
import signal
import threading

__all__ = ["die_with_parent", "worker_init", "worker_ready"]

#: How often a worker looks whether its parent is still alive, s.
PARENT_CHECK_S = 0.5


def worker_init() -> None:
    """Initializer of a worker process of the batch engine: Ctrl-C is left to the parent, and
    the worker ends when its parent does (:func:`die_with_parent`)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    die_with_parent()


def die_with_parent() -> None:
    """End this process within :data:`PARENT_CHECK_S` of its parent's end, however that ends
    (SIGKILL included, which runs no clean-up in the parent): a daemon thread watches the
    parent's process id, which changes when the parent is gone (the orphan is adopted)."""
    parent = os.getppid()

    def watch() -> None:
        while os.getppid() == parent:
            threading.Event().wait(PARENT_CHECK_S)
        os._exit(1)

    threading.Thread(target=watch, name="jointplay-parent-watch", daemon=True).start()


def worker_ready() -> bool:
    """A task sent to a new worker so that it starts and imports the compiled kernels while
    the parent prepares the batch."""
    import jointplay._kernels.batch  # noqa: F401

    return True
