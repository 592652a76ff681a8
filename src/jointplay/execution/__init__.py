"""The execution room: where work runs, apart from what it computes.

Executors own the pools, clients, interrupts, task status and the progress bar; the engines
(the single Radau engine, the batch engine's explicit and implicit kernels, its GPU kernel)
own the numerics. A study or a batch is given one :class:`Backend` and asks
:func:`~jointplay.execution.executors.executor` for its executor; nothing else chooses.

* :mod:`~jointplay.execution.backends` — the backend names (:data:`BACKENDS`, the only list)
  and the :class:`Backend` setting (standard library only: the command line uses it);
* :mod:`~jointplay.execution.executors` — one executor class per backend;
* :mod:`~jointplay.execution.tasks` — :func:`~jointplay.execution.tasks.run_tasks`,
  independent tasks with failures as data;
* :mod:`~jointplay.execution.pool` — the batch engine's worker processes, kept for the process;
* :mod:`~jointplay.execution.dask` — the one Dask connection and waiting on a cluster;
* :mod:`~jointplay.execution.interrupts` — SIGINT and SIGTERM in compiled loops;
* :mod:`~jointplay.execution.progress` — the progress bar.

Importing this package imports only :mod:`~jointplay.execution.backends`.
"""

from jointplay.execution.backends import ALIASES, BACKENDS, Backend, BackendKind, backend_kind

__all__ = ["ALIASES", "BACKENDS", "Backend", "BackendKind", "backend_kind"]
