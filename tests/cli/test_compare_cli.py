"""The compare command: tables, the discrepancy line, JSON, files written with --out, bad input."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from jointplay.cli import run
from jointplay.io.config import load_preset
from jointplay.io.measurements import MeasurementConventions
from jointplay.study.comparison import nominal_cycle, rig_mechanism

#: The cheapest clearance method (penalty RM, ~0.1 s per revolution).
CHEAP = ["--method", "nominal", "--method", "rm-ecs-spherical", "--revolutions", "1"]


def test_text_output_shows_points_statistics_and_discrepancy(
    capsys: pytest.CaptureFixture[str],
) -> None:
    assert run(["compare", "--method", "nominal"]) == 0
    out = capsys.readouterr().out
    for text in (
        "paper Table 7",
        "speed in deg/s, counter-clockwise positive; crank turning clockwise",
        "(measured − simulated) / simulated × 100",
        "rocker speed (deg/s)",
        "RMS err %",
        "best agreement",
        "WHAT-IF, not applied",
        "228.7 RPM",
        "printed MBD column",
        "0°, 90°",
    ):
        assert text in out, text
    row = next(line.split() for line in out.splitlines() if line.split()[:2] == ["30", "644"])
    assert row[2:4] == ["648.6", "-0.71"]


def test_out_writes_csv_json_and_overlays(tmp_path: Path) -> None:
    out = tmp_path / "cmp"
    assert run(["compare", *CHEAP, "--out", str(out)]) == 0
    points = pd.read_csv(out / "comparison.csv")
    assert points["method"].unique().tolist() == ["nominal", "rm-ecs-spherical"]
    assert {"crank_deg", "measured", "simulated", "error_percent", "difference_rad_s"} <= set(
        points.columns
    )
    document = json.loads((out / "comparison.json").read_text())
    assert document["best"]["by_rms_error_percent"] in ("nominal", "rm-ecs-spherical")
    assert document["discrepancy"]["speed_factor"] == pytest.approx(1.143, abs=0.005)
    assert document["provenance"]["jointplay_version"]
    for name in ("overlay.png", "overlay_nominal.png", "overlay_rm-ecs-spherical.png"):
        assert (out / name).stat().st_size > 10_000


def test_json_and_a_file_in_other_conventions(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A file made from the nominal kinematics in rpm, CCW crank, CW-positive speeds: 0 % error."""
    conventions = MeasurementConventions("rpm", "ccw", "ccw", 90.0, -1)
    mechanism = rig_mechanism(load_preset("paper-fourbar"), conventions)
    angles = np.arange(0.0, 360.0, 45.0)
    speeds = conventions.speed_from_si(
        nominal_cycle(mechanism).at(conventions.crank_to_model(angles))
    )
    path = tmp_path / "rig.csv"
    pd.DataFrame({"phi": angles, "n4": speeds}).to_csv(path, index=False, float_format="%.17g")
    argv = ["compare", "--json", "--method", "nominal", "--measurements", str(path)]
    argv += ["--angle-column", "phi", "--unit", "rpm", "--crank-direction", "ccw"]
    argv += ["--angle-direction", "ccw", "--angle-origin", "90 deg", "--speed-positive", "cw"]
    assert run(argv) == 0
    document = json.loads(capsys.readouterr().out)
    assert document["conventions"]["speed_sign"] == -1 and document["unit"] == "rpm"
    stats = document["methods"][0]
    assert stats["rms_error_percent"] == pytest.approx(0.0, abs=1e-10)
    assert document["discrepancy"]["speed_factor"] == pytest.approx(1.0, rel=1e-14)
    assert document["printed_errors"] is None


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--unit", "furlong"], "--unit must be one of deg/s, rpm, rad/s"),
        (["--crank-direction", "up"], "--crank-direction must be one of cw, ccw"),
        (["--angle-origin", "5"], "has no unit"),
        (["--method", "ifm"], "unknown method 'ifm'"),
        (["--revolutions", "0.5"], "--revolutions must be >= 1"),
        (["--ecs-source", "book"], "--ecs-source must be computed or paper"),
        (["--speed-column", "nope"], "no column 'nope'"),
        (["--measurements", "/nonexistent/rig.csv"], "not found"),
        (["--preset", "no-such-preset"], "unknown preset"),
    ],
)
def test_bad_input_is_one_line_and_exit_2(
    capsys: pytest.CaptureFixture[str], argv: list[str], message: str
) -> None:
    assert run(["compare", "--method", "nominal", *argv]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("jointplay: error:") and message in err
    assert len(err.splitlines()) == 1


def test_malformed_file_is_one_line_and_exit_2(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = tmp_path / "rig.csv"
    path.write_text("crank_deg,speed\n0,12\n30,twelve\n")
    assert run(["compare", "--method", "nominal", "--measurements", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert err == (
        f"jointplay: error: {path}: line 3, column 'speed' has 'twelve', not a finite number"
    )


@pytest.mark.parametrize(
    ("source", "words"),
    [("computed", "computed (our estimate"), ("paper", "the paper's published values")],
)
def test_every_output_says_which_ecs_source_it_used(
    source: str, words: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The console, comparison.json (whole and per method) and the plot title name the ECS
    parameters; the nominal and a conventional method use none."""
    out = tmp_path / "cmp"
    assert run(["compare", *CHEAP, "--ecs-source", source, "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    assert f"ECS parameters: {words}" in printed
    document = json.loads((out / "comparison.json").read_text())
    assert document["ecs_source"] == source
    assert words in document["ecs_source_meaning"]
    per_method = {c["method"]: c["ecs_source"] for c in document["comparisons"]}
    assert per_method == {"nominal": None, "rm-ecs-spherical": source}
    assert words in document["comparisons"][1]["description"]
    assert run(["compare", "--method", "nominal", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["ecs_source"] is None
