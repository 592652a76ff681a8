"""Typed exceptions raised at jointplay's API boundary.

Every error carries a message a user can act on: what is wrong and how to fix it.
The CLI prints ``str(error)`` on one line and exits non-zero; compiled kernels never
raise, they return a status that is turned into one of these here.
"""

from __future__ import annotations


class JointplayError(Exception):
    """Base class of every error jointplay raises on purpose."""


class ConfigError(JointplayError, ValueError):
    """A configuration value, file or unit is malformed or out of range."""


class AssemblyError(JointplayError, ValueError):
    """The mechanism cannot be assembled (or its crank cannot turn) at some input angle."""


class IntegrationError(JointplayError, RuntimeError):
    """The time integration failed (step size underflow, too many steps, non-finite state)."""


class StandardsError(JointplayError, ValueError):
    """A tolerance designation or size lies outside what ISO 286 / ISO 2768 define."""


class PartialInterrupt(KeyboardInterrupt):
    """SIGINT or SIGTERM stopped a computation that keeps what it finished before it.

    A KeyboardInterrupt, so that code that does not look for the partial result sees an
    interrupt as from any Python code; code that does takes :attr:`partial`.

    Attributes:
        partial: the computation's result, with what did not finish marked as not run (each
            raiser says how).
    """

    def __init__(self, partial: object, message: str = "interrupted") -> None:
        super().__init__(message)
        self.partial = partial


def caused_by_interrupt(exc: BaseException) -> bool:
    """Whether a KeyboardInterrupt is among the causes of ``exc``: Numba reports a Ctrl-C
    that arrived in compiled code as a SystemError whose cause is the KeyboardInterrupt."""
    seen: set[int] = set()
    current: BaseException | None = exc
    while current is not None and id(current) not in seen:
        if isinstance(current, KeyboardInterrupt):
            return True
        seen.add(id(current))
        current = current.__cause__ or current.__context__
    return False
