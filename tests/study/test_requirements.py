"""The requirement grammar and its one-line errors."""

from __future__ import annotations

import numpy as np
import pytest

from jointplay.errors import ConfigError
from jointplay.study.requirements import parse_confidence, parse_requirement

UNITS = {
    "rocker_speed_error": "1",
    "joint_force": "N",
    "life": "s",
    "wear_rate": "m/s",
    "contact_pressure": "Pa",
}


@pytest.mark.parametrize(
    ("text", "response", "op", "limit", "confidence"),
    [
        ("rocker_speed_error <= 1 %", "rocker_speed_error", "<=", 0.01, None),
        ("rocker_speed_error<2%", "rocker_speed_error", "<", 0.02, None),
        ("joint_force <= 150 N", "joint_force", "<=", 150.0, None),
        ("joint_force<=0.15 kN@99.73", "joint_force", "<=", 150.0, 0.9973),
        ("joint_force <= 150 N @ 95 %", "joint_force", "<=", 150.0, 0.95),
        ("life >= 2000 h", "life", ">=", 7.2e6, None),
        ("life > 1 day", "life", ">", 86400.0, None),
        ("wear_rate <= 3.6 um/h", "wear_rate", "<=", 1e-9, None),
        ("contact_pressure <= 500 MPa @0.5 %", "contact_pressure", "<=", 5e8, 0.005),
    ],
)
def test_grammar(text: str, response: str, op: str, limit: float, confidence: float | None) -> None:
    r = parse_requirement(text, UNITS)
    assert (r.response, r.comparison, r.text) == (response, op, text.strip())
    assert r.limit == pytest.approx(limit, rel=1e-12)
    assert r.confidence == (None if confidence is None else pytest.approx(confidence))


def test_met_per_sample_and_nan_never_meets() -> None:
    r = parse_requirement("joint_force <= 150 N", UNITS)
    assert r.met(np.array([149.0, 150.0, 151.0, np.nan])).tolist() == [True, True, False, False]
    assert parse_requirement("life > 1 s", UNITS).met(np.array([1.0, 2.0])).tolist() == [
        False,
        True,
    ]


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("joint_force = 150 N", "expected RESPONSE <=|<|>=|> VALUE"),
        ("joint_force 150 N", "expected RESPONSE"),
        ("", "expected RESPONSE"),
        ("<= 150 N", "expected RESPONSE"),
        ("force <= 150 N", "unknown response 'force'; expected one of"),
        ("joint_force <= 150 mm", "cannot be converted to N"),
        ("joint_force <= 150 N @abc", "after '@': expected a confidence in %"),
        ("joint_force <= 150 N @100", "between 0 and 100"),
        ("rocker_speed_error <= 1 mm", "dimensionless; expected a number with %"),
        ("joint_force <= 150 N @0.9973", "did you mean '99.73 %'?"),
    ],
)
def test_malformed_requirements_are_one_line_errors(text: str, expected: str) -> None:
    with pytest.raises(ConfigError, match=expected) as info:
        parse_requirement(text, UNITS)
    assert "\n" not in str(info.value)


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        (
            "joint_force <= <= 150 N",
            r"one comparison only, found '<=' and then '<=' \(character 16\)",
        ),
        ("joint_force >= <= 150 N", r"found '>=' and then '<=' \(character 16\)"),
        ("joint_force <= >= 150 N", r"found '<=' and then '>=' \(character 16\)"),
        ("joint_force < = 150 N", r"found '<' and then '=' \(character 15\)"),
        ("joint_force <= 150 N >= 100 N", r"found '<=' and then '>=' \(character 22\)"),
        ("rocker_speed_error <= <= 3 %", r"one comparison only"),
        ("joint_force == 150 N", r"'==' \(character 13\) is not a comparison; write one of"),
        ("joint_force =< 150 N", r"'=<' \(character 13\) is not a comparison"),
        ("joint_force !<= 150 N", r"'!<=' \(character 13\) is not a comparison"),
    ],
)
def test_a_requirement_has_exactly_one_comparison(text: str, expected: str) -> None:
    """Checked token by token: ``>= <=`` would flip a requirement; each stray comparison is
    one line naming it (they were read as the value, or ``== 150 N`` as a malformed whole)."""
    with pytest.raises(ConfigError, match=expected) as info:
        parse_requirement(text, UNITS)
    assert "\n" not in str(info.value)
    assert parse_requirement("joint_force<=150N@99.73", UNITS).limit == 150.0  # spaces optional
    assert parse_requirement("joint_force >= -5 N", UNITS).limit == -5.0  # a sign is no comparison


@pytest.mark.parametrize(
    ("text", "suggestion"),
    [
        ("rocker_speed_error <= 3", "did you mean 'rocker_speed_error <= 3 %'?"),
        ("rocker_speed_error <= 0.03", "'rocker_speed_error <= 0.03 %' (or '3 %' if 0.03 is"),
        ("life >= 200", "did you mean 'life >= 200 h'?"),
        ("contact_pressure <= 500", "did you mean 'contact_pressure <= 500 MPa'?"),
        ("joint_force <= 150", "did you mean 'joint_force <= 150 N'?"),
        ("wear_rate <= 2", "did you mean 'wear_rate <= 2 um/h'?"),
    ],
)
def test_a_bare_limit_is_refused_with_its_unit_suggested(text: str, suggestion: str) -> None:
    """Read as SI, these would be 300 %, 200 s, 500 Pa: another question, silently."""
    with pytest.raises(ConfigError, match="needs its unit") as info:
        parse_requirement(text, UNITS)
    assert suggestion in str(info.value) and "\n" not in str(info.value)


@pytest.mark.parametrize(
    ("text", "level"), [("99.73", 0.9973), ("99.73 %", 0.9973), ("95%", 0.95), ("0.5 %", 0.005)]
)
def test_confidence_is_in_percent_with_the_sign_optional(text: str, level: float) -> None:
    assert parse_confidence(text) == pytest.approx(level, rel=1e-12)


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("0.9973", "did you mean '99.73 %'? (write '0.9973 %' if you mean 0.9973 %)"),
        ("1", "did you mean '100 %'?"),
        ("100", "between 0 and 100 %"),
        ("0 %", "between 0 and 100 %"),
        ("high", "expected a confidence in %"),
    ],
)
def test_confidence_refusals_are_one_line(text: str, expected: str) -> None:
    with pytest.raises(ConfigError, match=r"^confidence") as info:  # the CLI names its option
        parse_confidence(text)
    assert expected in str(info.value)
