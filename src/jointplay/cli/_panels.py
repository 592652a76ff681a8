"""The help panels of the command line: every command groups its options under the same
titles, in one order (:data:`PANEL_ORDER`), and an option without a declared panel goes to
the one of its name (:func:`option_panel`). Names only: the option declarations
(:mod:`jointplay.cli._common`, :mod:`jointplay.cli._simulation`, the commands) and the help's
renderer (:mod:`jointplay.cli._app`) read them."""

from __future__ import annotations

from typing import Any

from jointplay.dynamics.declared import CONTACT_PANEL, CONTACT_SETTINGS, RUN_PANEL, RUN_SETTINGS

#: Help panels: every command groups its options under the same titles, in this order
#: (Typer's "Options" first: what is studied, the mechanism and its speed).
REQUIREMENTS_PANEL = "Requirements"
SAMPLING_PANEL = "Sampling"
#: CONTACT_PANEL ("Contact") and RUN_PANEL ("The dynamic run"): the settings' declarations
#: name them (:mod:`jointplay.dynamics.declared`).
WEAR_PANEL = "Wear and cost"
MEASUREMENTS_PANEL = "Measurements file"
EXECUTION_PANEL = "Execution"
OUTPUT_PANEL = "Output"
PANEL_ORDER = (
    "Options",
    REQUIREMENTS_PANEL,
    SAMPLING_PANEL,
    CONTACT_PANEL,
    RUN_PANEL,
    WEAR_PANEL,
    MEASUREMENTS_PANEL,
    EXECUTION_PANEL,
    OUTPUT_PANEL,
)
#: The panel of an option by its name, on every command whose declaration names none (one
#: grammar across commands: ``--settle`` is under "The dynamic run" wherever it appears).
#: The contact and run options come from their declarations
#: (:mod:`jointplay.dynamics.declared`); ``--method`` is not here: it names a contact method on the simulating commands (declared
#: in the Contact panel) and a tolerance method on ``tolerance``.
# fmt: off
OPTION_PANELS = {
    **dict.fromkeys(("--require", "--spec-limit", "--confidence"), REQUIREMENTS_PANEL),
    **dict.fromkeys(
        ("--samples", "--max-samples", "--seed", "--sampling", "--distribution", "--cpk",
         "--truncate", "--rare-defects", "--clearances", "--corners", "--fd-step"),
        SAMPLING_PANEL),
    **dict.fromkeys(
        (*(s.option for s in CONTACT_SETTINGS if s.offered and s.key != "method"),
         "--paper-method", "--clearance", "--joints", "--model-sensitivity"),
        CONTACT_PANEL),
    **dict.fromkeys(
        (*(s.option for s in RUN_SETTINGS), "--output-step", "--sample-deg",
         "--experiment-revolutions"),
        RUN_PANEL),
    **dict.fromkeys(
        ("--clearance-limit", "--table", "--wear-coefficient", "--hardness", "--hours",
         "--update-hours"),
        WEAR_PANEL),
    **dict.fromkeys(
        ("--measurements", "--column", "--quantity", "--unit", "--angle-column",
         "--speed-column", "--angle-direction", "--angle-origin", "--crank-direction",
         "--speed-positive"),
        MEASUREMENTS_PANEL),
    **dict.fromkeys(("--backend", "--workers", "--dask-scheduler"), EXECUTION_PANEL),
    **dict.fromkeys(
        ("--out", "--plots", "--progress", "--force", "--figure-format", "--json", "--format",
         "--animation"),
        OUTPUT_PANEL),
}
# fmt: on


def option_panel(param: Any) -> str:
    """The help panel of ``param`` (a Click parameter): its declared one, else the one of
    :data:`OPTION_PANELS` for its long name, else Typer's "Options"."""
    declared = getattr(param, "rich_help_panel", None)
    if declared:
        return str(declared)
    names = [*getattr(param, "opts", ()), *getattr(param, "secondary_opts", ())]
    return next((OPTION_PANELS[n] for n in names if n in OPTION_PANELS), "Options")
