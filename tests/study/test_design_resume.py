"""--resume: a design study goes on from its earlier run's samples and gives, bit for bit,
what one uninterrupted run gives; a changed study is refused with the difference named."""

from __future__ import annotations

import dataclasses
import json
import re

import numpy as np
import pandas as pd
import pytest

from jointplay.errors import ConfigError
from jointplay.io.output import json_text
from jointplay.study import design as design_module
from jointplay.study.design import Earlier, design_study
from jointplay.tolerance.execution import NOT_RUN, Backend

SERIAL = Backend("serial")
FITS = ["H9/d9", "H11/c11"]
CLASSES = ["m", "c", "v"]
#: kinematic (fast), cost-ordered: class v (with both fits on its one stream) fails at the
#: first look, class c meets at the look at 1 600 (no failure), class m, dearer, never runs
REQUIRE = ["omega4_peak <= 13.97 rad/s", "rocker_swing <= 56 deg"]


def _study(mechanism, **options):
    return design_study(mechanism, FITS, CLASSES, REQUIRE, backend=SERIAL, **options)


def _kept(result, tmp_path) -> Earlier:
    """The result as its folder keeps it: summary.json's settings and samples.parquet."""
    path = tmp_path / "samples.parquet"
    result.samples.to_parquet(path, index=False)
    settings = json.loads(json_text(result.summary()))["settings"]
    return Earlier(str(tmp_path), settings, pd.read_parquet(path))


def _interrupting(monkeypatch, at_call: int) -> None:
    """The study's runs, with the ``at_call``-th interrupted half way through its samples
    (the first key's block finished, the others not run), as Ctrl-C leaves a run."""
    real = design_module.run
    calls = {"n": 0}

    def run(model, x, **kwargs):
        outcome = real(model, x, **kwargs)
        calls["n"] += 1
        if calls["n"] != at_call:
            return outcome
        status = outcome.status.copy()
        status[len(x) // 2 :] = NOT_RUN
        return dataclasses.replace(outcome, status=status, interrupted=True)

    monkeypatch.setattr(design_module, "run", run)


def test_an_interrupted_study_resumed_is_the_uninterrupted_one(
    paper_fourbar, tmp_path, monkeypatch
) -> None:
    whole = _study(paper_fourbar)
    decided = whole.table.set_index("scheme")["decided_at"].to_dict()
    assert decided == {"H9/d9 / c": 1600, "H9/d9 / v": 100, "H11/c11 / c": 1600, "H11/c11 / v": 100}
    assert [r["scheme"] for r in whole.settings["not_run"]] == ["H9/d9 / m", "H11/c11 / m"]
    assert whole.best == "H11/c11 / c"
    with monkeypatch.context() as patch:
        _interrupting(patch, at_call=9)  # of 17 blocks: class v's one, then class c's 16
        cut = _study(paper_fourbar)
    assert cut.interrupted and cut.best is None
    assert cut.verdict.endswith("(resume the study: its samples are kept)")
    assert sorted(cut.table["samples"]) == [100, 100, 700, 700]  # the 9th block not kept
    resumed = _study(paper_fourbar, resume=_kept(cut, tmp_path))
    assert not resumed.interrupted
    pd.testing.assert_frame_equal(resumed.table, whole.table, check_exact=True)
    pd.testing.assert_frame_equal(resumed.samples, whole.samples, check_exact=True)
    assert resumed.best == whole.best and resumed.verdict == whole.verdict
    assert resumed.settings["not_run"] == whole.settings["not_run"]
    runs = resumed.settings["runs"]
    assert [r["run"] for r in runs] == [1, 2] and runs[0]["interrupted"]
    kept = sum(cut.samples.groupby("scheme")["sample"].count().groupby(
        cut.table.set_index("scheme")["length_class"]).max())  # fmt: skip
    assert runs[1]["samples_kept"] == kept == runs[0]["samples_computed"] == 800
    assert runs[1]["samples_computed"] == 100 + 1600 - kept  # one stream per length class


def test_a_larger_max_samples_goes_on_from_an_undecided_study(paper_fourbar, tmp_path) -> None:
    short = _study(paper_fourbar, max_samples=800)
    stopped = short.table.set_index("scheme")["stopped"]
    # class c undecided at 800, so class m (dearer) got its turn, undecided too
    assert (stopped[stopped.index.str.endswith(("c", "m"))] == "max-samples").all()
    resumed = _study(paper_fourbar, resume=_kept(short, tmp_path))
    whole = _study(paper_fourbar)
    pd.testing.assert_frame_equal(resumed.table, whole.table, check_exact=True)
    assert resumed.settings["not_run"] == whole.settings["not_run"]  # class m no longer needed
    assert resumed.settings["runs"][1]["samples_computed"] == 800  # class c from 800 to 1 600


@pytest.mark.parametrize(
    ("change", "named"),
    [
        ({"requirements": ["omega4_peak <= 101 rad/s", REQUIRE[1]]}, "requirements[0].text"),
        ({"fits": ["H9/d9", "H8/f7"]}, "schemes[3]"),
        ({"seed": 1}, "seed"),
        ({"confidence": 0.99}, "confidence"),
    ],
)
def test_a_changed_study_is_refused_naming_the_difference(
    paper_fourbar, tmp_path, change, named
) -> None:
    earlier = _kept(_study(paper_fourbar, max_samples=200), tmp_path)
    options = {"fits": FITS, "requirements": REQUIRE, **change}
    pattern = "different " + re.escape(named) + ": .* there, .* now"
    with pytest.raises(ConfigError, match=pattern):
        design_study(
            paper_fourbar, options.pop("fits"), CLASSES, options.pop("requirements"),
            backend=SERIAL, resume=earlier, **options,
        )  # fmt: skip


def test_samples_not_of_the_study_stream_are_refused(paper_fourbar, tmp_path) -> None:
    earlier = _kept(_study(paper_fourbar, max_samples=200), tmp_path)
    samples = earlier.samples.copy()
    samples.loc[0, "length_crank"] = np.nextafter(samples.loc[0, "length_crank"], 1.0)
    with pytest.raises(ConfigError, match="not this study's sample stream"):
        _study(paper_fourbar, resume=dataclasses.replace(earlier, samples=samples))


@pytest.mark.slow
def test_a_dynamic_study_resumed_is_the_uninterrupted_one(
    paper_fourbar, tmp_path, monkeypatch
) -> None:
    """The same on the batch engine (peaks): two schemes, two blocks of 100 each, cheapest
    first (H11/c11 / c, undecided at 200, then H8/f7 / c), the last block interrupted."""
    options = {"responses": "dynamic", "max_samples": 200, "backend": SERIAL}
    args = (paper_fourbar, ["H8/f7", "H11/c11"], ["c"], ["joint_force <= 150 N"])
    whole = design_study(*args, **options)
    with monkeypatch.context() as patch:
        _interrupting(patch, at_call=4)
        cut = design_study(*args, **options)
    assert cut.interrupted and sorted(cut.table["samples"]) == [100, 200]
    resumed = design_study(*args, resume=_kept(cut, tmp_path), **options)
    pd.testing.assert_frame_equal(resumed.table, whole.table, check_exact=True)
    assert resumed.settings["runs"][1]["samples_computed"] == 100
