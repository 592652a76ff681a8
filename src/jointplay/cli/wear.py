"""``jointplay wear``: joint wear over the life, coupled to the dynamics.

Import-light: NumPy and the dynamics load when the command runs.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer
from rich.console import Console

from jointplay.cli._app import app
from jointplay.cli._common import (
    ConfigOption,
    FigureFormatOption,
    ForceOption,
    GravityOption,
    HardnessOption,
    OutOption,
    PresetOption,
    RpmOption,
    SettleOption,
    WearCoefficientOption,
    check_figure_format,
    compiling_kernels,
    provenance,
)
from jointplay.cli._simulation import (
    NO_CONTACT_OPTIONS,
    ContactValues,
    with_contact_options,
)
from jointplay.errors import ConfigError
from jointplay.settings.mechanism import mechanism_from_options, quantity_option
from jointplay.settings.simulation import contact_from_options

console = Console(highlight=False, soft_wrap=True)


@app.command("wear")
@with_contact_options()
def wear_command(
    out: OutOption,
    hours: Annotated[
        str, typer.Option("--hours", help="Operating time to simulate, e.g. '600 h'.")
    ],
    clearance_limit: Annotated[
        str,
        typer.Option(
            "--clearance-limit",
            help="Radial clearance that ends a joint's life: '80 um', or '+20 um' = the fit's "
            "largest radial clearance plus 20 µm.",
        ),
    ],
    preset: PresetOption = None,
    config: ConfigOption = None,
    update_hours: Annotated[
        str | None,
        typer.Option(
            "--update-hours",
            help="Operating time between re-simulations, e.g. '50 h' (default: --hours / 10).",
        ),
    ] = None,
    fit: Annotated[
        str | None,
        typer.Option("--fit", help="Give every pin joint this ISO 286 fit at its mean clearance."),
    ] = None,
    table: Annotated[
        Path | None,
        typer.Option(
            "--table",
            help="TOML file with a [wear] table (coefficient, hardness, joints.<J>); the same "
            "table may sit in the --config file, and this one replaces it.",
        ),
    ] = None,
    wear_coefficient: WearCoefficientOption = None,
    hardness: HardnessOption = None,
    settle: SettleOption = 2,
    rpm: RpmOption = None,
    gravity: GravityOption = None,
    contact_options: ContactValues = NO_CONTACT_OPTIONS,
    plots: Annotated[bool, typer.Option("--plots/--no-plots", help="Write PNG plots.")] = True,
    force: ForceOption = False,
    figure_format: FigureFormatOption = "png",
) -> None:
    """Wear life: Archard wear of every clearance joint over the steady cycle, re-simulated at
    the worn clearance every --update-hours; the clearance, peak force and rocker-speed error
    over the life, the worn profile of each bearing, and the hours until the limit.

    Writes DIR/wear.csv, DIR/profiles.csv, DIR/summary.json, PNG plots and DIR/report.html.
    """
    from jointplay.cli.design import parse_clearance_limit, read_table, wear_settings
    from jointplay.dynamics.wear import wear_life
    from jointplay.io.output import output_dir
    from jointplay.report.design import write_wear
    from jointplay.tolerance import iso286

    figure_format = check_figure_format(figure_format)
    mechanism = mechanism_from_options(preset, config, rpm=rpm, gravity=gravity)
    life_hours = quantity_option(hours, "s", "--hours", example="h", positive=True) / 3600.0
    step = (
        life_hours / 10.0
        if update_hours is None
        else quantity_option(update_hours, "s", "--update-hours", example="h", positive=True)
        / 3600.0
    )
    limit, allowance = parse_clearance_limit(clearance_limit)
    settings = wear_settings(read_table(table, config), wear_coefficient, hardness)
    contact_used = contact_from_options(config, mechanism, preset=preset, **contact_options)
    joints = []
    limits: dict[str, float] = {}
    for joint in mechanism.revolute_joints:
        if joint.fit is None:
            continue
        designation = fit or joint.fit.fit
        if fit is not None or joint.fit.clearance is None:
            if designation is None:
                continue
            clearance = iso286.fit(designation, joint.fit.diameter).radial_clearance_mean
        else:
            clearance = joint.fit.clearance
        if allowance is not None:
            if designation is None:
                raise ConfigError(
                    f"joint {joint.name!r} has no fit: give --clearance-limit as a clearance"
                )
            limits[joint.name] = (
                iso286.fit(designation, joint.fit.diameter).radial_clearance_max + allowance
            )
        else:
            limits[joint.name] = float(limit)  # type: ignore[arg-type]
        joints.extend(contact_used.joints(mechanism, [joint.name], clearance=clearance))
    if not joints:
        raise ConfigError("no clearance joints: give joints a fit and a diameter, or --fit")
    from jointplay.dynamics.setup import regime_line

    lubrication = contact_used.joint_lubrication(mechanism, joints)
    with output_dir(
        out, force=force, inputs=(config, table)
    ) as folder:  # checked before the wear runs
        print(regime_line(contact_used, mechanism, [j.joint for j in joints]))
        with compiling_kernels():
            history = wear_life(
                mechanism,
                joints,
                hours=life_hours,
                update_hours=step,
                clearance_limit=limits,
                settings=settings,
                settle=settle,
                on_update=lambda done, total: console.print(
                    f"  {done:g} of {total:g} h", style="dim"
                ),
            )
        write_wear(
            history,
            folder,
            plots=plots,
            provenance=provenance(
                {**history.summary(), "contact": contact_used.describe(mechanism)}
            ),
            lubrication=lubrication,
            figure_format=figure_format,
        )
    for name, life in history.life.items():
        how = " (extrapolated)" if history.life_extrapolated[name] else ""
        why = history.no_wear(name)
        console.print(
            f"{name}: clearance {history.clearance[name][0] * 1e6:.1f} → "
            f"{history.clearance[name][-1] * 1e6:.1f} µm, limit {history.limit[name] * 1e6:.1f} "
            + (f"µm, no wear: {why}" if why else f"µm, life {life:,.1f} h{how}")
        )
    _print_regimes(history)
    if all(history.no_wear(name) for name in history.life):
        console.print(
            f"mechanism life: no joint wears over {life_hours:g} h (no contact force, above); "
            f"results written to {out}"
        )
    else:
        console.print(f"mechanism life: {history.mechanism_life:,.1f} h; results written to {out}")


def _print_regimes(history: object) -> None:
    """Each lubricated joint's regimes at the last re-simulation, one line each."""
    from jointplay.dynamics.regimes import regime_line

    regimes = getattr(history, "regimes", {})
    last = {name: runs[-1] for name, runs in regimes.items() if runs}
    if any(r is not None for r in last.values()):
        console.print("lubrication regimes at the last re-simulation:")
        for name, regime in last.items():
            console.print("  " + regime_line(name, regime), markup=False)
