"""The time left of a long run: smoothed, and never far below what the elapsed speed says."""

from __future__ import annotations

import numpy as np
import pytest

from jointplay.progress import FLOOR, SHOWN_AFTER, Eta

#: A 200-sample dynamic study as its progress bar sees it (synthetic, seeded): two workers
#: take chunks of 8 samples; each worker's first chunk waits 20 s for the kernels to load,
#: the others take 6 s ± 60 %, so chunks finish in bursts; the bar redraws 10 times a second.
SAMPLES, CHUNK, WORKERS = 200, 8, 2


def schedule(seed: int = 5) -> list[tuple[float, int]]:
    """(time, samples done) at every redraw of the bar."""
    rng = np.random.default_rng(seed)
    free = [0.0] * WORKERS
    finish = []
    for k in range(SAMPLES // CHUNK):
        worker = int(np.argmin(free))
        free[worker] += 20.0 if k < WORKERS else 6.0 * rng.uniform(0.4, 1.6)
        finish.append(free[worker])
    finish.sort()
    times = np.arange(0.0, finish[-1] + 0.1, 0.1)
    return [(t, CHUNK * int(np.searchsorted(finish, t, side="right"))) for t in times]


def test_the_time_left_is_never_below_80_percent_of_the_elapsed_speed_after_10_percent() -> None:
    eta = Eta(SAMPLES)
    shown = []
    for t, done in schedule():
        eta.update(t, done)
        left = eta.remaining(t)
        if done < SHOWN_AFTER * SAMPLES:
            assert left is None  # too little to go on: nothing shown
            continue
        assert left is not None
        by_elapsed = (SAMPLES - done) * t / done
        assert left >= FLOOR * by_elapsed - 1e-9, (t, done, left, by_elapsed)
        shown.append(left)
    assert shown[-1] == 0.0  # done: nothing left


def test_without_the_floor_the_smoothed_speed_alone_breaks_the_rule(monkeypatch) -> None:
    """The check can fail: the smoothed speed alone, after the slow start, reads the time
    left far below what the elapsed speed gives (the floor is what holds the rule)."""
    import jointplay.progress

    monkeypatch.setattr(jointplay.progress, "FLOOR", 1e-9)
    eta = Eta(SAMPLES)
    worst = np.inf
    for t, done in schedule():
        eta.update(t, done)
        left = eta.remaining(t)
        if left is not None and done < SAMPLES:
            worst = min(worst, left / ((SAMPLES - done) * t / done))
    assert worst < FLOOR


@pytest.mark.parametrize("total", [0, 10])
def test_nothing_is_shown_before_any_work_is_done(total: int) -> None:
    eta = Eta(total)
    eta.update(5.0, 0)
    assert eta.remaining(5.0) is None


def test_the_progress_bar_column_shows_the_rule_s_time_left() -> None:
    """The column a real bar draws (a fake clock drives it): nothing before 10 % of the work,
    then a time left never below 80 % of what the elapsed speed gives."""
    import io

    from rich.console import Console
    from rich.progress import Progress

    from jointplay.progress import eta_column

    clock = [0.0]
    column = eta_column()
    bar = Progress(column, console=Console(file=io.StringIO()), get_time=lambda: clock[0])
    task_id = bar.add_task("samples", total=SAMPLES)
    bar.start_task(task_id)
    for t, done in schedule()[::10]:  # the bar redraws every second here
        clock[0] = t
        bar.update(task_id, completed=done)
        shown = str(column.render(bar.tasks[0]))
        if done < SHOWN_AFTER * SAMPLES:
            assert shown == "-:--:--"
            continue
        hours, minutes, seconds = (int(part) for part in shown.split(":"))
        left = 3600 * hours + 60 * minutes + seconds
        assert left >= FLOOR * (SAMPLES - done) * t / done - 0.5, (t, done, shown)
