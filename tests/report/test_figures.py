"""What every figure shares: thinning that keeps every extreme, the palette, the file formats."""

from __future__ import annotations

import numpy as np
import pytest

from jointplay.errors import ConfigError
from jointplay.report.figures import (
    METHOD_COLOURS,
    check_format,
    save,
    thin,
    tick_label,
)
from jointplay.study.methods import METHODS


def test_thin_keeps_every_extreme_and_the_order() -> None:
    rng = np.random.default_rng(3)
    x = np.sort(rng.uniform(0.0, 360.0, 200_000))
    y = np.sin(np.radians(x)) + 0.01 * rng.standard_normal(x.size)
    spikes = rng.choice(x.size, 25, replace=False)
    y[spikes] += rng.choice([-50.0, 50.0], 25)  # start-up impacts: one sample wide
    tx, ty = thin(x, y, bins=500)
    assert tx.size <= 3 * 500 + 1
    assert np.all(np.diff(tx) >= 0)  # still a line: the order kept
    assert ty.max() == y.max() and ty.min() == y.min()
    assert set(spikes) <= set(np.flatnonzero(np.isin(x, tx)))  # every spike survives
    # every column of the x range keeps its own smallest and largest value
    columns = np.minimum(((x - x[0]) / (x[-1] - x[0]) * 500).astype(int), 499)
    kept = np.minimum(((tx - x[0]) / (x[-1] - x[0]) * 500).astype(int), 499)
    for c in rng.choice(500, 40, replace=False):
        assert ty[kept == c].max() == y[columns == c].max()
        assert ty[kept == c].min() == y[columns == c].min()


def test_thin_leaves_short_lines_alone_and_ignores_nans() -> None:
    x = np.arange(10.0)
    assert np.array_equal(thin(x, x**2)[1], x**2)
    long_x = np.arange(10_000.0)
    y = np.cos(long_x / 100)
    y[::7] = np.nan
    _, ty = thin(long_x, y, bins=100)
    assert np.nanmax(ty) == np.nanmax(y) and np.nanmin(ty) == np.nanmin(y)


def test_every_method_has_its_own_colour() -> None:
    assert set(METHOD_COLOURS) == set(METHODS)
    assert len(set(METHOD_COLOURS.values())) == len(METHODS)


def test_formats_png_always_and_a_print_copy_on_request(tmp_path) -> None:
    from jointplay.report._mpl import pyplot

    plt = pyplot()
    for fmt, expected in (
        ("png", ["f.png"]),
        ("svg", ["f.png", "f.svg"]),
        ("pdf", ["f.png", "f.pdf"]),
    ):
        fig, ax = plt.subplots(figsize=(2, 1))
        ax.plot([0, 1], [0, 1])
        written = save(fig, tmp_path / "f.png", fmt)
        assert [p.name for p in written] == expected
        assert all(p.stat().st_size > 0 for p in written)
    with pytest.raises(ConfigError, match="png, svg, pdf"):
        check_format("bmp")


def test_a_saved_png_keeps_its_look_in_a_palette_a_third_of_the_size(tmp_path) -> None:
    """The palette PNG against matplotlib's own RGBA file of the same figure: smaller by at
    least half, and no pixel's colour off by more than 16 of 255 per channel, 1 on average
    (the 256-colour max-coverage palette moves only the antialiased edge pixels, by up to
    16 here; median cut moved them by up to 48)."""
    from PIL import Image

    from jointplay.report._mpl import pyplot

    plt = pyplot()

    def figure():
        fig, ax = plt.subplots(figsize=(8, 5), dpi=100)
        x = np.linspace(0.0, 360.0, 2000)
        for k, colour in enumerate(METHOD_COLOURS.values()):
            ax.plot(x, np.sin(np.radians(x) * (k + 1)), color=colour, linewidth=1.2)
        ax.set_title("six colours, antialiased")
        return fig

    raw = tmp_path / "raw.png"
    fig = figure()
    fig.savefig(raw, dpi=100)
    plt.close(fig)
    compact = save(figure(), tmp_path / "compact.png")[0]
    with Image.open(compact) as image:
        assert image.mode == "P"
        palette = np.asarray(image.convert("RGB"), dtype=int)
    with Image.open(raw) as image:
        original = np.asarray(image.convert("RGB"), dtype=int)
    assert compact.stat().st_size < 0.5 * raw.stat().st_size
    difference = np.abs(palette - original)
    assert difference.max() <= 16 and difference.mean() < 1.0


@pytest.mark.parametrize(
    ("value", "label"),
    [
        (0.0, "0"),
        (-3000.0, "-3,000"),
        (0.25, "0.25"),
        (2.5e8, "2.5×10⁸"),
        (-6e4, "-60,000"),
        (1e-4, "1×10⁻⁴"),
    ],
)
def test_tick_labels_carry_their_magnitude(value: float, label: str) -> None:
    assert tick_label(value) == label


def test_encode_gives_the_png_and_the_print_copy_by_file_name() -> None:
    from jointplay.report._mpl import pyplot
    from jointplay.report.figures import encode

    fig = pyplot().figure()
    files = encode(fig, "demo", "pdf")
    assert list(files) == ["demo.png", "demo.pdf"]
    assert files["demo.png"].startswith(b"\x89PNG") and files["demo.pdf"].startswith(b"%PDF")
    with pytest.raises(ConfigError, match="png, svg, pdf"):
        encode(pyplot().figure(), "demo", "jpg")


def test_overlapping_text_finds_labels_that_collide_and_only_those() -> None:
    from jointplay.report._mpl import pyplot
    from jointplay.report.figures import overlapping_text

    plt = pyplot()
    fig, ax = plt.subplots(figsize=(4, 3))
    ax.plot([0, 1], [0, 1])
    ax.set_xlabel("crank angle (deg)")
    assert overlapping_text(fig) == []
    ax.annotate("an annotation on the tick labels", (0.5, 0.0), xycoords="data",
                xytext=(0.0, -0.04), textcoords="axes fraction")  # fmt: skip
    found = overlapping_text(fig)
    assert found and all("an annotation on the tick labels" in pair for pair in found)
    plt.close(fig)


def test_a_saved_png_is_made_from_the_drawing_without_matplotlibs_png(
    tmp_path, monkeypatch
) -> None:
    """save() quantizes the figure's drawn pixels (no matplotlib PNG compressed and read back,
    ~70 ms a figure of every simulate): the same image, pixel for pixel and in the same
    palette, as matplotlib's PNG put through compact_png, at 100 and 150 dpi."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from PIL import Image

    from jointplay.report._mpl import pyplot
    from jointplay.report.figures import compact_png

    plt = pyplot()

    def figure():
        fig, axes = plt.subplots(2, 1, figsize=(6.4, 4.8))
        x = np.linspace(0.0, 360.0, 2000)
        for k, colour in enumerate(METHOD_COLOURS.values()):
            axes[k % 2].plot(x, np.sin(np.radians(x) * (k + 1)), color=colour, linewidth=1.2)
        axes[0].set_title("six colours, antialiased, two panels")
        fig.tight_layout()
        return fig

    encoded: list[int] = []
    for dpi in (100, 150):
        reference = tmp_path / f"reference{dpi}.png"
        fig = figure()
        fig.savefig(reference, dpi=dpi)
        plt.close(fig)
        compact_png(reference)
        with monkeypatch.context() as patched:
            patched.setattr(
                FigureCanvasAgg, "print_png", lambda *a, **k: encoded.append(1), raising=True
            )
            mine = save(figure(), tmp_path / f"mine{dpi}.png", dpi=dpi)[0]
        assert not encoded  # matplotlib's PNG was never written
        with Image.open(mine) as image, Image.open(reference) as expected:
            assert image.mode == expected.mode == "P"
            assert image.size == expected.size
            assert image.getpalette() == expected.getpalette()
            assert image.tobytes() == expected.tobytes()
