"""Writing simulation results: time series (CSV or Parquet) and the stable summary.json."""

from __future__ import annotations

from pathlib import Path
from typing import Any, Literal

import pandas as pd

from jointplay.errors import SettingError
from jointplay.io.output import write_csv

TableFormat = Literal["csv", "parquet"]


def write_table(table: pd.DataFrame, folder: Path, stem: str, fmt: str) -> Path:
    """Write ``table`` as ``folder/stem.csv`` or ``.parquet``; returns the path."""
    if fmt == "csv":
        path = folder / f"{stem}.csv"
        write_csv(table, path)
    elif fmt == "parquet":
        path = folder / f"{stem}.parquet"
        table.to_parquet(path, index=False)
    else:
        raise SettingError("{format} must be csv or parquet, got {got!r}", got=fmt)
    return path


def simulation_summary(result: Any, provenance: dict[str, Any]) -> dict[str, Any]:
    """The stable summary.json: peaks, nominal_peaks, increase_percent, solver, provenance."""
    return {**result.summary(), "provenance": provenance}
