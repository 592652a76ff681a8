"""The ``ecs`` command: text and JSON output, files written with --out, bad inputs."""

from __future__ import annotations

import json
from pathlib import Path

import pandas as pd
import pytest

from jointplay.cli import run


def _json(capsys: pytest.CaptureFixture[str], argv: list[str]) -> dict:
    assert run(["ecs", "--json", *argv]) == 0
    return json.loads(capsys.readouterr().out)


def test_text_output_shows_conventions_values_and_paper(capsys: pytest.CaptureFixture[str]) -> None:
    assert run(["ecs", "--preset", "paper-fourbar"]) == 0
    out = capsys.readouterr().out
    for text in (
        "conformal",
        "johnson",
        "link-thickness",
        "0.01 s",
        "Spherical contact (eqs. 9–10)",
        "Cylindrical contact (eqs. 11–12)",
        "paper Table 5",
        "paper Table 4",
        "ours / paper",
        "K (N/mm)",
        "D (N·s/mm)",
        "E* (N/mm²)",
    ):
        assert text in out, text
    overall = [line.split() for line in out.splitlines() if line.startswith(" overall (A)")]
    assert len(overall) == 2
    assert "7778" in overall[0] and "233812" in overall[1]
    assert "242348" in out and "2500" in out
    assert "0.1223 N" in out  # Table 5's load lower bound


def test_json_output_si_and_paper_units(capsys: pytest.CaptureFixture[str]) -> None:
    data = _json(capsys, ["--contact", "cylindrical"])
    assert data["contacts"] == ["cylindrical"]
    overall = data["ecs"]["overall"]
    assert list(overall) == ["cylindrical"]
    cyl = overall["cylindrical"]
    assert cyl["paper_units"]["stiffness_N_per_mm"] == pytest.approx(233811.5, rel=1e-4)
    assert cyl["si"]["stiffness_N_per_m"] == pytest.approx(233811.5e3, rel=1e-4)
    assert cyl["si"]["damping_N_s_per_m"] == pytest.approx(0.01 * cyl["si"]["stiffness_N_per_m"])
    assert cyl["si"]["half_width_m"] == pytest.approx(7.44e-6, rel=1e-3)
    assert data["ecs"]["conventions"]["radius"] == "conformal"
    paper = data["paper"]["cylindrical"]
    assert paper["paper_units"]["stiffness_N_per_mm"] == 242348.0
    assert paper["ours_over_paper"]["stiffness"] == pytest.approx(0.9648, rel=1e-3)
    impact = data["simulator_parameters"]["cylindrical"]["paper"]["impact"]
    assert impact["stiffness_N_per_mm^e"] == pytest.approx(242348.0)
    assert impact["d_max_mm"] == pytest.approx(2.69e-10)
    o2 = next(j for j in data["ecs"]["joints"] if j["joint"] == "O2")
    assert o2["cylindrical"]["status"] == "zero-load"
    assert o2["cylindrical"]["si"]["log_term"] is None  # inf written as null


def test_json_options_rpm_load_ratio_sweep(capsys: pytest.CaptureFixture[str]) -> None:
    data = _json(
        capsys,
        [
            "--rpm",
            "100 rpm",
            "--load",
            "reaction",
            "--damping-ratio",
            "0.02 s",
            "--sweep",
            "100,200 rpm",
        ],
    )
    assert data["ecs"]["crank_speed_rpm"] == pytest.approx(100.0)
    assert data["ecs"]["overall_joint"] == "O2"
    sph = data["ecs"]["overall"]["spherical"]["si"]
    assert sph["damping_N_s_per_m"] == pytest.approx(0.02 * sph["stiffness_N_per_m"])
    assert [row["rpm"] for row in data["sweep"]] == [100.0, 200.0]
    warning = data["simulator_parameters"]["spherical"]["paper"]["derivation"]["warning"]
    assert "200 RPM" in warning


def test_out_writes_json_csv_and_plots(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "ecs"
    assert run(["ecs", "--sweep", "100:300:100 rpm", "--out", str(out)]) == 0
    assert "results written to" in capsys.readouterr().out
    document = json.loads((out / "ecs.json").read_text())
    assert document["provenance"]["jointplay_version"]
    table = pd.read_csv(out / "ecs_sweep.csv")
    assert table["rpm"].tolist() == [100, 200, 300]
    assert table["K_spherical_N_per_mm"].iloc[1] == pytest.approx(7778.0, rel=1e-4)
    assert table["K_spherical_N_per_m"].iloc[1] == pytest.approx(7778.0e3, rel=1e-4)
    for name in ("ecs_sweep.png", "ecs_damping.png"):
        assert (out / name).stat().st_size > 1000


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--contact", "elliptical"], "--contact"),
        (["--rpm", "-5 rpm"], "--rpm"),
        (["--rpm", "200"], "--rpm: '200' has no unit"),
        (["--rpm", "0 rpm"], "--rpm"),
        (["--rpm", "fast"], "--rpm"),
        (["--damping-ratio", "-0.01 s"], "--damping-ratio"),
        (["--damping-ratio", "0.01"], "--damping-ratio: '0.01' has no unit"),
        (["--damping-ratio", "1%"], "--damping-ratio"),
        (["--load", "torque"], "--load"),
        (["--radius", "convex"], "--radius"),
        (["--length", "12"], "--length"),
        (["--sweep", "500:50:50 rpm"], "--sweep"),
        (["--sweep", "50:500:50"], "--sweep: '50:500:50' has no unit"),
        (["--sweep", "50:500:50 mm"], "not a unit of crank speed"),
        (["--restitution", "1.5"], "--restitution"),
    ],
)
def test_bad_inputs_exit_2_with_one_line(
    capsys: pytest.CaptureFixture[str], argv: list[str], message: str
) -> None:
    assert run(["ecs", *argv]) == 2
    captured = capsys.readouterr()
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1, captured.err
    assert lines[0].startswith("jointplay: error:") and message in lines[0]
    assert captured.out == ""
