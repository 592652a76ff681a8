"""Typed exceptions raised at jointplay's API boundary.

Every error carries a message a user can act on: what is wrong and how to fix it.
The CLI prints ``str(error)`` on one line and exits non-zero; compiled kernels never
raise, they return a status that is turned into one of these here.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any


class JointplayError(Exception):
    """Base class of every error jointplay raises on purpose."""


class ConfigError(JointplayError, ValueError):
    """A configuration value, file or unit is malformed or out of range."""


class QuantityError(ConfigError):
    """A value is not a quantity in the unit asked for (:func:`jointplay.units.parse_quantity`).

    Its message is ``"<field>: <detail>"``; :attr:`field` and :attr:`detail` are the two
    parts, for callers that name the field their own way (:class:`SettingError`).
    """

    def __init__(self, field: str, detail: str) -> None:
        super().__init__(f"{field}: {detail}")
        self.field, self.detail = field, detail

    def __reduce__(self) -> tuple[Any, ...]:
        return QuantityError, (self.field, self.detail)


def name_settings(template: str, names: Mapping[str, str] | None = None, /, **values: Any) -> str:
    """``template`` (:meth:`str.format` syntax) with each ``{setting}`` field called by its
    name in ``names`` (setting → name; a setting not in it by its own name) and the other
    fields from ``values``: how :class:`SettingError` and the diagnostics' advice
    (:class:`jointplay.dynamics.diagnostics.Diagnostic`) name settings, so that each caller
    shows its own names for them (the command line its options')."""
    known = names or {}

    class _Names(dict[str, Any]):
        def __missing__(self, key: str) -> str:
            return known.get(key, key)

    return template.format_map(_Names(values))


class SettingError(ConfigError):
    """A setting is out of range; the message names the settings it is about by their names
    in a template, and each caller shows its own name for them (:meth:`named`): the Python
    API the setting's name (``stiffness``), the command line its option's. No module
    below the command line names an option.

    Args:
        template: the message (:meth:`str.format` syntax): ``{stiffness}`` where a setting is
            named, other fields for ``values``.
        values: what the template shows besides setting names (e.g. ``got=value``).
    """

    def __init__(self, template: str, /, **values: Any) -> None:
        self.template = template
        self.values = values
        self.names: dict[str, str] = {}
        super().__init__(self._render())

    def _render(self) -> str:
        return name_settings(self.template, self.names, **self.values)

    def named(self, names: Mapping[str, str]) -> SettingError:
        """The same error, its settings called by ``names`` (setting → name) where given."""
        renamed = SettingError(self.template, **self.values)
        renamed.names = {**self.names, **names}
        renamed.args = (renamed._render(),)
        return renamed

    def __reduce__(self) -> tuple[Any, ...]:
        return _rebuilt, (self.template, self.values, self.names)


def _rebuilt(template: str, values: dict[str, Any], names: dict[str, str]) -> SettingError:
    return SettingError(template, **values).named(names)


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


class Interrupted(Exception):
    """Raised inside :func:`jointplay.io.output.output_dir` by a command that was interrupted after some of its
    work finished and was written to the staging folder.

    ``output_dir`` publishes the partial result (its module's docstring) and sets
    :attr:`written_to`; the command line prints :meth:`line` and exits 130.

    Args:
        finished: items finished (points, schemes, samples).
        total: items asked for.
        unit: what an item is, plural (``"points"``).
        missing: what else is missing, if anything (``"the figures and report"``).
    """

    def __init__(self, finished: int, total: int, unit: str, missing: str = "") -> None:
        super().__init__(f"{finished} of {total} {unit} finished")
        self.finished, self.total, self.unit, self.missing = finished, total, unit, missing
        self.written_to: Path | None = None
        self.kept: Path | None = None

    def line(self) -> str:
        """One line: what finished and where it was written."""
        what = f"{self.finished} of {self.total} {self.unit} finished"
        if self.missing:
            what += f" ({self.missing} missing)"
        if self.written_to is None:
            return f"{what}; nothing was written (the output folder is as it was)"
        where = f"{what}; their results were written to {self.written_to}"
        if self.kept is not None:
            where += f" (the more complete result in {self.kept} was kept)"
        return where

    @property
    def complete_share(self) -> float:
        """How complete the partial result is, 0-1 (for comparing with an older one)."""
        return (self.finished - (0.5 if self.missing else 0.0)) / max(self.total, 1)


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
