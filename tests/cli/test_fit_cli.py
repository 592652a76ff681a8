"""The ``fit`` (ISO 286) and ``general-tolerance`` (ISO 2768-1) commands."""

from __future__ import annotations

import json

import pytest

from jointplay.cli import run


def _json(capsys: pytest.CaptureFixture[str], argv: list[str]) -> object:
    assert run(argv) == 0
    return json.loads(capsys.readouterr().out)


def test_fit_json_structure_h8_g7(capsys: pytest.CaptureFixture[str]) -> None:
    """docs/contact-laws.md §6c: H8/g7 at Ø10 gives 5 … 42 µm diametral, 2.5 … 21 µm radial."""
    assert _json(capsys, ["fit", "H8/g7", "--size", "10mm", "--json"]) == {
        "hole": {"designation": "H8", "upper_um": 22, "lower_um": 0},
        "shaft": {"designation": "g7", "upper_um": -5, "lower_um": -20},
        "fit_type": "clearance",
        "clearance_um": {"min": 5, "max": 42, "mean": 23.5},
        "radial_clearance_um": {"min": 2.5, "max": 21, "mean": 11.75},
    }


def test_fit_json_interference_is_negative_clearance(capsys: pytest.CaptureFixture[str]) -> None:
    data = _json(capsys, ["fit", "H7 / s6", "--size", "50 mm", "--json"])
    assert isinstance(data, dict)
    assert data["fit_type"] == "interference"
    assert data["clearance_um"] == {"min": -59, "max": -18, "mean": -38.5}
    assert data["radial_clearance_um"] == {"min": -29.5, "max": -9, "mean": -19.25}


def test_single_class_json(capsys: pytest.CaptureFixture[str]) -> None:
    assert _json(capsys, ["fit", "K7", "--size", "120mm", "--json"]) == {
        "designation": "K7",
        "kind": "hole",
        "upper_um": 10,
        "lower_um": -25,
    }
    assert _json(capsys, ["fit", "js6", "--size", "0.025 m", "--json"]) == {
        "designation": "js6",
        "kind": "shaft",
        "upper_um": 6.5,
        "lower_um": -6.5,
    }


def test_fit_text_output(capsys: pytest.CaptureFixture[str]) -> None:
    assert run(["fit", "H8/g7", "--size", "10mm"]) == 0
    out = capsys.readouterr().out
    assert "H8/g7" in out
    assert "over 6 up to and including 10 mm" in out
    assert "fit type: clearance" in out
    hole = next(line for line in out.splitlines() if line.startswith("hole"))
    shaft = next(line for line in out.splitlines() if line.startswith("shaft"))
    assert hole.split() == ["hole", "H8", "+22", "0", "+0.022", "0"]
    assert shaft.split() == ["shaft", "g7", "-5", "-20", "-0.005", "-0.02"]
    diametral = next(line for line in out.splitlines() if line.startswith("diametral"))
    radial = next(line for line in out.splitlines() if line.startswith("radial"))
    assert diametral.split() == ["diametral", "+5", "+42", "+23.5"]
    assert radial.split() == ["radial", "+2.5", "+21", "+11.75"]


def test_single_class_text_output(capsys: pytest.CaptureFixture[str]) -> None:
    assert run(["fit", "K7", "--size", "120mm"]) == 0
    out = capsys.readouterr().out
    assert "K7 (hole)" in out
    assert "119.975 … 120.01 mm" in out


def test_general_tolerance_text(capsys: pytest.CaptureFixture[str]) -> None:
    assert run(["general-tolerance", "c", "--size", "270.5mm"]) == 0
    out = capsys.readouterr().out
    assert "±1.2 mm" in out
    assert "over 120 up to and including 400 mm" in out


def test_general_tolerance_json(capsys: pytest.CaptureFixture[str]) -> None:
    assert _json(capsys, ["general-tolerance", "c", "--size", "270.5mm", "--json"]) == {
        "class": "c",
        "size_mm": 270.5,
        "deviation_mm": 1.2,
    }


def test_general_tolerance_other_tables(capsys: pytest.CaptureFixture[str]) -> None:
    assert _json(
        capsys, ["general-tolerance", "m", "--size", "30mm", "--feature", "angular", "--json"]
    ) == {"class": "m", "feature": "angular", "size_mm": 30, "deviation_deg": 0.5}
    assert _json(
        capsys, ["general-tolerance", "v", "--size", "2 mm", "--feature", "broken-edge", "--json"]
    ) == {"class": "v", "feature": "broken-edge", "size_mm": 2, "deviation_mm": 0.4}
    assert run(["general-tolerance", "c", "--size", "5mm", "--feature", "angular"]) == 0
    assert "±1°30'" in capsys.readouterr().out


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["fit", "I7", "--size", "10mm"], "no fundamental deviation 'I'"),  # unknown letter
        (["fit", "H8/q7", "--size", "10mm"], "no fundamental deviation 'q'"),
        (["fit", "H19", "--size", "10mm"], "no standard tolerance grade IT19"),  # bad grade
        (["fit", "J9", "--size", "10mm"], "J6, J7 and J8"),  # grade the letter does not have
        (["fit", "H7", "--size", "4000mm"], "up to 3150 mm"),  # size out of range
        (["fit", "T7", "--size", "20mm"], "over 24 up to and including 3150 mm"),
        (["fit", "H7", "--size", "10"], 'no unit; write it with one, e.g. "10 mm"'),  # no unit
        (["fit", "H7", "--size", "10 kg"], "cannot be converted to m"),
        (["fit", "g7/H8", "--size", "10mm"], "hole/shaft"),
        (["general-tolerance", "f", "--size", "2500mm"], "leaves class f (fine) empty"),
        (["general-tolerance", "v", "--size", "2mm"], "leaves class v (very coarse) empty"),
        (["general-tolerance", "m", "--size", "0.3mm"], "stated on the dimension itself"),
        (["general-tolerance", "x", "--size", "10mm"], "unknown ISO 2768-1 tolerance class"),
        (["general-tolerance", "m", "--size", "10"], "no unit"),
    ],
)
def test_errors_exit_2_with_one_line(
    capsys: pytest.CaptureFixture[str], argv: list[str], message: str
) -> None:
    assert run(argv) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1, captured.err
    assert lines[0].startswith("jointplay: error: ")
    assert message in lines[0]
    assert "Traceback" not in captured.err


@pytest.mark.parametrize(
    ("command", "text"),
    [("fit", "ISO 286"), ("general-tolerance", "ISO 2768-1")],
)
def test_help(capsys: pytest.CaptureFixture[str], command: str, text: str) -> None:
    assert run([command, "--help"]) == 0
    out = capsys.readouterr().out
    assert text in out
    assert "--size" in out
    assert "--json" in out
