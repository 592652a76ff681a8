"""The kinematics, presets and show commands, and the CLI's error boundary."""

from __future__ import annotations

import json

import pandas as pd
import pytest

from jointplay.cli import run

FOURBAR_COLUMNS = [
    "crank_deg", "theta3_deg", "theta4_deg", "omega3", "omega4", "alpha3", "alpha4",
    "F_O2", "F_A", "F_B", "F_O4", "torque",
]  # fmt: skip


def test_kinematics_writes_documented_files(tmp_path) -> None:
    out = tmp_path / "k"
    assert (
        run(["kinematics", "--preset", "paper-fourbar", "--rpm", "200 rpm", "--out", str(out)]) == 0
    )
    table = pd.read_csv(out / "kinematics.csv")
    assert list(table.columns) == FOURBAR_COLUMNS
    assert len(table) == 361
    assert table["crank_deg"].tolist() == list(range(361))
    summary = json.loads((out / "summary.json").read_text())
    assert summary["grashof"]["class"] == "crank-rocker"
    assert summary["rocker_swing_deg"] == pytest.approx(52.65, abs=0.01)
    assert summary["columns"]["omega4"]["peak_abs"] == pytest.approx(table["omega4"].abs().max())
    assert summary["provenance"]["jointplay_version"]
    for name in (
        "angular_velocity.png",
        "angular_acceleration.png",
        "joint_forces.png",
        "torque.png",
    ):
        assert (out / name).stat().st_size > 1000


def test_clockwise_crank_counts_down_and_mirrors_the_motion(tmp_path) -> None:
    assert run(["kinematics", "--out", str(tmp_path / "ccw"), "--no-plots"]) == 0
    assert (
        run(["kinematics", "--direction", "cw", "--out", str(tmp_path / "cw"), "--no-plots"]) == 0
    )
    ccw = pd.read_csv(tmp_path / "ccw" / "kinematics.csv")
    cw = pd.read_csv(tmp_path / "cw" / "kinematics.csv")
    assert cw["crank_deg"].iloc[1] == -1
    # Same positions at the same crank angle, opposite velocities, same accelerations.
    matched = cw.iloc[::-1].reset_index(drop=True)
    pd.testing.assert_series_equal(
        matched["theta4_deg"], ccw["theta4_deg"], atol=1e-9, check_names=False
    )
    pd.testing.assert_series_equal(-matched["omega4"], ccw["omega4"], atol=1e-9, check_names=False)
    pd.testing.assert_series_equal(matched["alpha4"], ccw["alpha4"], atol=1e-7, check_names=False)


def test_slider_crank_columns(tmp_path) -> None:
    assert (
        run(["kinematics", "-p", "flores-slider-crank", "--out", str(tmp_path), "--no-plots"]) == 0
    )
    columns = pd.read_csv(tmp_path / "kinematics.csv").columns.tolist()
    assert columns == [
        "crank_deg", "theta3_deg", "omega3", "alpha3", "slider_x", "slider_v", "slider_a",
        "F_O2", "F_A", "F_B", "F_S", "M_S", "torque",
    ]  # fmt: skip


def test_presets_and_show(capsys) -> None:
    assert run(["presets"]) == 0
    assert "paper-fourbar" in capsys.readouterr().out
    assert run(["show", "paper-fourbar"]) == 0
    assert 'crank = "108 mm"' in capsys.readouterr().out


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--preset", "nope"], "unknown preset 'nope'"),
        (["--rpm", "-5 rpm"], "--rpm must be a positive"),
        (["--rpm", "200"], "--rpm: '200' has no unit; write it with one, e.g. \"200 rpm\""),
        (["--direction", "sideways"], "--direction must be ccw or cw"),
        (["--start-angle", "30"], "has no unit"),
        (["--step", "7 deg"], "must divide 360"),
        (["--step", "1"], "--step: '1' has no unit"),
    ],
)
def test_bad_input_gives_one_line_and_no_output(tmp_path, capsys, args, message) -> None:
    out = tmp_path / "out"
    assert run(["kinematics", "--out", str(out), *args]) == 2
    err = capsys.readouterr().err
    assert message in err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert not out.exists()
    assert list(tmp_path.iterdir()) == []  # no staging folder left behind either


@pytest.mark.parametrize(
    ("content", "message"),
    [
        ("[mechanism\n", "malformed TOML"),
        ('[mechanism]\n[driver]\nspeed = "1 rpm"\n[geometry]\ncrank = "0.1"\n', "has no unit"),
        (
            '[mechanism]\n[geometry]\ncrank = "108 mm"\ncoupler = "50 mm"\nrocker = "50 mm"\n'
            'ground = "279.4 mm"\n[driver]\nspeed = "200 rpm"\n',
            "cannot be assembled",
        ),
    ],
)
def test_bad_config_files(tmp_path, capsys, content, message) -> None:
    config = tmp_path / "bad.toml"
    config.write_text(content)
    out = tmp_path / "out"
    assert run(["kinematics", "--config", str(config), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1
    assert not out.exists()


@pytest.mark.parametrize("args", [["kinematics", "--bogus"], ["fit"], ["show"]])
def test_usage_errors_exit_2_without_traceback(capsys, args) -> None:
    assert run(args) == 2
    assert "Traceback" not in capsys.readouterr().err


def test_figure_format_writes_a_vector_copy_of_every_figure(tmp_path) -> None:
    out = tmp_path / "k"
    assert run(["kinematics", "--out", str(out), "--figure-format", "pdf"]) == 0
    pngs = sorted(p.stem for p in out.glob("*.png"))
    assert pngs and sorted(p.stem for p in out.glob("*.pdf")) == pngs
    assert all((out / f"{stem}.pdf").read_bytes().startswith(b"%PDF") for stem in pngs)


def test_an_unknown_figure_format_is_refused_before_anything_is_written(tmp_path, capsys) -> None:
    out = tmp_path / "k"
    assert run(["kinematics", "--out", str(out), "--figure-format", "jpg"]) == 2
    assert "--figure-format must be one of png, svg, pdf" in capsys.readouterr().err
    assert not out.exists()


@pytest.mark.parametrize(
    ("preset", "units"),
    [
        ("paper-fourbar", {"theta4_deg": "deg", "omega4": "rad/s", "F_A": "N", "torque": "N·m"}),
        ("flores-slider-crank", {"slider_x": "m", "slider_a": "m/s²", "alpha3": "rad/s²"}),
    ],
)
def test_the_printed_table_gives_every_quantity_its_unit(tmp_path, capsys, preset, units) -> None:
    out = tmp_path / "k"
    assert run(["kinematics", "-p", preset, "--out", str(out), "--no-plots"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0].split()[:2] == ["quantity", "unit"]
    rows = {line.split()[0]: line.split()[1] for line in lines[1:] if line.startswith(" ")}
    rows = {name: unit for name, unit in rows.items() if name != "results"}
    for name, unit in units.items():
        assert rows[name] == unit
    columns = json.loads((out / "summary.json").read_text())["columns"]
    assert set(rows) == set(columns) - {"crank_deg"}  # every column printed, with a unit
