"""RunSettings: the settings of a run of the clearance dynamics, checked once, built once
by the command line and by the Python API alike."""

from __future__ import annotations

import pytest

from jointplay.dynamics.settings import RunSettings
from jointplay.dynamics.setup import (
    DEFAULT_IMPACT,
    ContactModel,
    ContactSettings,
    FrictionSettings,
    conventional_contact,
)
from jointplay.dynamics.simulate import SolverOptions, Start
from jointplay.errors import SettingError


def test_the_defaults_are_the_physical_running_mechanism() -> None:
    run = RunSettings()
    assert run.contact == ContactModel() and run.contact.friction.coefficient == 0.1
    assert run.start == Start("steady") and (run.settle, run.revolutions) == (2, 1.0)
    assert run.solver == SolverOptions()


@pytest.mark.parametrize(
    ("fields", "setting"),
    [
        ({"settle": -1}, "settle"),
        ({"settle": 1.5}, "settle"),
        ({"revolutions": 0}, "revolutions"),
        ({"revolutions": float("nan")}, "revolutions"),
        ({"revolutions": "1"}, "revolutions"),
        ({"contact": "ifm-conventional"}, "contact"),
        ({"solver": 1e-6}, "solver"),
        ({"start": 3}, "start"),
    ],
)
def test_bad_values_are_refused_by_the_field_they_are_in(fields, setting) -> None:
    with pytest.raises(SettingError) as caught:
        RunSettings(**fields)
    assert str(caught.value).startswith(setting)
    option = "--" + setting
    assert str(caught.value.named({setting: option})).startswith(option)


def test_loose_keywords_build_the_same_settings_once() -> None:
    assert RunSettings.of() == RunSettings()
    conventional = RunSettings.of(contact="ifm-conventional", settle=0, start="rest")
    assert conventional.contact == conventional_contact()
    assert conventional.start == Start("rest") and conventional.settle == 0
    bare = RunSettings.of(contact=DEFAULT_IMPACT)  # a law: frictionless, as before
    assert bare.contact.law == DEFAULT_IMPACT and not bare.contact.friction.enabled
    given = RunSettings(revolutions=2.0)
    assert RunSettings.of(given) is given
    with pytest.raises(SettingError, match="either as run or as settle, not both"):
        RunSettings.of(given, settle=1)


def test_the_command_line_and_the_api_build_equal_settings(monkeypatch, tmp_path) -> None:
    """``jointplay tolerance`` builds its RunSettings once from its options; the Python API
    builds the same from the same inputs, and the study gets that object."""
    from jointplay.cli import run as cli
    from jointplay.tolerance import analysis

    seen = {}

    def capture(*args, **kwargs):
        seen.update(kwargs)
        raise KeyboardInterrupt

    monkeypatch.setattr(analysis, "tolerance_study", capture)
    args = [
        "tolerance", "--preset", "paper-fourbar", "--responses", "dynamic", "--start", "rest",
        "--settle", "1", "--revolutions", "0.5", "--rtol", "1e-7", "--contact", "hertz",
        "--stiffness-law", "hertz", "--friction", "0.05", "--no-progress", "--out",
        str(tmp_path / "out"),
    ]  # fmt: skip
    cli(args)
    expected = RunSettings.of(
        contact=ContactModel(
            settings=ContactSettings(law="hertz", stiffness_law="hertz"),
            friction=FrictionSettings(coefficient=0.05),
        ),
        start="rest",
        settle=1,
        revolutions=0.5,
        solver=SolverOptions(rtol=1e-7),
    )
    assert seen["run_settings"] == expected
    assert not {"contact", "start", "settle", "revolutions", "solver"} & set(seen)


def test_simulate_run_is_simulate_with_the_settings(paper_fourbar) -> None:
    """The simulate-level helper: the run's contact on the fitted joints, its start, settle,
    revolutions and solver; the same numbers as simulate given them one by one."""
    from jointplay.dynamics.settings import simulate_run
    from jointplay.dynamics.simulate import simulate

    run = RunSettings.of(contact="ifm-conventional", start="rest", settle=0, revolutions=0.02)
    helped = simulate_run(paper_fourbar, None, run)
    direct = simulate(
        paper_fourbar,
        conventional_contact().joints(paper_fourbar),
        revolutions=0.02,
        settle=0,
        start=Start("rest"),
        solver=SolverOptions(),
    )
    assert helped.peaks == direct.peaks
    assert helped.timeseries.equals(direct.timeseries)
