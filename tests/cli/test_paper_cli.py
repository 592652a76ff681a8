"""`jointplay paper` refuses bad options before any work, and names its simulations in words."""

from __future__ import annotations

from pathlib import Path

import pytest

from jointplay.cli import run
from jointplay.study.paper import PaperStudyOptions, corner_words, plan, task_label


@pytest.mark.parametrize(
    ("option", "value"),
    [
        ("--figure-format", "bmp"),
        ("--rpm", "200"),  # a crank speed needs its unit
        ("--rpm", "200 mm"),
        ("--ecs-source", "both-and-more"),
    ],
)
def test_bad_options_are_refused_before_the_study_runs(
    tmp_path: Path, option: str, value: str, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "x"
    assert run(["paper", "--out", str(out), option, value]) == 2
    assert not out.exists()
    assert option in capsys.readouterr().err  # the message names the option to fix


def test_every_simulation_is_named_in_words() -> None:
    tasks = plan(PaperStudyOptions())
    labels = [t.label for t in tasks]
    assert len(set(labels)) == len(labels)  # each one tells its simulation apart
    for label in labels:
        assert "/" not in label and "+" not in label  # no internal keys such as corner/+-+-
    assert task_label("corner/+-+-", "ifm-ecs-spherical", "paper") == (
        "IFM with spherical ECS (paper's values), from rest, lengths at the corner "
        "crank upper, coupler lower, rocker upper, ground lower"
    )
    assert task_label("steady/rm-conventional/-", "rm-conventional", "-").startswith(
        "RM, conventional parameters, steady start"
    )
    assert corner_words("----") == "crank lower, coupler lower, rocker lower, ground lower"
