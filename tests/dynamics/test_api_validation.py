"""The Python API checks its arguments at the door: ConfigError with the CLI's messages,
never an AttributeError or TypeError from deep inside; and an interrupt stops the compiled
integrator with a status."""

from __future__ import annotations

import math
import signal

import numba
import numpy as np
import pytest

from jointplay._kernels import driver
from jointplay._kernels.ids import (
    STATUS_INTERRUPTED,
)
from jointplay._kernels.lanes.cpu import compiled
from jointplay.contact.laws import get_law
from jointplay.dynamics.clearance import ClearanceJoint
from jointplay.dynamics.integrate import IntegrationStatus, integrate
from jointplay.dynamics.setup import ContactSettings, FrictionSettings, contact_from_strings
from jointplay.dynamics.simulate import SolverOptions, Start, simulate
from jointplay.errors import ConfigError, SettingError
from jointplay.io.config import load_config, load_preset

#: The loop's interrupt test (the lane source's, compiled for the CPU).
interrupt_pending = compiled["interrupt_pending"]
LAW = get_law("hertz", stiffness=1e10, exponent=1.5)


@pytest.fixture(scope="module")
def setup() -> tuple[object, list[ClearanceJoint]]:
    return load_preset("paper-fourbar"), [ClearanceJoint("A", 2.1e-5, 0.005, LAW)]


def test_load_config_needs_a_path() -> None:
    with pytest.raises(ConfigError, match="file path"):
        load_config(None)  # type: ignore[arg-type]


@pytest.mark.parametrize(
    ("keywords", "culprit"),
    [
        ({"start": "rest"}, "Start"),
        ({"solver": {"rtol": 1e-6}}, "SolverOptions"),
        ({"revolutions": "1"}, "revolutions"),
        ({"output_step": "1 ms"}, "output_step"),
        ({"output_step": 1e-12, "revolutions": 5.0}, "output step"),
        ({"sample_deg": 1e-9}, "sample_deg"),
    ],
    ids=["start", "solver", "revolutions", "output_step", "output size", "sample_deg"],
)
def test_simulate_checks_its_arguments(setup, keywords, culprit) -> None:  # type: ignore[no-untyped-def]
    mechanism, joints = setup
    with pytest.raises(ConfigError, match=culprit):
        simulate(mechanism, joints, **keywords)


def test_simulate_checks_mechanism_and_joints(setup) -> None:  # type: ignore[no-untyped-def]
    mechanism, joints = setup
    with pytest.raises(ConfigError, match="Mechanism"):
        simulate("paper-fourbar", joints)  # type: ignore[arg-type]
    with pytest.raises(ConfigError, match="ClearanceJoint"):
        simulate(mechanism, ["A"])  # type: ignore[list-item]


@pytest.mark.parametrize(
    "build",
    [
        lambda: SolverOptions(rtol="1e-6"),  # type: ignore[arg-type]
        lambda: SolverOptions(max_steps=1.5),  # type: ignore[arg-type]
        lambda: Start("ramp", ramp_time="1 s"),  # type: ignore[arg-type]
        lambda: Start(3),  # type: ignore[arg-type]
    ],
    ids=["rtol text", "max_steps float", "ramp text", "mode number"],
)
def test_options_check_their_types(build) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(ConfigError):
        build()


@pytest.mark.parametrize(
    ("keywords", "culprit"),
    [
        ({"clearance": "21 um"}, "clearance must be a number in metres"),
        ({"clearance": 1e-300}, "1 nm"),
        ({"journal_radius": None}, "journal_radius"),
        ({"friction": "ambrosio"}, "FrictionLaw"),
    ],
)
def test_clearance_joint_checks_its_fields(keywords, culprit) -> None:  # type: ignore[no-untyped-def]
    fields = {"clearance": 2.1e-5, "journal_radius": 0.005, "law": LAW, **keywords}
    with pytest.raises(ConfigError, match=culprit):
        ClearanceJoint("A", **fields)


@pytest.mark.parametrize("mu", [math.nan, math.inf, -0.1, "0.1"])
def test_friction_coefficient_must_be_a_finite_number(mu) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(ConfigError, match=r"^friction must be") as error:
        FrictionSettings(coefficient=mu)
    # the command line calls the setting by its option
    assert str(error.value.named({"friction": "--friction"})).startswith("--friction must be")


@pytest.mark.parametrize(
    ("settings", "setting", "option"),
    [
        ({"law": "impact", "restitution": 0.5}, "restitution", "--restitution"),
        ({"law": "hertz", "stiffness": 1e10, "c_max": 1.0}, "c_max", "--cmax"),
        ({"law": "hertz", "stiffness": 1e10, "damping": 1.0}, "damping", "--damping"),
        ({"law": "restitution", "stiffness": 1e10, "depth": 1e-4}, "depth", "--depth"),
    ],
)
def test_options_that_a_law_does_not_use_are_errors(settings, setting, option) -> None:  # type: ignore[no-untyped-def]
    """The API names the setting; the command line shows its option instead."""
    from jointplay.cli._simulation import SETTING_OPTIONS

    with pytest.raises(SettingError, match=f"^{setting} does not apply") as caught:
        ContactSettings(**settings)
    assert repr(settings["law"]) in str(caught.value)
    shown = str(caught.value.named(SETTING_OPTIONS))
    assert shown.startswith(f"{option} does not apply") and "--contact" in shown


def test_a_clearance_larger_than_the_links_is_impossible() -> None:
    from jointplay.dynamics.setup import clearance_joints

    with pytest.raises(ConfigError, match="impossible geometry"):
        clearance_joints(load_preset("paper-fourbar"), ["A"], clearance=1.0)


def test_kelvin_voigt_stiffness_is_in_newtons_per_metre() -> None:
    settings = contact_from_strings(
        {"contact": "kelvin-voigt", "k": "1e7 N/m", "damping": "100 N*s/m"}
    )
    assert settings.stiffness == pytest.approx(1e7)
    with pytest.raises(ConfigError, match="N/m"):
        contact_from_strings(
            {"contact": "kelvin-voigt", "k": "1e4 N/mm^1.5", "damping": "100 N*s/m"}
        )


# --- interrupts ----------------------------------------------------------------------------------


@numba.njit
def _decay(t, y, args):  # type: ignore[no-untyped-def]
    return -y


def test_interrupt_flags_name_the_signals() -> None:
    flags = np.zeros(8, dtype=np.uint8)
    assert not interrupt_pending(flags)
    flags[0] = int(signal.SIGWINCH)  # another signal with a Python handler: not a stop
    assert not interrupt_pending(flags)
    flags[1] = int(signal.SIGINT)
    assert interrupt_pending(flags)


def test_a_pending_interrupt_stops_the_kernel_with_a_status() -> None:
    flags = np.zeros(8, dtype=np.uint8)
    flags[0] = int(signal.SIGTERM)
    status, t, _, counters = driver.run_core(
        "radau", _decay, driver.accept_every_step, driver.no_after_step, 0.0, np.ones(1), 1.0,
        (np.zeros(1),), 1e-6, np.full(1, 1e-9), np.inf, 0.0, 1000, interrupt=flags,
    )  # fmt: skip
    assert status == STATUS_INTERRUPTED == IntegrationStatus.INTERRUPTED
    assert t.shape == (1,) and counters[3] == 0
    assert "interrupted" in IntegrationStatus.INTERRUPTED.summary


def test_without_an_interrupt_the_result_is_unchanged() -> None:
    run = integrate(_decay, (0.0, 1.0), [1.0], args=(np.zeros(1),), rtol=1e-8)
    assert run.status is IntegrationStatus.SUCCESS
    assert run.y[-1, 0] == pytest.approx(math.exp(-1.0), rel=1e-7)


def _stops_at_two(shared: object, item: int) -> int:
    if item == 2:  # what Numba raises when Ctrl-C lands in compiled code
        try:
            raise KeyboardInterrupt
        except KeyboardInterrupt as exc:
            raise SystemError("CPUDispatcher(f) returned a result with an exception set") from exc
    return item * 10


def test_an_interrupt_inside_compiled_code_stops_a_serial_run() -> None:
    from jointplay.tolerance.execution import Backend, run_tasks

    run = run_tasks(_stops_at_two, [0, 1, 2, 3], Backend("serial"))
    assert run.interrupted
    assert run.results[:2] == (0, 10)
    assert list(run.status) == [0, 0, 2, 2]  # ok, ok, not run, not run
