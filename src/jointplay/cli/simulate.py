"""``jointplay simulate``: forward dynamics with clearance joints."""

from __future__ import annotations

import math
import sys
from pathlib import Path
from typing import Annotated, Any

import typer
from rich.console import Console
from rich.table import Table

from jointplay._kernels import single_engine
from jointplay.cli._app import app
from jointplay.cli._common import (
    ConfigOption,
    DirectionOption,
    FigureFormatOption,
    ForceOption,
    GravityOption,
    OutOption,
    PresetOption,
    ProgressOption,
    RpmOption,
    StartAngleOption,
    check_figure_format,
    compiling_kernels,
    provenance,
    status,
    whole_headers,
)
from jointplay.cli._simulation import (
    NO_CONTACT_OPTIONS,
    SETTING_OPTIONS,
    AtolOption,
    ClearanceOption,
    ContactValues,
    IntegratorOption,
    JointsOption,
    MaxStepOption,
    OnsetToleranceOption,
    RampTimeOption,
    RtolOption,
    StartOption,
    run_settings_of,
    with_contact_options,
)
from jointplay.errors import ConfigError
from jointplay.settings.mechanism import mechanism_from_options, quantity_option
from jointplay.settings.simulation import (
    check_revolutions,
    contact_model,
    finite_number,
    joint_list,
    over_table,
    solver_tolerances,
)
from jointplay.units import parse_quantity

console = Console(stderr=True)


def _opt(help_text: str, *names: str) -> Any:
    return typer.Option(*names, help=help_text)


@app.command("simulate")
@with_contact_options()
def simulate_command(
    out: OutOption,
    force: ForceOption = False,
    progress: ProgressOption = True,
    preset: PresetOption = None,
    config: ConfigOption = None,
    rpm: RpmOption = None,
    direction: DirectionOption = None,
    start_angle: StartAngleOption = None,
    gravity: GravityOption = None,
    contact_options: ContactValues = NO_CONTACT_OPTIONS,
    clearance: ClearanceOption = None,
    joints: JointsOption = None,
    start: StartOption = None,
    ramp_time: RampTimeOption = None,
    revolutions: Annotated[
        float | None,
        _opt(
            "Analysed time in crank periods, after the --settle revolutions (default 1).",
            "--revolutions",
        ),
    ] = None,
    settle: Annotated[
        int | None,
        _opt(
            "Start-up revolutions simulated first and left out of peaks and statistics (default: 2 with the steady start; 0 with rest, impulsive and ramp, whose start-up is what they show).",
            "--settle",
        ),
    ] = None,
    sample_deg: Annotated[
        str | None,
        _opt(
            "Also report peaks of the solution sampled every so much crank angle, with a unit, "
            "e.g. '5 deg' (labelled as sampled).",
            "--sample-deg",
        ),
    ] = None,
    output_step: Annotated[
        str | None,
        _opt(
            "Sampling interval of timeseries, e.g. '0.1 ms' (default: 0.5° of crank).",
            "--output-step",
        ),
    ] = None,
    rtol: RtolOption = None,
    integrator: IntegratorOption = None,
    max_step: MaxStepOption = None,
    atol: AtolOption = None,
    onset_tolerance: OnsetToleranceOption = None,
    fmt: Annotated[
        str | None, _opt("Time-series format: csv (default) or parquet.", "--format")
    ] = None,
    ensemble: Annotated[
        int | None,
        _opt(
            "Also run this many runs (>= 5), each started 0.01° of crank further on, and report "
            "the per-revolution peak distributions over them (runs as batches): the statistics "
            "of irregular (chaotic) running that converge (docs/performance.md).",
            "--ensemble",
        ),
    ] = None,
    plots: Annotated[bool, typer.Option("--plots/--no-plots", help="Write PNG plots.")] = True,
    figure_format: FigureFormatOption = "png",
) -> None:
    """Simulate the mechanism with radial clearance in its revolute joints.

    Writes DIR/timeseries.csv (or .parquet), DIR/steps.* (every integrator step),
    DIR/summary.json (peaks located on the continuous solution, nominal peaks, % increase,
    per-revolution statistics, periodicity, diagnostics, solver statistics, provenance) and
    PNG plots. Options override the [simulation] table of a --config file.
    """
    # The options and the configuration are read and checked first, with the standard
    # library, NumPy and (for a unit outside the common ones) pint: a mistyped option is one
    # error line before SciPy, pandas and Numba are loaded (docs/cli.md, "Start-up").
    from jointplay.io.config import simulation_settings
    from jointplay.io.output import output_dir

    figure_format = check_figure_format(figure_format)
    with output_dir(out, force=force, inputs=(config,)) as folder:
        table = simulation_settings(config, preset)
        given = {
            **contact_options, "clearance": clearance, "joints": joints, "start": start,
            "ramp_time": ramp_time, "start_angle": start_angle, "revolutions": revolutions,
            "settle": settle, "sample_deg": sample_deg, "output_step": output_step, "rtol": rtol,
            "integrator": integrator, "max_step": max_step, "format": fmt, "atol": atol,
            "onset_tolerance": onset_tolerance,
        }  # fmt: skip
        values = over_table(table, given)
        mechanism = mechanism_from_options(
            preset, config, rpm, direction, values.get("start_angle"), gravity
        )
        clearance_value = _quantity(values, "clearance", "m")
        step = _quantity(values, "output_step", "s")
        _quantity(values, "ramp_time", "s")  # read again by run_settings_of
        _quantity(values, "max_step", "s")
        solver_tolerances(values)  # --atol, --onset-tolerance: read again by run_settings_of
        fmt_value = str(values.get("format", "csv"))
        if fmt_value not in ("csv", "parquet"):
            raise ConfigError(f"--format must be csv or parquet, got {fmt_value!r}")
        turns = finite_number(values, "revolutions", 1.0)
        check_revolutions(turns)
        sample = _sample_step(values.get("sample_deg"))
        _check_ensemble(ensemble, turns)
        # The numerical stack from here: the contact model, the run's settings, the engine.
        from jointplay.dynamics import diagnostics as dg
        from jointplay.dynamics.settings import simulate_run
        from jointplay.dynamics.simulate import check_outputs, preferred_integrator
        from jointplay.io.output import write_json
        from jointplay.io.results import simulation_summary, write_table
        from jointplay.model.summary import mechanism_summary

        contact_used = contact_model(values, mechanism)
        clear = contact_used.joints(
            mechanism, joint_list(values.get("joints")), clearance=clearance_value
        )
        from jointplay.dynamics.setup import regime_line

        print(regime_line(contact_used, mechanism, [c.joint for c in clear]))
        run = run_settings_of(values, mechanism, contact_used, revolutions=turns, max_step=True)
        settle_turns = run.settle
        check_outputs(mechanism, turns, settle_turns, step, sample)  # before compiling
        integrator = run.solver.integrator or preferred_integrator(
            contact_used.integrator, mechanism, clear
        )
        with (
            compiling_kernels(
                lambda line: console.print(line, markup=False, highlight=False),
                kernels=single_engine(integrator),
            ),
            status(
                progress,
                f"simulating {settle_turns + turns:g} revolution(s) of {mechanism.name} with clearance in {', '.join(c.joint for c in clear)}",
            ),
        ):
            result = simulate_run(
                mechanism,
                clear,
                run,
                output_step=step,
                sample_deg=sample,
                nominal=True,
            )
            running = result.running
        found_ensemble = None
        if ensemble is not None:
            from jointplay.dynamics.ensemble import simulate_ensemble

            with status(progress, f"simulating an ensemble of {ensemble} runs"):
                found_ensemble = simulate_ensemble(mechanism, clear, run, runs=ensemble)
        record = provenance(
            {
                "mechanism": mechanism_summary(mechanism),
                "simulation": _jsonable(values),
                "method": contact_used.record,
            }
        )
        findings = dg.simulation_findings(result.diagnostics, mechanism)
        write_table(result.timeseries, folder, "timeseries", fmt_value)
        write_table(result.steps, folder, "steps", fmt_value)
        summary = simulation_summary(result, record)
        summary["contact"] = contact_used.describe(mechanism)
        summary["lubrication"] = contact_used.joint_lubrication(mechanism, clear)
        summary["diagnostics"] = [finding.as_dict() for finding in findings]
        if found_ensemble is not None:
            summary["ensemble"] = found_ensemble.summary()
        write_json(folder / "summary.json", summary)
        if plots:
            from jointplay.report.plots import simulation_figures
            from jointplay.report.running import per_revolution_plot, poincare_plot

            simulation_figures(result, folder, mechanism.name, figure_format=figure_format)
            periodicity = running.periodicity
            if periodicity.verdict != "undetermined":  # >= 3 points: a section to read
                poincare_plot(
                    periodicity.points,
                    periodicity.coordinates,
                    [c.joint for c in clear],
                    periodicity.verdict,
                    folder / "poincare.png",
                    title=mechanism.name,
                    figure_format=figure_format,
                )
            if _revolutions_drawn(running.per_revolution) > 1:  # peaks to compare
                per_revolution_plot(
                    running.per_revolution,
                    1,
                    folder / "peaks_per_revolution.png",
                    title=mechanism.name,
                    figure_format=figure_format,
                )
    print(f"contact: {contact_used.describe(mechanism)['text']}")
    _print(result, findings, Path(out))
    if found_ensemble is not None:
        _print_ensemble(found_ensemble)
    _print_regimes(result)


def _revolutions_drawn(per_revolution: dict[str, list[float]]) -> int:
    """The simulated revolutions (start-up included) with a peak in ``per_revolution``
    (quantity -> peaks).

    The figures of the running behaviour are drawn when they have something to show
    (docs/cli.md, "Start-up time"): the peaks per revolution from 2 revolutions on (one
    peak each is the printed table), the Poincaré section from 3 points on (fewer: its
    verdict is "undetermined"). The default run (settle 2 + 1 analysed revolution) has 2
    points: its four panels, ~0.45 s of CPU (a quarter of its plotting), are not drawn."""
    return max((len(peaks) for peaks in per_revolution.values()), default=0)


def _check_ensemble(runs: int | None, turns: float) -> None:
    """``--ensemble``: a whole number of runs >= 5, each with a whole analysed revolution."""
    from jointplay.dynamics.irregular import MIN_RUNS

    if runs is None:
        return
    if runs < MIN_RUNS:
        raise ConfigError(f"--ensemble must be at least {MIN_RUNS} runs, got {runs}")
    if turns < 1:
        raise ConfigError(
            f"--ensemble needs at least 1 whole analysed revolution per run, got --revolutions "
            f"{turns:g}; give --revolutions 1 or more"
        )


def _print_ensemble(found: Any) -> None:
    """The ensemble's per-revolution peak distributions, one line per quantity."""
    from jointplay.dynamics.irregular import describe

    runs = len(found.per_run)
    stdout = Console(soft_wrap=True)
    stdout.print(
        f"ensemble of {runs} runs (start angles {found.start_offsets_deg[1]:g}° apart), "
        f"{found.revolutions} revolution(s) each; periodicity: "
        + ", ".join(f"{v} ×{found.verdicts.count(v)}" for v in dict.fromkeys(found.verdicts))
        + "; per-revolution peak distributions over the runs (95 % intervals, runs as batches):"
    )
    for name, distribution in found.distributions.items():
        stdout.print("  " + describe(name, distribution))


def _print_regimes(result: Any) -> None:
    """The lubricated joints' regimes over the analysed revolutions, one line each."""
    from jointplay.dynamics.regimes import regime_line

    regimes = result.film_regimes
    if any(r is not None for r in regimes.values()):
        print("lubrication regimes over the analysed revolutions:")
        for name, regime in regimes.items():
            print("  " + regime_line(name, regime))


#: Slider columns of a slider-crank's results and how the console table names them.
SLIDER_COLUMNS = {"slider_x": "slider_x", "slider_v": "slider_v", "slider_a": "slider_a"}


def _slider_rows(result: Any) -> list[tuple[str, ...]]:
    """Console rows of the slider (slider-crank only): its peaks over the analysed
    revolutions, found among the integrator's accepted steps (marked ``*``).

    ``slider_x`` is the position (m from the crank pivot along the slider axis), so its row
    gives the stroke: the per-revolution range of the position, nominal beside it.
    """
    steps, nominal = result.steps, result.nominal
    if "slider_x" not in steps.columns:
        return []
    running = result.running
    t = steps["t"].to_numpy()
    rows: list[tuple[str, ...]] = []
    windows = list(enumerate(running.windows, start=1))[running.settle :]
    for column in SLIDER_COLUMNS:
        values = steps[column].to_numpy()
        per_revolution = []
        for number, (start, end) in windows:
            inside = (t >= start) & (t <= end)
            if not inside.any():
                continue
            chunk = values[inside]
            if column == "slider_x":
                per_revolution.append((float(chunk.max() - chunk.min()), number, start))
            else:
                k = int(abs(chunk).argmax())
                crank = float(steps["crank_deg"].to_numpy()[inside][k])
                per_revolution.append((float(abs(chunk[k])), number, crank))
        if not per_revolution:
            continue
        peak, number, crank = max(per_revolution)
        low = min(v for v, _, _ in per_revolution)
        high = max(v for v, _, _ in per_revolution)
        ideal = nominal[column].to_numpy() if nominal is not None else None
        if ideal is None:
            reference = float("nan")
        elif column == "slider_x":
            reference = float(ideal.max() - ideal.min())
        else:
            reference = float(abs(ideal).max())
        increase = 100.0 * (peak / reference - 1.0) if reference > 0 else float("nan")
        rows.append(
            (
                "slider stroke (m)*" if column == "slider_x" else f"{column}*",
                f"{peak:.5g}",
                str(number),
                "" if column == "slider_x" else f"{crank:.1f}",
                f"{low:.4g}–{high:.4g}",
                f"{reference:.5g}",
                "" if increase != increase else f"{increase:+.1f}",
            )
        )
    return rows


def _quantity(values: dict[str, Any], key: str, unit: str) -> float | None:
    """``values[key]`` (an option, or its ``[simulation]`` key) in the SI unit ``unit``;
    ``None`` where not given. Its error names the option (``--output-step``)."""
    value = values.get(key)
    if value is None:
        return None
    return parse_quantity(value, unit, field="--" + key.replace("_", "-"))


def _sample_step(value: Any) -> float | None:
    """``--sample-deg`` (or ``[simulation] sample_deg``) in degrees, within (0, 360]."""
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, str):
        raise ConfigError(
            f"--sample-deg must be a crank angle with a unit, e.g. '5 deg', got {value!r}"
        )
    step = math.degrees(quantity_option(value, "rad", "--sample-deg", example="deg"))
    if not 0 < step <= 360:
        raise ConfigError(f"--sample-deg must lie in (0, 360] degrees, got {value!r}")
    return step


def _jsonable(values: dict[str, Any]) -> dict[str, Any]:
    return {
        k: (v if isinstance(v, int | float | str | list | type(None)) else str(v))
        for k, v in values.items()
    }


def _print_irregular(running: Any, stdout: Console) -> None:
    """For a motion that is not periodic: the per-revolution peak distributions, and that the
    peak column is a draw (docs/performance.md, "Accuracy of irregular (chaotic) running")."""
    from jointplay.dynamics.irregular import CAVEAT, describe, irregular_summary

    if not running.irregular:
        return
    found = irregular_summary(running.distributions, running.whole_revolutions)
    needed = found["revolutions_for_bounded_percentile"]
    if not running.distributions:
        stdout.print(
            f"irregular motion: each peak above is a draw (it moves when the tolerances change); "
            f"{running.whole_revolutions} whole revolution(s) are too few for its distribution: "
            f"analyse at least {needed} (--revolutions {needed})"
        )
        return
    stdout.print(
        "irregular motion: each peak above is a draw (it moves when the tolerances change); "
        "read the distribution of the per-revolution peak instead (95 % intervals):"
    )
    for name, distribution in running.distributions.items():
        stdout.print("  " + describe(name, distribution))
    stdout.print("  " + CAVEAT)
    if needed > running.whole_revolutions:
        stdout.print(
            f"  a 95th percentile bounded above needs {needed} revolutions (--revolutions "
            f"{needed}); this run analysed {running.whole_revolutions}"
        )


def _print(result: Any, findings: list[Any], out: Path) -> None:
    running = result.running
    stats = running.statistics
    table = Table(
        "quantity",
        "peak |value|",
        "revolution",
        "crank in it (deg)",
        "per-revolution min–max",
        "nominal",
        "increase %",
        box=None,
    )
    for key, peak in result.peaks.items():
        increase = result.increase_percent.get(key)
        table.add_row(
            key,
            f"{peak['value']:.5g}",
            str(peak["revolution"]),
            f"{peak['revolution_deg']:.1f}",
            f"{stats[key]['min']:.4g}–{stats[key]['max']:.4g}",
            f"{result.nominal_peaks.get(key, float('nan')):.5g}",
            "" if increase is None else f"{increase:+.1f}",
        )
    slider = _slider_rows(result)
    for row in slider:
        table.add_row(*row)
    stdout = Console(soft_wrap=True)
    if not stdout.is_terminal:  # a file or a pipe: the whole table, not 80 columns
        stdout.width = 132
    stdout.print(
        f"peaks over revolutions {running.settle + 1}–{len(running.windows)}, located on the "
        "continuous solution; periodicity: " + running.periodicity.verdict
    )
    stdout.print(whole_headers(table))
    if slider:
        stdout.print(
            "* the slider (position m, velocity m/s, acceleration m/s²): peaks among the "
            "integrator's accepted steps, not interpolated; the stroke is the range of the "
            "position in a revolution"
        )
    if running.max_penetration:
        clearances = {c.joint: c.clearance for c in result.system.clearances}
        deepest = ", ".join(
            f"{joint} {value * 1e6:.3g} µm (clearance {clearances[joint] * 1e6:.3g} µm)"
            for joint, value in running.max_penetration.items()
        )
        stdout.print(
            "deepest penetration over the analysed revolutions, at the accepted steps: " + deepest
        )
    _print_irregular(running, stdout)
    for finding in findings:  # one line each, on stderr
        print(f"jointplay: {finding.line(SETTING_OPTIONS)}", file=sys.stderr)
    stats = result.solver_stats
    stdout.print(
        f"{stats['steps']} steps ({stats['rejected_steps']} rejected), {stats['rhs_evaluations']} evaluations, "
        f"impacts {stats['impacts']}, max penetration {stats['max_penetration_m'] * 1e6:.3g} µm "
        "over the whole run (start-up included), "
        f"energy residual {stats['energy_residual']:.2e}, {stats['wall_s']:.3f} s"
    )
    stdout.print(f"results written to {out}")
