"""The simulate command: files and columns it promises, settings from TOML, bad input."""

from __future__ import annotations

import json

import pandas as pd
import pytest

from jointplay.cli import run
from jointplay.io.config import preset_text

PAPER_ARGS = [
    "simulate", "--preset", "paper-fourbar", "--contact", "impact", "--k", "1e4 N/mm^1.5",
    "--exponent", "1.5", "--cmax", "10 N*s/mm", "--depth", "0.1 mm", "--clearance", "0.021 mm",
    "--joints", "O2,A,B,O4", "--start", "rest", "--revolutions", "0.05",
]  # fmt: skip
COLUMNS = ["t", "crank_deg", "theta3_deg", "theta4_deg", "omega3", "omega4", "alpha3", "alpha4",
           "F_O2", "F_A", "F_B", "F_O4", "torque"]  # fmt: skip


def test_simulate_writes_the_documented_outputs(tmp_path) -> None:
    out = tmp_path / "run"
    assert run([*PAPER_ARGS, "--out", str(out)]) == 0
    series = pd.read_csv(out / "timeseries.csv")
    assert series.columns[: len(COLUMNS)].tolist() == COLUMNS
    for joint in ("O2", "A", "B", "O4"):
        assert {f"e_{joint}", f"pen_{joint}", f"contact_{joint}"} <= set(series.columns)
    summary = json.loads((out / "summary.json").read_text())
    keys = ["omega3", "omega4", "alpha3", "alpha4", "F_O2", "F_A", "F_B", "F_O4", "torque"]
    assert list(summary["peaks"]) == keys
    assert set(summary["peaks"]["omega3"]) >= {"value", "t", "crank_deg"}
    assert list(summary["nominal_peaks"]) == keys and list(summary["increase_percent"]) == keys
    assert set(summary["solver"]) >= {
        "method", "steps", "rejected_steps", "rhs_evaluations", "impacts", "max_penetration_m", "energy_residual", "wall_s",
    }  # fmt: skip
    assert set(summary["solver"]["impacts"]) == {"O2", "A", "B", "O4"}
    provenance = summary["provenance"]
    assert provenance["jointplay_version"] and "simulate" in provenance["command_line"]
    assert provenance["configuration"]["mechanism"]["geometry_m"]["crank"] == pytest.approx(0.108)
    for name in (
        "angular_velocity.png",
        "angular_acceleration.png",
        "joint_forces.png",
        "journal_orbits.png",
    ):
        assert (out / name).stat().st_size > 1000


def test_parquet_and_output_step(tmp_path) -> None:
    out = tmp_path / "pq"
    args = [
        *PAPER_ARGS,
        "--format",
        "parquet",
        "--output-step",
        "1 ms",
        "--no-plots",
        "--out",
        str(out),
    ]
    assert run(args) == 0
    series = pd.read_parquet(out / "timeseries.parquet")
    assert series["t"].diff().dropna().round(9).unique().tolist() == [0.001]


def test_settings_from_a_toml_file(tmp_path) -> None:
    config = tmp_path / "mine.toml"
    config.write_text(
        preset_text("paper-fourbar")
        + '\n[simulation]\ncontact = "lankarani-nikravesh"\nk = "1e10 N/m^1.5"\nrestitution = 0.6\n'
        'joints = ["A", "B"]\nrevolutions = 0.03\nstart = "steady"\n'
    )
    out = tmp_path / "toml"
    assert run(["simulate", "--config", str(config), "--no-plots", "--out", str(out)]) == 0
    summary = json.loads((out / "summary.json").read_text())
    assert set(summary["clearance_joints"]) == {"A", "B"}
    assert summary["clearance_joints"]["A"]["law"] == "lankarani-nikravesh"
    assert summary["start"]["mode"] == "steady"
    # command-line options override the file
    out2 = tmp_path / "override"
    assert (
        run(
            ["simulate", "--config", str(config), "--joints", "B", "--no-plots", "--out", str(out2)]
        )
        == 0
    )
    assert set(json.loads((out2 / "summary.json").read_text())["clearance_joints"]) == {"B"}


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--clearance", "-0.01 mm"], "must be positive"),
        (["--contact", "rubber"], "unknown contact law 'rubber'"),
        (["--joints", "O2,Q"], "no revolute joint 'Q'"),
        (["--k", "1e4"], "has no unit"),
        (["--k", "1e4 N/mm"], "cannot be converted"),
        (["--start", "sideways"], "start mode"),
        (["--revolutions", "0"], "revolutions"),
        (["--format", "xlsx"], "--format"),
        (["--friction", "-0.1"], "friction"),
        (["--ensemble", "3"], "--ensemble must be at least 5 runs"),
        (["--ensemble", "5"], "--ensemble needs at least 1 whole analysed revolution"),
    ],
)
def test_bad_input(tmp_path, capsys, args, message) -> None:
    out = tmp_path / "bad"
    assert run([*PAPER_ARGS, *args, "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1 and "Traceback" not in err
    assert not out.exists()


LAW_OPTIONS = {
    "impact": [],
    "restitution": ["--k", "1e7 N/m", "--restitution", "0.8"],
    "hertz": ["--k", "1e10 N/m^1.5"],
    "kelvin-voigt": ["--k", "1e7 N/m", "--exponent", "1", "--damping", "200 N*s/m"],
    "hunt-crossley": ["--k", "1e10 N/m^1.5"],
    "lankarani-nikravesh": ["--k", "1e10 N/m^1.5"],
    "flores": ["--k", "1e10 N/m^1.5"],
    "gonthier": ["--k", "1e10 N/m^1.5"],
    "hu-guo": ["--k", "1e10 N/m^1.5"],
    "herbert-mcwhannell": ["--k", "1e10 N/m^1.5"],
    "lee-wang": ["--k", "1e10 N/m^1.5"],
    "zhiying-qishao": ["--k", "1e10 N/m^1.5"],
}


@pytest.mark.parametrize("law", list(LAW_OPTIONS))
def test_every_law_runs_from_the_cli(tmp_path, law) -> None:
    out = tmp_path / law
    args = ["simulate", "--contact", law, *LAW_OPTIONS[law], "--revolutions", "0.01", "--no-plots"]
    assert run([*args, "--out", str(out)]) == 0
    assert json.loads((out / "summary.json").read_text())["clearance_joints"]["A"]["law"] == law


@pytest.mark.parametrize(
    "start",
    [["--start", "rest"], ["--start", "steady"], ["--start", "ramp", "--ramp-time", "5 ms"]],
)
def test_every_start_mode_and_friction_runs(tmp_path, start) -> None:
    out = tmp_path / "s"
    args = ["simulate", *start, "--friction", "0.1", "--revolutions", "0.01", "--no-plots"]
    assert run([*args, "--out", str(out)]) == 0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["clearance_joints"]["O2"]["friction"]["law"] == "ambrosio"
    assert summary["solver"]["energy_residual"] < 1e-5


def test_stiffness_from_geometry(tmp_path) -> None:
    out = tmp_path / "geo"
    args = [
        "simulate",
        "--contact",
        "lankarani-nikravesh",
        "--stiffness-law",
        "pereira",
        "--revolutions",
        "0.01",
    ]
    assert run([*args, "--no-plots", "--out", str(out)]) == 0
    law = json.loads((out / "summary.json").read_text())["clearance_joints"]["A"]["law_parameters"]
    assert 1.2 < law["exponent"] < 1.4  # Pereira's n for a 21 µm clearance is ~1.3


def test_default_is_the_running_mechanism_and_diagnostics_reach_the_user(tmp_path, capsys) -> None:
    """Without --start the answer is steady running after two start-up revolutions; the
    soft conventional contact (no longer the default: --method) sinks deeper than the
    clearance and says so, one line each."""
    out = tmp_path / "steady"
    args = ["simulate", "--preset", "paper-fourbar", "--joints", "A,B", "--sample-deg", "1 deg",
            "--method", "ifm-conventional"]  # fmt: skip
    assert run([*args, "--revolutions", "2", "--no-plots", "--out", str(out)]) == 0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["start"]["mode"] == "steady" and summary["settle_revolutions"] == 2
    assert summary["cycles"]["first_analysed_revolution"] == 3
    assert len(summary["cycles"]["per_revolution"]["F_A"]) == 2
    assert summary["peaks"]["F_A"]["revolution"] in (3, 4)
    assert summary["sampled_peaks"]["every_deg"] == 1
    assert summary["periodicity"]["verdict"]
    codes = {(d["code"], d["joint"]) for d in summary["diagnostics"]}
    assert ("penetration-exceeds-clearance", "A") in codes
    # Warned exactly where the running pin (start-up left out) sinks beyond the clearance.
    deepest = summary["cycles"]["deepest_penetration_m"]
    beyond = {joint for joint, value in deepest.items() if value > 21e-6}
    assert {j for code, j in codes if code == "penetration-exceeds-clearance"} == beyond
    err = capsys.readouterr().err.splitlines()
    lines = [line for line in err if "penetration-exceeds-clearance" in line]
    assert len(lines) == len(beyond) and all(
        line.startswith("jointplay: warning:") for line in lines
    )


def test_start_up_on_request_and_the_settle_option(tmp_path) -> None:
    out = tmp_path / "rest"
    assert run([*PAPER_ARGS, "--no-plots", "--out", str(out)]) == 0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["start"]["mode"] == "rest" and summary["settle_revolutions"] == 0
    assert summary["peaks"]["F_A"]["value"] > 1000  # the start-up impact the paper reports
    assert run([*PAPER_ARGS, "--settle", "-1", "--out", str(tmp_path / "bad")]) == 2
    assert not (tmp_path / "bad").exists()


def test_the_slider_crank_console_table_shows_the_slider(tmp_path, capsys) -> None:
    """The slider's stroke, velocity and acceleration peaks are in the console table, and
    they agree with the time series written beside it."""
    out = tmp_path / "slider"
    args = ["simulate", "--preset", "flores-slider-crank", "--settle", "1", "--revolutions", "1"]
    assert run([*args, "--no-plots", "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    rows = {line.split()[0]: line.split() for line in printed.splitlines() if line.strip()}
    assert {"slider_v*", "slider_a*"} <= set(rows)
    assert "slider stroke (m)*" in printed
    steps = pd.read_csv(out / "steps.csv")
    turned = (steps["crank_deg"] - steps["crank_deg"].iloc[0]).abs()
    analysed = steps[turned >= 360.0 - 1e-9]  # after the one start-up revolution
    assert float(rows["slider_v*"][1]) == pytest.approx(analysed["slider_v"].abs().max(), rel=1e-4)
    assert float(rows["slider_a*"][1]) == pytest.approx(analysed["slider_a"].abs().max(), rel=1e-4)


def test_the_diagnostics_advice_names_the_options(tmp_path, capsys) -> None:
    """The layers below name the setting (settle, for the Python API); the command line
    shows its option: the advice on stderr says --settle, summary.json keeps the setting."""
    out = tmp_path / "advice"
    assert run([*PAPER_ARGS, "--no-plots", "--out", str(out)]) == 0
    lines = [
        line for line in capsys.readouterr().err.splitlines() if "start-transient-dominates" in line
    ]
    assert lines and all(
        line.endswith("simulate more start-up revolutions (--settle)") for line in lines
    )
    written = json.loads((out / "summary.json").read_text())["diagnostics"]
    advice = [d["message"] for d in written if d["code"] == "start-transient-dominates"]
    assert advice and all(m.endswith("(settle)") and "--" not in m for m in advice)
    assert all("template" not in d for d in written)


def test_the_integrator_is_the_methods_unless_named(tmp_path) -> None:
    """--method ifm-ecs-spherical runs RODAS4 (the method's own), --integrator overrides it,
    and the physical default runs Radau; summary.json says which."""
    ecs = ["simulate", "--method", "ifm-ecs-spherical", "--ecs-source", "paper", "--start",
           "rest", "--revolutions", "0.01", "--no-plots"]  # fmt: skip
    cases = {
        "rodas4": [*ecs, "--out", str(tmp_path / "ecs")],
        "radau": [*ecs, "--integrator", "radau", "--out", str(tmp_path / "named")],
    }
    for integrator, args in cases.items():
        assert run(args) == 0
        summary = json.loads((tmp_path / args[-1].rsplit("/", 1)[-1] / "summary.json").read_text())
        assert summary["solver"]["integrator"] == integrator
        assert summary["solver"]["method"].startswith(
            {"rodas4": "RODAS4", "radau": "Radau"}[integrator]
        )
    physical = tmp_path / "physical"
    assert run([*PAPER_ARGS[:3], "--revolutions", "0.01", "--settle", "0", "--no-plots",
                "--out", str(physical)]) == 0  # fmt: skip
    assert json.loads((physical / "summary.json").read_text())["solver"]["integrator"] == "radau"


def test_irregular_running_reports_the_peak_distributions(tmp_path, capsys) -> None:
    """Dry joints rattle chaotically: the peak column is a draw, and simulate says so and
    reports the per-revolution peak distributions with their intervals (issue 40 item 1)."""
    out = tmp_path / "dry"
    args = ["simulate", "--preset", "paper-fourbar", "--lubrication", "dry", "--settle", "2",
            "--revolutions", "12", "--no-plots", "--out", str(out)]  # fmt: skip
    assert run(args) == 0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["periodicity"]["verdict"] == "not periodic"
    irregular = summary["irregular"]
    assert irregular["motion"] == "irregular" and irregular["revolutions"] == 12
    assert irregular["revolutions_for_bounded_percentile"] >= 72
    stats = irregular["statistics"]["F_O2"]
    per_revolution = summary["cycles"]["per_revolution"]["F_O2"]
    assert stats["revolutions"] == 12
    assert stats["mean"]["value"] == pytest.approx(sum(per_revolution) / 12)
    assert stats["mean"]["low"] < stats["mean"]["value"] < stats["mean"]["high"]
    assert stats["max"]["value"] == pytest.approx(max(per_revolution))
    assert stats["max"]["high"] is None  # a repeat's max exceeds this one half of the time
    assert stats["percentile_95"]["high"] is None  # 12 revolutions cannot bound it
    assert summary["peaks"]["F_O2"]["value"] == pytest.approx(max(per_revolution))
    printed = capsys.readouterr().out
    assert "irregular motion: each peak above is a draw" in printed
    assert "F_O2 over 12 revolutions: mean " in printed and " N, 95th percentile " in printed
    assert "the intervals are the sampling uncertainty of this run's revolutions only" in printed
    needed = irregular["revolutions_for_bounded_percentile"]
    assert f"needs {needed} revolutions (--revolutions {needed})" in printed


def test_periodic_running_has_no_irregular_statistics(tmp_path, capsys) -> None:
    out = tmp_path / "rest"
    assert run([*PAPER_ARGS, "--no-plots", "--out", str(out)]) == 0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["periodicity"]["verdict"] != "not periodic"
    assert summary["irregular"] is None
    assert "irregular motion" not in capsys.readouterr().out


def test_an_ensemble_reports_the_distributions_over_its_runs(tmp_path, capsys) -> None:
    """``--ensemble 5``: five runs from start angles 0.01 deg apart (the first is the run
    itself), the statistics over their revolutions with the runs as batches."""
    out = tmp_path / "ensemble"
    args = ["simulate", "--preset", "paper-fourbar", "--lubrication", "dry", "--settle", "2",
            "--revolutions", "2", "--ensemble", "5", "--no-plots", "--out", str(out)]  # fmt: skip
    assert run(args) == 0
    summary = json.loads((out / "summary.json").read_text())
    ensemble = summary["ensemble"]
    assert ensemble["runs"] == 5 and ensemble["revolutions_per_run"] == 2
    assert ensemble["start_offsets_deg"] == pytest.approx([0.0, 0.01, 0.02, 0.03, 0.04])
    per_run = [values["F_O2"] for values in ensemble["per_run"]]
    assert per_run[0] == pytest.approx(summary["cycles"]["per_revolution"]["F_O2"], rel=1e-12)
    assert len({tuple(values) for values in per_run}) == 5  # perturbed: five trajectories
    stats = ensemble["statistics"]["F_O2"]
    assert stats["revolutions"] == 10 and stats["batches"] == 5
    assert stats["mean"]["value"] == pytest.approx(sum(map(sum, per_run)) / 10)
    assert stats["max"]["value"] == pytest.approx(max(map(max, per_run)))
    printed = capsys.readouterr().out
    assert "ensemble of 5 runs (start angles 0.01° apart), 2 revolution(s) each" in printed
    assert "F_O2 over 10 revolutions: mean " in printed


@pytest.mark.parametrize(
    ("settle", "revolutions", "running_figures"),
    [
        ("0", "1", set()),  # one revolution: one peak each, a section of 2 points
        ("2", "1", {"peaks_per_revolution.png"}),  # the default: 3 revolutions, 2 points
        ("0", "3", {"peaks_per_revolution.png", "poincare.png"}),
    ],
)
def test_the_running_figures_are_drawn_when_they_show_something(
    tmp_path, settle: str, revolutions: str, running_figures: set[str]
) -> None:
    """The Poincaré section is drawn from 3 points on (with fewer its verdict is
    "undetermined"; its four panels were a quarter of the default run's plotting), the
    peaks per revolution from 2 revolutions on; the time figures and the orbits always."""
    out = tmp_path / "run"
    arguments = ["simulate", "--settle", settle, "--revolutions", revolutions, "--no-progress"]
    assert run([*arguments, "--out", str(out)]) == 0
    always = {"angular_velocity.png", "angular_acceleration.png", "joint_forces.png",
              "journal_orbits.png"}  # fmt: skip
    assert {path.name for path in out.glob("*.png")} == always | running_figures
    verdict = json.loads((out / "summary.json").read_text())["periodicity"]["verdict"]
    assert (verdict == "undetermined") == ("poincare.png" not in running_figures)
