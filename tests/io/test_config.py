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


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (
            lambda d: d["mechanism"].update(gravity="1e300 m/s^2"),
            r"mechanism\.gravity must be at most 1000 m/s² .*got '1e300 m/s\^2'",
        ),
        (lambda d: d["mechanism"].update(gravity="9.81 km/s^2"), "at most 1000 m/s²"),
        (
            lambda d: d["mechanism"].update(gravity=["0 m/s^2", "-2000 m/s^2"]),
            "mechanism.gravity must be at most 1000 m/s²",
        ),
        (
            lambda d: d["driver"].update(start_angle="1e300 deg"),
            r"driver\.start_angle = '1e300 deg' is not a plausible angle: .* within ±720°",
        ),
        (lambda d: d["driver"].update(start_angle="721 deg"), "within ±720°"),
        (lambda d: d["driver"].update(start_angle="-13 rad"), "within ±720°"),
        (lambda d: d["driver"].update(start_angle="1e300 rad"), "within ±720°"),
    ],
)
def test_physical_inputs_beyond_their_bounds_are_refused(edit, message) -> None:
    """Each was accepted and run (1e300 m/s² of gravity, a start angle of 1e300°)."""
    data = _paper()
    edit(data)
    with pytest.raises(ConfigError, match=message) as info:
        parse_config(data)
    assert "\n" not in str(info.value)


@pytest.mark.parametrize(
    ("edit", "check"),
    [
        (lambda d: d["mechanism"].update(gravity="1000 m/s^2"), lambda m: m.gravity[1] == -1000),
        (
            lambda d: d["driver"].update(start_angle="-720 deg"),
            lambda m: m.driver.start_angle == pytest.approx(-4 * math.pi),
        ),
        (
            lambda d: d["driver"].update(start_angle="450 deg"),
            lambda m: m.driver.start_angle == pytest.approx(2.5 * math.pi),
        ),
    ],
)
def test_physical_inputs_at_their_bounds_are_taken(edit, check) -> None:
    data = _paper()
    edit(data)
    assert check(parse_config(data))


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


# --- keys: the option spelling, allowed keys, "did you mean" -------------------------------------


def _with_simulation(tmp_path, lines: str, name: str = "c.toml"):
    from jointplay.io.config import preset_text

    path = tmp_path / name
    path.write_text(preset_text("paper-fourbar") + "\n[simulation]\n" + lines, encoding="utf-8")
    return path


def test_simulation_keys_accept_the_option_spelling(tmp_path) -> None:
    from jointplay.io.config import simulation_settings

    path = _with_simulation(
        tmp_path, 'stiffness-law = "hertz"\nfriction-law = "adams"\nsample-deg = "5 deg"\n'
    )
    assert simulation_settings(path) == {
        "stiffness_law": "hertz",
        "friction_law": "adams",
        "sample_deg": "5 deg",
    }


def test_a_wrong_simulation_key_lists_every_allowed_key_and_the_closest(tmp_path) -> None:
    from jointplay.io.config import SIMULATION_KEYS, simulation_settings

    path = _with_simulation(tmp_path, 'contact = "impact"\nstifness_law = "hertz"\n')
    with pytest.raises(ConfigError) as info:
        simulation_settings(path)
    message = str(info.value)
    assert "unknown key 'stifness_law' (did you mean 'stiffness_law'?)" in message
    allowed = message.split("allowed keys: ")[1].split(" (each")[0].split(", ")
    assert allowed == sorted(SIMULATION_KEYS)  # all of them, not only the ones used


def test_both_spellings_of_one_key_are_refused(tmp_path) -> None:
    from jointplay.io.config import simulation_settings

    path = _with_simulation(tmp_path, 'friction_law = "adams"\nfriction-law = "ambrosio"\n')
    with pytest.raises(ConfigError, match="'friction_law' and 'friction-law' are the same key"):
        simulation_settings(path)


def test_mechanism_tables_accept_the_option_spelling_but_not_names(tmp_path) -> None:
    """A setting key may use '-'; names (links, joints) are data and stay as written."""
    from jointplay.io.config import load_config, preset_text

    text = preset_text("paper-fourbar").replace("poisson_ratio", "poisson-ratio")
    assert "poisson-ratio" in text
    path = tmp_path / "dashed.toml"
    path.write_text(text, encoding="utf-8")
    assert load_config(path) == load_preset("paper-fourbar")
    wrong = tmp_path / "wrong.toml"
    wrong.write_text(
        text.replace('pin_mass = "0.02 kg"', 'pin-mas = "0.02 kg"', 1), encoding="utf-8"
    )
    with pytest.raises(ConfigError) as info:
        load_config(wrong)
    message = str(info.value)
    assert "joints.O2: unknown key 'pin-mas' (did you mean 'pin_mass'?)" in message
    assert "allowed keys: clearance, diameter, fit, pin_length, pin_mass" in message


def test_tolerance_and_design_tables_accept_the_option_spelling() -> None:
    from jointplay.io.config import COST_KEYS, design_table_keys
    from jointplay.io.tolerances import parse_tolerance_table
    from jointplay.tolerance.cost import CostModel

    mechanism = load_preset("paper-fourbar")
    spec = parse_tolerance_table(
        {"joints": {"A": {"clearance-min": "5 um", "clearance-max": "30 um"}}}, mechanism
    )
    assert spec["clearance_A"].tolerance.limits == pytest.approx((5e-6, 30e-6))
    tables = design_table_keys(
        {"wear": {"coefficient": 1e-6, "joints": {"A": {"hardness": "2 GPa"}}}, "cost": {"a": 2}},
        "t.toml",
    )
    assert tables["wear"]["joints"]["A"] == {"hardness": "2 GPa"}
    with pytest.raises(ConfigError, match=r"\[wear\]: unknown key 'coeficient' \(did you mean"):
        design_table_keys({"wear": {"coeficient": 1e-6}}, "t.toml")
    # COST_KEYS are exactly what the cost model reads: each accepted, another refused.
    for key in COST_KEYS:
        value = {"model": "exponential", "reference": "0.1 mm", "it": {}, "iso2768": {}}.get(
            key, 1.0
        )
        CostModel.from_table({key: value})
    with pytest.raises(ConfigError):
        CostModel.from_table({"colour": 1})


def test_an_edited_copy_of_a_preset_is_named_as_such(tmp_path) -> None:
    """Titles use the file's name: an edited copy that keeps the preset's name says so; an
    unedited copy keeps the preset's name; a renamed file keeps its own."""
    from jointplay.io.config import load_config, preset_text

    text = preset_text("paper-fourbar")
    same = tmp_path / "copy.toml"
    same.write_text(text, encoding="utf-8")
    assert load_config(same).name == "paper-fourbar"
    edited = tmp_path / "my.toml"
    edited.write_text(text.replace('crank = "108 mm"', 'crank = "100 mm"'), encoding="utf-8")
    assert load_config(edited).name == "paper-fourbar (edited: my.toml)"
    renamed = tmp_path / "renamed.toml"
    renamed.write_text(
        text.replace('crank = "108 mm"', 'crank = "100 mm"').replace(
            'name = "paper-fourbar"', 'name = "rig B"'
        ),
        encoding="utf-8",
    )
    assert load_config(renamed).name == "rig B"


def test_a_clearance_outside_its_fit_is_refused_naming_both() -> None:
    """A copy of the paper preset whose fit was changed to H7/g6 but kept the copied
    ``clearance = "0.021 mm"``: simulate ran 21 µm, above H7/g6's 14.5 µm, while the tolerance
    studies used the fit."""
    text = preset_text("paper-fourbar")
    assert 'fit = "H8/g7"' in text and 'clearance = "0.021 mm"' in text
    data = tomllib.loads(text.replace('fit = "H8/g7"', 'fit = "H7/g6"', 1))
    with pytest.raises(ConfigError) as error:
        parse_config(data, source="my.toml")
    message = str(error.value)
    assert "clearance = 21 µm lies outside the radial clearance of its fit H7/g6" in message
    assert "(2.5 … 14.5 µm)" in message and "remove the clearance" in message
    # within the fit's range (its ends included), the clearance is what is simulated
    within = text.replace("H8/g7", "H7/g6").replace("0.021 mm", "14.5 um")
    parse_config(tomllib.loads(within), source="my.toml")
