"""``jointplay paper``: the README's main job on the paper's mechanism."""

from __future__ import annotations

import typer

from jointplay.cli._app import app
from jointplay.cli._common import OutOption, RpmOption, mechanism_from_options, provenance
from jointplay.io.output import output_dir, write_json


@app.command("paper")
def paper_command(out: OutOption, rpm: RpmOption = None) -> None:
    """Analyse the paper's crank-rocker (Akhadkar et al.) and write results and plots to OUT."""
    from jointplay.report.plots import kinematics_plots
    from jointplay.study.nominal import nominal_analysis

    mechanism = mechanism_from_options("paper-fourbar", None, rpm)
    result = nominal_analysis(mechanism)
    with output_dir(out) as folder:
        result.table.to_csv(folder / "kinematics.csv", index=False, float_format="%.10g")
        write_json(
            folder / "summary.json",
            {**result.summary, "provenance": provenance(result.summary["configuration"])},
        )
        kinematics_plots(result.table, folder, mechanism.name)
    typer.echo(f"nominal analysis of {mechanism.name} written to {out}")
