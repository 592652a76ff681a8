"""The calibrate command: Table 7 by default, JSON in the issue's shape, files written with
--out (a calibrated config that --config accepts), several files, other responses, bad input."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from jointplay.cli import run
from jointplay.io.config import load_config, load_preset
from jointplay.io.measurements import MeasurementConventions
from jointplay.study.calibration import Dataset, synthetic_dataset

RPM = math.pi / 30.0


def _write_run(
    path: Path, rpm: float, *, phase_deg: float = 0.0, quantity: str = "omega4", unit_factor=1.0
) -> None:
    """A noise-free rig file made by the nominal model: rpm units, CCW crank, CW-positive."""
    conventions = MeasurementConventions("rpm", "ccw", "ccw", 90.0, -1)
    from jointplay.io.measurements import Measurements

    angles = np.arange(0.0, 360.0, 20.0)
    template = Dataset(
        Measurements(angles, np.ones_like(angles), conventions),
        quantity=quantity,
        unit_factor=unit_factor,
        unit="x",
    )
    truth = {"crank-speed": rpm * RPM, "phase": math.radians(phase_deg)}
    data = synthetic_dataset(load_preset("paper-fourbar"), template, truth)
    pd.DataFrame({"phi": angles, "value": data.measurements.speed}).to_csv(
        path, index=False, float_format="%.17g"
    )


RIG = ["--angle-column", "phi", "--crank-direction", "ccw", "--angle-direction", "ccw"]
RIG += ["--angle-origin", "90 deg", "--speed-positive", "cw"]


def test_table7_text_output(capsys: pytest.CaptureFixture[str]) -> None:
    assert run(["calibrate"]) == 0
    out = capsys.readouterr().out
    for text in (
        "paper Table 7",
        "model: nominal",
        "227.93 RPM (216.87 .. 238.98)",
        "-2.274 deg",
        "RMS error 17.02 % -> 10.99 %",
        "correlation",
        "no identifiability warnings",
    ):
        assert text in out, text


def test_json_is_the_issue_shape(capsys: pytest.CaptureFixture[str]) -> None:
    assert run(["calibrate", "--column", "mbd_printed", "--json"]) == 0
    document = json.loads(capsys.readouterr().out)
    assert set(document) == {"parameters", "rms_before", "rms_after", "warnings"}
    speed = document["parameters"]["crank-speed"]
    assert set(speed) == {"value", "stderr", "ci95", "unit"}
    assert speed["unit"] == "rad/s" and document["parameters"]["phase"]["unit"] == "rad"
    assert speed["ci95"][0] < speed["value"] < speed["ci95"][1]
    assert 226 * RPM < speed["value"] < 242 * RPM
    assert document["rms_after"] < document["rms_before"]
    assert document["warnings"] == []


def test_out_writes_results_and_a_config_that_loads(tmp_path: Path) -> None:
    out = tmp_path / "cal"
    assert run(["calibrate", "--fit", "crank-speed,phase,rocker-length", "--out", str(out)]) == 0
    document = json.loads((out / "calibration.json").read_text())
    assert document["correlation"]["parameters"] == ["crank-speed", "phase", "rocker-length"]
    assert document["provenance"]["jointplay_version"]
    points = pd.read_csv(out / "calibration_points.csv")
    assert {"measured", "before", "after", "error_percent_after"} <= set(points.columns)
    for name in ("overlay_experiment_printed.png", "residuals_experiment_printed.png"):
        assert (out / name).stat().st_size > 10_000
    mechanism = load_config(out / "calibrated.toml")
    fitted = document["parameters"]
    assert mechanism.driver.speed == pytest.approx(fitted["crank-speed"]["value"], rel=1e-9)
    geometry = mechanism.template.geometry  # type: ignore[attr-defined]
    assert geometry.rocker == pytest.approx(fitted["rocker-length"]["value"], rel=1e-9)
    assert "phase" in (out / "calibrated.toml").read_text()  # in the header, as a comment


def test_two_runs_at_different_speeds(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    slow, fast = tmp_path / "slow.csv", tmp_path / "fast.csv"
    _write_run(slow, 160.0, phase_deg=1.0)
    _write_run(fast, 290.0, phase_deg=1.0)
    argv = ["calibrate", "--json", "-m", str(slow), "-m", str(fast), *RIG, "--unit", "rpm"]
    argv += ["--rpm-of", "slow.csv=150rpm", "--rpm-of", f"{fast}=300 rpm"]
    assert run(argv) == 0
    parameters = json.loads(capsys.readouterr().out)["parameters"]
    assert list(parameters) == ["crank-speed@slow", "crank-speed@fast", "phase"]
    assert parameters["crank-speed@slow"]["value"] == pytest.approx(160 * RPM, rel=1e-6)
    assert parameters["crank-speed@fast"]["value"] == pytest.approx(290 * RPM, rel=1e-6)
    assert parameters["phase"]["value"] == pytest.approx(math.radians(1.0), abs=1e-6)


def test_another_response_in_its_unit(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """The rocker's angular acceleration in deg/s² (signed like the speeds: CW positive)."""
    path = tmp_path / "accel.csv"
    _write_run(path, 215.0, quantity="alpha4", unit_factor=math.pi / 180)
    argv = ["calibrate", "--json", "-m", str(path), *RIG, "--quantity", "alpha4"]
    argv += ["--unit", "deg/s^2", "--fit", "crank-speed"]
    assert run(argv) == 0
    parameters = json.loads(capsys.readouterr().out)["parameters"]
    assert parameters["crank-speed"]["value"] == pytest.approx(215 * RPM, rel=1e-6)


def test_unidentifiable_lengths_warn(capsys: pytest.CaptureFixture[str]) -> None:
    fit = "crank-speed,crank-length,coupler-length,rocker-length,ground-length"
    assert run(["calibrate", "--json", "--fit", fit]) == 0
    captured = capsys.readouterr()
    warnings = json.loads(captured.out)["warnings"]
    assert any("not identifiable" in w for w in warnings)
    assert "jointplay: warning: not identifiable" in captured.err


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--column", "nope"], "Table 7 has no value column 'nope'"),
        (["--measurements", "/nonexistent/rig.csv"], "not found"),
        (["--fit", "crank-speed,speed"], "unknown parameter(s) speed"),
        (["--fit-more", "phase"], "'phase' is not a contact parameter"),
        (["--loss", "l3"], "--loss must be one of"),
        (["--rpm-of", "other.csv=200rpm"], "--rpm-of names no measurement file"),
        (["--rpm-of", "nonsense"], "--rpm-of must read NAME=VALUE"),
        (["--quantity", "omega9"], "cannot compare 'omega9'"),
        (["--quantity", "speed"], "cannot fit 'speed'"),
        (["--initial", "phase=2"], "has no unit"),
        (["--initial", "k=1e4N/mm^1.5"], "--initial names k, which is not fitted"),
        (["--unit", "furlong"], "--unit must be one of"),
    ],
)
def test_bad_input_is_one_line_exit_2_and_writes_nothing(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], argv: list[str], message: str
) -> None:
    out = tmp_path / "never"
    assert run(["calibrate", "--out", str(out), *argv]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("jointplay: error:") and message in err, err
    assert len(err.splitlines()) == 1
    assert not out.exists()
    assert list(tmp_path.iterdir()) == []


def test_malformed_file_and_unknown_column(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = tmp_path / "rig.csv"
    path.write_text("crank_deg,speed\n0,12\n30,twelve\n")
    assert run(["calibrate", "-m", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert (
        err == f"jointplay: error: {path}: line 3, column 'speed' has 'twelve', not a finite number"
    )
    path.write_text("crank_deg,speed\n0,12\n30,13\n")
    assert run(["calibrate", "-m", str(path), "--column", "rocker"]) == 2
    err = capsys.readouterr().err.strip()
    assert "no column 'rocker'" in err and len(err.splitlines()) == 1


@pytest.mark.slow
def test_contact_parameter_on_the_clearance_model(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "dyn"
    argv = ["calibrate", "--json", "--fit", "crank-speed", "--fit-more", "c_max"]
    argv += ["--max-nfev", "4", "--out", str(out), "--no-plots"]
    assert run(argv) == 0
    document = json.loads(capsys.readouterr().out)
    assert document["parameters"]["c_max"]["unit"] == "N*s/m"
    assert json.loads((out / "calibration.json").read_text())["model"] == "clearance"
    text = (out / "calibrated.toml").read_text()
    assert "cmax" in text
