"""The output folder: all or nothing, never stale, never a temporary folder left behind."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from jointplay.errors import ConfigError
from jointplay.io.output import MARKER, output_dir


def _leftovers(parent: Path, keep: str) -> list[str]:
    return sorted(p.name for p in parent.iterdir() if p.name != keep)


def test_a_run_replaces_the_whole_folder(tmp_path: Path) -> None:
    target = tmp_path / "out"
    with output_dir(target) as folder:
        (folder / "timeseries.csv").write_text("old", encoding="utf-8")
        (folder / "plot.png").write_bytes(b"png")
    with output_dir(target) as folder:
        (folder / "summary.json").write_text("{}", encoding="utf-8")
    assert sorted(p.name for p in target.iterdir()) == [MARKER, "summary.json"]
    assert json.loads((target / MARKER).read_text(encoding="utf-8"))["written_by"] == "jointplay"
    assert _leftovers(tmp_path, "out") == []


def test_a_failed_run_leaves_the_previous_result(tmp_path: Path) -> None:
    target = tmp_path / "out"
    with output_dir(target) as folder:
        (folder / "summary.json").write_text("first", encoding="utf-8")
    with pytest.raises(RuntimeError), output_dir(target) as folder:
        (folder / "summary.json").write_text("second", encoding="utf-8")
        raise RuntimeError("boom")
    assert (target / "summary.json").read_text(encoding="utf-8") == "first"
    assert _leftovers(tmp_path, "out") == []


def test_an_interrupted_run_leaves_nothing(tmp_path: Path) -> None:
    target = tmp_path / "out"
    with pytest.raises(KeyboardInterrupt), output_dir(target) as folder:
        (folder / "half.csv").write_text("1,2", encoding="utf-8")
        raise KeyboardInterrupt
    assert not target.exists()
    assert _leftovers(tmp_path, "out") == []


def test_the_staging_folder_exists_before_the_work(tmp_path: Path) -> None:
    with output_dir(tmp_path / "out") as folder:
        assert folder.is_dir() and folder.parent == tmp_path


def test_foreign_folders_are_refused_unless_forced(tmp_path: Path) -> None:
    target = tmp_path / "out"
    target.mkdir()
    (target / "notes.txt").write_text("mine", encoding="utf-8")
    with pytest.raises(ConfigError, match="--force"), output_dir(target):
        pass
    assert (target / "notes.txt").exists()
    with output_dir(target, force=True) as folder:
        (folder / "a.txt").write_text("a", encoding="utf-8")
    assert sorted(p.name for p in target.iterdir()) == [MARKER, "a.txt"]


def test_an_empty_existing_folder_is_fine(tmp_path: Path) -> None:
    target = tmp_path / "out"
    target.mkdir()
    with output_dir(target) as folder:
        (folder / "a.txt").write_text("a", encoding="utf-8")
    assert (target / "a.txt").exists()


@pytest.mark.parametrize("name", ["", "."])
def test_the_current_folder_is_refused(name: str) -> None:
    with pytest.raises(ConfigError, match="--out"), output_dir(name):
        pass


def test_a_failed_rename_restores_the_previous_result(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    target = tmp_path / "out"
    with output_dir(target) as folder:
        (folder / "summary.json").write_text("first", encoding="utf-8")
    real_rename = Path.rename

    def failing(self: Path, destination: Path) -> Path:
        if self.name.startswith(".out.partial-"):
            raise OSError(28, "No space left on device")
        return real_rename(self, destination)

    monkeypatch.setattr(Path, "rename", failing)
    with pytest.raises(OSError), output_dir(target) as folder:
        (folder / "summary.json").write_text("second", encoding="utf-8")
    monkeypatch.undo()
    assert (target / "summary.json").read_text(encoding="utf-8") == "first"
    assert _leftovers(tmp_path, "out") == []


# --- JSON numbers: rounded to what they mean --------------------------------------------------


def test_json_numbers_are_rounded_to_twelve_significant_digits() -> None:
    """Round-off of unit conversions disappears; every meaningful digit stays."""
    import math

    import numpy as np

    from jointplay.io.output import JSON_DIGITS, json_text, jsonable, round_significant
    from jointplay.units import parse_quantity

    rpm = parse_quantity("200 rpm", "rad/s", field="x") * 30 / math.pi
    assert rpm == 199.99999999999997  # the noise the sanitiser removes
    assert jsonable(math.degrees(math.radians(30))) == 30.0
    assert JSON_DIGITS == 12
    assert jsonable({"rpm": rpm, "sum": 0.1 + 0.2}) == {"rpm": 200.0, "sum": 0.3}
    assert '"rpm": 200.0' in json_text({"rpm": np.float64(rpm)})
    third = jsonable(1.0 / 3.0)
    assert third == 0.333333333333 and abs(third - 1.0 / 3.0) < 5e-13
    for exact in (0.1, 21e-6, 1.5e-300, -2.5e12, 12345678901.5, 0.0):
        assert jsonable(exact) == exact  # 12 digits or fewer: unchanged
    assert jsonable(7) == 7 and jsonable(True) is True  # integers and booleans as they are
    assert jsonable(math.nan) is None and jsonable(-math.inf) is None
    rng = np.random.default_rng(0)
    values = rng.normal(size=1000) * 10.0 ** rng.integers(-300, 300, size=1000)
    once = [round_significant(float(v)) for v in values]
    assert once == [round_significant(v) for v in once]  # idempotent
    assert all(
        abs(a - float(v)) <= 5e-12 * abs(float(v)) for a, v in zip(once, values, strict=True)
    )
