"""The page's query of ``jointplay explore``: what it accepts, what it refuses, and the
configuration file it becomes (read back as ``jointplay simulate --config`` reads it)."""

from __future__ import annotations

import pytest

from jointplay.errors import ConfigError
from jointplay.explore.settings import config_data, load_base, parse_query


@pytest.fixture(scope="module")
def base():
    return load_base("paper-fourbar")


def test_the_controls_are_the_mechanisms_own(base) -> None:
    assert [j.name for j in base.joints] == ["O2", "A", "B", "O4"]
    assert {j.fit for j in base.joints} == {"H8/g7"}
    # the fit's radial clearance: (10.022 - 9.980) / 2 and (10.000 - 9.995) / 2 mm
    low, high = base.joints[1].fit_range
    assert low == pytest.approx(2.5e-6) and high == pytest.approx(21e-6)
    crank = next(length for length in base.lengths if length.name == "crank")
    # ISO 2768-1 coarse: ±0.8 mm over 30-120 mm (the paper's Table 1)
    assert (crank.nominal, crank.lower, crank.upper) == pytest.approx((0.108, -0.8e-3, 0.8e-3))
    assert base.rpm == pytest.approx(200)


def test_the_defaults_parse_and_round_trip(base) -> None:
    settings = parse_query(base, {})
    assert settings.contact == "physical" and settings.settle == 2
    assert parse_query(base, settings.query()) == settings
    changed = parse_query(
        base, {"c.A": "50", "c.B": "H8/g7:min", "c.O4": "off", "contact": "ifm-conventional"}
    )
    assert parse_query(base, changed.query()) == changed


@pytest.mark.parametrize(
    ("query", "words"),
    [
        ({"evil": "1"}, "unknown parameter 'evil'"),
        ({"c.Z": "5"}, "unknown parameter 'c.Z'"),
        ({"rpm": "fast"}, "must be a number"),
        ({"rpm": "nan"}, "finite"),
        ({"rpm": "0"}, "crank speed must lie within"),
        ({"c.A": "-3"}, "clearance of joint A must lie within"),
        ({"c.A": "abc"}, "clearance of joint A (µm) must be a number"),
        ({"c.A": "H8/g7:most"}, "min, mean or max"),
        ({"c.A": "Q99/z1:max"}, "clearance of joint A"),
        ({"c.A": "H7/s6:max"}, "H7/s6 is an interference fit at Ø10 mm"),
        ({"c.A": "H7/s6:mean"}, "so its mean leaves no clearance"),
        ({"c.B": "H7/k6:min"}, "H7/k6 is a transition fit"),
        ({"contact": "glue"}, "unknown contact 'glue'"),
        ({"mu": "2"}, "friction coefficient must lie within 0–1"),
        ({"start": "sideways"}, "the start must be one of"),
        ({"settle": "1.5"}, "whole number"),
        ({"settle": "11"}, "start-up revolutions must lie within"),
        ({"L.crank": "120"}, "crank length must lie within its ISO 2768-c tolerance"),
        ({"c.O2": "off", "c.A": "off", "c.B": "off", "c.O4": "off"}, "every joint is ideal"),
        ({"rpm": "1" * 41}, "longer than 40 characters"),
    ],
)
def test_bad_values_are_refused_with_a_line_that_says_why(base, query, words) -> None:
    with pytest.raises(ConfigError) as caught:
        parse_query(base, query)
    assert words in str(caught.value)


def test_a_parameter_given_twice_is_refused(base) -> None:
    class Twice:
        def multi_items(self):
            return [("rpm", "200"), ("rpm", "300")]

    with pytest.raises(ConfigError, match="given twice"):
        parse_query(base, Twice())


def test_the_configuration_is_what_simulate_reads(base, tmp_path) -> None:
    from jointplay.io.config import simulation_settings
    from jointplay.io.config_writer import write_config
    from jointplay.settings.mechanism import mechanism_from_options

    settings = parse_query(
        base,
        {
            "c.A": "50",
            "c.B": "H8/g7:min",
            "c.O4": "off",
            "contact": "ifm-conventional",
            "mu": "0.05",
            "rpm": "150",
            "L.crank": "108.5",
            "start": "rest",
            "settle": "1",
        },
    )
    path = tmp_path / "settings.toml"
    write_config(path, config_data(base, settings))
    mechanism = mechanism_from_options(None, path)
    joints = {j.name: j.fit for j in mechanism.joints if getattr(j, "fit", None) is not None}
    assert joints["A"].clearance == pytest.approx(50e-6)
    assert joints["A"].fit is None  # 50 µm is no H8/g7 clearance: a clearance of its own
    assert joints["B"].clearance == pytest.approx(2.5e-6) and joints["B"].fit == "H8/g7"
    assert mechanism.driver.speed == pytest.approx(150 * 2 * 3.141592653589793 / 60)
    crank = mechanism.link("crank").points
    assert abs(crank["A"][0] - crank["O2"][0]) == pytest.approx(0.1085)
    values = simulation_settings(path)
    assert values["method"] == "ifm-conventional" and values["friction"] == 0.05
    assert values["joints"] == ["O2", "A", "B"]
    assert (values["start"], values["settle"], values["revolutions"]) == ("rest", 1, 1)


def test_presets_without_fit_tables_have_no_joint_controls() -> None:
    general = load_base("general-fourbar")
    assert general.lengths == ()
    with pytest.raises(ConfigError, match="not both"):
        load_base("paper-fourbar", "x.toml")


def test_a_configuration_file_is_explored_as_given(tmp_path) -> None:
    from jointplay.io.config import preset_text

    text = preset_text("paper-fourbar").replace('speed = "200 rpm"', 'speed = "150 rpm"')
    path = tmp_path / "mine.toml"
    path.write_text(text, encoding="utf-8")
    mine = load_base(config=path)
    assert mine.rpm == pytest.approx(150) and "mine.toml" in mine.source
    assert parse_query(mine, {}).rpm == pytest.approx(150)


def test_a_joint_may_have_its_own_contact_and_friction(base, tmp_path) -> None:
    from jointplay.io.config import simulation_settings
    from jointplay.io.config_writer import write_config

    mixed = parse_query(base, {"contact.A": "ifm-conventional", "mu.B": "0.02"})
    assert mixed.contact_of("A") == ("ifm-conventional", None)
    assert mixed.contact_of("B") == ("physical", 0.02)
    assert mixed.contact_of("O2") == ("physical", None)
    assert mixed.uniform() is None
    assert parse_query(base, mixed.query()) == mixed
    # the same own contact everywhere (the ideal joint aside) is one contact for all, which a
    # configuration file says
    same = {f"contact.{j}": "rm-conventional" for j in ("O2", "A", "B")}
    alike = parse_query(base, {**same, "c.O4": "off", "mu": "0.05"})
    assert alike.uniform() == ("rm-conventional", 0.05)
    path = tmp_path / "alike.toml"
    write_config(path, config_data(base, alike))
    assert simulation_settings(path)["method"] == "rm-conventional"


@pytest.mark.parametrize(
    ("query", "words"),
    [
        ({"contact.A": "glue"}, "unknown contact of joint A 'glue'"),
        ({"mu.B": "-0.1"}, "friction coefficient of joint B must lie within 0–1"),
        ({"mu.B": "x"}, "friction coefficient of joint B must be a number"),
        ({"contact.Z": "physical"}, "unknown parameter 'contact.Z'"),
    ],
)
def test_bad_joint_contacts_are_refused(base, query, words) -> None:
    with pytest.raises(ConfigError) as caught:
        parse_query(base, query)
    assert words in str(caught.value)


def test_a_transition_fits_clearance_is_taken_where_it_has_one(base) -> None:
    # H7/k6 at 10 mm: radial clearance -5 to +4.5 µm; its max is a clearance
    settings = parse_query(base, {"c.B": "H7/k6:max"})
    assert settings.clearances["B"].fit == "H7/k6"
