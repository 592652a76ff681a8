"""What every figure of jointplay shares: the palette, the thinning of lines, the file formats.

* **One colour per method, everywhere** (:data:`METHOD_COLOURS`, the colour-blind-safe
  Okabe–Ito palette): a method keeps its colour in every figure of a report; the nominal
  (ideal-joint) mechanism is always black and dashed, measurements black points.
* **Lines thinned to what the eye sees** (:func:`thin`): a line of a million integrator steps
  is drawn as the smallest and largest value in each of ~1000 columns of its x range, in
  order, so every spike and every extreme survives while the figure is drawn in milliseconds.
* **Formats** (:func:`save`): PNG always (a report embeds it), plus SVG or PDF for print when
  ``figure_format`` asks for one. The PNG is stored with a palette of at most
  :data:`PNG_COLOURS` colours (:func:`compact_png`): a line plot has few colours, and the
  palette makes it about a third of matplotlib's RGBA file, which keeps a report with a dozen
  embedded figures small.

No physics here; matplotlib is only imported when a figure is saved or drawn.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from jointplay.errors import ConfigError

#: File formats a figure can be written in besides the PNG that reports embed.
FIGURE_FORMATS = ("png", "svg", "pdf")

#: The paper's six methods (Table 2), one colour each (Okabe–Ito).
METHOD_COLOURS = {
    "ifm-conventional": "#0072B2",  # blue
    "rm-conventional": "#56B4E9",  # sky blue
    "ifm-ecs-cylindrical": "#D55E00",  # vermillion
    "rm-ecs-cylindrical": "#E69F00",  # orange
    "ifm-ecs-spherical": "#009E73",  # bluish green
    "rm-ecs-spherical": "#CC79A7",  # reddish purple
}
#: The two ECS contact geometries, in the colour of their IFM method.
CONTACT_COLOURS = {"spherical": "#009E73", "cylindrical": "#D55E00"}
#: Hysteresis-damping laws of the Hunt–Crossley family (the ECS damping figure).
LAW_COLOURS = {
    "lankarani-nikravesh": "#0072B2",
    "hunt-crossley": "#CC79A7",
    "flores": "#E69F00",
    "hu-guo": "#56B4E9",
}
#: Colours of the series of one figure that are not methods (joints, links, quantities).
SERIES_COLOURS = ("#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9", "#000000")
#: Line styles of the series' nominal (ideal-joint) counterparts, one per series.
NOMINAL_STYLES = ("--", ":", "-.", (0, (5, 1, 1, 1, 1, 1)))
#: The nominal mechanism (ideal joints): black, dashed.
NOMINAL = {"color": "black", "linestyle": "--", "linewidth": 1.0}
#: Colours of a saved PNG's palette (:func:`compact_png`).
PNG_COLOURS = 256
#: Columns of a figure's x range a thinned line keeps its extremes in.
THIN_BINS = 1000


def check_format(figure_format: str, field: str = "figure format") -> str:
    """``figure_format`` if it is one of :data:`FIGURE_FORMATS`.

    Args:
        figure_format: the format asked for.
        field: its name in the message (the command line passes its option's).

    Raises:
        ConfigError: another format.
    """
    if figure_format not in FIGURE_FORMATS:
        raise ConfigError(
            f"{field} must be one of {', '.join(FIGURE_FORMATS)}, got {figure_format!r}"
        )
    return figure_format


def method_colour(method: str) -> str:
    """The colour of one of the paper's methods (grey for anything else)."""
    return METHOD_COLOURS.get(method, "0.4")


def save(fig: Any, path: Path, figure_format: str = "png", *, dpi: int = 100) -> list[Path]:
    """Write ``fig`` as ``path`` (PNG) and, unless ``figure_format`` is ``"png"``, also as
    ``path`` with the suffix of ``figure_format``; close it.

    Returns:
        The files written, the PNG first.
    """
    check_format(figure_format)
    png = path.with_suffix(".png")
    _save_palette_png(fig, png, dpi)
    written = [png]
    if figure_format != "png":
        vector = path.with_suffix(f".{figure_format}")
        fig.savefig(vector)
        written.append(vector)
    from jointplay.report._mpl import pyplot

    pyplot().close(fig)
    return written


def compact_png(path: Path) -> Path:
    """Rewrite the PNG at ``path`` with a palette of :data:`PNG_COLOURS` colours (no
    dithering, so lines stay crisp); returns ``path``."""
    from PIL import Image

    with Image.open(path) as image:
        image.load()
        _palette(image).save(path, format="PNG")
    return path


def _palette(image: Any) -> Any:
    """``image`` (PIL, RGB or RGBA) in a palette of :data:`PNG_COLOURS` colours: the
    max-coverage palette without dithering, so lines stay crisp."""
    from PIL import Image

    return image.convert("RGB").quantize(
        colors=PNG_COLOURS, method=Image.Quantize.MAXCOVERAGE, dither=Image.Dither.NONE
    )


def _save_palette_png(fig: Any, path: Path, dpi: int) -> None:
    """``fig`` drawn at ``dpi`` as :func:`compact_png` would leave matplotlib's PNG of it, the
    same pixels in the same palette, but from the drawing's pixels: matplotlib's own PNG
    (compressed, then read back) is never made, and the palette PNG is compressed at zlib's
    default level, not with ``optimize`` (level 9: 10-20 % smaller, 8x slower). ~70 ms less
    per figure on a 2-core machine, ~0.35 s of a ``jointplay simulate`` (docs/cli.md,
    "Start-up time")."""
    import io

    import numpy as np
    from PIL import Image

    drawn = io.BytesIO()
    fig.savefig(drawn, format="rgba", dpi=dpi)  # as for a PNG: the same drawing, unencoded
    shape = np.shape(fig.canvas.buffer_rgba())  # (height, width, 4) of that drawing
    if len(shape) != 3 or shape[0] * shape[1] * 4 != drawn.getbuffer().nbytes:
        fig.savefig(path, dpi=dpi)  # pragma: no cover - not Agg: matplotlib's PNG first
        compact_png(path)  # pragma: no cover
        return  # pragma: no cover
    image = Image.frombuffer("RGBA", (shape[1], shape[0]), drawn.getvalue(), "raw", "RGBA", 0, 1)
    _palette(image).save(path, format="PNG")


def encode(fig: Any, stem: str, figure_format: str = "png", **savefig: Any) -> dict[str, bytes]:
    """``fig`` as file contents by file name: ``stem.png`` and, unless ``figure_format`` is
    ``"png"``, ``stem.svg`` or ``stem.pdf`` too (for print); close it.

    For the reports that embed their images from memory; ``savefig`` goes to
    :meth:`matplotlib.figure.Figure.savefig` (dpi, bbox_inches).
    """
    import io

    from jointplay.report._mpl import pyplot

    check_format(figure_format)
    formats = ("png",) if figure_format == "png" else ("png", figure_format)
    files = {}
    for suffix in formats:
        buffer = io.BytesIO()
        fig.savefig(buffer, format=suffix, **savefig)
        files[f"{stem}.{suffix}"] = buffer.getvalue()
    pyplot().close(fig)
    return files


def thin(x: Any, y: Any, bins: int = THIN_BINS) -> tuple[np.ndarray, np.ndarray]:
    """The points of the line (x, y) the eye can tell apart: in each of ``bins`` equal
    columns of the x range, the first, smallest and largest point, in their order.

    A line with at most ``3 * bins`` points is returned as it is. NaNs are kept out of the
    extremes. ``x`` must be sorted (time or crank angle).
    """
    xs = np.asarray(x, dtype=float)
    ys = np.asarray(y, dtype=float)
    n = xs.shape[0]
    if n <= 3 * bins:
        return xs, ys
    lo, hi = xs[0], xs[-1]
    if not hi > lo:
        return xs, ys
    column = np.minimum(((xs - lo) / (hi - lo) * bins).astype(np.int64), bins - 1)
    starts = np.flatnonzero(np.r_[True, column[1:] != column[:-1]])
    finite = np.isfinite(ys)
    low = np.where(finite, ys, np.inf)
    high = np.where(finite, ys, -np.inf)
    keep = np.zeros(n, dtype=bool)
    keep[starts] = True
    keep[-1] = True
    owner = np.repeat(np.arange(starts.shape[0]), np.diff(np.r_[starts, n]))
    for values, reduce in ((low, np.minimum), (high, np.maximum)):
        extreme = reduce.reduceat(values, starts)
        hits = np.flatnonzero(values == extreme[owner])
        owners = owner[hits]  # sorted: the first hit of each column is its first extreme
        keep[hits[np.r_[True, owners[1:] != owners[:-1]]]] = True
    return xs[keep], ys[keep]


_SUPERSCRIPT = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")


def tick_label(value: float, _position: Any = None) -> str:
    """A tick label that needs no offset above the axis: ``-3,000``, ``0.25``, ``2.5×10⁸``."""
    if value == 0:
        return "0"
    magnitude = abs(value)
    if magnitude >= 1e5 or magnitude < 1e-3:
        mantissa, exponent = f"{value:.2e}".split("e")
        mantissa = mantissa.rstrip("0").rstrip(".")
        return f"{mantissa}×10{str(int(exponent)).translate(_SUPERSCRIPT)}"
    if magnitude >= 1000:
        return f"{value:,.0f}"
    return f"{value:.4g}"


def tick_formatter() -> Any:
    """A matplotlib formatter of :func:`tick_label`: each label carries its own magnitude."""
    from matplotlib.ticker import FuncFormatter

    return FuncFormatter(tick_label)


def style() -> Any:
    """An rc-context with the report's font sizes (use as ``with style(): ...``)."""
    from jointplay.report._mpl import pyplot

    return pyplot().rc_context(
        {
            "font.size": 9,
            "axes.titlesize": 10,
            "axes.labelsize": 9,
            "xtick.labelsize": 8,
            "ytick.labelsize": 8,
            "legend.fontsize": 8,
            "axes.grid": True,
            # a fixed title height: matplotlib otherwise measures every axis to place it
            "axes.titley": 1.0,
            "axes.titlepad": 4.0,
            "grid.alpha": 0.3,
            "axes.formatter.use_mathtext": False,
            "axes.formatter.limits": (-3, 4),
            "path.simplify": True,
            "agg.path.chunksize": 10000,
        }
    )


def overlapping_text(fig: Any, *, margin_px: float = 1.0) -> list[tuple[str, str]]:
    """Pairs of texts of ``fig`` that overlap once drawn: tick labels (those of ticks inside
    the view, the ones drawn), axis labels, titles, annotations and legend entries (their
    bounding boxes, shrunk by ``margin_px`` so that boxes that only touch do not count).
    For the figure tests: a figure is legible when this is empty."""
    from matplotlib.text import Text

    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    ticks, drawn = set(), []
    for ax in fig.get_axes():
        for axis, index in ((ax.xaxis, 0), (ax.yaxis, 1)):
            low, high = sorted(axis.get_view_interval())
            span = 1e-9 * max(abs(low), abs(high), 1.0)
            for label in axis.get_ticklabels(which="both"):
                ticks.add(id(label))
                at = label.get_position()[index]
                if low - span <= at <= high + span:
                    drawn.append(label)
    texts = [t for t in fig.findobj(Text) if id(t) not in ticks] + drawn
    boxes = []
    for text in texts:
        if not (text.get_visible() and text.get_text().strip()):
            continue
        box = text.get_window_extent(renderer)
        if box.width > 0 and box.height > 0:
            boxes.append((text.get_text(), box.padded(-margin_px)))
    return [
        (first, second)
        for i, (first, a) in enumerate(boxes)
        for second, b in boxes[i + 1 :]
        if a.overlaps(b)
    ]
