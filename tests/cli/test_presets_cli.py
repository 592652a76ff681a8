"""Presets carry their published contact (issue 40, item 3): ``flores-slider-crank`` runs the
paper's dry Lankarani–Nikravesh contact with no option, the command line overrides it, and
every preset states its source and what it reproduces (``presets``, ``show``)."""

from __future__ import annotations

import json
import math
import tomllib

import pandas as pd
import pytest

from jointplay.cli import run
from jointplay.io.config import list_presets, preset_text

FLORES = ["simulate", "--preset", "flores-slider-crank", "--no-plots"]
#: The preset's crank speed, rev/min, and its clearance at the piston pin, m.
RPM = 5000.0
CLEARANCE = 0.5e-3


def _impacts_per_revolution(steps: pd.DataFrame, settle: int) -> list[int]:
    """Contact onsets at the piston pin B (its penetration turning positive between two
    accepted steps) in each revolution after the ``settle`` start-up ones."""
    period = 60.0 / RPM
    pen = steps["pen_B"].to_numpy()
    onset = (pen[1:] > 0) & (pen[:-1] <= 0)
    revolution = (steps["t"].to_numpy()[1:] // period).astype(int)
    total = round(steps["t"].iloc[-1] / period)
    return [int(onset[revolution == r].sum()) for r in range(settle, total)]


def test_the_flores_preset_runs_the_published_contact_by_default(tmp_path, capsys) -> None:
    """With no contact option the preset runs dry, frictionless Lankarani–Nikravesh with
    e = 0.9 and K = 6.6e10 N/m^1.5, and shows the paper's pattern over 20 settled
    revolutions: ≥ 5 impacts per settled revolution on average (measured 12.0: 13 of the 20
    revolutions 13–21 impacts, the others 0–1, the pin sliding round the wall in continuous
    contact), the deepest penetration < 30 % of the clearance (measured 70.5 µm of 500, 14 %),
    the pin's force peak several times the ideal joint's (measured 2.7–14.5×, mean 7.9×).
    Under the default oil film before this change: no impact at all. ~3 s of integration."""
    out = tmp_path / "flores"
    settle, revolutions = 2, 20
    args = ["--settle", str(settle), "--revolutions", str(revolutions), "--out", str(out)]
    assert run([*FLORES, *args]) == 0
    printed = capsys.readouterr().out
    assert "lubrication: dry (B)" in printed
    summary = json.loads((out / "summary.json").read_text())
    settings = summary["contact"]["settings"]
    assert settings["law"] == "lankarani-nikravesh"
    assert settings["stiffness"] == pytest.approx(6.6e10)
    assert settings["restitution"] == pytest.approx(0.9)
    assert summary["contact"]["friction"]["coefficient"] == 0.0
    assert summary["lubrication"]["B"]["regime"] == "dry"
    impacts = _impacts_per_revolution(pd.read_csv(out / "steps.csv"), settle=settle)
    assert len(impacts) == revolutions
    assert sum(impacts) / revolutions >= 5.0, impacts
    deepest = summary["cycles"]["deepest_penetration_m"]["B"]
    assert 0.0 < deepest < 0.3 * CLEARANCE
    ratio = summary["peaks"]["F_B"]["value"] / summary["nominal_peaks"]["F_B"]
    assert ratio > 3.0


@pytest.mark.parametrize(
    ("args", "law", "regime"),
    [
        # a paper method named: the preset's law and its parameters make way (no clash)
        (["--method", "ifm-conventional"], None, "dry"),
        # a key given: that key overrides, the others of the preset stay
        (["--restitution", "0.6"], "lankarani-nikravesh", "dry"),
        # another law named: its own parameters, not the preset's K and e
        (["--contact", "hertz"], "hertz", "dry"),
        # the lubrication named: every joint's, over the preset's declaration
        (["--lubrication", "oil"], "lankarani-nikravesh", "oil"),
    ],
)
def test_the_command_line_overrides_the_presets_contact(
    tmp_path, args: list[str], law: str | None, regime: str
) -> None:
    out = tmp_path / "over"
    given = ["--settle", "0", "--revolutions", "0.05", "--start", "steady"]
    assert run([*FLORES, *given, *args, "--out", str(out)]) == 0
    summary = json.loads((out / "summary.json").read_text())
    contact = summary["contact"]
    if law is None:
        assert contact["method"] == "ifm-conventional"
    else:
        assert contact["settings"]["law"] == law
        if law == "hertz":
            assert contact["settings"].get("restitution") is None
            assert contact["settings"].get("stiffness") != pytest.approx(6.6e10)
    if "--restitution" in args:
        assert contact["settings"]["restitution"] == pytest.approx(0.6)
        assert contact["settings"]["stiffness"] == pytest.approx(6.6e10)
    assert summary["lubrication"]["B"]["regime"] == regime


def test_every_preset_states_its_source_and_what_it_reproduces(capsys) -> None:
    """``jointplay presets`` lists each preset's source and what it reproduces; ``jointplay
    show`` prints them in the preset's [mechanism] table."""
    presets = list_presets()
    assert {p.name for p in presets} >= {"paper-fourbar", "general-fourbar", "flores-slider-crank"}
    assert run(["presets"]) == 0
    listed = " ".join(capsys.readouterr().out.split())  # the table wraps its cells
    for preset in presets:
        assert preset.source.strip() and preset.reproduces.strip()
        assert f"source: {' '.join(preset.source.split())}" in listed
        assert f"reproduces: {' '.join(preset.reproduces.split())}" in listed
        assert run(["show", preset.name]) == 0
        shown = tomllib.loads(capsys.readouterr().out)
        assert shown["mechanism"]["source"] == preset.source
        assert shown["mechanism"]["reproduces"] == preset.reproduces
    flores = tomllib.loads(preset_text("flores-slider-crank"))
    assert "Flores & Ambrosio (2004)" in flores["mechanism"]["source"]
    assert flores["simulation"]["contact"] == "lankarani-nikravesh"
    assert flores["lubrication"]["regime"] == "dry"
    assert math.isclose(flores["simulation"]["restitution"], 0.9)
