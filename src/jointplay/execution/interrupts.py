"""Interrupts in compiled loops (flags that the C-level signal handler writes), and interrupts
noted while finished work is being put together.

:func:`interrupts_gated` lets SIGINT and SIGTERM act as usual until the work it surrounds has
finished its compiled part (:func:`close_gates`, where a batch's lanes end), then only notes
them until that work is kept: no instant is left in between where an interrupt loses it.
:func:`interrupts_noted` holds SIGINT and SIGTERM back while finished work is put together
(a block's results after its lanes ran): the caller sees that one came and returns the work
as interrupted instead of losing it. :func:`interrupts_watched` lends a compiled loop (the Radau kernel, the batch kernels) a
uint8 array that becomes non-zero when SIGINT or SIGTERM arrives, and raises
:class:`KeyboardInterrupt` when the loop has returned, so that callers see an interrupt
exactly as in plain Python code.
"""

from __future__ import annotations

import mmap
import os
import signal
import tempfile
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

import numpy as np
import numpy.typing as npt

__all__ = ["close_gates", "interrupts_gated", "interrupts_noted", "interrupts_watched"]


class _InterruptFlags:
    """One page of shared memory behind a file descriptor, seen as a uint8 array.

    Python's C-level signal handler writes the number of each signal it catches to the
    wakeup descriptor (:func:`signal.set_wakeup_fd`). Pointed at this descriptor, those
    bytes land in memory that the compiled integrator reads between steps, so Ctrl-C and
    SIGTERM stop it with a status instead of raising through Numba.
    """

    def __init__(self) -> None:
        size = mmap.PAGESIZE
        if hasattr(os, "memfd_create"):
            self.fd = os.memfd_create("jointplay-interrupt", os.MFD_CLOEXEC)
        else:  # pragma: no cover - not Linux
            self._file = tempfile.TemporaryFile()  # noqa: SIM115 (kept open for good)
            self.fd = self._file.fileno()
        os.ftruncate(self.fd, size)
        os.set_blocking(self.fd, False)
        self._map = mmap.mmap(self.fd, size)
        self.array = np.frombuffer(self._map, dtype=np.uint8)

    def reset(self) -> None:
        os.lseek(self.fd, 0, os.SEEK_SET)
        self._map[:] = bytes(len(self._map))


_flags: _InterruptFlags | None = None


@contextmanager
def interrupts_watched() -> Iterator[npt.NDArray[np.uint8] | None]:
    """Flags for the kernel while SIGINT and SIGTERM are watched (``None``: not watched).

    Only in the main thread, and only for signals that have a Python handler (a worker
    process that ignores SIGINT keeps ignoring it). While watched, a signal is only noted;
    when the integration returns the context raises KeyboardInterrupt, so that callers see
    an interrupt exactly as in plain Python code.
    """
    global _flags
    if threading.current_thread() is not threading.main_thread():
        yield None
        return
    watched = [s for s in (signal.SIGINT, signal.SIGTERM) if callable(signal.getsignal(s))]
    if not watched:
        yield None
        return
    try:
        if _flags is None:
            _flags = _InterruptFlags()
        _flags.reset()
    except (OSError, ValueError):  # pragma: no cover - no shared memory: no watching
        yield None
        return
    noted: list[int] = []
    previous = {s: signal.signal(s, lambda number, frame: noted.append(number)) for s in watched}
    try:
        old_fd = signal.set_wakeup_fd(_flags.fd, warn_on_full_buffer=False)
    except ValueError:  # pragma: no cover
        old_fd = None
    try:
        yield _flags.array
    finally:
        if old_fd is not None:
            signal.set_wakeup_fd(old_fd)
        for s, handler in previous.items():
            signal.signal(s, handler)
    if noted:
        raise KeyboardInterrupt(f"signal {noted[0]}")


@contextmanager
def interrupts_noted() -> Iterator[list[int]]:
    """Note SIGINT and SIGTERM instead of raising them, for a stretch that puts finished work
    together (the list yielded receives their numbers); the caller then returns that work
    marked interrupted, so that an interrupt there never loses it.

    Only in the main thread and for signals with a Python handler (elsewhere the list stays
    empty and a signal acts as before). The handlers in place are put back on exit, where
    nothing is raised: acting on the signals is the caller's.
    """
    noted: list[int] = []
    if threading.current_thread() is not threading.main_thread():
        yield noted
        return
    watched = [s for s in (signal.SIGINT, signal.SIGTERM) if callable(signal.getsignal(s))]
    previous = {s: signal.signal(s, lambda number, frame: noted.append(number)) for s in watched}
    try:
        yield noted
    finally:
        for s, handler in previous.items():
            signal.signal(s, handler)


class Gate:
    """What :func:`interrupts_gated` yields: ``closed`` once :func:`close_gates` ran, and the
    signals ``noted`` from then on; ``forward``: the handlers an open gate calls."""

    def __init__(self) -> None:
        self.closed = False
        self.noted: list[int] = []
        self.forward: dict[signal.Signals, Any] = {}


_open_gates: list[Gate] = []


@contextmanager
def interrupts_gated() -> Iterator[Gate]:
    """SIGINT and SIGTERM act as before (their handlers are called) until :func:`close_gates`;
    from then until the context ends they are only noted in the yielded :class:`Gate`, and the
    caller acts on them once it has kept the finished work.

    For a block of work whose compiled part (a batch's lanes) is followed by Python code that
    puts its result together: closing the gate is one assignment in the code that ran the
    lanes, so a signal either interrupts the lanes (which keep what finished) or is noted;
    none lands in between, where the finished lanes would be lost. Contexts inside it
    (:func:`interrupts_watched`, :func:`interrupts_noted`) replace the handlers for their own
    stretch and put the gate's back. Only in the main thread and for signals with a Python
    handler; elsewhere the gate never notes anything.
    """
    gate = Gate()
    if threading.current_thread() is not threading.main_thread():
        yield gate
        return
    handlers = {s: h for s in (signal.SIGINT, signal.SIGTERM) if callable(h := signal.getsignal(s))}
    # an open gate inside another (a second batch in the same task) acts as the handlers
    # outside every gate, not as the outer gate, which may be closed already
    outer = _open_gates[0].forward if _open_gates else {}
    gate.forward = {s: outer.get(s, h) for s, h in handlers.items()}

    def gated(number: int, frame: Any) -> Any:
        if gate.closed:
            gate.noted.append(number)
            return None
        return gate.forward[signal.Signals(number)](number, frame)

    for s in handlers:
        signal.signal(s, gated)
    _open_gates.append(gate)
    try:
        yield gate
    finally:
        _open_gates.remove(gate)
        for s, handler in handlers.items():
            signal.signal(s, handler)


def close_gates() -> None:
    """From now on every open :func:`interrupts_gated` notes SIGINT and SIGTERM instead of
    acting on them (nothing if none is open). Call it as the last statement of the ``try``
    around the compiled work and first in its ``except KeyboardInterrupt``."""
    for gate in _open_gates:
        gate.closed = True
