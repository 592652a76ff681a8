"""Random values and types in every field of a configuration: an error is always a
ConfigError (exit status 2 on the command line), never a traceback or an exit 3."""

from __future__ import annotations

import contextlib
import copy
import json
import math
import tomllib
from pathlib import Path
from typing import Any

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from jointplay.cli import run
from jointplay.errors import JointplayError
from jointplay.io.config import SIMULATION_KEYS, parse_config, preset_text

BASE: dict[str, Any] = tomllib.loads(preset_text("paper-fourbar"))


def _leaves(data: Any, path: tuple[str, ...] = ()) -> list[tuple[str, ...]]:
    if isinstance(data, dict):
        found = [path] if path else []
        for key, value in data.items():
            found += _leaves(value, (*path, key))
        return found
    return [path]


FIELDS = _leaves(BASE) + [("simulation", key) for key in SIMULATION_KEYS]

SCALARS = st.one_of(
    st.booleans(),
    st.integers(min_value=-(10**20), max_value=10**20),
    st.floats(allow_nan=True, allow_infinity=True),
    st.text(max_size=12),
    st.sampled_from(
        ["1 mm", "-1 mm", "0 mm", "1e30 mm", "1e-300 mm", "nan mm", "inf m", "200 rpm", "1 kg",
         "10 N*s/mm", "1e4 N/mm^1.5", "abc", "", "ccw", "cw", "impact", "hertz", "H8/g7",
         "steady", "ramp", "crank.A", "ground.O2", "four-bar", "1 m"]
    ),
)  # fmt: skip
VALUES = st.one_of(  # None: the key is removed
    st.none(),
    SCALARS,
    st.lists(SCALARS, max_size=3),
    st.dictionaries(st.text(max_size=5), SCALARS, max_size=2),
)


def _mutate(path: tuple[str, ...], value: Any) -> dict[str, Any]:
    data = copy.deepcopy(BASE)
    table = data
    for key in path[:-1]:
        table = table.setdefault(key, {})
        if not isinstance(table, dict):
            return data
    if value is None:
        table.pop(path[-1], None)
    else:
        table[path[-1]] = value
    return data


def _toml(value: Any) -> str:
    """``value`` as a TOML value (inline tables), enough for these tests."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, list):
        return "[" + ", ".join(_toml(v) for v in value) + "]"
    return "{" + ", ".join(f"{json.dumps(k)} = {_toml(v)}" for k, v in value.items()) + "}"


def _document(data: dict[str, Any]) -> str:
    return "\n".join(f"{json.dumps(key)} = {_toml(value)}" for key, value in data.items()) + "\n"


@settings(max_examples=300, deadline=None)
@given(field=st.sampled_from(FIELDS), value=VALUES)
def test_parse_config_raises_only_config_errors(field: tuple[str, ...], value: Any) -> None:
    with contextlib.suppress(JointplayError):
        parse_config(_mutate(field, value))


class _Reached(Exception):
    """Stands in for the integration: the settings got through validation."""


@settings(
    max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(field=st.sampled_from(FIELDS), value=VALUES)
def test_the_command_line_never_sees_a_traceback(
    field: tuple[str, ...],
    value: Any,
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    import jointplay.dynamics.simulate as simulate_module

    def reached(*args: Any, **kwargs: Any) -> None:
        raise _Reached

    monkeypatch.setattr(simulate_module, "simulate", reached)
    config = tmp_path / "fuzz.toml"
    config.write_text(_document(_mutate(field, value)), encoding="utf-8")
    out = tmp_path / "out"
    command = "simulate" if field[0] == "simulation" else "kinematics"
    status = run([command, "--config", str(config), "--no-plots", "--force", "--out", str(out)])
    err = capsys.readouterr().err
    assert "Traceback" not in err
    if "_Reached" in err:  # validation passed; the stand-in stopped the run
        return
    assert status in (0, 2), err
    if status == 2:
        assert len(err.strip().splitlines()) == 1, err
