"""The progress bar of every run (on stderr): work done, rate, time elapsed and left.

Rich is imported only when a bar is shown.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from contextlib import AbstractContextManager, contextmanager, nullcontext

__all__ = ["bar", "progress_bar"]


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


@contextmanager
def progress_bar(total: int, description: str) -> Iterator[Callable[[int], None]]:
    """A bar for ``total`` units of work labelled ``description``; yields ``advance(count)``."""
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
        task = shown.add_task(description, total=total)
        yield lambda count: shown.advance(task, count)
