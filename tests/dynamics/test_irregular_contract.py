"""The accuracy contract of irregular (chaotic) running, on the dry paper four-bar (issue 40).

Dry joints (no film), steady start, settle 2, then 150 analysed revolutions, at the default
tolerances and at all three tolerances (rtol, atol_position, atol_velocity) 100 times tighter.
The motion is not periodic. The contract asked for (docs/performance.md, "Accuracy of
irregular (chaotic) running"): the per-revolution peak is a draw (two runs' revolutions are
unrelated), but the *statistics* of the per-revolution peak — the mean and the 95th
percentile — change by less than their reported (95 %) intervals when the tolerances are
tightened x100.

Measured (2026-11-29): the per-revolution peaks of the two runs differ by a median 11-16 %
(forces). The mean and 95th percentile of F_O4 and omega4, and the 95th percentile of F_B,
meet the contract. The mean of F_O2, F_A and F_B and the 95th percentile of F_O2 and F_A do
NOT: the motion has (at least) two states — a calm one (F_O2 mean about 97 N, where the runs
at rtol 1e-7 and 1e-10 stay for 150-250 revolutions) and a rougher one (F_O2 mean 108-119 N,
where those at 1e-6 and 1e-8 go) — and which one a trajectory dwells in over hundreds of
revolutions is itself decided by the tolerances. These cases are strict xfails: the contract
does not hold for them, and the test says so until it does.

An ensemble of 12 runs from start angles 0.01 deg apart, settle 2 + 20 revolutions each
(``simulate_ensemble``; the runs are the batches) samples the states instead of dwelling in
one: there the means of F_O2, F_A, F_B and omega4 and the 95th percentiles of F_O2, F_A and
F_O4 meet the contract; F_O4's mean does not (3 %), and two 95th percentiles cannot be judged
at that size (strict xfails, ``ENSEMBLE_NOT_MET``). The whole file: about 3.5 min on the
2-core machine under load (the two long runs 100 s, the two ensembles 100 s).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from jointplay.dynamics.ensemble import Ensemble, simulate_ensemble
from jointplay.dynamics.irregular import agrees, peak_distribution
from jointplay.dynamics.settings import RunSettings, simulate_run
from jointplay.dynamics.setup import ContactModel
from jointplay.dynamics.simulate import SolverOptions
from jointplay.model.mechanism import Mechanism

pytestmark = pytest.mark.slow

REVOLUTIONS = 150
QUANTITIES = ("F_O2", "F_A", "F_B", "F_O4", "omega4")
STATISTICS = ("mean", "quantile")

#: Measured: these statistics change by more than their intervals (module docstring).
NOT_CONVERGED = {
    (
        "F_O2",
        "mean",
    ): "measured 118.7 [113.7, 123.7] N at the default against 107.8 [105.2, 110.3] N",
    ("F_A", "mean"): "measured 114.1 [108.8, 119.4] N at the default against 101.7 [99.3, 104.0] N",
    (
        "F_B",
        "mean",
    ): "measured 132.0 [129.3, 134.7] N at the default against 124.5 [121.7, 127.2] N",
    (
        "F_O2",
        "quantile",
    ): "measured 157.9 [148.6, 177.3] N at the default against 135.5 [129.5, 154.3] N",
    (
        "F_A",
        "quantile",
    ): "measured 150.7 N (above 142.5) at the default against 130.0 [120.7, 147.3] N",
}


def _tighter(solver: SolverOptions, factor: float) -> SolverOptions:
    return dataclasses.replace(
        solver,
        rtol=solver.rtol / factor,
        atol_position=solver.atol_position / factor,
        atol_velocity=solver.atol_velocity / factor,
        max_steps=10 * solver.max_steps,
    )


@pytest.fixture(scope="module")
def dry_runs(paper_fourbar: Mechanism) -> dict[str, dict[str, list[float]]]:
    """Per-revolution peaks of the analysed revolutions at the default and x100 tolerances."""
    out = {}
    for name, factor in (("default", 1.0), ("tight", 100.0)):
        run = RunSettings(
            contact=ContactModel(lubrication="dry"),
            settle=2,
            revolutions=float(REVOLUTIONS),
            solver=_tighter(SolverOptions(), factor),
        )
        result = simulate_run(paper_fourbar, None, run)
        running = result.running
        assert running.irregular, running.periodicity.verdict
        assert set(QUANTITIES) <= set(running.distributions)
        out[name] = running.analysed_per_revolution
    return out


def test_the_per_revolution_peak_is_a_draw(dry_runs) -> None:
    """What a run reports today (the peak of a revolution, and the largest of them) does not
    converge: the same revolution of the two runs differs by as much as two independent
    draws. A per-trajectory contract fails here; converged trajectories differ by < 1e-3."""
    for name in ("F_O2", "F_A", "F_B", "F_O4"):
        default = np.array(dry_runs["default"][name])
        tight = np.array(dry_runs["tight"][name])
        assert default.size == tight.size == REVOLUTIONS
        paired = np.median(np.abs(default - tight) / tight)
        assert paired > 0.05, (name, paired)  # measured 0.11-0.16


def _cases(expected_to_fail: dict[tuple[str, str], str]) -> list:
    cases = []
    for quantity in QUANTITIES:
        for statistic in STATISTICS:
            reason = expected_to_fail.get((quantity, statistic))
            marks = [] if reason is None else [pytest.mark.xfail(strict=True, reason=reason)]
            cases.append(pytest.param(quantity, statistic, marks=marks))
    return cases


@pytest.mark.parametrize(("quantity", "statistic"), _cases(NOT_CONVERGED))
def test_the_statistics_converge_when_the_tolerances_tighten_x100(
    dry_runs, quantity: str, statistic: str
) -> None:
    """The difference lies within its own 95 % interval (``agrees``), judged only where the
    sides of the two intervals that face each other are bounded."""
    default = peak_distribution(dry_runs["default"][quantity])
    tight = peak_distribution(dry_runs["tight"][quantity])
    found = getattr(default, statistic), getattr(tight, statistic)
    low, high = sorted(found, key=lambda e: e.value)
    assert np.isfinite(low.high) and np.isfinite(high.low), found
    assert agrees(default, tight, (statistic,))[statistic], found


# An ensemble of runs from perturbed starts (``simulate_ensemble``): the runs sample the
# states instead of dwelling in one, and they are the batches of the intervals.
ENSEMBLE_RUNS = 12
ENSEMBLE_REVOLUTIONS = 20


@pytest.fixture(scope="module")
def dry_ensembles(paper_fourbar: Mechanism) -> dict[str, Ensemble]:
    """Ensembles of 12 runs (start angles 0.01 deg apart), settle 2 + 20 revolutions each, at
    the default and x100 tolerances."""
    out = {}
    for name, factor in (("default", 1.0), ("tight", 100.0)):
        run = RunSettings(
            contact=ContactModel(lubrication="dry"),
            settle=2,
            revolutions=float(ENSEMBLE_REVOLUTIONS),
            solver=_tighter(SolverOptions(), factor),
        )
        out[name] = simulate_ensemble(paper_fourbar, None, run, runs=ENSEMBLE_RUNS)
    return out


#: Measured (12 x 20 revolutions): F_O4's mean moves by 3 % (beyond its interval) — a
#: tolerance effect on the calm state's F_O4 that the ensemble resolves; the 95th percentiles
#: of F_B and omega4 are not judged: the default's is unbounded above at this size (fewer than
#: 72 effective revolutions: the runs differ, so they count for less than their revolutions).
ENSEMBLE_NOT_MET = {
    ("F_O4", "mean"): "measured 84.50 [82.96, 86.05] N at the default against 81.85 [80.34, "
    "83.35] N",
    ("F_B", "quantile"): "not judged: 141.4 N (above 135.0) at the default, 142.0 [137.9, "
    "152.7] N tight",
    ("omega4", "quantile"): "not judged: 13.8834 (above 13.8832) at the default, 13.8839 "
    "[13.8825, 13.8863] rad/s tight",
}


@pytest.mark.parametrize(("quantity", "statistic"), _cases(ENSEMBLE_NOT_MET))
def test_the_ensemble_statistics_converge_when_the_tolerances_tighten_x100(
    dry_ensembles, quantity: str, statistic: str
) -> None:
    """The contract on the ensemble: the difference within its own 95 % interval. Measured:
    met by the means of F_O2, F_A, F_B and omega4 and the 95th percentiles of F_O2, F_A and
    F_O4, which one trajectory's statistics miss by 8-12 %."""
    default = dry_ensembles["default"].distributions[quantity]
    tight = dry_ensembles["tight"].distributions[quantity]
    assert default.revolutions == tight.revolutions == ENSEMBLE_RUNS * ENSEMBLE_REVOLUTIONS
    found = getattr(default, statistic), getattr(tight, statistic)
    low, high = sorted(found, key=lambda e: e.value)
    assert np.isfinite(low.high) and np.isfinite(high.low), found
    assert agrees(default, tight, (statistic,))[statistic], found
