"""The progress bar of every run (on stderr): work done, rate, time elapsed and left.

Rich is imported only when a bar is shown.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from contextlib import AbstractContextManager, contextmanager, nullcontext
from typing import Any

__all__ = ["StudyBar", "bar", "progress_bar", "study_bar"]


def bar(
    enabled: bool, total: int, description: str
) -> AbstractContextManager[Callable[[int], None]]:
    """``with bar(enabled, total, description) as advance:`` — ``advance(count)`` adds work
    done to :func:`progress_bar`; without ``enabled`` it does nothing (and no bar is made)."""
    if not enabled:
        return nullcontext(_nothing)
    return progress_bar(total, description)


def _nothing(count: int) -> None:
    """The ``advance`` of a run without a bar."""


class StudyBar:
    """The handle of :func:`study_bar`: work done, and the total and label as they change."""

    def __init__(self, advance: Callable[[int], None], update: Callable[..., None]) -> None:
        self._advance, self._update = advance, update

    def advance(self, count: int) -> None:
        """``count`` more units of work done."""
        self._advance(count)

    def update(self, *, total: int | None = None, description: str | None = None) -> None:
        """A new total (e.g. the most work still possibly needed) or label."""
        self._update(total=total, description=description)


@contextmanager
def study_bar(enabled: bool, total: int, description: str) -> Iterator[StudyBar]:
    """One bar for a whole study whose total may shrink as it goes (:class:`StudyBar`); the
    columns, rate and time left of :func:`progress_bar`. Without ``enabled``, a handle that
    does nothing."""
    if not enabled:
        yield StudyBar(_nothing, lambda **_: None)
        return
    with _progress(total, description) as (shown, task):

        def update(*, total: int | None = None, description: str | None = None) -> None:
            changes: dict[str, object] = {}
            if total is not None:
                changes["total"] = total
            if description is not None:
                changes["description"] = description
            shown.update(task, **changes)

        yield StudyBar(lambda count: shown.advance(task, count), update)


@contextmanager
def progress_bar(total: int, description: str) -> Iterator[Callable[[int], None]]:
    """A bar for ``total`` units of work labelled ``description``; yields ``advance(count)``."""
    with _progress(total, description) as (shown, task):
        yield lambda count: shown.advance(task, count)


@contextmanager
def _progress(total: int, description: str) -> Iterator[tuple[Any, Any]]:
    """The Rich progress display of one task (shown on stderr), and the task."""
    from rich.console import Console
    from rich.progress import (
        BarColumn,
        MofNCompleteColumn,
        Progress,
        ProgressColumn,
        Task,
        TextColumn,
        TimeElapsedColumn,
    )
    from rich.text import Text

    from jointplay.progress import eta_column

    class RateColumn(ProgressColumn):
        """Units of work per second."""

        def render(self, task: Task) -> Text:
            speed = task.finished_speed or task.speed
            return Text("" if speed is None or not math.isfinite(speed) else f"{speed:,.1f}/s")

    shown = Progress(
        TextColumn("{task.description}"),
        BarColumn(),
        MofNCompleteColumn(),
        RateColumn(),
        TimeElapsedColumn(),
        TextColumn("left"),
        eta_column(),
        console=Console(stderr=True),
        transient=False,
    )
    with shown:
        yield shown, shown.add_task(description, total=total)
