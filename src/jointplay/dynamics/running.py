"""What a simulated mechanism does as it runs: exact peaks, cycles, periodicity, diagnostics.

:func:`characterise` turns a finished simulation (its accepted steps and a function that
evaluates every documented column at any time on the continuous solution) into a frozen
:class:`RunningBehaviour`:

- the crank revolutions are counted from the start (1, 2, …); the first ``settle`` are the
  start-up, left out of the statistics; the next ``revolutions`` are *analysed*;
- each quantity's peak in each revolution is located on the continuous solution
  (:mod:`jointplay.dynamics.peaks`), with its time, crank angle and revolution;
- across the analysed revolutions: mean / min / max / std of each quantity's peak
  (:mod:`jointplay.dynamics.cycles`);
- a Poincaré section at the start of every analysed revolution and after the last (the
  crank at the same angle), with the periodicity verdict;
- with ``sample_deg``, the peaks of the solution sampled every ``sample_deg`` degrees of
  crank, labelled as sampled (what tools that report sampled curves show);
- when the section is not periodic (irregular, chaotic running), each quantity's
  per-revolution peak *distribution* over the whole analysed revolutions: mean, 95th
  percentile and maximum with their intervals (:mod:`jointplay.dynamics.irregular`), the
  statistics that converge where the single largest peak is a draw;
- the plausibility diagnostics (:mod:`jointplay.dynamics.diagnostics`).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from jointplay.dynamics import diagnostics as dg
from jointplay.dynamics.clearance import ClearanceJoint
from jointplay.dynamics.cycles import Periodicity, periodicity, revolution_statistics, thresholds
from jointplay.dynamics.irregular import PeakDistribution, irregular_summary, peak_distributions
from jointplay.dynamics.peaks import LocatedPeak, locate_peaks
from jointplay.model.mechanism import Mechanism

FloatArray = NDArray[np.float64]
Evaluate = Callable[[FloatArray], Mapping[str, FloatArray]]

#: Quantities whose peaks are reported: the columns that start so.
PEAK_KEYS = ("omega", "alpha", "F_", "torque")

#: How the peaks of :attr:`RunningBehaviour.peaks` are taken, as summary.json says it.
CONTINUOUS = (
    "located on the continuous solution: cubic Hermite interpolation of the state between "
    "accepted integrator steps (4th order, as the integrator's dense output), forces and "
    "accelerations evaluated exactly at the interpolated state; never below a step value"
)


@dataclass(frozen=True)
class RunningBehaviour:
    """The running behaviour of a simulated mechanism.

    Attributes:
        settle: start-up revolutions left out of the statistics.
        revolutions: analysed revolutions (the last may be partial).
        windows: ``(start, end)`` times of every revolution, the start-up ones first, s.
        peaks: each quantity's peak over the analysed revolutions: ``value`` (largest
            \\|value\\|), ``signed_value``, ``t`` (s), ``crank_deg`` (turned since the start),
            ``revolution`` (1 = the first simulated one) and ``revolution_deg`` (turned
            within that revolution, 0-360°: what tables and summaries show beside the
            revolution's number).
        start_up_peaks: the same over the start-up revolutions (empty without any).
        per_revolution: each quantity's peak in every simulated revolution, start-up
            included (the analysed ones are the last ``len(windows) - settle``).
        statistics: across the analysed revolutions, per quantity: mean, min, max, std.
        periodicity: the Poincaré section of the analysed revolutions and its verdict.
        sampled_peaks: with ``sample_deg``, the peaks of the solution sampled every
            ``sample_deg`` degrees of crank over the analysed revolutions; else empty.
        sample_deg: the sampling interval of ``sampled_peaks``, deg (``None``: none).
        max_penetration: each clearance joint's deepest penetration δ = |e| − c over the
            analysed revolutions, m, taken at the integrator's accepted steps (sampled, as
            the batch engine's ``pen_<joint>``; negative: the pin never touched).
        diagnostics: the plausibility findings, warnings first.
        distributions: when the motion is not periodic, each quantity's per-revolution peak
            distribution over the whole analysed revolutions (at least
            :data:`~jointplay.dynamics.irregular.MIN_REVOLUTIONS`; else empty): the
            statistics of irregular running that converge.
    """

    settle: int
    revolutions: float
    windows: tuple[tuple[float, float], ...]
    peaks: dict[str, dict[str, float]]
    start_up_peaks: dict[str, dict[str, float]]
    per_revolution: dict[str, list[float]]
    statistics: dict[str, Any]
    periodicity: Periodicity
    sampled_peaks: dict[str, dict[str, float]]
    sample_deg: float | None
    max_penetration: dict[str, float]
    diagnostics: tuple[dg.Diagnostic, ...]
    distributions: dict[str, PeakDistribution] = dataclasses.field(default_factory=dict)

    @property
    def irregular(self) -> bool:
        """Whether the motion is irregular: its Poincaré section is not periodic (see
        :func:`rattling`)."""
        return rattling(self.periodicity)

    @property
    def whole_revolutions(self) -> int:
        """The analysed revolutions that are whole (a partial last one left out)."""
        return math.floor(self.revolutions + 1e-9)

    @property
    def analysed_per_revolution(self) -> dict[str, list[float]]:
        """Each quantity's peak in every analysed revolution."""
        return {name: values[self.settle :] for name, values in self.per_revolution.items()}

    def summary(self) -> dict[str, Any]:
        """The ``cycles``, ``periodicity``, ``sampled_peaks`` and ``diagnostics`` of
        summary.json."""
        return {
            "cycles": {
                "settle_revolutions": self.settle,
                "analysed_revolutions": self.revolutions,
                "first_analysed_revolution": self.settle + 1,
                "peaks_located": CONTINUOUS,
                "per_revolution": self.analysed_per_revolution,
                "start_up_per_revolution": {
                    name: values[: self.settle] for name, values in self.per_revolution.items()
                },
                "across_revolutions": self.statistics,
                "deepest_penetration_m": self.max_penetration,
                "deepest_penetration_taken": (
                    "over the analysed revolutions, at the integrator's accepted steps "
                    "(sampled, not located between them); negative: the pin never touched"
                ),
            },
            "periodicity": self.periodicity.summary(),
            "irregular": (
                irregular_summary(self.distributions, self.whole_revolutions)
                if self.irregular
                else None
            ),
            "sampled_peaks": (
                {}
                if self.sample_deg is None
                else {
                    "every_deg": self.sample_deg,
                    "note": (
                        f"peaks of the solution sampled every {self.sample_deg:g} deg of "
                        "crank (as tools that report sampled curves show them); lower bounds "
                        "of the located peaks"
                    ),
                    "peaks": self.sampled_peaks,
                }
            ),
            "diagnostics": dg.as_records(self.diagnostics),
        }


def rattling(section: Periodicity) -> bool:
    """Whether a section that is not periodic shows irregular running, not a start-up
    transient: it does not become periodic once its first revolutions are left out, and its
    steps do not shrink (:meth:`Periodicity.settles_after`, :attr:`Periodicity.converging`;
    those ask for more ``settle``, not for statistics)."""
    return (
        section.verdict == "not periodic"
        and section.settles_after() is None
        and not section.converging
    )


def revolution_windows(
    t: FloatArray, crank_turned_deg: FloatArray, driven: bool, period: float
) -> tuple[tuple[float, float], ...]:
    """Start and end times of each crank revolution of a simulation (the last may be partial).

    A driven crank's revolutions are counted by its angle (so a speed ramp is followed); a
    coasting one's by the nominal period.
    """
    t_end = float(t[-1])
    if driven:
        turned = np.abs(crank_turned_deg)
        count = int(np.floor(turned[-1] / 360.0 + 1e-9))
        edges = [float(np.interp(360.0 * k, turned, t)) for k in range(count + 1)]
    else:
        count = int(np.floor(t_end / period + 1e-9))
        edges = [k * period for k in range(count + 1)]
    if t_end - edges[-1] > 1e-9 * max(period, 1e-300) or len(edges) == 1:
        edges.append(t_end)
    edges[0] = float(t[0])
    return tuple((edges[k], edges[k + 1]) for k in range(len(edges) - 1))


def characterise(
    *,
    mechanism: Mechanism,
    clearances: Sequence[ClearanceJoint],
    t: FloatArray,
    step_columns: Mapping[str, FloatArray],
    evaluate: Evaluate,
    settle: int,
    steady_start: bool,
    driven: bool,
    sample_deg: float | None,
    nominal_peaks: Mapping[str, float],
    energy_residual: float,
    tolerances: tuple[float, float],
) -> RunningBehaviour:
    """The running behaviour of a finished simulation (see the module docstring).

    Args:
        mechanism: the simulated mechanism.
        clearances: its clearance joints.
        t: accepted step times, s.
        step_columns: the documented columns at those steps.
        evaluate: the documented columns at any times inside ``[t[0], t[-1]]``.
        settle: start-up revolutions to leave out of the statistics.
        steady_start: the motion started from the nominal steady state.
        driven: the crank is driven (revolutions counted by its angle).
        sample_deg: also report peaks sampled every ``sample_deg`` degrees (``None``: no).
        nominal_peaks: ideal-joint peaks, when known (for ``force-far-above-ideal``).
        energy_residual: the relative drift of the energy balance.
        tolerances: the integrator's absolute tolerances on positions (m) and velocities
            (m/s), which set the periodicity thresholds of the rate coordinates.
    """
    period = mechanism.driver.period
    crank = step_columns["crank_deg"]
    turned = crank - crank[0]
    windows = revolution_windows(t, turned, driven, period)
    settle = min(settle, len(windows) - 1)
    names = [name for name in step_columns if name.startswith(PEAK_KEYS)]
    located = locate_peaks(t, {name: step_columns[name] for name in names}, evaluate, windows)

    def record(peak: LocatedPeak, revolution: int) -> dict[str, float]:
        crank_at = float(np.interp(peak.t, t, turned))
        return {
            "value": peak.value,
            "signed_value": peak.signed_value,
            "t": peak.t,
            "crank_deg": crank_at,
            "revolution": revolution,
            "revolution_deg": min(max(crank_at - 360.0 * (revolution - 1), 0.0), 360.0),
        }

    def overall(first: int, last: int) -> dict[str, dict[str, float]]:
        out = {}
        for name in names:
            k = first + int(np.argmax([located[name][w].value for w in range(first, last)]))
            out[name] = record(located[name][k], k + 1)
        return out

    analysed = range(settle, len(windows))
    peaks = overall(settle, len(windows))
    start_up = overall(0, settle) if settle else {}
    per_revolution = {name: [p.value for p in located[name]] for name in names}
    statistics = revolution_statistics(
        {name: values[settle:] for name, values in per_revolution.items()}
    )
    last = (windows[-1][1] - windows[-1][0]) / period  # 1, or less when it is partial
    section_times = np.array([windows[w][0] for w in analysed] + [windows[-1][1]])
    if last < 0.999:  # the section is taken at whole revolutions only
        section_times = section_times[:-1]
    section = _section(evaluate, section_times, clearances, mechanism, tolerances)
    sampled = (
        _sampled_peaks(evaluate, names, windows[settle][0], windows[-1][1], sample_deg, period)
        if sample_deg is not None
        else {}
    )
    result_periodicity = periodicity(section[0], section[1], threshold=thresholds(section[2]))
    whole = len(windows) - (0 if last >= 0.999 else 1)  # the partial last one left out
    distributions = (
        peak_distributions({name: values[settle:whole] for name, values in per_revolution.items()})
        if rattling(result_periodicity)
        else {}
    )
    in_window = t >= windows[settle][0]
    max_penetration = {
        joint.joint: float(np.max(step_columns[f"pen_{joint.joint}"][in_window]))
        for joint in clearances
    }
    found = _diagnose(
        mechanism,
        clearances,
        peaks,
        per_revolution,
        settle,
        steady_start,
        result_periodicity,
        nominal_peaks,
        energy_residual,
        max_penetration,
        located,
    )
    return RunningBehaviour(
        settle=settle,
        revolutions=len(windows) - settle - 1 + (1.0 if last >= 0.999 else last),
        windows=windows,
        peaks=peaks,
        start_up_peaks=start_up,
        per_revolution=per_revolution,
        statistics=statistics,
        periodicity=result_periodicity,
        sampled_peaks=sampled,
        sample_deg=sample_deg,
        max_penetration=max_penetration,
        diagnostics=tuple(found),
        distributions=distributions,
    )


def _section(
    evaluate: Evaluate,
    times: FloatArray,
    clearances: Sequence[ClearanceJoint],
    mechanism: Mechanism,
    tolerances: tuple[float, float],
) -> tuple[FloatArray, list[str], FloatArray]:
    """Normalised Poincaré section points at ``times``, their coordinate names and their
    normalised integration tolerances.

    Eccentricities are divided by the clearance, their rates by clearance × crank speed,
    link angular velocities by the crank speed. ``tolerances`` are the integrator's absolute
    tolerances on positions (m) and velocities (m/s, rad/s); an eccentricity or its rate is
    the difference of two points, so its tolerance is twice theirs.
    """
    speed = mechanism.driver.speed
    position, velocity = tolerances
    values = evaluate(times)
    columns: list[FloatArray] = []
    names: list[str] = []
    scales: list[float] = []
    for joint in clearances:
        c = joint.clearance
        for key, scale, tolerance in (
            (f"ex_{joint.joint}", c, 2 * position),
            (f"ey_{joint.joint}", c, 2 * position),
            (f"dex_{joint.joint}", c * speed, 2 * velocity),
            (f"dey_{joint.joint}", c * speed, 2 * velocity),
        ):
            columns.append(np.asarray(values[key]) / scale)
            names.append(f"{key}/c" if key.startswith("e") else f"{key}/(c*omega)")
            scales.append(tolerance / scale)
    for key in values:
        if key.startswith("omega"):
            columns.append(np.asarray(values[key]) / speed)
            names.append(f"{key}/omega_crank")
            scales.append(velocity / speed)
    points = np.column_stack(columns) if columns else np.zeros((times.size, 0))
    return points, names, np.array(scales)


def _sampled_peaks(
    evaluate: Evaluate,
    names: Sequence[str],
    start: float,
    end: float,
    sample_deg: float,
    period: float,
) -> dict[str, dict[str, float]]:
    """Peaks of the solution sampled every ``sample_deg`` of crank (constant speed)."""
    step = period * sample_deg / 360.0
    times = np.arange(start, end + 0.5 * step, step)
    times = times[times <= end]
    values = evaluate(times)
    out = {}
    for name in names:
        series = np.asarray(values[name])
        i = int(np.argmax(np.abs(series)))
        out[name] = {
            "value": float(abs(series[i])),
            "signed_value": float(series[i]),
            "t": float(times[i]),
        }
    return out


def _diagnose(
    mechanism: Mechanism,
    clearances: Sequence[ClearanceJoint],
    peaks: Mapping[str, Mapping[str, float]],
    per_revolution: Mapping[str, Sequence[float]],
    settle: int,
    steady_start: bool,
    result_periodicity: Periodicity,
    nominal_peaks: Mapping[str, float],
    energy_residual: float,
    max_penetration: Mapping[str, float],
    located: Mapping[str, Sequence[LocatedPeak]],
) -> list[dg.Diagnostic]:
    findings: list[dg.Diagnostic | None] = []
    for joint in clearances:
        name = joint.joint
        findings.append(dg.check_penetration(name, max_penetration[name], joint.clearance))
        force = max(p.value for p in located[f"F_{name}"][settle:])
        width = mechanism.bearing_width(name)
        spec = mechanism.joint(name)
        bearing = mechanism.material_of(spec.link_a)
        pin = mechanism.material_of(spec.link_b)
        approach = dg.hertz_approach(force, joint.journal_radius, joint.clearance, bearing, pin)
        findings.append(dg.check_elastic(name, max_penetration[name], approach, force))
        if width is not None:
            findings.append(
                dg.check_hertz_validity(
                    name, force, width, joint.journal_radius, joint.clearance, bearing, pin
                )
            )
            pressure = dg.line_contact_pressure(
                force, width, joint.journal_radius, joint.clearance, bearing, pin
            )
            weaker = min(
                (bearing, pin),
                key=lambda m: (
                    math.inf if m.contact_pressure_limit is None else m.contact_pressure_limit
                ),
            )
            findings.append(dg.check_pressure(name, pressure, weaker, force))
    for key, value in peaks.items():
        if key.startswith("F_") and key in nominal_peaks:
            findings.append(
                dg.check_force_against_ideal(
                    key.removeprefix("F_"), value["value"], nominal_peaks[key]
                )
            )
    if settle == 0:  # the start-up is inside the reported peaks
        transients = [
            dg.check_start_transient(
                name,
                values,
                steady_start=steady_start,
                first_peak_crank_deg=float(peaks[name]["crank_deg"]) if len(values) == 1 else None,
            )
            for name, values in per_revolution.items()
        ]
        findings.append(_worst(transients))
    settled = [dg.check_settled(name, values[settle:]) for name, values in per_revolution.items()]
    findings.append(_worst(settled))
    analysed = len(next(iter(per_revolution.values()), [])) - settle
    findings.append(
        dg.check_periodic(
            result_periodicity.verdict,
            result_periodicity.period,
            analysed,
            settles_after=result_periodicity.settles_after(),
            converging=result_periodicity.converging,
        )
    )
    findings.append(
        dg.check_dry_undetermined(
            result_periodicity.verdict,
            analysed,
            [c.joint for c in clearances if c.film_damping == 0.0],
        )
    )
    findings.append(dg.check_energy(energy_residual))
    findings.append(dg.check_transmission_angle(mechanism))
    return dg.collect(findings)


def _worst(findings: Sequence[dg.Diagnostic | None]) -> dg.Diagnostic | None:
    """The finding whose value is furthest beyond its limit."""
    present = [f for f in findings if f is not None]
    if not present:
        return None
    return max(present, key=lambda f: f.value / f.limit if f.limit else math.inf)
