"""An honest time-left estimate for the progress bars of long runs.

Rich's own estimate divides the work left by the speed of the last 30 s, which swings with
every burst of finished chunks (3:28, 6:19, then 0:01 in one run) and, while the first
chunks come in fast, reads 40-50 % low. :class:`Eta` smooths the speed instead (an
exponential average over time, :data:`HALF_LIFE_S`) and never lets it exceed the average
speed since the start by more than 1/:data:`FLOOR` - 1 = 25 %: the time left it shows is
never below :data:`FLOOR` (80 %) of what the elapsed average speed gives. Before
:data:`SHOWN_AFTER` of the work is done there is too little to go on, and nothing is shown.

:func:`eta_column` wraps it as a column for a :class:`rich.progress.Progress` bar (Rich is
imported only there).
"""

from __future__ import annotations

import math
from typing import Any

#: Half-life of the smoothed speed, s: a speed measured this long ago weighs half as much.
HALF_LIFE_S = 20.0
#: The time left is never below this share of (work left) / (average speed since the start).
FLOOR = 0.8
#: Share of the work done before a time left is shown.
SHOWN_AFTER = 0.1


class Eta:
    """The time left of one run from a smoothed speed, bounded by the elapsed speed.

    Feed it :meth:`update` with the elapsed time and the work done whenever either changes
    (the calls may repeat); :meth:`remaining` gives the time left in seconds, or ``None``
    while less than :data:`SHOWN_AFTER` of the work is done.
    """

    def __init__(self, total: float, *, half_life: float = HALF_LIFE_S) -> None:
        self.total = float(total)
        self.half_life = half_life
        self._elapsed = 0.0
        self._done = 0.0
        self._speed: float | None = None

    def update(self, elapsed: float, done: float) -> None:
        """Record that ``done`` units of work were finished ``elapsed`` seconds in."""
        if done <= self._done or elapsed <= self._elapsed:  # nothing new to learn from yet
            return
        interval = elapsed - self._elapsed
        speed = (done - self._done) / interval
        weight = 1.0 - 0.5 ** (interval / self.half_life)
        self._speed = speed if self._speed is None else self._speed + weight * (speed - self._speed)
        self._elapsed, self._done = elapsed, done

    def remaining(self, elapsed: float) -> float | None:
        """Seconds left at ``elapsed`` seconds in, or ``None`` before :data:`SHOWN_AFTER`."""
        if self._speed is None or self.total <= 0 or self._done < SHOWN_AFTER * self.total:
            return None
        average = self._done / max(elapsed, self._elapsed)
        speed = min(self._speed, average / FLOOR)
        return (self.total - self._done) / speed if speed > 0 else math.inf


def eta_column() -> Any:
    """A :class:`rich.progress.ProgressColumn` that shows :class:`Eta`'s time left per task
    ("-:--:--" until there is enough to go on)."""
    from rich.progress import ProgressColumn, Task
    from rich.text import Text

    class EtaColumn(ProgressColumn):
        def __init__(self) -> None:
            super().__init__()
            self._estimates: dict[Any, Eta] = {}

        def render(self, task: Task) -> Text:
            if task.total is None or task.elapsed is None:
                return Text("-:--:--", style="progress.remaining")
            estimate = self._estimates.get(task.id)
            if estimate is None or estimate.total != task.total:
                estimate = self._estimates[task.id] = Eta(task.total)
            estimate.update(task.elapsed, task.completed)
            left = 0.0 if task.finished else estimate.remaining(task.elapsed)
            if left is None or not math.isfinite(left):
                return Text("-:--:--", style="progress.remaining")
            minutes, seconds = divmod(round(left), 60)
            hours, minutes = divmod(minutes, 60)
            return Text(f"{hours}:{minutes:02d}:{seconds:02d}", style="progress.remaining")

    return EtaColumn()
