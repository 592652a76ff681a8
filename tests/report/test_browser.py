"""A report page in a real browser: no horizontal scroll at 1400 px, every image loads.

The page is rendered by headless Chromium (Debian's ``chromium`` package) with a small probe
script that writes, once the page has loaded, the document's scroll width and the number of
images that failed to decode into an attribute of ``<body>``; ``--dump-dom`` returns the DOM
after the load, so the test reads what the browser measured. Skipped, with the reason, when no
Chromium is on PATH, except in CI (``tests/_programs.py``).
"""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

import pandas as pd
import pytest

from _programs import need
from jointplay.report.html import HtmlReport

WIDTH = 1400  # px: the window the issue asks the page to fit
PROBE = """<script>window.addEventListener('load', function () {
  var images = Array.from(document.images);
  var broken = images.filter(function (i) { return !(i.complete && i.naturalWidth > 0); });
  document.body.setAttribute('data-probe', JSON.stringify({
    scrollWidth: document.documentElement.scrollWidth,
    clientWidth: document.documentElement.clientWidth,
    images: images.length,
    broken: broken.map(function (i) { return i.alt; })
  }));
});</script>"""


@pytest.fixture
def browser() -> str:
    return need("chromium", "chromium-browser", package="chromium")


def measure(page: Path, tmp_path: Path, browser: str) -> dict[str, object]:
    """Load ``page`` in headless Chromium at :data:`WIDTH` px and return what the probe saw."""
    import json

    probed = tmp_path / f"probed-{page.name}"
    text = page.read_text(encoding="utf-8")
    probed.write_text(text.replace("</body>", PROBE + "</body>"), encoding="utf-8")
    run = subprocess.run(
        [
            browser,
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--hide-scrollbars",
            f"--window-size={WIDTH},900",
            "--virtual-time-budget=10000",  # let the load event fire before the dump
            f"--user-data-dir={tmp_path / 'profile'}",
            "--dump-dom",
            probed.as_uri(),
        ],
        capture_output=True,
        text=True,
        timeout=120,
    )
    found = re.search(r'data-probe="([^"]*)"', run.stdout)
    assert found, f"the probe did not run (exit {run.returncode}): {run.stderr[-2000:]}"
    return json.loads(found.group(1).replace("&quot;", '"'))


def png(tmp_path: Path) -> Path:
    """A real 1500 px wide PNG (wider than the page: it must shrink to the column)."""
    from jointplay.report._mpl import pyplot

    plt = pyplot()
    fig, ax = plt.subplots(figsize=(15, 2), dpi=100)
    ax.plot([0, 1], [0, 1])
    path = tmp_path / "wide.png"
    fig.savefig(path)
    plt.close(fig)
    return path


def test_a_report_with_wide_tables_fits_1400_px_and_its_images_load(
    tmp_path: Path, browser: str
) -> None:
    page = HtmlReport("A page with everything that used to push it sideways")
    page.heading("Tables", anchor="tables")
    wide = pd.DataFrame(
        {f"c_eq_lankarani-nikravesh_spherical_N_s_per_mm_{i}": [1.234567e-4 * i] for i in range(26)}
    )
    page.table(wide, caption="26 snake_case columns")
    page.table(
        [("a long claim " * 12, 1.0, "why " * 60)],
        ["claim", "value", "note"],
        text_columns=(0, 2),
        groups=[(0, "group", "a detail " * 40)],
    )
    page.heading("Figures", anchor="figures")
    page.figure(png(tmp_path), "a figure wider than the page")
    with page.details("folded"):
        page.figure(png(tmp_path), "a folded figure")
    page.preformatted("x" * 3000)
    path = page.write(tmp_path / "report.html")
    seen = measure(path, tmp_path, browser)
    assert seen["scrollWidth"] <= WIDTH, seen
    assert seen["images"] == 2 and seen["broken"] == [], seen


def test_a_page_that_overflows_is_caught(tmp_path: Path, browser: str) -> None:
    """The check can fail: a fixed-width block wider than the window is measured as overflow."""
    path = tmp_path / "wide.html"
    path.write_text(
        '<!DOCTYPE html><html><body><div style="width:3000px">x</div>'
        '<img alt="missing" src="data:image/png;base64,AAAA"/></body></html>',
        encoding="utf-8",
    )
    seen = measure(path, tmp_path, browser)
    assert seen["scrollWidth"] > WIDTH
    assert seen["broken"] == ["missing"]


@pytest.mark.slow
def test_the_paper_report_fits_1400_px_and_its_images_load(tmp_path: Path, browser: str) -> None:
    """The real page of `jointplay paper`, on a reduced study (a few degrees of crank, two
    length corners, no experiment): every section, table and figure is there."""
    from jointplay.report.paper import write_paper_report
    from jointplay.study.paper import PaperStudyOptions, run_paper_study

    options = PaperStudyOptions(revolutions=0.03, ecs_sources=("paper",), corners=False, workers=1)
    calls: list[tuple[str, int, int]] = []
    study = run_paper_study(
        options, experiment=False, animation=True, progress=lambda *a: calls.append(a)
    )
    # progress names what runs now, in words, and counts up to its total
    labels = [label for label, _, _ in calls]
    assert labels[0].startswith("nominal kinematics")
    assert any(label.startswith("simulating IFM with spherical ECS") for label in labels)
    assert not any("/" in label for label in labels)  # no internal keys
    done = [d for _, d, _ in calls]
    assert done == sorted(done) and calls[-1][1] == calls[-1][2] and labels[-1] == "study done"
    write_paper_report(study, tmp_path, {"command_line": "test"})
    seen = measure(tmp_path / "report.html", tmp_path, browser)
    assert seen["scrollWidth"] <= WIDTH, seen
    assert seen["broken"] == [], seen
    assert seen["images"] >= 12, seen  # 8 method figures, orbits, mechanism, nominal, ECS...
