"""Lubrication on the command line (issue 39, item 3): a dry law named runs dry unless a
lubricant is named with it, the command line and the Python API run the same physics for the
same arguments, and the run says which regime every joint ran in."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from jointplay.cli import run
from jointplay.dynamics.settings import RunSettings, simulate_run
from jointplay.dynamics.setup import ContactModel, ContactSettings, FrictionSettings
from jointplay.model.mechanism import Mechanism

PEAKS = ("omega3", "omega4", "F_O2", "F_A", "F_B", "F_O4", "torque")
SHORT = ["--revolutions", "0.1", "--settle", "0", "--no-plots"]


def test_the_command_line_and_the_python_api_run_the_same_dry_law(
    tmp_path: Path, paper_fourbar: Mechanism, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "cli"
    law = ["--contact", "lankarani-nikravesh", "--friction", "0"]
    assert run(["simulate", *law, *SHORT, "--out", str(out)]) == 0
    printed = capsys.readouterr().out.splitlines()
    assert printed[0] == "lubrication: dry (O2, A, B, O4)", printed[:3]
    summary = json.loads((out / "summary.json").read_text())
    assert {entry["regime"] for entry in summary["lubrication"].values()} == {"dry"}
    assert all(j["film_damping_N_s_m"] == 0.0 for j in summary["clearance_joints"].values())
    contact = ContactModel(ContactSettings(law="lankarani-nikravesh"), FrictionSettings())
    result = simulate_run(paper_fourbar, None, RunSettings(contact, settle=0, revolutions=0.1))
    for key in PEAKS:
        assert summary["peaks"][key]["value"] == pytest.approx(
            result.peaks[key]["value"], rel=1e-9, abs=1e-12
        ), key


def test_a_lubricant_named_with_the_law_runs_in_its_film(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "oiled"
    law = ["--contact", "lankarani-nikravesh", "--lubrication", "oil"]
    assert run(["simulate", *law, *SHORT, "--out", str(out)]) == 0
    assert capsys.readouterr().out.splitlines()[0] == (
        "lubrication: lubricated, 0.05 Pa*s oil (O2, A, B, O4)"
    )
    summary = json.loads((out / "summary.json").read_text())
    assert summary["lubrication"]["A"] == {
        "regime": "oil", "viscosity_Pa_s": 0.05, "film_model": "short-bearing-pi",
        "film_damping_N_s_m": summary["clearance_joints"]["A"]["film_damping_N_s_m"],
        "declared": "command",
    }  # fmt: skip
    assert summary["lubrication"]["A"]["film_damping_N_s_m"] > 0


def test_an_iso_vg_grade_names_the_oil(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """``--lubrication "oil ISO VG 46"``: the oil's viscosity is the grade's at 40 °C (46
    mm²/s × 870 kg/m³), and the regime says so."""
    out = tmp_path / "graded"
    assert run(["simulate", "--lubrication", "oil ISO VG 46", *SHORT, "--out", str(out)]) == 0
    printed = capsys.readouterr().out.splitlines()
    assert printed[0] == (
        "lubrication: lubricated, oil ISO VG 46 (0.040 Pa*s at 40 °C) (O2, A, B, O4)"
    )
    summary = json.loads((out / "summary.json").read_text())
    entry = summary["lubrication"]["A"]
    assert entry["regime"] == "oil" and entry["iso_vg_grade"] == 46
    assert entry["viscosity_Pa_s"] == pytest.approx(46e-6 * 870, rel=1e-12)
    assert summary["contact"]["lubrication"]["iso_vg_grade"] == 46


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--lubrication", "wet"], "--lubrication must be one of dry, oil, grease, got 'wet'"),
        (
            ["--lubrication", "dry", "--lubricant-viscosity", "0.05 Pa*s"],
            "--lubrication dry runs the joints without a film: drop --lubricant-viscosity",
        ),
        (["--lubricant-viscosity", "-1 Pa*s"], "--lubricant-viscosity must be >= 0"),
        (["--lubrication", "grease"], "--lubrication grease needs its base oil's viscosity"),
        (
            ["--lubrication", "oil ISO VG 47"],
            "--lubrication: 'ISO VG 47' is not an ISO 3448 viscosity grade; the grades are ISO "
            "VG 2, 3, 5, 7, 10, 15, 22, 32, 46, 68, 100, 150, 220, 320, 460, 680, 1000, 1500, "
            "2200, 3200",
        ),
        (
            ["--lubrication", "oil ISO VG 46", "--lubricant-viscosity", "0.05 Pa*s"],
            "--lubrication 'oil ISO VG 46' names the lubricant's viscosity (at 40 °C): give no "
            "--lubricant-viscosity",
        ),
    ],
)
def test_bad_lubrication_is_one_line_and_exit_2(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], args: list[str], message: str
) -> None:
    wear = ["wear", "--hours", "600 h", "--clearance-limit", "+20 um"]
    for command in (["simulate"], wear, ["tolerance", "--responses", "dynamic"]):
        out = tmp_path / command[0]
        assert run([*command, *args, "--out", str(out)]) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and message in err[0], err
        assert not out.exists()


def test_every_dynamic_command_states_the_regime_first(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """``wear``, ``tolerance`` and ``design`` open with the regime, write it per joint in
    ``summary.json``, and the design's choice says it."""
    wear = ["wear", "--fit", "H8/g7", "--clearance-limit", "+20 um", "--hours", "10 h",
            "--update-hours", "10 h", "--lubrication", "dry", "--no-plots"]  # fmt: skip
    assert run([*wear, "--out", str(tmp_path / "wear")]) == 0
    assert capsys.readouterr().out.splitlines()[0] == "lubrication: dry (O2, A, B, O4)"
    summary = json.loads((tmp_path / "wear" / "summary.json").read_text())
    assert summary["lubrication"]["A"]["regime"] == "dry"
    assert summary["lubrication"]["A"]["declared"] == "command"
    tolerance = ["tolerance", "--responses", "dynamic", "--samples", "2", "--no-plots"]
    assert run([*tolerance, "--out", str(tmp_path / "tolerance")]) == 0
    oil = "lubrication: lubricated, 0.05 Pa*s oil (O2, A, B, O4)"
    assert capsys.readouterr().out.splitlines()[0] == oil
    summary = json.loads((tmp_path / "tolerance" / "summary.json").read_text())
    described = json.dumps(summary)
    assert '"lubrication_text": "lubricated, 0.05 Pa*s oil"' in described
    design = ["design", "--fits", "H8/g7", "--classes", "m", "--require", "joint_force <= 1 kN",
              "--samples", "2", "--confidence", "10 %", "--no-model-sensitivity", "--no-plots"]  # fmt: skip
    assert run([*design, "--out", str(tmp_path / "design")]) == 0
    printed = capsys.readouterr().out.splitlines()
    assert printed[0] == oil
    chosen = [line for line in printed if line.startswith("choose ")]
    assert chosen and chosen[0].startswith("choose H8/g7 / m — lubricated, 0.05 Pa*s oil: "), (
        printed
    )
    summary = json.loads((tmp_path / "design" / "summary.json").read_text())
    assert summary["verdict"].endswith("H8/g7 / m — lubricated, 0.05 Pa*s oil"), summary["verdict"]


def test_the_mechanism_file_declares_each_joint(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    from jointplay.io.config import preset_text

    config = tmp_path / "m.toml"
    config.write_text(
        preset_text("paper-fourbar")
        + '\n[lubrication.joints.A]\nregime = "grease"\nviscosity = "0.15 Pa*s"\n'
    )
    out = tmp_path / "declared"
    args = ["simulate", "--config", str(config), "--contact", "hertz", *SHORT]
    assert run([*args, "--out", str(out)]) == 0
    printed = capsys.readouterr().out.splitlines()
    assert printed[0] == "lubrication: O2, B, O4 dry; A lubricated, 0.15 Pa*s grease base oil"
    summary = json.loads((out / "summary.json").read_text())
    assert summary["lubrication"]["A"]["declared"] == "mechanism"
    assert summary["lubrication"]["A"]["viscosity_Pa_s"] == 0.15
    assert summary["lubrication"]["B"] == {
        "regime": "dry", "viscosity_Pa_s": None, "film_model": None,
        "film_damping_N_s_m": 0.0, "declared": "default",
    }  # fmt: skip
    # the command's lubrication over the file's
    assert run([*args, "--lubrication", "dry", "--out", str(tmp_path / "dry")]) == 0
    assert capsys.readouterr().out.splitlines()[0] == "lubrication: dry (O2, A, B, O4)"


def test_the_design_verdict_names_the_grade(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The issue's words: "choose H8/g7 / m — lubricated, oil ISO VG 46 (0.040 Pa*s at
    40 °C)", in the printed choice and in ``summary.json``."""
    design = ["design", "--fits", "H8/g7", "--classes", "m", "--require", "joint_force <= 1 kN",
              "--samples", "2", "--confidence", "10 %", "--no-model-sensitivity", "--no-plots",
              "--settle", "0", "--revolutions", "0.25", "--lubrication", "oil ISO VG 46"]  # fmt: skip
    assert run([*design, "--out", str(tmp_path / "design")]) == 0
    words = "lubricated, oil ISO VG 46 (0.040 Pa*s at 40 °C)"
    printed = capsys.readouterr().out.splitlines()
    assert printed[0] == f"lubrication: {words} (O2, A, B, O4)"
    assert any(line.startswith(f"choose H8/g7 / m — {words}: ") for line in printed), printed
    summary = json.loads((tmp_path / "design" / "summary.json").read_text())
    assert summary["verdict"].endswith(f"H8/g7 / m — {words}")
    assert summary["settings"]["model"]["lubrication"]["A"]["iso_vg_grade"] == 46
