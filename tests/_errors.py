"""The command line's contract for bad input, checked once for every command's tests."""

from __future__ import annotations


def assert_one_line_error(status: int, err: str, culprit: str) -> None:
    """Exit status 2 and one stderr line, ``jointplay: error: …``, naming ``culprit``;
    no traceback."""
    lines = err.strip().splitlines()
    assert status == 2, err
    assert len(lines) == 1, err
    assert lines[0].startswith("jointplay: error: "), err
    assert culprit in lines[0], err
    assert "Traceback" not in err
