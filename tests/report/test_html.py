"""The HTML builder: escaping, embedded figures, the table of contents, tables that cannot push
the page sideways, and the one number format."""

from __future__ import annotations

import math
import re

import numpy as np
import pandas as pd
import pytest

from jointplay.report.format import MISSING, number, percent, quantity
from jointplay.report.html import HtmlReport


def test_escaping_tables_and_figures(tmp_path) -> None:
    page = HtmlReport("a < b")
    page.paragraph("x & y")
    page.table(pd.DataFrame({"name": ["<k>"], "value": [1234.5678]}), caption="c")
    png = tmp_path / "f.png"
    png.write_bytes(b"\x89PNG\r\n\x1a\n")
    page.figure(png, "fig")
    text = page.render()
    assert "a &lt; b" in text and "x &amp; y" in text and "&lt;k&gt;" in text
    assert "1,235" in text  # four significant digits, thousands separated
    assert "data:image/png;base64,iVBORw0KGgo=" in text


def test_gif_and_svg_are_embedded_with_their_type(tmp_path) -> None:
    page = HtmlReport("t")
    page.figure(b"GIF89a....", "animation")
    page.figure(b'<svg xmlns="http://www.w3.org/2000/svg"/>', "vector")
    text = page.render()
    assert "data:image/gif;base64," in text and "data:image/svg+xml;base64," in text


def test_a_print_copy_is_linked_relative_to_the_page(tmp_path) -> None:
    (tmp_path / "figures").mkdir()
    svg = tmp_path / "figures" / "x.svg"
    svg.write_text("<svg/>")
    page = HtmlReport("t")
    page.figure(b"\x89PNG", "x", vector=svg, link_base=tmp_path)
    assert '<a href="figures/x.svg">SVG version for print</a>' in page.render()


def test_contents_list_the_anchored_headings_in_order() -> None:
    page = HtmlReport("t")
    page.heading("First", anchor="one")
    page.heading("Inside", level=3, anchor="one-a")
    page.heading("Not listed")  # no anchor: no entry, the heading as before
    page.heading("Second", anchor="two")
    text = page.render()
    nav = text[text.index("<nav") : text.index("</nav>")]
    links = re.findall(r'href="#([^"]+)"', nav)
    assert links == ["one", "one-a", "two"]
    assert "<h2>Not listed</h2>" in text
    assert nav.count("<ol>") == 2  # the level-3 heading nests under the first


def test_contents_can_follow_a_first_section() -> None:
    page = HtmlReport("t", contents_before="two")
    page.heading("Summary", anchor="one")
    page.paragraph("the answer")
    page.heading("Second", anchor="two")
    text = page.render()
    assert text.index("the answer") < text.index("<nav") < text.index('<h2 id="two">')
    assert re.findall(r'href="#([^"]+)"', text) == ["one", "two"]
    # without the option the contents stay under the title
    plain = HtmlReport("t")
    plain.heading("Summary", anchor="one")
    plain.heading("Second", anchor="two")
    plain.paragraph("after")
    rendered = plain.render()
    assert rendered.index("<nav") < rendered.index('<h2 id="one">')


def test_every_table_scrolls_in_its_own_box_and_groups_span_the_table() -> None:
    page = HtmlReport("t", toc=False)
    page.table(
        [("a", 1.0, 2.0), ("b", 3.0, 4.0)],
        ["name", "x (m)", "y (m)"],
        groups=[(0, "first", "what the first rows share"), (1, "second")],
        note="x and y: positions",
    )
    text = page.render()
    assert '<div class="scroll"><table>' in text and "</table></div>" in text
    assert text.count('<tr class="group"><td colspan="3">') == 2
    assert "<strong>first</strong> <span>what the first rows share</span>" in text
    assert '<p class="tablenote">x and y: positions</p>' in text


@pytest.mark.parametrize(
    ("value", "expected"),
    [
        (43.0, "43.00"),  # significant digits kept: 43.00 beside 46.01
        (46.01, "46.01"),
        (120.0, "120.0"),
        (90, "90"),  # an integer stays an integer
        (1662, "1,662"),
        (np.int64(-12345), "-12,345"),
        (242348.0, "242,348"),  # no digit of the integer part hidden in an exponent
        (56409.6, "56,410"),
        (0.021, "0.02100"),
        (3.67e-5, "3.670 × 10⁻⁵"),
        (2.5e9, "2.500 × 10⁹"),
        (9.99996, "10.00"),  # rounding carries into a new digit
        (-0.0, "0"),
        (0.0, "0"),
        (None, MISSING),
        (math.nan, MISSING),
        (math.inf, MISSING),
        ("text", "text"),
        (True, "True"),
    ],
)
def test_one_number_format(value: object, expected: str) -> None:
    assert number(value) == expected


def test_signed_percent_and_quantity() -> None:
    assert percent(15.016) == "+15.0 %"
    assert percent(-3.522) == "-3.52 %"
    assert percent(math.nan) == MISSING
    assert quantity(21.0, "µm") == "21.00 µm"
    assert quantity(None, "µm") == MISSING


def test_number_keeps_the_digits_it_promises() -> None:
    """Every float between 1e-3 and 1e3 printed with four significant digits reads back
    within half a unit of its last digit (an independent check: float() of the text)."""
    rng = np.random.default_rng(7)
    for value in 10.0 ** rng.uniform(-3, 3, 500) * rng.choice([-1, 1], 500):
        text = number(float(value)).replace(",", "")
        digits = len(text.lstrip("-").replace(".", "").lstrip("0"))
        assert digits == 4, (value, text)
        last = 10.0 ** (math.floor(math.log10(abs(float(text)))) - 3)
        assert abs(float(text) - value) <= 0.5 * last * (1 + 1e-9), (value, text)


def test_a_flagged_cell_is_marked_and_links_to_its_reason_once_per_table() -> None:
    from jointplay.report.html import Flagged

    page = HtmlReport("t")
    why = "Implausible: a < b"
    page.table([("x", Flagged(1234.5678, why)), ("y", Flagged(2.0, why)), ("z", 3.0)], ["k", "v"])
    page.table([("w", Flagged(5.0, "another"))], ["k", "v"])
    text = page.render()
    # both cells of the first table link to its one footnote, the second table to its own
    assert text.count('href="#flag-1"') == 2 and text.count('href="#flag-2"') == 1
    assert '<li id="flag-1" value="1">⚠ Implausible: a &lt; b</li>' in text
    assert '<td class="flag" title="Implausible: a &lt; b">1,235<a' in text
    assert "<td>3.000</td>" in text  # an unflagged cell as before
