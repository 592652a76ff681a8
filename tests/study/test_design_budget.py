"""One progress bar for a whole design study, and a time budget (``max_time``)."""

from __future__ import annotations

import json
from contextlib import contextmanager

import pandas as pd

from jointplay.io.output import json_text
from jointplay.study import design as design_module
from jointplay.study.design import Earlier, design_study
from jointplay.tolerance.execution import Backend

SERIAL = Backend("serial")
FITS = ["H9/d9", "H11/c11"]
CLASSES = ["c", "v"]
REQUIRE = ["omega4_peak <= 100 rad/s"]  # kinematic: every scheme decided at 1 600


def _kept(result, tmp_path) -> Earlier:
    """The result as its folder keeps it: summary.json's settings and samples.parquet."""
    path = tmp_path / "samples.parquet"
    result.samples.to_parquet(path, index=False)
    settings = json.loads(json_text(result.summary()))["settings"]
    return Earlier(str(tmp_path), settings, pd.read_parquet(path))


def test_one_bar_for_the_study_counts_down_what_it_can_still_need(
    paper_fourbar, monkeypatch
) -> None:
    seen: dict[str, list] = {"start": [], "advance": [], "update": []}

    class Recorder:
        def advance(self, count: int) -> None:
            seen["advance"].append(count)

        def update(self, *, total=None, description=None) -> None:
            seen["update"].append((total, description))

    @contextmanager
    def study_bar(enabled, total, description):
        seen["start"].append((enabled, total, description))
        yield Recorder()

    monkeypatch.setattr(design_module, "study_bar", study_bar)
    result = design_study(
        paper_fourbar, FITS, CLASSES, REQUIRE, max_samples=2000, backend=SERIAL, progress=True
    )
    # one bar: two length classes (a kinematic study evaluates each once) up to 2 000 each
    assert seen["start"] == [(True, 2 * 2000, "design: 0/4 schemes decided; samples")]
    # cost-ordered: class v (both fits on its one stream) meets at 1 600, and class c, dearer,
    # never runs; every sample computed once
    assert sum(seen["advance"]) == 1600
    totals = [t for t, _ in seen["update"]]
    # while open the most still needed stays 4 000; once decided it is what was done
    assert totals[:-1] == [2 * 2000] * (len(totals) - 1) and totals[-1] == 1600
    assert seen["update"][-1][1] == "design: 4/4 schemes decided; samples"
    assert (result.table["samples"] == 1600).all() and len(result.table) == 2


def test_a_time_budget_stops_with_the_verdicts_reached_and_resumes(paper_fourbar, tmp_path) -> None:
    cut = design_study(paper_fourbar, FITS, CLASSES, REQUIRE, max_time=1e-9, backend=SERIAL)
    # the first block always runs; the next would end after the budget
    # (the cheapest class's stream, both its schemes); class c waits, not run
    assert not cut.interrupted and (cut.table["samples"] == 100).all() and len(cut.table) == 2
    assert (cut.table["stopped"] == "time").all() and cut.settings["stopped_at_max_time"]
    assert [r["stopped"] for r in cut.settings["not_run"]] == ["time", "time"]
    rate = cut.settings["samples_per_s"]
    assert rate > 0
    note = cut.time_note
    assert note is not None and note.startswith(
        "stopped at the time budget (1e-09 s): 4 scheme(s) undecided (2 not run yet)"
    )
    assert (
        f"resume with max_time 2e-09 s would allow ~{rate * 2e-9:,.0f} more samples, the "
        "cheapest open scheme first" in note
    )
    assert cut.summary()["time_note"] == note
    resumed = design_study(
        paper_fourbar, FITS, CLASSES, REQUIRE, backend=SERIAL, resume=_kept(cut, tmp_path)
    )
    whole = design_study(paper_fourbar, FITS, CLASSES, REQUIRE, backend=SERIAL)
    pd.testing.assert_frame_equal(resumed.table, whole.table, check_exact=True)
    assert resumed.time_note is None
