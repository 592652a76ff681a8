"""``jointplay explore`` on the command line: the refusals that come before any page."""

from __future__ import annotations

import importlib.util
import socket

import pytest

from jointplay.cli import run


def test_missing_packages_say_how_to_install_them(monkeypatch, capsys) -> None:
    real = importlib.util.find_spec
    monkeypatch.setattr(
        importlib.util,
        "find_spec",
        lambda name, *args: None if name == "uvicorn" else real(name, *args),
    )
    assert run(["explore", "--no-browser"]) == 2
    error = capsys.readouterr().err
    assert "uvicorn" in error and "pip install 'jointplay[explore]'" in error
    assert "Traceback" not in error


def test_an_unknown_preset_is_one_line(capsys) -> None:
    pytest.importorskip("uvicorn", reason="jointplay[explore] is not installed")
    assert run(["explore", "--no-browser", "--preset", "nope"]) == 2
    error = capsys.readouterr().err
    assert "unknown preset 'nope'" in error and error.count("\n") == 1


def test_a_port_in_use_is_one_line(capsys) -> None:
    pytest.importorskip("uvicorn", reason="jointplay[explore] is not installed")
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        assert run(["explore", "--no-browser", "--port", str(port)]) == 2
    error = capsys.readouterr().err
    assert f"cannot serve on 127.0.0.1:{port}" in error and "--port" in error
