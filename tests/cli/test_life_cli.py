"""``jointplay life``: a tiny end-to-end run through the dynamics, and bad input (one line on
stderr, exit 2, nothing written)."""

from __future__ import annotations

import json
from pathlib import Path

import pandas as pd
import pytest

from _errors import assert_one_line_error
from jointplay.cli import run

#: Dry joints, a large wear coefficient and a tight limit: lives of a few hours, so that two
#: mechanisms fail within a handful of re-simulations.
TINY = [
    "life",
    "--fit", "H8/g7",
    "--clearance-limit", "+2 um",
    "--hours", "40 h",
    "--update-hours", "10 h",
    "--wear-coefficient", "1e-4",
    "--lubrication", "dry",
    "--samples", "2",
    "--backend", "local",
    "--no-plots",
    "--no-progress",
]  # fmt: skip


def test_a_tiny_population_runs_end_to_end(tmp_path: Path, capsys: pytest.CaptureFixture[str]):
    out = tmp_path / "life"
    status = run([*TINY, "--out", str(out)])
    text = capsys.readouterr().out
    assert status == 0, text
    lives = pd.read_csv(out / "lives.csv")
    assert len(lives) == 2
    assert {"life_h", "censored", "failing", "simulations", "clearance_A", "hole_A"} <= set(
        lives.columns
    )
    summary = json.loads((out / "summary.json").read_text())
    assert summary["mechanisms"] == 2
    assert summary["failures"] + summary["censored"] == 2
    failed = lives[~lives["censored"]]
    # a failing mechanism names its criterion; each life took at least two simulations
    assert all(str(f).startswith("clearance of ") for f in failed["failing"])
    assert (lives["simulations"] >= 2).all()
    assert (lives["life_h"] <= 40.0 + 1e-9).all()
    assert summary["headline"] in text
    assert (out / "report.html").exists()
    assert (out / "histories.csv").exists()


def test_fixed_steps_walk_the_update_hours(tmp_path: Path, capsys: pytest.CaptureFixture[str]):
    """``--fixed-steps``: every accepted step is ``--update-hours`` (here 0.25 h) long, the last
    one apart (the crossing, or the hours), and the summary states the smallest step as the
    first (without it the smallest is a quarter of the first)."""
    out = tmp_path / "life"
    arguments = [*TINY]
    arguments[arguments.index("--update-hours") + 1] = "0.25 h"
    assert run([*arguments, "--fixed-steps", "--out", str(out)]) == 0, capsys.readouterr().out
    histories = pd.read_csv(out / "histories.csv")
    steps = [
        history["hours"].diff().dropna().to_numpy()[:-1]
        for _, history in histories.groupby("mechanism")
    ]
    assert sum(len(s) for s in steps) >= 2  # steps walked before the last
    for walked in steps:
        assert walked == pytest.approx([0.25] * len(walked))
    settings = json.loads((out / "summary.json").read_text())["settings"]
    assert settings["min_step_s"] == settings["first_step_s"] == 900.0
    assert "fixed steps" in settings["update_rule"]  # not "else shortened" alone


@pytest.mark.parametrize(
    ("arguments", "culprit"),
    [
        (["--hours", "0 h", "--clearance-limit", "80 um"], "--hours"),
        (["--hours", "100 h"], "nothing ends a life"),
        (["--hours", "100 h", "--clearance-limit", "80 um", "--tolerance", "60 %"], "--tolerance"),
        (["--hours", "100 h", "--clearance-limit", "80 um", "--precision", "abc"], "--precision"),
        (["--hours", "100 h", "--require", "life >= 100 h"], "the life is what"),
        (["--hours", "100 h", "--require", "rocker_speed_error <= 3"], "3 %"),
        (["--hours", "100 h", "--clearance-limit", "80 um", "--fit", "H8/g7", "--fit", "H7/g6"], "--fit"),
        (["--hours", "100 h", "--clearance-limit", "80 um", "--samples", "0"], "--samples"),
        (
            ["--hours", "10 h", "--update-hours", "20 h", "--clearance-limit", "80 um"],
            "--update-hours",
        ),
        (["--hours", "100 h", "--clearance-limit", "80 um", "--backend", "cloud"], "--backend"),
    ],
    ids=[
        "zero-hours", "no-criterion", "tolerance", "precision", "life-requirement",
        "bare-number", "two-fits", "zero-samples", "update-beyond-hours", "backend",
    ],
)  # fmt: skip
def test_bad_input_is_one_line_exit_2_and_writes_nothing(
    arguments: list[str], culprit: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
):
    previous = tmp_path / "previous"
    previous.mkdir()
    (previous / "keep.txt").write_text("an earlier result")
    status = run(["life", *arguments, "--out", str(previous)])
    assert_one_line_error(status, capsys.readouterr().err, culprit)
    assert sorted(p.name for p in previous.iterdir()) == ["keep.txt"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["previous"]


README = Path(__file__).resolve().parents[2] / "README.md"


#: How far the README's dry population-life figures may lie from a run's: their rounding and
#: the machine (dry wear runs chaotically): an AMD EPYC's shape 18.9 [12.3–26.7] and 9.7
#: simulations per life, an Intel Xeon's (AVX-512) 18.2 [11.7–26.0] and 9.8, the largest
#: gap 4.6 % (the shape's lower bound).
MACHINE_SPREAD = 0.06


@pytest.mark.slow
def test_the_readmes_population_life_says_what_the_run_gives(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
):
    """The README's population-life command at its full size (10 mechanisms, ~38 CPU-s): its
    first-screen answer — B10, its interval, the failing share —, the Weibull line (shape and
    scale with their intervals) and the simulations per life are the run's, within
    :data:`MACHINE_SPREAD` (the figures' rounding and the machine's round-off in a dry,
    chaotic run: the README gives both machines' figures)."""
    import re
    import shlex

    text = README.read_text(encoding="utf-8")
    block = re.search(r"```bash\n(jointplay life .*?)```", text, flags=re.DOTALL)
    assert block, "the README no longer shows jointplay life"
    lines = re.sub(r"\\\n\s*", " ", block.group(1)).splitlines()
    command = lines[0].replace("--out life", f"--no-plots --no-progress --out {tmp_path / 'l'}")
    promised = next(line for line in lines if line.startswith("# B10 = "))
    status = run(shlex.split(command)[1:])
    assert status == 0, capsys.readouterr().err
    summary = json.loads((tmp_path / "l" / "summary.json").read_text())
    b10, low, high, share, failures = re.search(
        r"B10 = ([\d.]+) h \[([\d.]+)–([\d.]+) h\].* in (\d+) % of the (\d+) failures", promised
    ).groups()  # type: ignore[union-attr]
    fit = summary["weibull"]
    assert fit["B10_h"] == pytest.approx(float(b10), rel=MACHINE_SPREAD)
    assert fit["B10_interval_h"] == pytest.approx([float(low), float(high)], rel=MACHINE_SPREAD)
    assert summary["failures"] == int(failures)
    assert 100 * max(summary["failing_share"].values()) == pytest.approx(int(share), abs=5)
    weibull = next(line for line in lines if line.startswith("# Weibull "))
    shape, shape_low, shape_high, scale, scale_low, scale_high = re.search(
        r"shape ([\d.]+) \[([\d.]+)–([\d.]+)\], scale ([\d.]+) h \[([\d.]+)–([\d.]+) h\]", weibull
    ).groups()  # type: ignore[union-attr]
    assert fit["shape"] == pytest.approx(float(shape), rel=MACHINE_SPREAD)
    shape_interval = [float(shape_low), float(shape_high)]
    assert fit["shape_interval"] == pytest.approx(shape_interval, rel=MACHINE_SPREAD)
    assert fit["scale_h"] == pytest.approx(float(scale), rel=MACHINE_SPREAD)
    scale_interval = [float(scale_low), float(scale_high)]
    assert fit["scale_interval_h"] == pytest.approx(scale_interval, rel=MACHINE_SPREAD)
    mechanisms, per_life = re.search(
        r"\((\d+) mechanisms, ([\d.]+) simulations per life", text
    ).groups()  # type: ignore[union-attr]
    assert summary["mechanisms"] == int(mechanisms) and f"--samples {mechanisms} " in command
    assert summary["simulations_per_life"] == pytest.approx(float(per_life), abs=0.15)
