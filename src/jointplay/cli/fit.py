"""Commands about standard tolerances: ISO 286 fits (``fit``) and ISO 2768-1 (``general-tolerance``)."""

from __future__ import annotations

import json
from enum import StrEnum
from typing import Annotated, Any

import typer
from rich.console import Console
from rich.table import Table

from jointplay.cli._app import app
from jointplay.cli._common import whole_headers
from jointplay.errors import ConfigError
from jointplay.tolerance import iso286, iso2768
from jointplay.units import parse_quantity

console = Console(highlight=False, soft_wrap=True)

SizeOption = Annotated[
    str,
    typer.Option(
        "--size",
        help="Nominal size with a unit, e.g. '10mm', '10 mm' or '0.01 m' (a bare number is refused).",
        show_default=False,
    ),
]
JsonOption = Annotated[
    bool, typer.Option("--json", help="Print the result as JSON instead of a table.")
]


class Feature(StrEnum):
    """The three tables of ISO 2768-1."""

    linear = "linear"
    broken_edge = "broken-edge"
    angular = "angular"


@app.command("fit")
def fit_command(
    designation: Annotated[
        str,
        typer.Argument(
            help="A fit 'hole/shaft' such as 'H8/g7' or 'H7 / k6', or one tolerance class such as "
            "'K7' (hole: upper case) or 'g6' (shaft: lower case).",
            show_default=False,
        ),
    ],
    size: SizeOption,
    as_json: JsonOption = False,
) -> None:
    """ISO 286-1/-2 limit deviations of a tolerance class or a fit at a nominal size.

    A fit (H8/g7): hole and shaft limits in µm and mm, fit type, min/max/mean clearance.

    Clearances are given diametral and radial; a negative clearance is an interference.

    One class (K7, g6): its upper and lower limit deviations.
    """
    size_m = _size(size)
    if "/" in designation:
        result = iso286.fit(designation, size_m)
        if as_json:
            _print_json(result.as_dict_um())
        else:
            _print_fit(result)
    else:
        tolerance = iso286.tolerance_class(designation, size_m)
        if as_json:
            _print_json(iso286.class_as_dict_um(tolerance))
        else:
            _print_class(tolerance)


@app.command("general-tolerance")
def general_tolerance_command(
    tolerance_class: Annotated[
        str,
        typer.Argument(
            help="ISO 2768-1 class: f (fine), m (medium), c (coarse) or v (very coarse).",
            show_default=False,
        ),
    ],
    size: SizeOption,
    feature: Annotated[
        Feature,
        typer.Option(
            "--feature",
            help="Which table: linear (dimensions, Table 1), broken-edge (external radii and "
            "chamfer heights, Table 2) or angular (keyed by the shorter side, Table 3).",
        ),
    ] = Feature.linear,
    as_json: JsonOption = False,
) -> None:
    """ISO 2768-1 general tolerance (± deviation) of a dimension drawn without a tolerance.

    --size is the nominal size; with --feature angular, the length of the shorter side.
    """
    size_m = _size(size)
    if feature is Feature.angular:
        result = iso2768.angular_tolerance(tolerance_class, size_m)
    elif feature is Feature.broken_edge:
        result = iso2768.broken_edge_tolerance(tolerance_class, size_m)
    else:
        result = iso2768.linear_tolerance(tolerance_class, size_m)
    if as_json:
        data: dict[str, Any] = {"class": result.tolerance_class}
        if feature is not Feature.linear:
            data["feature"] = feature.value
        data["size_mm"] = result.nominal_size_mm
        if feature is Feature.angular:
            data["deviation_deg"] = result.deviation_deg
        else:
            data["deviation_mm"] = result.deviation_mm
        _print_json(data)
        return
    what = {"linear": "linear size", "broken edge": "broken edge", "angular": "angle, shorter side"}
    console.print(
        f"ISO 2768-1 class {result.tolerance_class} ({result.class_name}), "
        f"{what[result.feature]} {_plain(result.nominal_size_mm)} mm ({result.size_range}): "
        f"{result.text}"
    )


def _size(text: str) -> float:
    """``--size`` in metres: positive, and not below the tables' 1e-9 mm resolution."""
    size_m = parse_quantity(text, "m", field="--size")
    if not round(size_m * 1e3, 9) > 0:
        raise ConfigError(
            f"--size must be a positive size of at least 1e-9 mm, got {text!r} "
            f"(= {size_m * 1e3:.3g} mm)"
        )
    return size_m


def _print_json(data: dict[str, Any]) -> None:
    print(json.dumps(data, indent=2, ensure_ascii=False))


def _um(value: float) -> str:
    """µm with sign, no trailing zeros: +22, -6.5, 0."""
    return "0" if value == 0 else f"{value:+g}"


def _mm(value_um: float) -> str:
    """A deviation given in µm written in mm: +0.022, -0.0065, 0."""
    if value_um == 0:
        return "0"
    return f"{value_um / 1e3:+.6f}".rstrip("0").rstrip(".")


def _plain(value: float) -> str:
    """A number with up to 6 decimals and no trailing zeros: 270.5, 10, 119.975."""
    return f"{value:.6f}".rstrip("0").rstrip(".")


def _size_text(size_m: float) -> str:
    over, up_to = iso286.size_range_mm(size_m)
    size = _plain(size_m * 1e3)
    if over == 0.0:
        return f"{size} mm (size range up to and including {up_to:g} mm)"
    return f"{size} mm (size range over {over:g} up to and including {up_to:g} mm)"


def _limits_table(classes: list[iso286.ToleranceClass]) -> Table:
    table = Table(box=None, pad_edge=False)
    for header in ("", "class", "upper µm", "lower µm", "upper mm", "lower mm"):
        table.add_column(header, justify="left" if header in ("", "class") else "right")
    for tolerance in classes:
        table.add_row(
            tolerance.kind,
            tolerance.designation,
            _um(tolerance.upper_um),
            _um(tolerance.lower_um),
            _mm(tolerance.upper_um),
            _mm(tolerance.lower_um),
        )
    return table


def _print_fit(result: iso286.Fit) -> None:
    console.print(f"ISO 286 fit {result.designation} at {_size_text(result.nominal_size)}")
    console.print(whole_headers(_limits_table([result.hole, result.shaft])))
    console.print(f"fit type: {result.fit_type}")
    table = Table(box=None, pad_edge=False)
    for header in ("clearance", "min µm", "max µm", "mean µm"):
        table.add_column(header, justify="left" if header == "clearance" else "right")
    low, high, mean = result.clearance_min_um, result.clearance_max_um, result.clearance_mean_um
    table.add_row("diametral", _um(low), _um(high), _um(mean))
    table.add_row("radial", _um(low / 2), _um(high / 2), _um(mean / 2))
    console.print(whole_headers(table))
    console.print("(negative clearance = interference)")


def _print_class(tolerance: iso286.ToleranceClass) -> None:
    console.print(
        f"ISO 286 tolerance class {tolerance.designation} ({tolerance.kind}) at "
        f"{_size_text(tolerance.nominal_size)}"
    )
    console.print(whole_headers(_limits_table([tolerance])))
    nominal_mm = tolerance.nominal_size * 1e3
    low = _plain(nominal_mm + tolerance.lower_um / 1e3)
    high = _plain(nominal_mm + tolerance.upper_um / 1e3)
    console.print(f"limits of size: {low} … {high} mm")
