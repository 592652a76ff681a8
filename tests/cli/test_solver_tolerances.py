"""``--atol`` and ``--onset-tolerance`` (issue 40, item 2): the integrator's absolute
tolerance (a length; the velocities' at the defaults' ratio) and the contact-onset tolerance
(a length), declared once (``jointplay.dynamics.declared``), options of ``simulate`` and
``animate`` and keys of ``[simulation]``; their bad values in tests/cli/test_bad_input.py.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from jointplay.cli import run
from jointplay.cli._simulation import run_settings_of
from jointplay.dynamics.setup import ContactModel
from jointplay.dynamics.simulate import SolverOptions
from jointplay.errors import ConfigError
from jointplay.io.config import load_preset, simulation_settings
from jointplay.settings.simulation import ATOL_VELOCITY_PER_POSITION, solver_tolerances

#: The stiff case of issue 40 (tests/dynamics/test_stiff_contact.py), at the command line.
STIFF = [
    "simulate", "--contact", "lankarani-nikravesh", "--k", "1e10 N/m^1.5", "--restitution",
    "0.8", "--friction", "0", "--lubrication", "dry", "--clearance", "21 um", "--start",
    "steady", "--settle", "0", "--revolutions", "0.1", "--no-plots",
]  # fmt: skip
FORCES = ("F_O2", "F_A", "F_B", "F_O4")


def test_atol_sets_both_absolute_tolerances_at_the_defaults_ratio() -> None:
    defaults = SolverOptions()
    assert defaults.atol_velocity / defaults.atol_position == ATOL_VELOCITY_PER_POSITION
    read = solver_tolerances({"atol": "1e-12 m", "onset_tolerance": "2 nm"})
    assert read == pytest.approx(
        {"atol_position": 1e-12, "atol_velocity": 1e-8, "onset_tolerance": 2e-9}, rel=1e-12
    )
    assert solver_tolerances({}) == {}


def test_the_options_and_the_simulation_table_reach_the_solver(tmp_path: Path) -> None:
    config = tmp_path / "run.toml"
    config.write_text(
        '[simulation]\natol = "0.5 pm"\nonset_tolerance = "0.002 um"\n', encoding="utf-8"
    )
    table = simulation_settings(config)
    assert table == {"atol": "0.5 pm", "onset_tolerance": "0.002 um"}
    mechanism = load_preset("paper-fourbar")
    solver = run_settings_of(table, mechanism, ContactModel()).solver
    assert solver.atol_position == pytest.approx(5e-13)
    assert solver.atol_velocity == pytest.approx(5e-9)
    assert solver.onset_tolerance == pytest.approx(2e-9)
    assert solver.rtol == SolverOptions().rtol  # the others keep their defaults
    unset = run_settings_of({}, mechanism, ContactModel()).solver
    assert unset == SolverOptions()


@pytest.mark.parametrize(
    ("values", "message"),
    [
        ({"atol": "1e-12"}, "--atol: '1e-12' has no unit"),
        ({"atol": "1e-6 m/s"}, "--atol"),
        ({"atol": "0 m"}, "--atol must be a length > 0"),
        ({"atol": "2 um"}, "--atol must be a length > 0 and at most 1 um"),
        ({"onset_tolerance": "-1 nm"}, "--onset-tolerance must be a length > 0"),
        ({"onset_tolerance": 2e-9}, "--onset-tolerance: 2e-09 has no unit"),
    ],
)
def test_a_bad_tolerance_is_refused_naming_its_option(values: dict, message: str) -> None:
    with pytest.raises(ConfigError) as error:
        solver_tolerances(values)
    assert message in str(error.value)


def _forces(out: Path) -> tuple[dict[str, float], int]:
    summary = json.loads((out / "summary.json").read_text())
    return {k: summary["peaks"][k]["value"] for k in FORCES}, summary["solver"]["steps"]


def test_the_stiff_case_converges_at_the_defaults_and_the_options_reach_the_integrator(
    tmp_path: Path,
) -> None:
    """The issue's command: at the defaults its force peaks are within 1e-3 of the same
    command with every tolerance tightened by the options (rtol 1e-11, atol 1e-15 m, onset
    2.1 fm: converged, tests/dynamics/test_stiff_contact.py); with the old default onset
    tolerance given (0.21 µm, 1 % of the clearance) one is 8.5 % off."""
    runs = {
        "default": [],
        "converged": ["--rtol", "1e-11", "--atol", "1e-15 m", "--onset-tolerance", "2.1e-15 m"],
        "old onset": ["--onset-tolerance", "0.21 um"],
    }
    forces = {}
    steps = {}
    for name, extra in runs.items():
        out = tmp_path / name.replace(" ", "-")
        assert run([*STIFF, *extra, "--out", str(out)]) == 0, name
        forces[name], steps[name] = _forces(out)
    reference = forces["converged"]
    error = {name: max(abs(forces[name][k] / reference[k] - 1) for k in FORCES) for name in forces}
    assert error["default"] < 1e-3, error
    assert error["old onset"] > 1e-2, error
    assert steps["converged"] > 10 * steps["default"]
