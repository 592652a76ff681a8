"""The ``[lubrication]`` table of a mechanism file: a regime for every joint and per joint
(issue 39, item 3); bad entries are one line naming the table, and exit 2 on the command
line with nothing written."""

from __future__ import annotations

import tomllib
from pathlib import Path

import pytest

from jointplay.cli import run
from jointplay.errors import ConfigError
from jointplay.io.config import load_config, parse_config, preset_text
from jointplay.model.mechanism import Lubrication

DECLARED = """
[lubrication]
regime = "oil"
viscosity = "68 mPa*s"

[lubrication.joints.O2]
regime = "grease"
viscosity = "0.15 Pa*s"

[lubrication.joints]
B = "dry"
"""


def _paper(extra: str) -> dict:
    return tomllib.loads(preset_text("paper-fourbar") + extra)


def test_the_table_declares_each_joint_and_a_default() -> None:
    mechanism = parse_config(_paper(DECLARED))
    assert mechanism.lubrication is not None and mechanism.lubrication.regime == "oil"
    assert mechanism.lubrication.viscosity == pytest.approx(0.068)
    assert mechanism.lubrication_of("O2") == Lubrication("grease", 0.15)
    assert mechanism.lubrication_of("B") == Lubrication("dry")
    assert mechanism.lubrication_of("A") == mechanism.lubrication  # the mechanism's
    plain = parse_config(_paper('\n[lubrication]\nregime = "dry"\n'))
    assert plain.lubrication == Lubrication("dry") and not plain.joint_lubrication
    assert parse_config(_paper("")).lubrication is None  # nothing declared


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (
            '\n[lubrication]\nregime = "wet"\n',
            "lubrication: regime must be one of dry, oil, grease, got 'wet'",
        ),
        (
            '\n[lubrication]\nregime = "dry"\nviscosity = "0.05 Pa*s"\n',
            "lubrication: a dry joint has no lubricant",
        ),
        (
            '\n[lubrication.joints.A]\nviscosity = "-0.05 Pa*s"\n',
            "lubrication.joints.A: the lubricant's viscosity must be > 0 Pa*s",
        ),
        (
            '\n[lubrication.joints.Q]\nregime = "dry"\n',
            "lubrication.joints: no revolute joint 'Q' in 'paper-fourbar'",
        ),
        ('\n[lubrication]\ngrade = "VG 46"\n', "grade"),
        ('\n[lubrication.joints]\nA = "grease"\n', "base oil's viscosity"),
    ],
)
def test_bad_declarations_name_the_table(extra: str, message: str) -> None:
    with pytest.raises(ConfigError, match=message.replace("*", r"\*").replace("(", r"\(")):
        parse_config(_paper(extra), source="my.toml")


def test_a_bad_declaration_is_one_line_and_exit_2(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    config = tmp_path / "bad.toml"
    config.write_text(preset_text("paper-fourbar") + '\n[lubrication.joints.Q]\nregime = "dry"\n')
    out = tmp_path / "out"
    assert run(["simulate", "--config", str(config), "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "no revolute joint 'Q'" in err[0], err
    assert not out.exists()


def test_a_copied_file_keeps_its_declaration(tmp_path: Path) -> None:
    path = tmp_path / "m.toml"
    path.write_text(preset_text("paper-fourbar") + DECLARED)
    assert load_config(path).lubrication_of("B") == Lubrication("dry")


def test_the_flores_preset_declares_its_pin_dry() -> None:
    """flores-slider-crank declares the paper's dry pin (docs/contact.md, "Presets carry
    their published contact"); the four-bars declare nothing (below)."""
    mechanism = parse_config(tomllib.loads(preset_text("flores-slider-crank")))
    assert mechanism.lubrication == Lubrication("dry")
    assert mechanism.lubrication_of("B") == Lubrication("dry")


@pytest.mark.parametrize("name", ["paper-fourbar", "general-fourbar"])
def test_each_presets_lubrication_example_reads(name: str) -> None:
    """The four-bar presets declare nothing (the default holds) and show the table
    commented out: uncommented, it reads."""
    text = preset_text(name)
    assert parse_config(tomllib.loads(text)).lubrication is None
    lines = text.splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith("#   [lubrication]"))
    example = []
    for line in lines[start:]:
        if not line.startswith("#   "):
            break
        example.append(line.removeprefix("#   "))
    mechanism = parse_config(tomllib.loads(text + "\n" + "\n".join(example) + "\n"))
    assert mechanism.lubrication == Lubrication("oil", 0.05)
    assert [lub.regime for lub in mechanism.joint_lubrication.values()] == ["grease"]


GRADED = """
[lubrication]
grade = "ISO VG 46"

[lubrication.joints.O2]
regime = "grease"
grade = "ISO VG 220"

[lubrication.joints]
B = "oil ISO VG 68"
"""


def test_a_lubricant_is_named_by_its_iso_vg_grade() -> None:
    """``grade`` (or the regime ``"oil ISO VG 68"``) sets the viscosity at 40 °C: the grade's
    midpoint kinematic viscosity × 870 kg/m³."""
    mechanism = parse_config(_paper(GRADED))
    assert mechanism.lubrication == Lubrication("oil", grade=46)
    assert mechanism.lubrication is not None
    assert mechanism.lubrication.viscosity == pytest.approx(46e-6 * 870, rel=1e-12)
    assert mechanism.lubrication_of("O2") == Lubrication("grease", grade=220)
    assert mechanism.lubrication_of("B") == Lubrication("oil", grade=68)
    assert mechanism.lubrication_of("B").viscosity == pytest.approx(68e-6 * 870, rel=1e-12)


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (
            '\n[lubrication]\ngrade = "ISO VG 50"\n',
            "lubrication.grade: 'ISO VG 50' is not an ISO 3448 viscosity grade; the grades are "
            "ISO VG 2, 3, 5, 7, 10, 15, 22, 32, 46, 68, 100, 150, 220, 320, 460, 680, 1000, "
            "1500, 2200, 3200",
        ),
        (
            '\n[lubrication.joints]\nA = "oil ISO VG 47"\n',
            "lubrication.joints.A.regime: 'ISO VG 47' is not an ISO 3448 viscosity grade",
        ),
        (
            '\n[lubrication]\ngrade = "ISO VG 46"\nviscosity = "0.05 Pa*s"\n',
            "lubrication: give the lubricant's grade or its viscosity, not both",
        ),
        (
            '\n[lubrication]\nregime = "dry"\ngrade = "ISO VG 46"\n',
            "lubrication: a dry joint has no lubricant: drop its ISO VG grade",
        ),
        (
            '\n[lubrication]\nregime = "oil ISO VG 68"\ngrade = "ISO VG 46"\n',
            "lubrication: the regime names ISO VG 68 and grade ISO VG 46: give one",
        ),
    ],
)
def test_bad_grades_name_the_table(extra: str, message: str) -> None:
    with pytest.raises(ConfigError, match=message.replace("*", r"\*")):
        parse_config(_paper(extra), source="my.toml")
