"""Dynamic studies check that the scatter they report is the mechanism's, not the integrator's
(:func:`jointplay.tolerance.analysis.convergence_finding`).

Studies of at least ``CONVERGENCE_MIN_POINTS`` successful points are checked. At the default
tolerances the paper's conventional IFM set converges (its peaks move by < 1 % of their spread
over a study when the tolerances are 100x tighter; measured 0.07 %). Its RM (Hunt–Crossley
family) set converges on some seeds and warns on others: on seeds 1-12 (40 samples, one
revolution from rest) the share is 0.6-9.2 % on six of them (2, 3, 4, 8, 9, 12) and 12-157 %
on the other six. Before the contact memory v0 became the rate at the instant of contact
(commit 6016863), 11 of those 12 seeds warned (10-113 %). A coarse integration (rtol 1e-3)
does not converge: 91-137 % of the spread."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from jointplay.dynamics.simulate import SolverOptions
from jointplay.model.mechanism import Mechanism
from jointplay.study.methods import method_law
from jointplay.tolerance.analysis import (
    CONVERGENCE_LIMIT,
    CONVERGENCE_MIN_POINTS,
    CONVERGENCE_SAMPLES,
    CONVERGENCE_STATISTIC_SAMPLES,
    CONVERGENCE_TIGHTENING,
    _mean_shift,
    convergence_verdict,
    tolerance_study,
)
from jointplay.tolerance.execution import OK, Backend

LOCAL = Backend("local")
#: The paper's conventional set (the physical default is the one users get without a
#: contact): these tests are about the check, and it runs fast.
STUDY = {
    "responses": "dynamic", "contact": "ifm-conventional", "samples": 40, "seed": 1,
    "settle": 0, "revolutions": 1.0,
}  # fmt: skip


def test_the_conventional_set_converges_and_says_so(paper_fourbar: Mechanism) -> None:
    study = tolerance_study(paper_fourbar, backend=LOCAL, **STUDY)
    check = study.convergence
    assert check is not None and check.finding is None
    assert check.samples == CONVERGENCE_SAMPLES and 0 < check.share < CONVERGENCE_LIMIT
    assert "peaks-not-converged" not in {d.diagnostic.code for d in study.diagnostics}
    record = study.summary()["convergence_check"]
    assert record["converged"] is True and "100x tighter" in record["taken"]


@pytest.mark.parametrize(
    ("seed", "converges"),
    [
        # share 0.0046 (torque; 0.0064, torque and F_O4, with the onset tolerance at 1 % of
        # the clearance, before issue 40); 0.337 with the contact memory before 6016863
        (8, True),
        # share 0.75 (F_O4: an impact sequence that changes with the tolerances): one sample
        # of eight moved, and it runs irregularly (its section over 8 revolutions at rtol 1e-8
        # does not repeat), so the study is judged on its statistics (issue 40): F_O4_peak's
        # mean over 16 samples moved +0.275 N, within its +-0.276 N interval. Before, the
        # per-sample rule warned peaks-not-converged, "not usable as it stands" (the mean's
        # shift -0.28 to +0.46 of the spread). Seed 5 was this case with the onset tolerance
        # at 1 % (share 1.57; 1.13 before 6016863); at the 0.01 % default for laws that read
        # the impact velocity it converges (0.0077)
        (7, False),
    ],
)
def test_the_rm_set_converges_within_its_limit_or_on_its_statistics(
    paper_fourbar: Mechanism, seed: int, converges: bool
) -> None:
    """The paper's RM set at a fixed seed: the outcome measured for that seed, asserted,
    with the share on the right side of the limit; a study whose moved sample runs
    irregularly is judged, and passes, on its statistics."""
    law = method_law("rm-conventional", paper_fourbar)[0]
    study = tolerance_study(paper_fourbar, backend=LOCAL, **{**STUDY, "seed": seed, "contact": law})
    check = study.convergence
    assert check is not None
    assert (check.share < CONVERGENCE_LIMIT) is converges, check.share
    assert check.finding is None and check.usable
    codes = {d.diagnostic.code for d in study.diagnostics}
    assert "peaks-not-converged" not in codes
    assert study.summary()["convergence_check"]["converged"] is True
    if converges:
        assert check.rule == "per-sample" and check.note is None
        assert check.verdict.startswith("usable: the peaks moved")
    else:
        assert check.rule == "statistics" and (check.moved, check.irregular) == (1, 1)
        assert check.note is not None and "statistics-converged" in codes
        mean = check.statistics["F_O4_peak"][0]
        assert mean.judged and abs(mean.shift) <= mean.half_width
        assert check.verdict.startswith("usable for its statistics")
    record = study.summary()["convergence_check"]
    assert record["usable"] is check.usable and record["verdict"] == check.verdict


def test_a_coarse_integration_warns_with_the_share_recomputed_here(
    paper_fourbar: Mechanism,
) -> None:
    coarse = SolverOptions(rtol=1e-3)
    study = tolerance_study(paper_fourbar, backend=LOCAL, solver=coarse, **STUDY)
    check = study.convergence
    assert check is not None and check.finding is not None
    assert check.finding.diagnostic.code == "peaks-not-converged"
    assert check.finding.line().startswith(f"warning: peaks-not-converged: {check.response}:")
    # the samples that moved, classified at rtol 1e-5 over 8 revolutions: all of the first
    # eight's irregular, so the check ran 16; of the 15 that moved one approaches a cycle
    # ("converging": its peaks are not draws), so the per-sample rule judges all 16
    assert check.rule == "per-sample" and check.samples == CONVERGENCE_STATISTIC_SAMPLES
    assert (check.moved, check.irregular) == (15, 14)
    assert "1 of the 15 samples that moved does not run irregularly" in check.finding.line()
    # the share, recomputed from the model with tightened tolerances
    r = study.result
    ok = np.flatnonzero(r.run.status == OK)
    rows = ok[: check.samples]
    from jointplay.tolerance.analysis import build_model

    model, _ = build_model(
        paper_fourbar,
        study.spec,
        "dynamic",
        contact="ifm-conventional",
        settle=0,
        revolutions=1.0,
        solver=coarse,
    )
    loose = model.solver
    tight = dataclasses.replace(
        loose,
        rtol=loose.rtol / CONVERGENCE_TIGHTENING,
        atol_position=loose.atol_position / CONVERGENCE_TIGHTENING,
        atol_velocity=loose.atol_velocity / CONVERGENCE_TIGHTENING,
    )
    again = dataclasses.replace(model, solver=tight).evaluate(r.x[rows])
    j = r.response_names.index(check.response)
    spread = np.std(r.run.values[ok, j], ddof=1)
    share = np.max(np.abs(again.values[:, j] - r.run.values[rows, j])) / spread
    assert check.share == pytest.approx(share, rel=1e-9)
    assert check.share > CONVERGENCE_LIMIT
    # the mean of the 16 changes (measured: -0.07 of the spread, interval -0.33 to +0.19; over
    # the first 8 it was -0.60, interval -0.97 to -0.23): not shown within +-0.1, not usable
    signed = (again.values[:, j] - r.run.values[rows, j]) / spread
    assert check.mean_shift == pytest.approx(np.mean(signed), rel=1e-9)
    assert check.finding.line().endswith("Verdict: " + check.verdict) and not check.usable
    assert check.verdict.startswith("not usable")
    # the verdict is the worst response's; where the others stand, recomputed here
    spreads = np.std(r.run.values[ok], axis=0, ddof=1)
    shares = np.max(np.abs(again.values - r.run.values[rows]), axis=0) / spreads
    others = [k for k in range(len(shares)) if k != j and np.isfinite(shares[k])]
    within = sum(int(shares[k] <= CONVERGENCE_LIMIT) for k in others)
    assert f"of the other {len(others)} responses, {within} moved within" in check.verdict
    record = study.summary()["convergence_check"]
    assert record["mean_change_over_spread"] == check.mean_shift
    assert record["mean_change_interval_over_spread"] == list(check.mean_shift_interval)


def test_the_mean_shift_is_a_bonferroni_t_interval_over_the_spread() -> None:
    """Changes 1, 2, 3, 4 (mean 2.5, standard deviation 1.2910) over a spread of 2: with one
    response compared the interval is ±t(0.975, 3) s/√4 = ±3.1824·1.2910/2; with ten it is
    ±t(0.9975, 3)·1.2910/2 (t table: 3.1824463, 7.4533185); a failed sample (NaN) is left out."""
    changes = np.array([1.0, 2.0, 3.0, 4.0, np.nan])
    shift, (low, high) = _mean_shift(changes, 2.0, 1)
    half = 3.1824463053 * 1.2909944487 / 2
    assert shift == pytest.approx(1.25)
    assert (low, high) == pytest.approx(((2.5 - half) / 2, (2.5 + half) / 2), rel=1e-9)
    _, (low10, high10) = _mean_shift(changes, 2.0, 10)
    half10 = 7.4533185052 * 1.2909944487 / 2
    assert (low10, high10) == pytest.approx(((2.5 - half10) / 2, (2.5 + half10) / 2), rel=1e-9)
    assert np.isnan(_mean_shift(np.array([1.0, np.nan]), 2.0, 1)[0])


@pytest.mark.parametrize(
    ("shift", "interval", "usable", "start"),
    [
        # the coarse integration's measured shift: the interval excludes zero
        (-0.60, (-0.97, -0.23), False, "not usable: the integration biases the study"),
        # the physical default's measured shift (docs/cli.md): zero inside, but +-62 %
        (0.06, (-0.49, 0.62), False, "not usable as it stands: 8 samples bound"),
        # zero inside and the whole interval within the limit: the statistics hold
        (0.02, (-CONVERGENCE_LIMIT + 0.01, CONVERGENCE_LIMIT - 0.01), True, "usable for its"),
        # just beyond the limit on one side
        (0.02, (-0.05, CONVERGENCE_LIMIT + 0.01), False, "not usable as it stands"),
        # too few samples ran again for an interval
        (float("nan"), (float("nan"), float("nan")), False, "not usable as it stands"),
    ],
)
def test_the_warning_ends_with_a_verdict_by_the_stated_rule(
    shift: float, interval: tuple[float, float], usable: bool, start: str
) -> None:
    """Usable only where the mean change's interval lies within +-CONVERGENCE_LIMIT of the
    spread (docs/cli.md, "Converged?"); the sentence ends the warning and names the verdict."""
    verdict_usable, sentence = convergence_verdict(shift, interval, 8, 1e-8)
    assert verdict_usable is usable
    assert sentence[sentence.index("Verdict: ") + len("Verdict: ") :].startswith(start)
    if np.isfinite(shift):
        assert f"{100 * shift:+.0f} % of the spread" in sentence
    if not usable and interval[1] < 0:
        assert "({rtol} 1e-08)" in sentence  # the caller names the setting (--rtol)


def test_kinematic_and_small_studies_are_not_checked(paper_fourbar: Mechanism) -> None:
    study = tolerance_study(paper_fourbar, samples=50, seed=1, backend=LOCAL)
    assert study.convergence is None and study.summary()["convergence_check"] is None
    small = {**STUDY, "samples": CONVERGENCE_MIN_POINTS - 1, "revolutions": 0.25}
    assert tolerance_study(paper_fourbar, backend=LOCAL, **small).convergence is None
