"""A small builder for self-contained HTML reports (figures embedded as base64 PNG)."""

from __future__ import annotations

import base64
import html
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Any

import pandas as pd

_STYLE = """
body { font-family: -apple-system, Segoe UI, Helvetica, Arial, sans-serif; margin: 2em auto;
       max-width: 1100px; color: #222; line-height: 1.45; padding: 0 1em; }
h1 { border-bottom: 2px solid #444; padding-bottom: .2em; }
h2 { margin-top: 2em; border-bottom: 1px solid #bbb; }
table { border-collapse: collapse; margin: .8em 0 1.4em; font-size: 0.88em; }
th, td { border: 1px solid #ccc; padding: .25em .6em; text-align: right; vertical-align: top; }
th { background: #f0f0f0; }
td.text, th.text { text-align: left; }
caption { caption-side: top; text-align: left; font-weight: bold; padding-bottom: .3em; }
figure { margin: 1em 0 2em; }
figcaption { font-size: 0.88em; color: #555; }
img { max-width: 100%; }
.note { background: #fff8e0; border-left: 4px solid #e0b000; padding: .5em 1em; }
.small { font-size: 0.85em; color: #555; }
code, pre { background: #f5f5f5; }
pre { padding: .6em; overflow-x: auto; font-size: 0.82em; }
"""


def _fmt(value: Any) -> str:
    if isinstance(value, float):
        if value != value:  # NaN
            return "—"
        magnitude = abs(value)
        if magnitude != 0 and (magnitude >= 1e6 or magnitude < 1e-3):
            return f"{value:.4g}"
        return f"{value:.4g}" if magnitude < 100 else f"{value:,.1f}"
    if value is None:
        return "—"
    return str(value)


class HtmlReport:
    """Collects headings, text, tables and figures and renders one self-contained page."""

    def __init__(self, title: str) -> None:
        self.title = title
        self.parts: list[str] = []

    def heading(self, text: str, level: int = 2, anchor: str | None = None) -> None:
        ident = f' id="{html.escape(anchor)}"' if anchor else ""
        self.parts.append(f"<h{level}{ident}>{html.escape(text)}</h{level}>")

    def paragraph(self, text: str, css: str | None = None) -> None:
        klass = f' class="{css}"' if css else ""
        self.parts.append(f"<p{klass}>{html.escape(text)}</p>")

    def bullets(self, items: Iterable[str]) -> None:
        self.parts.append("<ul>" + "".join(f"<li>{html.escape(i)}</li>" for i in items) + "</ul>")

    def preformatted(self, text: str) -> None:
        self.parts.append(f"<pre>{html.escape(text)}</pre>")

    def table(
        self,
        rows: pd.DataFrame | Sequence[Any],
        headers: Sequence[str] | None = None,
        caption: str | None = None,
        text_columns: Sequence[int] = (0,),
    ) -> None:
        """A table; ``text_columns`` are left-aligned (the others hold numbers)."""
        if isinstance(rows, pd.DataFrame):
            headers = [str(c) for c in rows.columns]
            body = rows.itertuples(index=False, name=None)
        else:
            body = iter(list(rows))
        out = ["<table>"]
        if caption:
            out.append(f"<caption>{html.escape(caption)}</caption>")
        if headers:
            out.append(
                "<tr>"
                + "".join(
                    f'<th class="text">{html.escape(h)}</th>'
                    if i in text_columns
                    else f"<th>{html.escape(h)}</th>"
                    for i, h in enumerate(headers)
                )
                + "</tr>"
            )
        for row in body:
            cells = []
            for i, value in enumerate(row):
                css = ' class="text"' if i in text_columns else ""
                cells.append(f"<td{css}>{html.escape(_fmt(value))}</td>")
            out.append("<tr>" + "".join(cells) + "</tr>")
        out.append("</table>")
        self.parts.append("".join(out))

    def figure(self, image: Path | bytes, caption: str = "") -> None:
        data = image.read_bytes() if isinstance(image, Path) else image
        encoded = base64.b64encode(data).decode("ascii")
        self.parts.append(
            f'<figure><img alt="{html.escape(caption)}" src="data:image/png;base64,{encoded}"/>'
            f"<figcaption>{html.escape(caption)}</figcaption></figure>"
        )

    def render(self) -> str:
        body = "\n".join(self.parts)
        return (
            '<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8"/>'
            f"<title>{html.escape(self.title)}</title><style>{_STYLE}</style></head>"
            f"<body><h1>{html.escape(self.title)}</h1>\n{body}\n</body></html>\n"
        )

    def write(self, path: Path) -> Path:
        path.write_text(self.render(), encoding="utf-8")
        return path
