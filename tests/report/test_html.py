"""The HTML builder escapes text and embeds figures."""

from __future__ import annotations

import pandas as pd

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
    assert "1,234.6" in text
    assert "data:image/png;base64,iVBORw0KGgo=" in text
