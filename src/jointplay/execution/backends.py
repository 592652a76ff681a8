"""The execution backends' names and the typed setting that says where work runs.

Standard library only: the command line validates its backend option with it at start-up. The
names live here and nowhere else; what each backend does lives in
:mod:`jointplay.execution.executors`.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Literal

from jointplay.errors import ConfigError

__all__ = ["ALIASES", "BACKENDS", "DEVICE_BACKENDS", "Backend", "BackendKind", "backend_kind"]

#: A backend's name (``"serial"`` is another name of ``"local"``, :data:`ALIASES`).
BackendKind = Literal["local", "serial", "processes", "dask", "gpu", "cuda"]

#: The execution backends: ``"local"`` (this process), ``"processes"`` (local worker
#: processes), ``"dask"`` (a Dask cluster), ``"gpu"`` (the batch engine on JAX) and ``"cuda"``
#: (the batch engine's explicit lanes on numba-cuda, one GPU thread per sample: experimental,
#: not yet measured on a GPU; issue 26).
BACKENDS: tuple[BackendKind, ...] = ("local", "processes", "dask", "gpu", "cuda")
#: The backends that run the batch engine on a device, and nothing else.
DEVICE_BACKENDS: tuple[BackendKind, ...] = ("gpu", "cuda")
#: Other names accepted for a backend.
ALIASES: dict[str, BackendKind] = {"serial": "local"}

#: A Dask scheduler address: optional protocol, host name or [IPv6] address, optional port
#: and path (``inproc://`` addresses carry one).
_SCHEDULER_ADDRESS = re.compile(
    r"(?:(?:tcp|tls|inproc|ucx|ws|wss)://)?(?:[A-Za-z0-9_.\-]+|\[[0-9A-Fa-f:.]+\])(?::\d{1,5})?(?:/[A-Za-z0-9_.\-/]*)?"
)


def backend_kind(name: str) -> BackendKind:
    """The backend called ``name`` (an alias gives its backend).

    Raises:
        ConfigError: ``name`` is no backend's name.
    """
    kind = ALIASES.get(name, name)
    if kind not in BACKENDS:
        raise ConfigError(f"backend must be one of {', '.join(BACKENDS)}, got {name!r}")
    return kind


def _positive(value: int | None, name: str) -> None:
    if value is not None and (isinstance(value, bool) or not isinstance(value, int) or value < 1):
        raise ConfigError(f"{name} must be a positive integer, got {value!r}")


@dataclass(frozen=True)
class Backend:
    """Where the work runs: the one setting a study or a batch is given.

    Attributes:
        kind: ``"local"`` (``"serial"`` is the same), ``"processes"``, ``"dask"``, ``"gpu"``
            or ``"cuda"`` (:data:`BACKENDS`).
        workers: local worker processes (default: the number of CPUs); processes only.
        scheduler: address of the Dask scheduler, e.g. ``"tcp://10.0.0.5:8786"``; dask only.
        chunk_size: samples per task (default: the caller's own).

    Raises:
        ConfigError: a field is out of range, naming the field and what it takes.
    """

    kind: BackendKind = "processes"
    workers: int | None = None
    scheduler: str | None = None
    chunk_size: int | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "kind", backend_kind(self.kind))
        _positive(self.workers, "workers")
        _positive(self.chunk_size, "chunk size")
        if self.kind == "dask" and not self.scheduler:
            raise ConfigError("the dask backend needs the scheduler's address (scheduler=...)")
        if self.kind == "dask" and (
            not isinstance(self.scheduler, str) or not _SCHEDULER_ADDRESS.fullmatch(self.scheduler)
        ):
            raise ConfigError(
                f"scheduler {self.scheduler!r} is not a scheduler address; write "
                "PROTOCOL://HOST:PORT, e.g. tcp://10.0.0.5:8786 (or HOST:PORT)"
            )
        if self.kind != "dask" and self.scheduler:
            raise ConfigError("a scheduler address applies to the dask backend only")

    @property
    def on_device(self) -> bool:
        """Whether this backend runs the batch engine on a device (:data:`DEVICE_BACKENDS`)."""
        return self.kind in DEVICE_BACKENDS

    @classmethod
    def dask(cls, scheduler: str, *, chunk_size: int | None = None) -> Backend:
        """The Dask backend at ``scheduler``."""
        return cls("dask", scheduler=scheduler, chunk_size=chunk_size)
