"""The paper's study end to end: ECS, the six methods, nominal vs actual, sensitivities.

Akhadkar, Deoghare & Vaidya simulate their crank-rocker (Table 1, read as in
docs/paper-reading.md) with radial clearance 0.021 mm in all four joints, started
from rest, with six contact-modelling methods (Table 2), compare the "actual" mechanism
(toleranced lengths + clearance) with the nominal one (basic lengths, ideal joints), and check
the rocker speed against measurements (Table 7). :func:`run_paper_study` does all of that with
jointplay and returns a frozen :class:`PaperStudy`; :mod:`jointplay.report.paper` turns it into
the HTML report and ``results.json``.

The paper's simulations start from rest and report the first revolution, so their peaks are
start-up impacts (the crank is jerked to full speed with the pins centred). Beside each of the
six methods the study also runs the mechanism *as it runs*: started steady and left to settle
for :data:`~jointplay.dynamics.cycles.DEFAULT_SETTLE` revolutions, then one revolution
analysed (keys ``steady/<method>/<source>``).

Simulations are independent tasks (:class:`SimTask`) run through the one execution backend of
jointplay (:func:`jointplay.tolerance.execution.run_tasks`): in this process, on local
processes or on a Dask cluster.
"""

from __future__ import annotations

import itertools
import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pandas as pd

from jointplay.contact.ecs import EcsConventions
from jointplay.dynamics.cycles import DEFAULT_SETTLE
from jointplay.dynamics.nominal import nominal_analysis
from jointplay.dynamics.setup import clearance_joints
from jointplay.dynamics.simulate import (
    SimulationResult,
    SolverOptions,
    Start,
    preferred_integrator,
    simulate,
)
from jointplay.errors import JointplayError
from jointplay.io.config import load_preset
from jointplay.io.measurements import paper_table7
from jointplay.kinematics import fourbar
from jointplay.model.mechanism import Mechanism
from jointplay.model.summary import mechanism_summary
from jointplay.model.templates import FourBarGeometry, template_of, with_lengths
from jointplay.study.calibration import explain_table7
from jointplay.study.comparison import DEFAULT_METHODS, MethodsComparison, compare_methods
from jointplay.study.ecs import EcsSweep, ecs_analysis, ecs_sweep
from jointplay.study.methods import METHODS, method_law
from jointplay.study.published import PAPER_PUBLISHED
from jointplay.tolerance.execution import Backend, run_tasks

#: The paper's radial clearance in all four joints (the largest of Ø10 H8/g7), m.
PAPER_CLEARANCE = 21e-6
JOINTS = ("O2", "A", "B", "O4")
LENGTHS = ("crank", "coupler", "rocker", "ground")
PEAK_KEYS = ("omega3", "omega4", "alpha3", "alpha4", "F_O2", "F_A", "F_B", "F_O4", "torque")
TRACE_COLUMNS = (
    "t",
    "crank_deg",
    "omega3",
    "omega4",
    "alpha3",
    "alpha4",
    "F_O2",
    "F_A",
    "F_B",
    "F_O4",
    "torque",
)
#: Crank angle after the start shown as the start-up in the report's figures, deg.
STARTUP_PLOT_DEG = 30.0
#: Rows a kept trace is thinned to (each column's extremes kept; see :func:`decimate`).
TRACE_ROWS = 6000


@dataclass(frozen=True)
class PaperStudyOptions:
    """Settings of the paper study.

    Attributes:
        rpm: crank speed, rev/min (the paper's 200).
        revolutions: simulated crank revolutions from rest for every method and case.
        ecs_sources: parameter sources of the four ECS methods (``"paper"``: Tables 4–5;
            ``"computed"``: our ECS estimate).
        tolerance_method, tolerance_source: the method of the nominal-vs-actual study and the
            sensitivities (the paper's preferred IFM with spherical-contact ECS parameters).
        corners: simulate all 16 corners of the length tolerances (else only all-upper and
            all-lower).
        startup_deg: crank-angle window after the start in which start-up peaks are taken.
        workers: local processes for the simulations (1: in this process).
        experiment_revolutions: revolutions of the steady runs compared with Table 7.
        scheduler: address of a Dask scheduler (e.g. ``"tcp://host:8786"``) to run the
            simulations on that cluster instead of local processes (``workers`` is then unused).
    """

    rpm: float = 200.0
    revolutions: float = 1.0
    ecs_sources: tuple[str, ...] = ("paper", "computed")
    tolerance_method: str = "ifm-ecs-spherical"
    tolerance_source: str = "paper"
    corners: bool = True
    startup_deg: float = 10.0
    workers: int = 2
    experiment_revolutions: int = 3
    scheduler: str | None = None

    @property
    def backend(self) -> Backend:
        """Where the simulations run: the Dask cluster at ``scheduler``, else local processes."""
        if self.scheduler:
            return Backend.dask(self.scheduler)
        return Backend("processes", workers=self.workers)


@dataclass(frozen=True)
class SimTask:
    """One simulation of the study: a method, its parameter source and the link lengths."""

    key: str
    method: str
    ecs_source: str
    lengths: tuple[tuple[str, float], ...]
    revolutions: float
    rpm: float
    startup_deg: float
    keep_trace: bool = False
    start: str = "rest"
    settle: int = 0

    @property
    def label(self) -> str:
        """What this simulation is, in words (for progress lines and tables)."""
        return task_label(self.key, self.method, self.ecs_source)


@dataclass(frozen=True)
class SimOutcome:
    """What a task returns: the simulation summary, start-up peaks and (optionally) a trace."""

    task: SimTask
    summary: dict[str, Any] | None
    startup_peaks: dict[str, float] | None
    sampled_peaks: dict[str, float] | None
    trace: pd.DataFrame | None
    orbits: pd.DataFrame | None
    error: str | None
    wall_s: float

    @property
    def ok(self) -> bool:
        return self.error is None

    def peak(self, key: str) -> float:
        return float(self.summary["peaks"][key]["value"]) if self.summary else math.nan


def method_words(method: str, ecs_source: str = "-") -> str:
    """A method of Table 2 and its parameter source in words: "IFM with spherical ECS
    (paper's values)", "RM, conventional parameters"."""
    spec = METHODS.get(method)
    if spec is None:
        return method
    if not spec.uses_ecs:
        return f"{spec.family}, conventional parameters"
    source = {"paper": "paper's values", "computed": "our computed values"}.get(
        ecs_source, ecs_source
    )
    return f"{spec.family} with {spec.parameters} ECS ({source})"


def corner_words(signs: str) -> str:
    """A length corner such as ``+-+-`` in words (crank, coupler, rocker, ground order)."""
    return ", ".join(
        f"{name} {'upper' if sign == '+' else 'lower'}"
        for name, sign in zip(LENGTHS, signs, strict=True)
    )


def task_label(key: str, method: str, ecs_source: str) -> str:
    """The simulation of ``key`` in words: what runs, from which start, with which lengths."""
    kind, _, rest = key.partition("/")
    words = method_words(method, ecs_source)
    if kind == "method":
        return f"{words}, from rest, basic lengths"
    if kind == "steady":
        return f"{words}, steady start ({DEFAULT_SETTLE} revolutions to settle, then one analysed)"
    if kind == "corner":
        return f"{words}, from rest, lengths at the corner {corner_words(rest)}"
    if kind == "sensitivity":
        return f"{words}, from rest, the {rest} at its upper limit"
    if kind == "cylindrical":
        return f"{words}, from rest, every length at its {rest} limit"
    return f"{words} ({key})"


def paper_mechanism(rpm: float = 200.0) -> Mechanism:
    """The paper's crank-rocker at ``rpm``."""
    return load_preset("paper-fourbar").with_driver(speed=rpm * math.pi / 30.0)


def simulate_task(shared: None, task: SimTask) -> SimOutcome:
    """Run one :class:`SimTask` (a task of :func:`~jointplay.tolerance.execution.run_tasks`).

    Module-level, so that worker processes and Dask workers find it by reference; ``shared``
    is unused (every task carries its own settings).
    """
    wall = time.perf_counter()
    try:
        basic = paper_mechanism(task.rpm)
        # Contact parameters belong to the joints, not to the link lengths: derive them once
        # from the basic mechanism and keep them for every toleranced variant.
        law, _ = method_law(task.method, basic, ecs_source=task.ecs_source)
        mechanism = with_lengths(basic, **dict(task.lengths)) if task.lengths else basic
        joints = clearance_joints(mechanism, list(JOINTS), clearance=PAPER_CLEARANCE, law=law)
        result = simulate(
            mechanism,
            joints,
            revolutions=task.revolutions,
            settle=task.settle,
            start=Start(task.start),  # type: ignore[arg-type]  # "rest" or "steady"
            solver=SolverOptions(
                integrator=preferred_integrator(METHODS[task.method].integrator, mechanism, joints)
            ),
            nominal=True,  # the summary's increase_percent feeds the report
        )
    except JointplayError as exc:
        return SimOutcome(
            task,
            None,
            None,
            None,
            None,
            None,
            f"{type(exc).__name__}: {exc}",
            time.perf_counter() - wall,
        )
    steps = result.steps
    turned = steps["crank_deg"] - steps["crank_deg"].iloc[0]
    window = steps[turned <= task.startup_deg]
    startup = {key: float(window[key].abs().max()) for key in PEAK_KEYS}
    # The same peaks seen at a plotting resolution (every 0.5° of crank, as the time series):
    # how much of a peak survives output sampling, as in a post-processor's curves.
    sampled = {key: float(result.timeseries[key].abs().max()) for key in PEAK_KEYS}
    trace = orbits = None
    if task.keep_trace:
        orbit_columns = [c for j in JOINTS for c in (f"ex_{j}", f"ey_{j}")]
        if task.settle:  # the analysed revolutions only: the start-up is left to settle
            steps = steps[turned >= 360.0 * task.settle]
            trace = decimate(steps[list(TRACE_COLUMNS)], TRACE_ROWS)
            orbits = decimate(steps[orbit_columns], TRACE_ROWS)
        else:  # the start-up window at full detail, the rest of the run beside it
            early = (turned <= STARTUP_PLOT_DEG).to_numpy()
            trace = pd.concat(
                [
                    decimate(steps.loc[early, list(TRACE_COLUMNS)], TRACE_ROWS),
                    decimate(steps.loc[~early, list(TRACE_COLUMNS)], TRACE_ROWS),
                ],
                ignore_index=True,
            )
            orbits = decimate(steps[orbit_columns], TRACE_ROWS)
    return SimOutcome(
        task, result.summary(), startup, sampled, trace, orbits, None, time.perf_counter() - wall
    )


def decimate(table: pd.DataFrame, target: int) -> pd.DataFrame:
    """At most about ``target`` rows, keeping every column's extreme in each bin (spikes survive)."""
    if len(table) <= target:
        return table.reset_index(drop=True)
    values = table.to_numpy()
    bins = max(1, target // (2 * values.shape[1]))
    edges = np.linspace(0, len(table), bins + 1).astype(int)
    keep = {0, len(table) - 1}
    for lo, hi in itertools.pairwise(edges):
        if hi <= lo:
            continue
        block = np.abs(values[lo:hi])
        keep.update(lo + np.argmax(block, axis=0))
        keep.update(lo + np.argmin(block, axis=0))
        keep.add(lo)
    return table.iloc[sorted(keep)].reset_index(drop=True)


def execution_order(tasks: Sequence[SimTask]) -> list[SimTask]:
    """The order the simulations are handed to the workers: longest first, so that the slow
    cylindrical runs do not end up last on one worker."""
    return sorted(tasks, key=lambda t: "cylindrical" not in t.method)


def run_simulations(
    tasks: Sequence[SimTask],
    backend: Backend,
    progress: Callable[[SimOutcome], None] | None = None,
) -> dict[str, SimOutcome]:
    """Run ``tasks`` on ``backend``; the outcomes keyed by task, in the order of ``tasks``.

    A task whose simulation fails gives an outcome with its ``error``; so does one that raises
    anything else (the execution backend records it). ``progress`` is called with each outcome
    as it arrives.

    Raises:
        KeyboardInterrupt: the run was interrupted (Ctrl-C); finished simulations are dropped.
    """
    ordered = execution_order(tasks)

    def done(_index: int, outcome: SimOutcome) -> None:
        if progress:
            progress(outcome)

    run = run_tasks(
        simulate_task, ordered, backend, description="paper study simulations", on_done=done
    )
    if run.interrupted:
        raise KeyboardInterrupt
    outcomes: dict[str, SimOutcome] = {}
    for task, result, error in zip(ordered, run.results, run.errors, strict=True):
        if result is None:  # raised outside the simulation's own error handling
            result = SimOutcome(task, None, None, None, None, None, error, math.nan)
            done(0, result)
        outcomes[task.key] = result
    return {task.key: outcomes[task.key] for task in tasks}


def _limits(mechanism: Mechanism) -> dict[str, tuple[float, float]]:
    geometry = template_of(mechanism).geometry
    basic = geometry.lengths
    return {
        t.length: (basic[t.length] + t.lower, basic[t.length] + t.upper)
        for t in mechanism.tolerances
    }


def plan(options: PaperStudyOptions) -> list[SimTask]:
    """Every simulation of the study."""
    mechanism = paper_mechanism(options.rpm)
    limits = _limits(mechanism)
    tasks: list[SimTask] = []

    def add(
        key: str, method: str, source: str, lengths: dict[str, float], trace: bool = False
    ) -> None:
        tasks.append(
            SimTask(
                key,
                method,
                source,
                tuple(sorted(lengths.items())),
                options.revolutions,
                options.rpm,
                options.startup_deg,
                trace,
            )
        )

    for method in METHODS.values():
        sources = options.ecs_sources if method.uses_ecs else ("-",)
        for source in sources:
            add(f"method/{method.name}/{source}", method.name, source, {}, trace=True)
        steady_source = options.tolerance_source if method.uses_ecs else "-"
        tasks.append(
            SimTask(
                f"steady/{method.name}/{steady_source}",
                method.name,
                steady_source,
                (),
                1.0,
                options.rpm,
                options.startup_deg,
                keep_trace=True,
                start="steady",
                settle=DEFAULT_SETTLE,
            )
        )
    corners = (
        list(itertools.product((0, 1), repeat=len(LENGTHS)))
        if options.corners
        else [(1,) * len(LENGTHS), (0,) * len(LENGTHS)]
    )
    for corner in corners:
        lengths = {name: limits[name][side] for name, side in zip(LENGTHS, corner, strict=True)}
        label = "".join("+" if side else "-" for side in corner)
        add(f"corner/{label}", options.tolerance_method, options.tolerance_source, lengths)
    for name in LENGTHS:
        add(
            f"sensitivity/{name}",
            options.tolerance_method,
            options.tolerance_source,
            {name: limits[name][1]},
        )
    for side, label in ((1, "upper"), (0, "lower")):
        lengths = {name: limits[name][side] for name in LENGTHS}
        add(f"cylindrical/{label}", "ifm-ecs-cylindrical", options.tolerance_source, lengths)
    return tasks


@dataclass(frozen=True)
class PaperStudy:
    """Everything the paper study computed (SI; figures are made from it by the report)."""

    options: PaperStudyOptions
    mechanism: Mechanism
    nominal: pd.DataFrame
    nominal_summary: dict[str, Any]
    nominal_peaks: dict[str, float]
    ecs: dict[str, Any]
    ecs_sweep: EcsSweep
    outcomes: dict[str, SimOutcome]
    length_cases: pd.DataFrame
    sensitivities: pd.DataFrame
    experiment: MethodsComparison | None
    wall_s: float
    extra: dict[str, Any] = field(default_factory=dict)
    #: The running mechanism of the tolerance method (steady start, settled), simulated in
    #: this process for the report's animation (``None``: not asked for, or it failed).
    running_example: SimulationResult | None = None

    def outcome(self, key: str) -> SimOutcome:
        return self.outcomes[key]


def _nominal_peaks(table: pd.DataFrame) -> dict[str, float]:
    return {key: float(table[key].abs().max()) for key in PEAK_KEYS}


def run_paper_study(
    options: PaperStudyOptions | None = None,
    *,
    progress: Callable[[str, int, int], None] | None = None,
    experiment: bool = True,
    animation: bool = False,
) -> PaperStudy:
    """Run the whole study.

    ``progress(label, done, total)`` is called when each piece starts, with ``label`` naming
    in words what runs now (for the simulations: the ones the workers are running) and
    ``done`` the pieces finished; a last call with ``done == total`` says the study is done.
    ``animation``: also simulate the running mechanism of the tolerance method in this
    process (:attr:`PaperStudy.running_example`), for the report's animation.
    """
    options = options or PaperStudyOptions()
    wall = time.perf_counter()
    # What each part of the study took, s, back to back from ``wall``: the command line's
    # timing line (every second of the run accounted for, docs/cli.md).
    phases: dict[str, float] = {}
    lap = [wall]

    def timed(phase: str) -> None:
        now_s = time.perf_counter()
        phases[phase] = phases.get(phase, 0.0) + now_s - lap[0]
        lap[0] = now_s

    mechanism = paper_mechanism(options.rpm)
    tasks = plan(options)
    total = len(tasks) + 4 + (1 if experiment else 0) + (1 if animation else 0)
    done = 0

    def now(label: str, finished: int = 0) -> None:
        nonlocal done
        done += finished
        if progress:
            progress(label, done, total)

    now("nominal kinematics and inverse dynamics (ideal joints)")
    nominal = nominal_analysis(mechanism, step_deg=0.1)
    now("ECS contact parameters (eqs. 9-13) and their crank-speed sweep", 1)
    conventions = EcsConventions()
    ecs = ecs_analysis(mechanism, conventions, nominal=nominal)
    sweep = ecs_sweep(mechanism, list(range(50, 501, 50)), conventions)
    now("compiling the simulation kernels (the first run only; cached afterwards)", 1)
    # Compile (or load) the kernels once here, so worker processes find them in the cache.
    warm = clearance_joints(
        mechanism,
        ["A"],
        clearance=PAPER_CLEARANCE,
        law=method_law("ifm-conventional", mechanism)[0],
    )
    timed("nominal analysis and ECS")
    kernels = time.perf_counter()
    # the IFM ECS methods run RODAS4, the IFM conventional one DOPRI5, the others Radau
    for integrator in ("radau", "rodas4", "dopri5"):
        simulate(
            mechanism,
            warm,
            revolutions=0.002,
            settle=0,
            start=Start("rest"),
            solver=SolverOptions(integrator=integrator),
        )
    kernels_s = time.perf_counter() - kernels
    timed("kernels")
    ordered = execution_order(tasks)
    finished: set[str] = set()
    at_once = options.workers if options.scheduler is None else 1

    def running(finished_now: int) -> None:
        pending = [t for t in ordered if t.key not in finished]
        if not pending:
            now("simulations done", finished_now)
            return
        more = min(at_once, len(pending)) - 1
        also = f" (and {more} more at once)" if more > 0 else ""
        now(f"simulating {pending[0].label}{also}", finished_now)

    def arrived(outcome: SimOutcome) -> None:
        finished.add(outcome.task.key)
        running(1)

    running(1)
    outcomes = run_simulations(tasks, options.backend, arrived)
    timed("simulations")
    experiment_result = None
    explained: dict[str, Any] | None = None
    if experiment:
        now("comparing the steady rocker speed with the measurements (Table 7)")
        experiment_result = compare_methods(
            paper_table7(),
            mechanism,
            DEFAULT_METHODS,
            revolutions=options.experiment_revolutions,
            ecs_source=options.tolerance_source,
            clearance=PAPER_CLEARANCE,
        )
        # Which crank speed (and phase) makes the nominal model match each column.
        explained = explain_table7(mechanism)
        timed("Table 7 comparison")
    now("nominal vs actual mechanism and the sensitivities", 1 if experiment else 0)
    length_cases = _length_cases(mechanism, outcomes, options)
    sensitivities = _sensitivities(mechanism, outcomes, options)
    timed("tolerance cases")
    example = None
    if animation:
        now(
            f"simulating {method_words(options.tolerance_method, options.tolerance_source)}, "
            "running steadily, for the animation",
            1,
        )
        example = running_example(mechanism, options)
        timed("animation run")
    now("study done", 1)
    return PaperStudy(
        options=options,
        mechanism=mechanism,
        nominal=nominal.table,
        nominal_summary=nominal.summary,
        nominal_peaks=_nominal_peaks(nominal.table),
        ecs={
            "computed": ecs.as_dict(),
            "published": {name: value.as_dict() for name, value in PAPER_PUBLISHED.items()},
            "conventions": conventions.as_dict(),
        },
        ecs_sweep=sweep,
        outcomes=outcomes,
        length_cases=length_cases,
        sensitivities=sensitivities,
        experiment=experiment_result,
        wall_s=time.perf_counter() - wall,
        extra={
            "configuration": mechanism_summary(mechanism),
            "table7_explained": explained,
            "kernels_s": kernels_s,
            "phases": phases,
        },
        running_example=example,
    )


def running_example(mechanism: Mechanism, options: PaperStudyOptions) -> SimulationResult | None:
    """The tolerance method's mechanism running steadily: started on the nominal motion,
    :data:`~jointplay.dynamics.cycles.DEFAULT_SETTLE` revolutions to settle, one more
    simulated (``None`` if the simulation fails: the report then goes without it)."""
    try:
        law, _ = method_law(
            options.tolerance_method, mechanism, ecs_source=options.tolerance_source
        )
        joints = clearance_joints(mechanism, list(JOINTS), clearance=PAPER_CLEARANCE, law=law)
        result = simulate(
            mechanism,
            joints,
            revolutions=1.0,
            settle=DEFAULT_SETTLE,
            start=Start("steady"),
            solver=SolverOptions(
                integrator=preferred_integrator(
                    METHODS[options.tolerance_method].integrator, mechanism, joints
                )
            ),
        )
    except JointplayError:
        return None
    return result if result.success else None


def _kinematic_peaks(mechanism: Mechanism, lengths: dict[str, float]) -> dict[str, float]:
    variant = with_lengths(mechanism, **lengths) if lengths else mechanism
    return _nominal_peaks(nominal_analysis(variant, step_deg=0.1).table)


def _length_cases(
    mechanism: Mechanism, outcomes: dict[str, SimOutcome], options: PaperStudyOptions
) -> pd.DataFrame:
    """Nominal vs actual: each length case with and without clearance, % change vs nominal."""
    nominal = _kinematic_peaks(mechanism, {})
    rows = []
    for key, outcome in outcomes.items():
        if not key.startswith(("corner/", "cylindrical/")):
            continue
        lengths = dict(outcome.task.lengths)
        ideal = _kinematic_peaks(mechanism, lengths)
        row: dict[str, Any] = {
            "case": key,
            "method": outcome.task.method,
            "ecs_source": outcome.task.ecs_source,
            **{f"{name}_mm": lengths[name] * 1e3 for name in LENGTHS},
            "status": "ok" if outcome.ok else outcome.error,
        }
        for peak in PEAK_KEYS:
            row[f"{peak}_ideal"] = ideal[peak]
            row[f"{peak}_ideal_change_pct"] = 100 * (ideal[peak] / nominal[peak] - 1)
            value = outcome.peak(peak) if outcome.ok else math.nan
            row[peak] = value
            row[f"{peak}_change_pct"] = 100 * (value / nominal[peak] - 1)
        rows.append(row)
    table = pd.DataFrame(rows)
    if not table.empty:
        table = table.sort_values("case").reset_index(drop=True)
    return table


def worst_corners(length_cases: pd.DataFrame, method: str) -> pd.DataFrame:
    """For each output, the length corner with the largest peak (clearance runs of ``method``)."""
    corners = length_cases[
        length_cases["case"].str.startswith("corner/") & (length_cases["method"] == method)
    ]
    rows = []
    for peak in PEAK_KEYS:
        valid = corners.dropna(subset=[peak])
        if valid.empty:
            continue
        best = valid.iloc[int(np.argmax(valid[peak].to_numpy()))]
        rows.append(
            {
                "output": peak,
                "worst_corner": best["case"].removeprefix("corner/"),
                "peak": best[peak],
                "change_pct": best[f"{peak}_change_pct"],
                "ideal_worst_corner": str(
                    valid["case"].iloc[int(np.argmax(valid[f"{peak}_ideal"].to_numpy()))]
                ).removeprefix("corner/"),
                "ideal_peak": valid[f"{peak}_ideal"].max(),
            }
        )
    return pd.DataFrame(rows)


def _sensitivities(
    mechanism: Mechanism, outcomes: dict[str, SimOutcome], options: PaperStudyOptions
) -> pd.DataFrame:
    """% change of the rocker's peak angular acceleration when one length is at its upper limit.

    Kinematic: ideal joints, steady motion (a smooth function of the lengths). Dynamic: with
    clearance, from rest, the tolerance method — dominated by the start-up impacts.
    """
    limits = _limits(mechanism)
    basic_lengths = template_of(mechanism).geometry.lengths
    nominal_alpha = _kinematic_peaks(mechanism, {})["alpha4"]
    reference = outcomes.get(f"method/{options.tolerance_method}/{options.tolerance_source}")
    dynamic_base = reference.peak("alpha4") if reference and reference.ok else math.nan
    rows = []
    for name in LENGTHS:
        upper = limits[name][1]
        kinematic = _kinematic_peaks(mechanism, {name: upper})["alpha4"]
        outcome = outcomes[f"sensitivity/{name}"]
        dynamic = outcome.peak("alpha4") if outcome.ok else math.nan
        rows.append(
            {
                "length": name,
                "basic_mm": basic_lengths[name] * 1e3,
                "deviation_mm": (upper - basic_lengths[name]) * 1e3,
                "kinematic_alpha4": kinematic,
                "kinematic_change_pct": 100 * (kinematic / nominal_alpha - 1),
                "dynamic_alpha4": dynamic,
                "dynamic_change_pct": 100 * (dynamic / dynamic_base - 1),
            }
        )
    return pd.DataFrame(rows)


def geometry_figures(mechanism: Mechanism) -> dict[str, Any]:
    """Grashof class, rocker swing and transmission angles of the paper's mechanism."""
    geometry = template_of(mechanism).geometry
    assert isinstance(geometry, FourBarGeometry)
    extended, folded = fourbar.rocker_limit_positions(geometry, mechanism.branch)
    mu = np.degrees(fourbar.transmission_angle(geometry, np.radians(np.arange(0, 360, 0.1))))
    return {
        "grashof": fourbar.grashof(geometry).kind,
        "rocker_swing_deg": math.degrees(abs(extended.rocker_angle - folded.rocker_angle)),
        "transmission_angle_deg": [float(mu.min()), float(mu.max())],
    }
