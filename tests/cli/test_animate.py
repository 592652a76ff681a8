"""``jointplay animate``: the file it writes, what it prints, and bad input (exit 2)."""

from __future__ import annotations

import pytest
from PIL import Image

from jointplay.cli import run

#: A cheap run: no start-up revolution, a few frames (each call about a second).
QUICK = ["animate", "--settle", "0", "--frames", "6"]


def test_writes_a_gif_with_the_frames_asked_for(tmp_path, capsys) -> None:
    out = tmp_path / "fourbar.gif"
    assert run([*QUICK, "--preset", "paper-fourbar", "--fps", "12", "--out", str(out)]) == 0
    with Image.open(out) as image:
        assert image.format == "GIF" and image.n_frames == 6
        assert image.info["duration"] == 80  # ms: GIF times are whole hundredths of a second
    printed = capsys.readouterr().out
    # the default magnification of the paper's 21 µm clearance and 108 mm crank
    assert f"wrote {out}: 6 frames at 12 fps" in printed and "x 500" in printed
    assert "revolution 1 of paper-fourbar" in printed
    assert "O2" in printed and "(21 µm)" in printed
    assert [p.name for p in tmp_path.iterdir()] == ["fourbar.gif"]  # no partial file left


@pytest.mark.parametrize(
    ("size", "pixels"),
    [(None, (960, 640)), ("1280x720", (1280, 720)), ("1200", (1200, 800)), ("640X480", (640, 480))],
)
def test_the_gif_is_960_px_wide_by_default_and_sized_by_size(tmp_path, size, pixels) -> None:
    """At the old 480 x 320 the paper four-bar's x500 clearance circles were about 10 px
    across; the default is 960 x 640 now, and --size asks for another (a width alone keeps
    the 3:2 aspect)."""
    out = tmp_path / "a.gif"
    extra = [] if size is None else ["--size", size]
    assert run([*QUICK, "--preset", "paper-fourbar", *extra, "--out", str(out)]) == 0
    with Image.open(out) as image:
        assert image.size == pixels


def test_slider_crank_with_ideal_joints_and_a_stated_factor(tmp_path, capsys) -> None:
    out = tmp_path / "slider.gif"
    args = [*QUICK, "--preset", "flores-slider-crank", "--joints", "none", "--out", str(out)]
    assert run(args) == 0
    assert "ideal joints" in capsys.readouterr().out
    out2 = tmp_path / "slider-play.gif"
    assert run([*QUICK, "--preset", "flores-slider-crank", "--magnification", "20",
                "--out", str(out2)]) == 0  # fmt: skip
    assert "x 20," in capsys.readouterr().out
    with Image.open(out2) as image:
        assert image.n_frames == 6


def test_an_existing_file_needs_force(tmp_path, capsys) -> None:
    out = tmp_path / "a.gif"
    out.write_bytes(b"mine")
    assert run([*QUICK, "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert "exists" in err and "--force" in err and err.count("\n") == 1
    assert out.read_bytes() == b"mine"
    assert run([*QUICK, "--force", "--out", str(out)]) == 0
    with Image.open(out) as image:
        assert image.n_frames == 6


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--out", "{tmp}/a.avi"], "must end in .gif or .mp4"),
        (["--out", "{tmp}"], "is a folder"),
        (["--out", "{tmp}/a.gif", "--magnification", "-5"], "--magnification"),
        (["--out", "{tmp}/a.gif", "--magnification", "0"], "--magnification"),
        (["--out", "{tmp}/a.gif", "--frames", "1"], "--frames"),
        (["--out", "{tmp}/a.gif", "--fps", "0"], "--fps"),
        (["--out", "{tmp}/a.gif", "--fps", "60"], "between 1 and 50"),
        (["--out", "{tmp}/a.gif", "--joints", "O2,Q"], "no revolute joint 'Q'"),
        (["--out", "{tmp}/a.gif", "--start", "sideways"], "start mode"),
        (["--out", "{tmp}/a.gif", "--settle", "-1"], "--settle"),
        (["--out", "{tmp}/a.gif", "--clearance", "-0.01 mm"], "must be positive"),
        (["--out", "{tmp}/a.gif", "--size", "1280x"], "--size"),
        (["--out", "{tmp}/a.gif", "--size", "big"], "WIDTHxHEIGHT"),
        (["--out", "{tmp}/a.gif", "--size", "100x100"], "from 160 to 4000"),
        (["--out", "{tmp}/a.gif", "--size", "99999"], "from 160 to 4000"),
        (["--out", "{tmp}/a.gif", "--size", "1280x720x3"], "--size"),
    ],
)
def test_bad_input(tmp_path, capsys, args, message) -> None:
    folder = tmp_path / "out"
    folder.mkdir()
    argv = ["animate", *(a.replace("{tmp}", str(folder)) for a in args)]
    assert run(argv) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1 and "Traceback" not in err
    assert list(folder.iterdir()) == []  # nothing written, no partial file left


def test_mp4_without_ffmpeg_says_what_to_do(tmp_path, capsys, monkeypatch) -> None:
    from matplotlib import animation

    monkeypatch.setattr(animation.writers, "is_available", lambda name: False)
    out = tmp_path / "a.mp4"
    assert run([*QUICK, "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert "install" in err and "ffmpeg" in err and ".gif" in err
    assert not out.exists()
