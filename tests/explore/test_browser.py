"""``jointplay explore`` in a real browser: the command serves the page, headless Chromium
(Debian's ``chromium``, driven by Playwright) loads it, moves the clearance slider of joint A
from 5 to 50 µm and reads what the page then shows: the orbit, the peaks table (equal to
``jointplay simulate`` on the same settings), a bad value's message with the last good view
kept, and the URL that reproduces the view. Ctrl-C stops the server cleanly.

Skipped, with the reason, without Chromium or Playwright, except in CI (``tests/_programs.py``).
The update times are printed (``-s``) and reported in docs/performance.md, not asserted.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
import tomllib
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from _programs import need

pytestmark = pytest.mark.slow  # ~45 s: Chromium, a server, and simulate to compare with

#: ``jointplay simulate``'s options for the comparison: no plots, no spinner.
QUIET = ("--no-plots", "--no-progress")
#: Seconds the page may take for one view (generous: a shared 2-core machine under load).
WAIT_MS = 60_000


def _playwright() -> Any:
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        if os.environ.get("CI") == "true":
            pytest.fail("playwright is missing: CI installs .[test], which includes it")
        pytest.skip("playwright is not installed (pip install '.[test]')")
    return sync_playwright


def _serve(*args: str) -> tuple[subprocess.Popen[str], str]:
    """Start ``jointplay explore --no-browser --port 0`` and return it with its URL."""
    process = subprocess.Popen(
        [sys.executable, "-m", "jointplay", "explore", "--no-browser", "--port", "0", *args],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env={**os.environ, "MPLBACKEND": "Agg"},
    )
    assert process.stdout is not None
    line = process.stdout.readline()  # after the kernels are compiled or loaded
    if "http://" not in line:
        process.kill()
        raise AssertionError(f"no URL from jointplay explore: {line!r} {process.stderr.read()!r}")
    return process, line[line.index("http://") :].split()[0]


def _stop(process: subprocess.Popen[str]) -> tuple[int, str]:
    process.send_signal(signal.SIGINT)
    try:
        _, stderr = process.communicate(timeout=30)
    except subprocess.TimeoutExpired:
        process.kill()
        raise
    return process.returncode, stderr


@pytest.fixture(scope="module")
def server() -> Iterator[str]:
    process, url = _serve("--preset", "paper-fourbar")
    yield url
    _stop(process)


@pytest.fixture(scope="module")
def browser() -> Iterator[Any]:
    chromium = need("chromium", "chromium-browser", package="chromium")
    with _playwright()() as driver:
        launched = driver.chromium.launch(executable_path=chromium, args=["--no-sandbox"])
        yield launched
        launched.close()


@pytest.fixture
def page(browser) -> Iterator[Any]:
    # bypass_csp: Playwright's waits evaluate strings, which the page's own policy forbids
    context = browser.new_context(viewport={"width": 1400, "height": 1000}, bypass_csp=True)
    opened = context.new_page()
    errors: list[str] = []
    opened.on("pageerror", lambda error: errors.append(str(error)))
    opened.errors = errors
    yield opened
    context.close()
    assert not errors, errors


def _views(page: Any, count: int) -> None:
    """Wait until the page has drawn ``count`` views and nothing is pending."""
    page.wait_for_function(
        f"document.body.dataset.views === '{count}' && document.body.dataset.state === 'ready'",
        timeout=WAIT_MS,
    )


def _peaks(page: Any) -> dict[str, float]:
    return page.evaluate(
        """Object.fromEntries([...document.querySelectorAll('#peaks tbody tr')].map(
            (row) => [row.dataset.key, Number(row.children[1].dataset.value)]))"""
    )


def _orbit(page: Any, joint: str) -> dict[str, list[float]]:
    """What the orbits figure draws for ``joint`` (µm): its clearance circle and orbit."""
    return page.evaluate(
        f"""(() => {{ const d = document.getElementById('orbits').data;
            const circle = d.find((t) => t.meta[0] === '{joint}' && t.meta[1] === 'clearance');
            const orbit = d.find((t) => t.meta[0] === '{joint}' && t.meta[1] === 'orbit');
            return {{circle: circle.x, x: orbit.x, y: orbit.y}}; }})()"""
    )


def _simulate_peaks(tmp_path: Path, clearance_mm: str, method: str | None) -> dict[str, float]:
    """The peaks of ``jointplay simulate`` on the paper four-bar with joint A's clearance set
    (its fit removed: 50 µm is none of H8/g7's) and ``method`` (None: the physical default)."""
    from jointplay.io.config import preset_text
    from jointplay.io.config_writer import write_config

    data = tomllib.loads(preset_text("paper-fourbar"))
    joint = data["joints"]["A"]
    joint.pop("fit")
    joint["clearance"] = clearance_mm
    if method is not None:
        data["simulation"] = {"method": method}
    config = tmp_path / f"paper-{clearance_mm.replace(' ', '')}-{method}.toml"
    write_config(config, data)
    out = tmp_path / f"out-{config.stem}"
    subprocess.run(
        [
            sys.executable,
            "-m",
            "jointplay",
            "simulate",
            "--config",
            str(config),
            "--out",
            str(out),
            *QUIET,
        ],
        check=True,
        capture_output=True,
        env={**os.environ, "MPLBACKEND": "Agg"},
    )
    summary = json.loads((out / "summary.json").read_text(encoding="utf-8"))
    return {key: peak["value"] for key, peak in summary["peaks"].items()}


@pytest.mark.parametrize("contact", ["ifm-conventional", "physical"])
def test_moving_the_clearance_slider_updates_every_view(page, server, tmp_path, contact) -> None:
    page.goto(f"{server}?contact={contact}&c.A=5")
    _views(page, 1)
    before, orbit_before = _peaks(page), _orbit(page, "A")
    assert max(orbit_before["circle"]) == pytest.approx(5)
    frame = page.get_attribute("#mechanism", "data-frame")
    page.wait_for_function(
        f"document.getElementById('mechanism').dataset.frame !== '{frame}'", timeout=WAIT_MS
    )  # the mechanism is animated

    page.fill("#clr-A-range", "50")
    _views(page, 2)
    seconds = float(page.get_attribute("body", "data-last-update-s"))
    print(f"\n{contact}: clearance of A 5 -> 50 µm, view updated in {seconds:.3f} s")
    after, orbit_after = _peaks(page), _orbit(page, "A")
    assert page.input_value("#clr-A") == "50"
    assert "c.A=50" in page.url
    assert max(orbit_after["circle"]) == pytest.approx(50)
    assert orbit_after["x"] != orbit_before["x"]
    assert max(map(abs, orbit_after["x"] + orbit_after["y"])) > 5  # beyond the old bearing
    assert after.keys() == before.keys() and after != before
    drawn = page.evaluate("document.getElementById('curves').data.map((t) => t.meta.join(' '))")
    for name in ("F_O2", "F_A", "F_B", "F_O4", "omega4", "torque"):
        assert f"{name} run" in drawn and f"{name} ideal" in drawn

    expected = _simulate_peaks(tmp_path, "0.05 mm", None if contact == "physical" else contact)
    assert after.keys() == expected.keys()
    for key, value in expected.items():
        assert after[key] == pytest.approx(value, rel=1e-9), key


def test_a_bad_value_shows_a_message_and_keeps_the_view(page, server) -> None:
    page.goto(f"{server}?contact=ifm-conventional&c.A=30")
    _views(page, 1)
    peaks, orbit = _peaks(page), _orbit(page, "A")
    page.fill("#clr-A", "abc")
    page.wait_for_function("document.body.dataset.state === 'error'", timeout=WAIT_MS)
    message = page.text_content("#message")
    assert page.is_visible("#message")
    assert "clearance of joint A" in message and "must be a number" in message
    assert page.get_attribute("body", "data-views") == "1"
    assert _peaks(page) == peaks and _orbit(page, "A") == orbit
    page.fill("#clr-A", "30.5")  # a good value again: the message goes
    _views(page, 2)
    assert not page.is_visible("#message")


def test_a_bad_shared_link_shows_the_defaults_and_the_error(page, server) -> None:
    """A link with a value the server refuses: the defaults' view under the message, not a
    blank page; the field keeps the link's value, and correcting it draws that view."""
    page.goto(f"{server}?contact=ifm-conventional&c.A=-3")
    page.wait_for_function("document.body.dataset.shown === 'defaults'", timeout=WAIT_MS)
    message = page.text_content("#message")
    assert page.is_visible("#message")
    assert "clearance of joint A must lie within" in message and "defaults" in message
    assert page.input_value("#clr-A") == "-3" and page.input_value("#contact") == "ifm-conventional"
    assert len(_peaks(page)) > 4  # the peaks table is filled
    assert max(_orbit(page, "A")["circle"]) == pytest.approx(21)  # the default clearance
    assert page.get_attribute("#mechanism", "viewBox") is not None
    page.fill("#clr-A", "30")
    _views(page, 2)
    assert not page.is_visible("#message")
    assert max(_orbit(page, "A")["circle"]) == pytest.approx(30)


def test_the_toolbar_is_off_the_titles(page, server) -> None:
    """Plotly's toolbar (the modebar, top right) overlaps no figure title."""
    page.goto(f"{server}?contact=ifm-conventional")
    _views(page, 1)
    for figure in ("orbits", "curves"):
        page.hover(f"#{figure}")  # the toolbar shows while the pointer is over the figure
        boxes = page.evaluate(
            f"""(() => {{
                const box = (e) => {{ const r = e.getBoundingClientRect();
                    return [r.left, r.top, r.right, r.bottom]; }};
                const root = document.getElementById('{figure}');
                return {{ bar: box(root.querySelector('.modebar')),
                    titles: [...root.querySelectorAll('.annotation-text')].map(box) }}; }})()"""
        )
        bar, titles = boxes["bar"], boxes["titles"]
        assert bar[2] > bar[0] and bar[3] > bar[1] and titles, boxes
        for title in titles:
            apart = (
                title[2] <= bar[0] or title[0] >= bar[2] or title[3] <= bar[1] or title[1] >= bar[3]
            )
            assert apart, (figure, bar, title)


def test_the_url_reproduces_the_view(page, browser, server) -> None:
    page.goto(f"{server}?contact=ifm-conventional")
    _views(page, 1)
    page.select_option("#mode-B", "max")
    _views(page, 2)
    assert max(_orbit(page, "B")["circle"]) == pytest.approx(21, rel=1e-3)  # H8/g7's largest
    page.fill("#fit-B", "H7/g6")
    page.dispatch_event("#fit-B", "change")
    _views(page, 3)
    # ISO 286 at Ø10 mm: H7 +15/0 µm, g6 -5/-14 µm, so the largest radial clearance is 14.5 µm
    assert max(_orbit(page, "B")["circle"]) == pytest.approx(14.5, rel=1e-3)
    page.fill("#len-crank", "108.4")
    _views(page, 4)
    url, peaks = page.url, _peaks(page)
    assert "c.B=H7%2Fg6%3Amax" in url and "L.crank=108.4" in url
    context = browser.new_context(bypass_csp=True)
    shared = context.new_page()
    shared.goto(url)
    _views(shared, 1)
    assert _peaks(shared) == peaks
    assert shared.input_value("#contact") == "ifm-conventional"
    assert shared.input_value("#mode-B") == "max"
    assert shared.input_value("#fit-B") == "H7/g6"
    assert shared.input_value("#len-crank") == "108.4"
    assert shared.url == url
    # a parameter the page has no control for is left out, and said, not refused forever
    shared.goto(f"{url}&c.Z=5")
    _views(shared, 1)
    assert "c.Z" in shared.text_content("#message") and "c.Z" not in shared.url
    assert _peaks(shared) == peaks
    context.close()


def test_a_joint_of_its_own_contact(page, server) -> None:
    page.goto(f"{server}?contact=ifm-conventional")
    _views(page, 1)
    peaks = _peaks(page)
    page.select_option("#contact-A", "physical")
    _views(page, 2)
    assert "contact.A=physical" in page.url
    contact = page.text_content("#diagnostics li")
    assert "A: restitution law" in contact and "O2: the paper's method ifm-conventional" in contact
    assert _peaks(page) != peaks
    page.select_option("#contact-A", "")  # as above again
    _views(page, 3)
    assert "contact.A" not in page.url and _peaks(page) == peaks


def test_the_download_button(page, server) -> None:
    import io
    import zipfile

    page.goto(f"{server}?contact=ifm-conventional&c.A=50&settle=1")
    _views(page, 1)
    with page.expect_download(timeout=WAIT_MS) as caught:
        page.click("#download")
    archive = zipfile.ZipFile(io.BytesIO(Path(caught.value.path()).read_bytes()))
    assert {"settings.toml", "summary.json", "timeseries.csv", "steps.csv"} <= set(
        archive.namelist()
    )
    summary = json.loads(archive.read("summary.json"))
    peaks = _peaks(page)
    assert {k: p["value"] for k, p in summary["peaks"].items()} == pytest.approx(peaks, rel=1e-9)
    # joints of their own contact: jointplay simulate cannot write them, and the page says so
    page.select_option("#contact-B", "physical")
    _views(page, 2)
    page.click("#download")
    page.wait_for_function("!document.getElementById('message').hidden", timeout=WAIT_MS)
    assert "one contact and friction for every joint" in page.text_content("#message")


def test_a_newer_change_supersedes_the_pending_one(page, server) -> None:
    page.goto(f"{server}?contact=ifm-conventional")
    _views(page, 1)
    for value in ("10", "20", "30", "40"):
        page.fill("#clr-A", value)
    page.wait_for_function(
        "document.body.dataset.state === 'ready' && "
        "Math.max(...document.getElementById('orbits').data[2].x) > 39.9",
        timeout=WAIT_MS,
    )
    time.sleep(0.5)  # nothing older lands afterwards
    assert max(_orbit(page, "A")["circle"]) == pytest.approx(40)
    assert page.input_value("#clr-A") == "40"


def test_ctrl_c_stops_the_server_cleanly() -> None:
    process, url = _serve()
    assert url.startswith("http://127.0.0.1:")
    status, stderr = _stop(process)
    assert status == 0, stderr
    assert "stopped" in stderr and "Traceback" not in stderr
