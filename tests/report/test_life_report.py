"""The population life's files and report, from a result built on a stub model (no
dynamics): the first-screen answer, the probability plot, the wear profiles."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from jointplay.report.life import write_life
from jointplay.study.life_result import HOUR, LifeResult, Lives


def _result(failures: bool = True) -> LifeResult:
    rng = np.random.default_rng(3)
    n = 40
    hours = 1500 * HOUR
    life = 1000 * HOUR * rng.weibull(2.0, n) if failures else np.full(n, hours)
    censored = life >= hours
    life = np.minimum(life, hours)
    failing = tuple(
        "" if c else ("rocker_speed_error <= 2 %" if i % 5 else "clearance of A <= 40 µm")
        for i, c in enumerate(censored)
    )
    history = tuple(
        ((0.0, (20e-6, 15e-6)), (float(t) / 2, (30e-6, 20e-6)), (float(t), (40e-6, 25e-6)))
        for t in life
    )
    lives = Lives(("A", "B"), life, censored, failing, np.full(n, 5), history, hours)
    features = rng.normal(size=(n, 2))
    return LifeResult(
        "paper-fourbar", ("rocker_speed_error <= 2 %", "clearance of A <= 40 µm"),
        ("clearance_A", "clearance_B"), ("hole_A", "pin_A"), features, features, lives,
        {"scheme": "H8/g7 / m", "clearance_limit_m": {"A": 40e-6}, "update_rule": "stated"},
    )  # fmt: skip


def test_the_report_opens_with_the_answer_and_shows_the_plots(tmp_path: Path):
    result = _result()
    written = write_life(result, tmp_path)
    names = {p.name for p in written}
    assert {"lives.csv", "histories.csv", "summary.json", "report.html"} <= names
    assert {"life_probability.png", "life_profiles.png"} <= names
    html = (tmp_path / "report.html").read_text()
    headline = result.headline()
    assert headline.startswith("B10 = ")
    assert "at 90 %" in headline
    failed = [f for f in result.lives.failing if f]
    share = failed.count("rocker_speed_error <= 2 %") / len(failed)
    assert f"rocker_speed_error <= 2 % fails first in {100 * share:.0f} %" in headline
    # the answer comes first: before the contents and any figure
    assert html.index(headline.split(";")[0]) < html.index("<figure")
    assert html.index(headline.split(";")[0]) < html.index("Contents")
    summary = json.loads((tmp_path / "summary.json").read_text())
    b10 = summary["weibull"]["B10_h"]
    low, high = summary["weibull"]["B10_interval_h"]
    assert low < b10 < high
    assert summary["failing_share"]["rocker_speed_error <= 2 %"] == pytest.approx(share)
    lives = pd.read_csv(tmp_path / "lives.csv")
    assert len(lives) == 40
    histories = pd.read_csv(tmp_path / "histories.csv")
    assert set(histories.columns) == {"mechanism", "hours", "clearance_A_um", "clearance_B_um"}


def test_all_censored_says_so_in_one_line_with_a_bound(tmp_path: Path):
    result = _result(failures=False)
    headline = result.headline()
    assert headline.startswith("no mechanism of 40 failed within 1 500 h")
    assert "B10 > 1 500 h at 98.52 % confidence" in headline
    written = write_life(result, tmp_path)
    assert "life_probability.png" not in {p.name for p in written}
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["weibull"] is None
    assert "no Weibull fit" in summary["weibull_note"]
