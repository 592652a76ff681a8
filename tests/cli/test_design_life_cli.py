"""``jointplay design --require "B10 >= … h"`` end to end on the paper four-bar: tiny (one
fit, one class, four samples, dry joints wearing fast, a short life, large update steps), and
its bad input (one line on stderr, exit 2, nothing written)."""

from __future__ import annotations

import json
from pathlib import Path

import pandas as pd
import pytest

from _errors import assert_one_line_error
from jointplay.cli import run

#: Dry joints, a large wear coefficient and a tight limit: each life ends within a handful of
#: re-simulations (about 8 h at A, O2, B or O4 for the first to pass 2 µm over the fit).
TINY = [
    "design",
    "--fits", "H8/g7",
    "--classes", "m",
    "--require", "B10 >= 40 h",
    "--clearance-limit", "+2 um",
    "--update-hours", "10 h",
    "--wear-coefficient", "1e-5",
    "--lubrication", "dry",
    "--samples", "4",
    "--backend", "local",
    "--no-model-sensitivity",
    "--no-progress",
]  # fmt: skip


@pytest.mark.slow
def test_a_b10_design_runs_end_to_end_and_shows_the_life_plot(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
):
    """Every sample's functional life is re-simulated and ends before 40 h: B10 >= 40 h fails
    on the exact interval, 4 failures in 4, and the report's first screen says so with the
    order-statistic B10; the report holds the Weibull-paper plot of the lives."""
    out = tmp_path / "design"
    status = run([*TINY, "--out", str(out)])
    text = capsys.readouterr().out
    assert status == 0, text
    samples = pd.read_parquet(out / "samples.parquet")
    assert len(samples) == 4
    life = samples["functional_life"] / 3600.0
    assert ((life > 0) & (life < 40)).all()
    assert not samples["functional_life_censored"].any()
    assert samples["functional_life_failing"].str.startswith("clearance of ").all()
    assert (samples["functional_life_simulations"] >= 3).all()  # re-simulated as it wore
    table = pd.read_parquet(out / "design.parquet")
    row = table.iloc[0]
    assert row["failures_B10 >= 40 h"] == 4
    assert row["verdict_B10 >= 40 h"] == "fails"
    assert row["verdict_high_B10 >= 40 h"] < 90.0  # the share outliving 40 h, below 90 %
    summary = json.loads((out / "summary.json").read_text())
    assert summary["settings"]["functional_life"]["hours_s"] == pytest.approx(40 * 3600.0)
    assert summary["settings"]["functional_life"]["first_step_s"] == pytest.approx(36000.0)
    assert summary["settings"]["functional_life"]["simulations"] == int(
        samples["functional_life_simulations"].sum()
    )
    assert "life: B10 >= 40 h: fails for H8/g7 / m — 4 of 4 samples fail before 40 h" in text
    html = (out / "report.html").read_text(encoding="utf-8")
    assert "Life: B10 &gt;= 40 h: fails" in html
    assert "B10 = " in html
    assert (out / "design_life.png").stat().st_size > 1000
    assert "design life" in html  # the figure, by its caption


@pytest.mark.parametrize(
    ("arguments", "culprit"),
    [
        (["--require", "B10 >= 40"], "did you mean 'B10 >= 40 h'?"),
        (["--require", "B120 >= 40 h"], "between 0 and 100"),
        (["--require", "B10 <= 40 h"], "write 'B10 >= 40 h'"),
        (["--require", "B10 >= 40 h"], "nothing ends a life"),
        (
            ["--require", "B10 >= 40 h", "--clearance-limit", "+2 um", "--update-hours", "50 h"],
            "--update-hours",
        ),
        (["--require", "joint_force <= 1 kN", "--update-hours", "5 h"], "--update-hours"),
    ],
    ids=["no-unit", "p-beyond-100", "upper-bound", "nothing-ends", "step-beyond", "no-b-p"],
)
def test_bad_b_p_input_is_one_line_exit_2_and_writes_nothing(
    arguments: list[str], culprit: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
):
    previous = tmp_path / "previous"
    previous.mkdir()
    (previous / "keep.txt").write_text("an earlier result")
    status = run(["design", "--fits", "H8/g7", "--classes", "m", "--no-progress",
                  *arguments, "--out", str(previous)])  # fmt: skip
    assert_one_line_error(status, capsys.readouterr().err, culprit)
    assert sorted(p.name for p in previous.iterdir()) == ["keep.txt"]
