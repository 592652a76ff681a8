"""An ensemble of runs from perturbed starts: statistics of irregular running that converge.

One trajectory of a chaotic motion can dwell in one of several states for hundreds of
revolutions, and which one it dwells in changes with the integrator's tolerances (the dry
paper four-bar: docs/performance.md, "Accuracy of irregular (chaotic) running"), so even
the statistics of its per-revolution peaks are a draw. :func:`simulate_ensemble` runs the
mechanism ``runs`` times, each started at a crank angle ``step_deg`` further on (a
perturbation far below anything a drawing fixes, which the chaos amplifies into an
independent trajectory), and gives each quantity's per-revolution peak distribution over the
ensemble with the runs as batches (:func:`jointplay.dynamics.irregular.replicate_distribution`:
independent replications), whose intervals hold however long each run dwells.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from jointplay.dynamics.clearance import ClearanceJoint
from jointplay.dynamics.irregular import (
    MIN_RUNS,
    PeakDistribution,
    replicate_distribution,
)
from jointplay.dynamics.settings import RunSettings, simulate_run
from jointplay.model.mechanism import Mechanism

#: Runs of an ensemble unless told.
DEFAULT_RUNS = 12

#: The crank start angle between successive runs, deg.
DEFAULT_STEP_DEG = 0.01


@dataclass(frozen=True)
class Ensemble:
    """Per-revolution peak distributions over an ensemble of runs from perturbed starts.

    Attributes:
        start_offsets_deg: each run's crank start angle past the mechanism's, deg.
        revolutions: the whole analysed revolutions of each run.
        per_run: each run's per-revolution peaks of every quantity (analysed revolutions).
        verdicts: each run's periodicity verdict.
        distributions: each quantity's distribution over the ensemble, runs as batches.
    """

    start_offsets_deg: tuple[float, ...]
    revolutions: int
    per_run: tuple[dict[str, list[float]], ...]
    verdicts: tuple[str, ...]
    distributions: dict[str, PeakDistribution]

    def summary(self) -> dict[str, Any]:
        """JSON-ready: how the ensemble was run and its statistics."""
        return {
            "runs": len(self.per_run),
            "revolutions_per_run": self.revolutions,
            "start_offsets_deg": list(self.start_offsets_deg),
            "verdicts": list(self.verdicts),
            "per_run": list(self.per_run),
            "statistics": {name: d.as_dict() for name, d in self.distributions.items()},
            "taken": (
                "each run started that much further on in crank angle; the runs are the "
                "batches of the mean's Student t interval (independent replications) and set "
                "the effective sample of the percentile's and the max's intervals"
            ),
        }


def simulate_ensemble(
    mechanism: Mechanism,
    clearances: Sequence[ClearanceJoint] | None,
    run: RunSettings,
    runs: int = DEFAULT_RUNS,
    step_deg: float = DEFAULT_STEP_DEG,
) -> Ensemble:
    """Simulate ``runs`` runs of ``run`` (settle + revolutions each), each started
    ``step_deg`` degrees of crank further on, and the ensemble's peak distributions.

    Args:
        mechanism: the mechanism (its driver's start angle is the first run's).
        clearances: its clearance joints (``None``: ``run``'s contact on every joint with a
            clearance in its fit).
        run: each run's settings; its ``revolutions`` are rounded down to whole ones.
        runs: the number of runs (at least :data:`~jointplay.dynamics.irregular.MIN_RUNS`).
        step_deg: the start angle between successive runs, deg (> 0).

    Raises:
        ValueError: fewer runs than the least, a step that is not > 0, or fewer than one whole
            analysed revolution.
    """
    if isinstance(runs, bool) or not isinstance(runs, int) or runs < MIN_RUNS:
        raise ValueError(f"an ensemble needs a whole number of runs >= {MIN_RUNS}, got {runs!r}")
    if not (math.isfinite(step_deg) and step_deg > 0):
        raise ValueError(f"the start angle step must be > 0 degrees, got {step_deg!r}")
    whole = math.floor(run.revolutions + 1e-9)
    if whole < 1:
        raise ValueError(f"an ensemble needs at least 1 whole revolution per run, got {whole}")
    each = dataclasses.replace(run, revolutions=float(whole))
    offsets = tuple(step_deg * k for k in range(runs))
    per_run = []
    verdicts = []
    for offset in offsets:
        started = mechanism.with_driver(
            start_angle=mechanism.driver.start_angle + math.radians(offset)
        )
        running = simulate_run(started, clearances, each).running
        per_run.append(running.analysed_per_revolution)
        verdicts.append(running.periodicity.verdict)
    distributions = {
        name: replicate_distribution([values[name] for values in per_run]) for name in per_run[0]
    }
    return Ensemble(
        start_offsets_deg=offsets,
        revolutions=whole,
        per_run=tuple(per_run),
        verdicts=tuple(verdicts),
        distributions=distributions,
    )
