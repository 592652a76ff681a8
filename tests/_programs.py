"""External programs some tests need (Chromium, ffmpeg): such a test is skipped where the
program is missing, except in CI (``CI=true``), where ``.ci/run`` installs them and a missing
one fails the test instead of skipping it out of sight."""

from __future__ import annotations

import os
import shutil

import pytest


def need(*names: str, package: str) -> str:
    """The path of the first of ``names`` on PATH; skip (fail in CI) when none is."""
    found = next((path for path in map(shutil.which, names) if path is not None), None)
    if found is not None:
        return found
    message = f"no {' or '.join(names)} on PATH (apt-get install {package})"
    if os.environ.get("CI") == "true":
        pytest.fail(f"{message}: .ci/run installs it in CI")
    pytest.skip(message)
