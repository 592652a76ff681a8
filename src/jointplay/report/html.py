"""A small builder for self-contained HTML reports (figures embedded as base64 data).

The page reads at 1400 px without scrolling sideways: the body is at most 1100 px wide, every
table sits in its own box that scrolls on its own if it must (``overflow-x: auto``), text
cells wrap between words but never inside one (a response's name, ``transmission_angle_min``,
stays whole: the table's box scrolls instead), and images shrink to the column. On a narrow
screen (a phone, up to 800 px) no column is squeezed below 8 characters, and a
table written as cards (``table(..., cards=True)``) stacks each row's cells, each under its
header, so that long text reads at the screen's width (there, words longer than the screen
may break). Headings with an anchor are listed in a
table of contents at the top. Numbers in tables are written by the one number format of
:mod:`jointplay.report.format`. A cell may be :class:`Flagged` (an implausible value): it is
shaded and carries a numbered mark that links to the reason, written as a footnote under its
table (and as the cell's tooltip), so the reason is one click away from the value.
"""

from __future__ import annotations

import base64
import html
from collections.abc import Iterable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pandas as pd

from jointplay.report.format import number

_STYLE = """
body { font-family: -apple-system, Segoe UI, Helvetica, Arial, sans-serif; margin: 2em auto;
       max-width: 1100px; color: #222; line-height: 1.45; padding: 0 1em; }
h1 { border-bottom: 2px solid #444; padding-bottom: .2em; }
h2 { margin-top: 2em; border-bottom: 1px solid #bbb; }
h3 { margin-top: 1.6em; }
nav.toc { background: #f7f7f7; border: 1px solid #ddd; padding: .4em 1.2em; font-size: .92em; }
nav.toc ol { margin: .3em 0; padding-left: 1.4em; } nav.toc ol ol { font-size: .95em; }
nav.toc > ol { columns: 2 20em; } nav.toc li { break-inside: avoid; }
.scroll { max-width: 100%; overflow-x: auto; margin: .8em 0 1.4em; }
table { border-collapse: collapse; font-size: 0.88em; }
th, td { border: 1px solid #ccc; padding: .25em .6em; text-align: right; vertical-align: top; }
td { white-space: nowrap; }
th { background: #f0f0f0; font-weight: 600; }
td.text, th.text { text-align: left; }
td.text { white-space: normal; }
td.flag { background: #fde4e1; }
a.flag { color: #a01010; font-weight: 700; text-decoration: none; margin-left: .25em; }
ol.flags { font-size: 0.85em; color: #5a1010; margin: -1em 0 1.4em; padding-left: 2.2em; }
ol.flags li:target { background: #fde4e1; }
tr.group td { background: #eef3f8; text-align: left; white-space: normal; }
caption { caption-side: top; text-align: left; font-weight: bold; padding-bottom: .3em; }
.tablenote { font-size: 0.85em; color: #555; margin: -1em 0 1.4em; }
figure { margin: 1em 0 2em; }
figcaption { font-size: 0.88em; color: #555; }
img, video { max-width: 100%; height: auto; }
.note { background: #fff8e0; border-left: 4px solid #e0b000; padding: .5em 1em; }
.summary { background: #eef6ee; border-left: 4px solid #3a8a3a; padding: .3em 1em; }
.small { font-size: 0.85em; color: #555; }
code, pre { background: #f5f5f5; }
pre { padding: .6em; overflow-x: auto; font-size: 0.82em; }
.cols { display: flex; flex-wrap: wrap; gap: 0 1.2em; align-items: flex-start; }
.cols table { font-size: 0.8em; }
.cols > div { max-width: 100%; min-width: 0; }
.cols > figure { flex: 1 1 320px; min-width: 0; margin: 0 0 1em; }
details { margin: 1em 0; } details > summary { cursor: pointer; font-weight: 600; color: #225; }
dl.defs dt { font-weight: 600; } dl.defs dd { margin: 0 0 .4em 1.4em; }
@media (max-width: 800px) {
  body { padding: 0 .5em; }
  th, td { min-width: 8ch; }
  table.cards, table.cards tbody, table.cards tr, table.cards td { display: block; }
  table.cards tr.head { display: none; }
  table.cards tr { border-bottom: 1px solid #ccc; padding: .3em 0; }
  table.cards td { border: none; text-align: left; white-space: normal; min-width: 0;
                   overflow-wrap: anywhere; }
  table.cards td[data-label]::before { content: attr(data-label) ": "; font-weight: 600; }
}
"""


@dataclass(frozen=True)
class Flagged:
    """A table cell whose value is implausible: shown as usual, shaded, with a numbered mark
    (⚠) that links to ``reason`` (a footnote under the table, also the cell's tooltip).

    Attributes:
        value: the cell's value (a number, written in the report's format, or text).
        reason: why the value is marked, and the rule that marked it, in words.
    """

    value: Any
    reason: str


def _fmt(value: Any) -> str:
    """A table cell: numbers in the report's one format, text unchanged."""
    return number(value)


def _image_mime(data: bytes) -> str:
    if data.startswith(b"GIF8"):
        return "image/gif"
    if data.lstrip().startswith((b"<?xml", b"<svg")):
        return "image/svg+xml"
    if data.startswith(b"\xff\xd8"):
        return "image/jpeg"
    return "image/png"


class HtmlReport:
    """Collects headings, text, tables and figures and renders one self-contained page.

    Args:
        title: the page title (``<h1>`` and ``<title>``).
        toc: list the anchored headings (``heading(..., anchor=...)``) in a table of contents
            under the title (only drawn when there are at least two).
        contents_before: the anchor of the heading the table of contents goes right before
            (e.g. after a summary that should fill the first screen; default: under the
            title).
    """

    def __init__(self, title: str, *, toc: bool = True, contents_before: str | None = None) -> None:
        self.title = title
        self.toc = toc
        self.contents_before = contents_before
        self.parts: list[str] = []
        self._headings: list[tuple[int, str, str]] = []
        self._flags = 0  # footnotes of flagged cells written so far (their ids are unique)

    def heading(self, text: str, level: int = 2, anchor: str | None = None) -> None:
        ident = f' id="{html.escape(anchor)}"' if anchor else ""
        if anchor:
            self._headings.append((level, anchor, text))
        self.parts.append(f"<h{level}{ident}>{html.escape(text)}</h{level}>")

    def paragraph(self, text: str, css: str | None = None) -> None:
        klass = f' class="{css}"' if css else ""
        self.parts.append(f"<p{klass}>{html.escape(text)}</p>")

    def bullets(
        self, items: Iterable[str | tuple[str, Sequence[str]]], css: str | None = None
    ) -> None:
        """A bulleted list; an item ``(text, sub_items)`` carries a nested list."""
        klass = f' class="{css}"' if css else ""

        def item(i: str | tuple[str, Sequence[str]]) -> str:
            if isinstance(i, str):
                return f"<li>{html.escape(i)}</li>"
            text, sub = i
            inner = "".join(f"<li>{html.escape(s)}</li>" for s in sub)
            return f"<li>{html.escape(text)}<ul>{inner}</ul></li>" if sub else item(text)

        self.parts.append(f"<ul{klass}>" + "".join(map(item, items)) + "</ul>")

    def definitions(self, items: Mapping[str, str] | Iterable[tuple[str, str]]) -> None:
        """A definition list: each term (e.g. a response) with what it means."""
        pairs = items.items() if isinstance(items, Mapping) else items
        self.parts.append(
            '<dl class="defs">'
            + "".join(f"<dt>{html.escape(t)}</dt><dd>{html.escape(d)}</dd>" for t, d in pairs)
            + "</dl>"
        )

    def preformatted(self, text: str) -> None:
        self.parts.append(f"<pre>{html.escape(text)}</pre>")

    def table(
        self,
        rows: pd.DataFrame | Sequence[Any],
        headers: Sequence[str] | None = None,
        caption: str | None = None,
        text_columns: Sequence[int] = (0,),
        *,
        note: str | None = None,
        groups: Sequence[tuple[int, str] | tuple[int, str, str]] = (),
        widths: Sequence[str | None] = (),
        cards: bool = False,
    ) -> None:
        """A table in its own horizontally scrolling box.

        Args:
            rows: a DataFrame (its columns are the headers unless ``headers`` is given) or
                a sequence of row tuples.
            headers: column headers, in words with units.
            caption: the table's title.
            text_columns: left-aligned columns (the others hold numbers, written by
                :func:`jointplay.report.format.number`).
            note: a sentence under the table (e.g. what its responses mean).
            groups: ``(row index, title)`` or ``(row index, title, detail)``: a full-width
                group row before that row, its title in bold and the detail (e.g. what the
                group's rows share) after it.
            widths: CSS widths of the first columns (e.g. ``"25%"``; ``None``: automatic).
            cards: on a narrow screen, each row a card: its cells stacked, each after its
                header (for a table of long text, e.g. claims with notes).

        A cell given as :class:`Flagged` is shaded and marked ⚠ with the number of its
        footnote (the reason; one footnote per distinct reason in the table).
        """
        if isinstance(rows, pd.DataFrame):
            headers = list(headers) if headers is not None else [str(c) for c in rows.columns]
            body = list(rows.itertuples(index=False, name=None))
        else:
            body = list(rows)
        width = len(headers) if headers else max((len(r) for r in body), default=1)
        starts = {g[0]: (g[1], g[2] if len(g) > 2 else "") for g in groups}
        klass = ' class="cards"' if cards else ""
        out = [f'<div class="tablebox"><div class="scroll"><table{klass}>']
        if caption:
            out.append(f"<caption>{html.escape(caption)}</caption>")
        if widths:
            out.append(
                "<colgroup>"
                + "".join(
                    f'<col style="width:{html.escape(w)}"/>' if w else "<col/>" for w in widths
                )
                + "</colgroup>"
            )
        if headers:
            out.append(
                '<tr class="head">'
                + "".join(
                    f'<th class="text">{html.escape(h)}</th>'
                    if i in text_columns
                    else f"<th>{html.escape(h)}</th>"
                    for i, h in enumerate(headers)
                )
                + "</tr>"
            )
        reasons: dict[str, int] = {}  # this table's footnotes, by reason
        for index, row in enumerate(body):
            if index in starts:
                title, detail = starts[index]
                more = f" <span>{html.escape(detail)}</span>" if detail else ""
                out.append(
                    f'<tr class="group"><td colspan="{width}"><strong>{html.escape(title)}'
                    f"</strong>{more}</td></tr>"
                )
            cells = []
            for i, value in enumerate(row):
                css = ' class="text"' if i in text_columns else ""
                if cards and headers and i < len(headers):
                    css += f' data-label="{html.escape(headers[i])}"'
                if isinstance(value, Flagged):
                    if value.reason not in reasons:
                        self._flags += 1
                        reasons[value.reason] = self._flags
                    n = reasons[value.reason]
                    reason = html.escape(value.reason)
                    css = css.replace(' class="text"', "")
                    klass = "text flag" if i in text_columns else "flag"
                    cells.append(
                        f'<td class="{klass}"{css} title="{reason}">'
                        f"{html.escape(_fmt(value.value))}"
                        f'<a class="flag" href="#flag-{n}" title="{reason}">⚠{n}</a></td>'
                    )
                    continue
                cells.append(f"<td{css}>{html.escape(_fmt(value))}</td>")
            out.append("<tr>" + "".join(cells) + "</tr>")
        out.append("</table></div>")
        if reasons:
            out.append(
                '<ol class="flags">'
                + "".join(
                    f'<li id="flag-{n}" value="{n}">⚠ {html.escape(reason)}</li>'
                    for reason, n in reasons.items()
                )
                + "</ol>"
            )
        if note:
            out.append(f'<p class="tablenote">{html.escape(note)}</p>')
        out.append("</div>")
        self.parts.append("".join(out))

    def figure(
        self,
        image: Path | bytes,
        caption: str = "",
        *,
        vector: Path | None = None,
        link_base: Path | None = None,
    ) -> None:
        """An embedded image (PNG, GIF, SVG or JPEG: the type is read from the data).

        Args:
            image: the image file or its bytes.
            caption: what the figure shows, in words.
            vector: an SVG or PDF copy of the figure for publication: linked under the
                caption (relative to ``link_base``, the folder of the page).
            link_base: the folder the page is written to (for ``vector``'s link).
        """
        data = image.read_bytes() if isinstance(image, Path) else image
        mime = _image_mime(data)
        encoded = base64.b64encode(data).decode("ascii")
        link = ""
        if vector is not None:
            href = vector.relative_to(link_base).as_posix() if link_base else vector.name
            kind = vector.suffix.lstrip(".").upper()
            link = f' <a href="{html.escape(href)}">{kind} version for print</a>'
        self.parts.append(
            f'<figure><img alt="{html.escape(caption)}" src="data:{mime};base64,{encoded}"/>'
            f"<figcaption>{html.escape(caption)}{link}</figcaption></figure>"
        )

    def video(self, data: bytes, caption: str = "", *, mime: str = "video/mp4") -> None:
        """An embedded video that loops (e.g. an MP4 animation)."""
        encoded = base64.b64encode(data).decode("ascii")
        self.parts.append(
            f'<figure><video controls autoplay loop muted playsinline src="data:{mime};base64,'
            f'{encoded}"></video><figcaption>{html.escape(caption)}</figcaption></figure>'
        )

    @contextmanager
    def details(self, summary: str) -> Iterator[None]:
        """What is added inside the ``with`` block is folded under ``summary`` (closed until
        the reader opens it): for material a reader may skip."""
        self.parts.append(f"<details><summary>{html.escape(summary)}</summary>")
        try:
            yield
        finally:
            self.parts.append("</details>")

    @contextmanager
    def side_by_side(self) -> Iterator[None]:
        """What is added inside the ``with`` block is laid out in a row that wraps (e.g. two
        narrow tables beside each other)."""
        self.parts.append('<div class="cols">')
        try:
            yield
        finally:
            self.parts.append("</div>")

    def raw(self, fragment: str) -> None:
        """Trusted HTML written by jointplay itself (never user text)."""
        self.parts.append(fragment)

    def _contents(self) -> str:
        if not self.toc or len(self._headings) < 2:
            return ""
        out = ['<nav class="toc"><strong>Contents</strong><ol>']
        open_sub = False
        for level, anchor, text in self._headings:
            link = f'<a href="#{html.escape(anchor)}">{html.escape(text)}</a>'
            if level <= 2:
                if open_sub:
                    out.append("</ol></li>")
                    open_sub = False
                elif len(out) > 1:
                    out.append("</li>")
                out.append(f"<li>{link}")
            else:
                if not open_sub:
                    out.append("<ol>")
                    open_sub = True
                out.append(f"<li>{link}</li>")
        out.append("</ol></li></ol></nav>" if open_sub else "</li></ol></nav>")
        return "".join(out)

    def render(self) -> str:
        parts, contents = list(self.parts), self._contents()
        marker = f' id="{html.escape(self.contents_before)}"' if self.contents_before else None
        at = next((i for i, part in enumerate(parts) if marker and marker in part), 0)
        parts.insert(at, contents)
        body = "\n".join(parts)
        return (
            '<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8"/>'
            '<meta name="viewport" content="width=device-width, initial-scale=1"/>'
            f"<title>{html.escape(self.title)}</title><style>{_STYLE}</style></head>"
            f"<body><h1>{html.escape(self.title)}</h1>\n{body}\n</body></html>\n"
        )

    def write(self, path: Path) -> Path:
        path.write_text(self.render(), encoding="utf-8")
        return path
