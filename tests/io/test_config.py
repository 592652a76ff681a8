"""Configuration files: presets, units, and an error naming the problem for each bad input."""

from __future__ import annotations

import math
import tomllib

import numpy as np
import pytest

from jointplay._kernels import constraints as ck
from jointplay.errors import ConfigError, JointplayError
from jointplay.io.config import list_presets, load_config, load_preset, parse_config, preset_text
from jointplay.kinematics.analysis import analyse
from jointplay.kinematics.solver import driver_at
from jointplay.units import parse_quantity


def test_units_are_converted_to_si() -> None:
    assert parse_quantity("270.5 mm", "m", field="x") == pytest.approx(0.2705)
    assert parse_quantity("200 rpm", "rad/s", field="x") == pytest.approx(200 * 2 * math.pi / 60)
    assert parse_quantity("207 GPa", "Pa", field="x") == pytest.approx(207e9)
    assert parse_quantity("1e4 N/mm^1.5", "N/m^1.5", field="x") == pytest.approx(1e4 * 1000**1.5)
    assert parse_quantity("10 N*s/mm", "N*s/m", field="x") == pytest.approx(1e4)


@pytest.mark.parametrize(
    ("value", "unit", "message"),
    [
        (270.5, "m", "has no unit"),
        ("270.5", "m", "has no unit"),
        ("3 kg", "m", "cannot be converted"),
        ("3 furlongz", "m", "cannot read"),
    ],
)
def test_bad_quantities(value, unit, message) -> None:
    with pytest.raises(ConfigError, match=message):
        parse_quantity(value, unit, field="geometry.crank")


def test_paper_preset_holds_table_1(paper_fourbar) -> None:
    geometry = paper_fourbar.template.geometry
    assert (geometry.crank, geometry.coupler, geometry.rocker, geometry.ground) == pytest.approx(
        (0.108, 0.2705, 0.2705, 0.2794)
    )
    assert [link.mass for link in paper_fourbar.links] == pytest.approx([0.14, 0.26, 0.31])
    assert paper_fourbar.driver.speed == pytest.approx(20.944, rel=1e-4)
    assert paper_fourbar.gravity == (0.0, 0.0)
    fit = paper_fourbar.joint("A").fit
    assert (
        fit.fit == "H8/g7"
        and fit.diameter == pytest.approx(0.010)
        and fit.clearance == pytest.approx(21e-6)
    )
    tolerances = {t.length: (t.lower, t.upper) for t in paper_fourbar.tolerances}
    assert tolerances["crank"] == pytest.approx((-0.8e-3, 0.8e-3))
    assert tolerances["ground"] == pytest.approx((-1.2e-3, 1.2e-3))
    assert sum(t.upper for t in paper_fourbar.tolerances) == pytest.approx(4.4e-3)  # "±4.4 mm"


@pytest.mark.parametrize("name", [preset.name for preset in list_presets()])
def test_every_preset_loads_and_assembles(name: str) -> None:
    mechanism = load_preset(name)
    assert mechanism.name == name
    angles = np.radians([0.0, 90.0])
    result = analyse(mechanism, angles)
    flat = result.flat
    for i, angle in enumerate(angles):
        # Every joint closes at the solved positions (round-off on ~0.1-1 m lengths).
        driver = driver_at(flat, float(result.crank_angle[i]))
        residual = ck.residual(result.q[i], 0.0, flat.joint_int, flat.joint_f, flat.active, driver)
        assert np.max(np.abs(residual)) < 1e-12, (name, math.degrees(angle))
    assert np.all(np.isfinite(result.qd)) and np.all(np.isfinite(result.qdd))


def test_general_description_equals_the_template(paper_fourbar) -> None:
    general = load_preset("general-fourbar")
    a = analyse(paper_fourbar)
    b = analyse(general)
    assert b.method == "general"
    np.testing.assert_allclose(a.omega("rocker"), b.omega("rocker"), rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(a.alpha("coupler"), b.alpha("coupler"), rtol=1e-6, atol=1e-6)


def test_round_trip_of_a_copied_preset(tmp_path) -> None:
    path = tmp_path / "mine.toml"
    path.write_text(preset_text("paper-fourbar").replace('crank = "108 mm"', 'crank = "100 mm"'))
    assert load_config(path).template.geometry.crank == pytest.approx(0.1)


def _paper() -> dict:
    return tomllib.loads(preset_text("paper-fourbar"))


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (lambda d: d["geometry"].update(crank="108"), "geometry.crank: '108' has no unit"),
        (lambda d: d["geometry"].update(crank=108), "has no unit"),
        (lambda d: d["geometry"].pop("rocker"), "missing required key 'rocker'"),
        (lambda d: d["geometry"].update(lenght="1 mm"), "unknown key"),
        (lambda d: d["mechanism"].update(template="six-bar"), "template must be"),
        (lambda d: d["driver"].update(direction="up"), "direction"),
        (lambda d: d["driver"].update(speed="200 kg"), "cannot be converted"),
        (lambda d: d["links"].update(slider={"mass": "1 kg"}), "unknown link"),
        (lambda d: d["joints"]["A"].update(clearance="-0.01 mm"), "clearance"),
        (lambda d: d["links"]["crank"].update(mass="-1 kg"), "mass"),
        (lambda d: d["joints"].update(Z={"diameter": "10 mm"}), "unknown joint"),
        (lambda d: d["mechanism"].update(gravity=[1, 2, 3]), "gravity"),
    ],
)
def test_bad_configurations_name_the_problem(edit, message) -> None:
    data = _paper()
    edit(data)
    with pytest.raises(ConfigError, match=message):
        parse_config(data)


def test_malformed_and_missing_files(tmp_path) -> None:
    bad = tmp_path / "bad.toml"
    bad.write_text("[mechanism\nname = 1")
    with pytest.raises(ConfigError, match="malformed TOML"):
        load_config(bad)
    with pytest.raises(ConfigError, match="not found"):
        load_config(tmp_path / "missing.toml")
    with pytest.raises(ConfigError, match="unknown preset 'nope'; available"):
        load_preset("nope")


def test_tolerance_table_with_a_general_class(tmp_path) -> None:
    """[tolerances] general = "c" resolves through ISO 2768-1 for every command."""
    text = preset_text("paper-fourbar")
    text = text[: text.index("# Link-length tolerances")] + '[tolerances]\ngeneral = "c"\n'
    path = tmp_path / "classes.toml"
    path.write_text(text)
    tolerances = {t.length: (t.lower, t.upper) for t in load_config(path).tolerances}
    assert tolerances["crank"] == pytest.approx((-0.8e-3, 0.8e-3))
    assert tolerances["coupler"] == pytest.approx((-1.2e-3, 1.2e-3))
    path.write_text(text.replace('general = "c"', 'general = "z"'))
    with pytest.raises(JointplayError, match="unknown ISO 2768-1 tolerance class 'z'"):
        load_config(path)


@pytest.mark.parametrize(
    "text", ["10 mm", "10mm", "270.5 mm", "0.021 mm", "21 um", "21 µm", "2.5e-3 mm", "1 m", "3 cm"]
)
def test_decimal_lengths_read_without_pint_equal_pints_reading(text: str) -> None:
    from jointplay.units import _registry

    expected = float(_registry().Quantity(text).to("m").magnitude)
    assert parse_quantity(text, "m", field="x") == expected  # the same float, bit for bit
