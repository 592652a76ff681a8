"""The ``jointplay design`` and ``jointplay wear`` commands."""

from __future__ import annotations

import json

import pandas as pd
import pytest

from jointplay.cli import run

QUIET = ["--no-progress", "--no-plots", "--workers", "1"]


def test_design_writes_one_row_per_scheme_and_names_the_choice(tmp_path, capsys) -> None:
    out = tmp_path / "design"
    code = run(
        ["design", "--preset", "paper-fourbar", "--fits", "H7/g6,H11/c11", "--classes", "f,v",
         "--require", "omega4_peak <= 100 rad/s", "--out", str(out), *QUIET]
    )  # fmt: skip
    assert code == 0
    printed = capsys.readouterr().out
    # --samples auto: 1 600 failure-free samples show 99.73 % (95 % interval)
    assert "choose H11/c11 / v" in printed
    assert "0 failures in 1,600 samples" in printed
    table = pd.read_parquet(out / "design.parquet")
    # cost-ordered: class v's stream (both fits) meets first; class f, dearer, never runs
    assert len(table) == 2 and set(pd.read_csv(out / "design.csv")["scheme"]) == set(
        table["scheme"]
    )
    summary = json.loads((out / "summary.json").read_text())
    assert summary["best"] == "H11/c11 / v"
    assert {r["scheme"] for r in summary["settings"]["not_run"]} == {"H7/g6 / f", "H11/c11 / f"}
    assert summary["provenance"]["command_line"].startswith("jointplay design")
    assert (out / "report.html").exists() and (out / "samples.parquet").exists()


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--require", "omega4_peak == 3"], "'==' (character 13) is not a comparison"),
        (["--require", "omega4_peak <= 3 rad/s", "--fit", "O2"], "expected JOINT=FIT"),
        (["--require", "omega4_peak <= 3 rad/s", "--confidence", "100"], "--confidence"),
        (["--require", "omega4_peak <= 3 rad/s", "--backend", "threads"], "--backend must be"),
        (["--require", "omega4_peak <= 3 rad/s", "--k", "1e6 N/mm^1.5"], "dynamic designs only"),
        (["--require", "joint_force <= 1 kN", "--k", "1e6"], "--k"),
        (["--require", "joint_force <= 1 kN", "--contact", "nonsense"], "nonsense"),
        (["--require", "rocker_speed_error <= 3"], "did you mean 'rocker_speed_error <= 3 %'?"),
        (["--require", "life >= 200"], "did you mean 'life >= 200 h'?"),
        (["--require", "contact_pressure <= 500"], "did you mean 'contact_pressure <= 500 MPa'?"),
        (["--require", "joint_force <= 1 kN", "--confidence", "0.9973"], "'99.73 %'?"),
        (["--require", "joint_force <= 1 kN", "--samples", "many"], "--samples: expected 'auto'"),
        (["--require", "joint_force <= 1 kN", "--samples", "9" * 25], "--samples: expected"),
        (["--require", "joint_force <= 1 kN", "--cpk", "bore=1.33"], "--cpk 'bore=1.33'"),
        (["--require", "joint_force <= 1 kN", "--cpk", "hole=-1"], "CPK > 0"),
        (["--require", "joint_force <= 1 kN", "--sampling", "worst"], "--sampling must be"),
        (
            ["--require", "joint_force <= 1 kN", "--sampling", "band", "--cpk", "pin=1.33"],
            "needs sampling 'parts'",
        ),
    ],
)
def test_design_errors_are_one_line(tmp_path, capsys, args: list[str], message: str) -> None:
    out = tmp_path / "x"
    code = run(["design", "--preset", "paper-fourbar", "--out", str(out), *args, *QUIET])
    assert code == 2
    err = capsys.readouterr().err
    assert message in err and len(err.strip().splitlines()) == 1 and "Traceback" not in err
    assert not out.exists()


@pytest.mark.parametrize(
    ("requirement", "message", "device"),
    [
        # kinematic: no dynamics to run
        *(("omega4_peak <= 3 rad/s", "--responses dynamic", d) for d in ("gpu", "cuda")),
        # the JAX kernel has no running responses (the CPU and CUDA lanes have them)
        (
            "rocker_speed_error <= 3 %",
            "gpu backend (JAX) computes no running responses: 'rocker_speed_error <= 3 %'",
            "gpu",
        ),
    ],
)
def test_the_gpu_backend_is_refused_where_the_batch_engine_cannot_answer(
    tmp_path, capsys, requirement: str, message: str, device: str
) -> None:
    out = tmp_path / "x"
    args = ["design", "--preset", "paper-fourbar", "--require", requirement, "--backend", device]
    assert run([*args, "--out", str(out), "--no-progress", "--no-plots"]) == 2
    err = capsys.readouterr().err
    assert message in err and device in err
    assert not out.exists()


#: A dynamic design as short as it gets: 2 samples of one scheme, a quarter turn, no start-up;
#: at 10 % two failure-free samples decide (the yield's lower bound is 0.025^(1/2) = 15.8 %).
FAST_DYNAMIC = ["design", "--preset", "paper-fourbar", "--fits", "H7/g6", "--classes", "m",
                "--require", "joint_force <= 1 kN", "--samples", "2", "--confidence", "10 %",
                "--settle", "0",
                "--revolutions", "0.25", "--backend", "local", "--no-progress", "--no-plots"]  # fmt: skip


def test_design_warns_on_stderr_when_pins_sink_deeper_than_the_clearance(tmp_path, capsys) -> None:
    """An absurdly soft --k (1e2 N/mm^1.5: every pin sinks several times its clearance):
    one warning line per clearance joint on stderr, as `jointplay tolerance` prints them,
    with the counts of samples.parquet; a stiff one (1e6 N/mm^1.5) prints none."""
    soft = tmp_path / "soft"
    # the IMPACT law (not the default) with these --k, and dry pins (a film would hold them)
    impact = ["--contact", "impact", "--lubricant-viscosity", "0"]
    assert run([*FAST_DYNAMIC, *impact, "--k", "1e2 N/mm^1.5", "--out", str(soft)]) == 0
    err = capsys.readouterr().err
    lines = [line for line in err.splitlines() if "penetration-exceeds-clearance" in line]
    frame = pd.read_parquet(soft / "samples.parquet")
    assert len(lines) == 4
    for line, joint in zip(lines, ("O2", "A", "B", "O4"), strict=True):
        count = int((frame[f"penetration_ratio_{joint}"] > 1).sum())
        assert count == 2  # absurdly soft: both samples
        assert line.startswith(
            f"jointplay: warning: penetration-exceeds-clearance [{joint}]: {count} of 2 samples "
            "(100 %) in 1 of 1 schemes: the pin of "
        )
        assert "the recommended scheme H7/g6 / m is concerned (2 of its 2 samples)" in line
    summary = json.loads((soft / "summary.json").read_text())
    codes = [(d["code"], d["joint"]) for d in summary["diagnostics"]]
    clearance = [j for code, j in codes if code == "penetration-exceeds-clearance"]
    assert clearance == ["O2", "A", "B", "O4"]
    # so soft a contact is not elastic either (penetration-exceeds-elastic, every joint)
    assert [j for code, j in codes if code == "penetration-exceeds-elastic"] == clearance
    assert summary["settings"]["model"]["contact_law"]["stiffness"] == pytest.approx(
        1e2 * 1000**1.5
    )
    stiff = tmp_path / "stiff"
    assert run([*FAST_DYNAMIC, *impact, "--k", "1e6 N/mm^1.5", "--out", str(stiff)]) == 0
    assert "penetration-exceeds-clearance" not in capsys.readouterr().err
    written = json.loads((stiff / "summary.json").read_text())["diagnostics"]
    assert [d for d in written if d["code"] == "penetration-exceeds-clearance"] == []
    assert (pd.read_parquet(stiff / "design.parquet")["penetration_exceeds_O2"] == 0).all()


def test_wear_writes_the_history_and_the_life(tmp_path, capsys) -> None:
    out = tmp_path / "wear"
    code = run(
        ["wear", "--preset", "paper-fourbar", "--hours", "2 h", "--update-hours", "1 h",
         "--clearance-limit", "+20 um", "--fit", "H7/g6", "--wear-coefficient", "1e-5",
         "--no-plots", "--out", str(out)]
    )  # fmt: skip
    assert code == 0
    printed = capsys.readouterr().out
    assert "mechanism life:" in printed
    history = pd.read_csv(out / "wear.csv")
    assert history["hours"].tolist() == [0.0, 1.0, 2.0]
    summary = json.loads((out / "summary.json").read_text())
    assert set(summary["life_hours"]) == {"O2", "A", "B", "O4"}
    assert summary["clearance_limit_m"]["A"] == pytest.approx(29e-6 / 2 + 20e-6)
    assert len(pd.read_csv(out / "profiles.csv")) == 720


def test_wear_and_cost_tables_sit_in_the_mechanism_config(tmp_path, capsys) -> None:
    """[wear] per joint and [cost] in the --config file reach the studies; --table replaces
    a table of the config."""
    from jointplay.io.config import load_config, preset_text

    plain = tmp_path / "plain.toml"
    plain.write_text(preset_text("paper-fourbar"), encoding="utf-8")
    worn = tmp_path / "worn.toml"
    worn.write_text(
        preset_text("paper-fourbar")
        + "\n[wear]\ncoefficient = 1e-5\n[wear.joints.A]\ncoefficient = 1e-3\n"
        + '\n[cost]\nmodel = "exponential"\n',
        encoding="utf-8",
    )
    assert load_config(worn).name == load_config(plain).name  # the mechanism is the same
    from jointplay.cli.design import read_table
    from jointplay.tolerance.cost import CostModel

    tables = read_table(None, worn)
    assert CostModel.from_table(tables["cost"]).model == "exponential"
    assert tables["wear"]["joints"]["A"]["coefficient"] == 1e-3

    def lives(config, *extra: str) -> dict[str, float]:
        out = tmp_path / f"wear-{config.stem}-{len(extra)}"
        args = ["wear", "--config", str(config), "--hours", "1 h", "--update-hours", "60 min",
                "--clearance-limit", "+20 um", "--fit", "H7/g6", "--lubricant-viscosity", "0",
                "--no-plots", "--out", str(out)]  # fmt: skip
        assert run([*args, *extra]) == 0
        return json.loads((out / "summary.json").read_text())["life_hours"]

    base = lives(plain, "--wear-coefficient", "1e-5")
    tabled = lives(worn)
    assert tabled["A"] < base["A"] / 10  # k 100 times larger in A: worn through within the hour
    assert min(tabled, key=tabled.__getitem__) == "A"
    override = tmp_path / "table.toml"
    override.write_text("[wear]\ncoefficient = 1e-5\n", encoding="utf-8")
    assert lives(worn, "--table", str(override)) == pytest.approx(base, rel=1e-12)
    capsys.readouterr()


def test_rtol_reaches_the_design_study(tmp_path) -> None:
    out = tmp_path / "tight"
    assert run([*FAST_DYNAMIC, "--rtol", "1e-8", "--out", str(out)]) == 0
    settings = json.loads((out / "summary.json").read_text())["settings"]
    assert settings["model"]["solver"]["rtol"] == 1e-8


def test_h7_h6_is_tried_only_when_named_with_a_note(tmp_path, capsys) -> None:
    """Its minimum radial clearance is zero: not among the default fits; named, a note."""
    from jointplay.cli.design import DEFAULT_FITS

    assert "H7/h6" not in DEFAULT_FITS
    base = ["design", "-r", "rocker_swing >= 50 deg", "--classes", "m", "--samples", "5"]
    assert run([*base, "--no-plots", "--out", str(tmp_path / "default")]) == 0
    assert "zero minimum" not in capsys.readouterr().err
    named = [*base, "--fits", "H7/h6,H8/g7", "--no-plots", "--out", str(tmp_path / "named")]
    assert run(named) == 0
    notes = [line for line in capsys.readouterr().err.splitlines() if "note:" in line]
    assert notes == [
        "jointplay: note: H7/h6 has a zero minimum radial clearance at Ø10 mm (0 … 12 µm): "
        "its samples near the lower limit leave the pin almost no room, where the "
        "clearance-joint model is least reliable"
    ]


def test_the_design_command_hands_the_study_one_run_settings(tmp_path, monkeypatch) -> None:
    """``jointplay design`` builds its RunSettings once from its options: equal to the Python
    API's for the same inputs, and the study gets no loose run keyword beside it."""
    from jointplay.dynamics.settings import RunSettings
    from jointplay.dynamics.setup import ContactModel
    from jointplay.dynamics.simulate import SolverOptions
    from jointplay.study import design

    seen = {}

    def capture(*args, **kwargs):
        seen.update(kwargs)
        raise KeyboardInterrupt

    monkeypatch.setattr(design, "design_study", capture)
    run([*FAST_DYNAMIC, "--rtol", "1e-7", "--out", str(tmp_path / "out")])
    expected = RunSettings.of(
        contact=ContactModel(), settle=0, revolutions=0.25, solver=SolverOptions(rtol=1e-7)
    )
    assert seen["run_settings"] == expected
    assert not {"contact", "start", "settle", "revolutions", "solver"} & set(seen)


def test_the_scheme_tables_read_at_80_columns(tmp_path, capsys, monkeypatch) -> None:
    """At 80 columns each scheme is one line in each table: its label whole (a fit per joint
    printed as S1, S2, ... with its key) and its yield's interval on one line, every response
    with its unit (a kinematic study of three requirements and two fixed-joint schemes)."""
    from rich.console import Console

    import jointplay.cli.design as design

    monkeypatch.setattr(design, "console", Console(width=80, soft_wrap=True, highlight=False))
    out = tmp_path / "design"
    code = run(
        ["design", "--preset", "paper-fourbar", "--fits", "H8/f7,H11/c11", "--fit", "O2=H7/g6",
         "--classes", "m,c", "--samples", "200", "--require", "omega4_peak <= 13.75 rad/s",
         "--require", "transmission_angle_min >= 36.8 deg", "--require", "rocker_swing >= 52 deg",
         "--out", str(out), *QUIET]
    )  # fmt: skip
    assert code == 0
    printed = capsys.readouterr().out
    table = pd.read_parquet(out / "design.parquet").sort_values("cost")
    lines = printed.splitlines()
    tables = lines[: next(i for i, line in enumerate(lines) if line.startswith("S1: "))]
    assert max(len(line) for line in tables) <= 80, printed
    for n, (_, row) in enumerate(table.iterrows(), start=1):
        label = f"S{n}"  # every scheme fixes O2: no label is short
        assert f"{label}: {row['scheme']}" in lines
        interval = f"{row['yield_low']:.2f}–{row['yield_high']:.2f}"
        mine = [line for line in lines if line.split()[:1] == [label]]
        assert len(mine) == 2, mine  # one line in each table
        assert interval in mine[0].split() and row["verdict"] in mine[0].split()
    # the responses' table: every header with its unit, the angles in degrees
    assert "(rad/s)" in printed and printed.count("(deg)") == 2
    assert "()" not in printed


def test_a_short_scheme_label_is_printed_whole() -> None:
    from jointplay.cli.design import scheme_labels

    long = "O2=H7/g6,A=H8/f7,B=H8/f7,O4=H8/f7 / m"
    assert scheme_labels(["H11/c11 / m", long, "H8/f7 / c", long + "x"]) == {
        "H11/c11 / m": "H11/c11 / m", long: "S1", "H8/f7 / c": "H8/f7 / c", long + "x": "S2",
    }  # fmt: skip
