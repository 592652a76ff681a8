"""Wear by regime (issue 39 item 4; docs/contact.md, "Wear by regime"): Archard wear takes the
asperity (contact-law) share of a joint's load only, not the film's; a joint in full film
wears nothing and says so in one line; the regimes reach the wear history and its summary.

The paper four-bar at 21 µm in every joint under the π-film: with the default roughness every
joint floats (h_min ≥ 6 µm > 3σ = 3.4 µm); with O2 rough (σ = 3 µm: 3σ = 9 µm) O2 runs mixed,
its asperities carry load and it wears, while the others still float and do not.
"""

from __future__ import annotations

import dataclasses
import math
import re

import pytest

from jointplay.dynamics.setup import ContactModel
from jointplay.dynamics.wear import WearHistory, WearSettings, wear_life
from jointplay.io.config import load_preset

JOINTS = ("O2", "A", "B", "O4")


def _history(o2_roughness: float | None) -> WearHistory:
    mechanism = load_preset("paper-fourbar")
    joints = [
        j.with_clearance(21e-6)
        for j in ContactModel(film_model="short-bearing-pi").joints(mechanism, JOINTS)
    ]
    if o2_roughness is not None:
        joints = [
            dataclasses.replace(j, roughness=o2_roughness) if j.joint == "O2" else j for j in joints
        ]
    return wear_life(
        mechanism, joints, hours=100.0, update_hours=100.0, clearance_limit=60e-6,
        settings=WearSettings(coefficient=1e-6), settle=1,
    )  # fmt: skip


@pytest.fixture(scope="module")
def smooth() -> WearHistory:
    return _history(None)


@pytest.fixture(scope="module")
def rough_o2() -> WearHistory:
    return _history(3e-6)


def test_a_joint_in_full_film_wears_nothing_and_says_why(smooth: WearHistory) -> None:
    for name in JOINTS:
        assert math.isinf(smooth.life[name])
        assert smooth.bearing_profile[name].max() == 0.0
        why = smooth.no_wear(name)
        assert why is not None
        match = re.fullmatch(
            r"full film throughout: h_min ≥ (\d+\.\d+) µm, no asperity contact", why
        )
        assert match and float(match.group(1)) > 3 * 1.12  # above 3σ of the default σ
        assert all(r is not None and r.full_film == 1.0 for r in smooth.regimes[name])
    summary = smooth.summary()
    assert summary["no_wear"]["O2"].startswith("full film throughout")
    assert summary["film_regimes"]["O2"][0]["full_film"] == 1.0
    assert summary["contact_force_peak_N"]["O2"] == [0.0, 0.0]


def test_only_the_asperity_share_wears(rough_o2: WearHistory) -> None:
    """O2's asperities carry load: it wears (a finite growth, no 'no wear' line); the film
    carries A's, B's and O4's whole load (tens of N): they wear nothing."""
    assert rough_o2.contact_peak["O2"][0] > 0.0
    assert rough_o2.bearing_profile["O2"].max() > 0.0
    assert rough_o2.clearance["O2"][-1] > rough_o2.clearance["O2"][0]
    assert rough_o2.no_wear("O2") is None
    o2 = rough_o2.regimes["O2"][0]
    assert o2 is not None and o2.full_film < 1.0
    for name in JOINTS[1:]:
        assert rough_o2.contact_peak[name] == (0.0, 0.0)
        assert rough_o2.bearing_profile[name].max() == 0.0
        assert (rough_o2.no_wear(name) or "").startswith("full film throughout")


def test_the_wear_command_says_why_a_joint_does_not_wear(tmp_path, capsys) -> None:
    """The README quick tour's wear command (shortened to 1 h) under the π-film: one line per
    joint saying it ran in full film, and the regimes; no bare 'life inf h'."""
    import json

    from jointplay.cli import run

    out = tmp_path / "wear"
    status = run(
        ["wear", "--fit", "H8/g7", "--clearance-limit", "+20 um", "--hours", "1 h",
         "--update-hours", "1 h", "--wear-coefficient", "1e-6", "--settle", "1",
         "--film-model", "short-bearing-pi", "--no-plots", "--out", str(out)]
    )  # fmt: skip
    text = capsys.readouterr().out
    assert status == 0, text
    for name in JOINTS:
        assert re.search(
            rf"^{name}: clearance .* no wear: full film throughout: h_min ≥ \d+\.\d+ µm, no "
            "asperity contact$",
            text,
            flags=re.MULTILINE,
        ), text
    assert "inf h" not in text
    assert "lubrication regimes at the last re-simulation:" in text
    summary = json.loads((out / "summary.json").read_text(encoding="utf-8"))
    assert summary["no_wear"]["A"].startswith("full film throughout")
