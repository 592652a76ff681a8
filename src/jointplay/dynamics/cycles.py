"""Steady running over many crank revolutions: per-revolution statistics and periodicity.

A mechanism with clearance joints need not settle into a periodic motion: the pins may keep
rattling differently from one revolution to the next (the clearance-joint literature reports
periodic, quasi-periodic and chaotic responses, e.g. Flores & Ambrósio 2004, Computers &
Structures 82). A single revolution therefore says little. This module holds the pure
functions that characterise the running motion:

- :func:`revolution_statistics`: across revolutions, mean / min / max / std of each
  quantity's per-revolution peak;
- :func:`periodicity`: the Poincaré section once per crank revolution (a point per
  revolution), the distance between successive points, and the verdict — periodic with
  period k (the section repeats every k revolutions) or not periodic.

Section points are normalised by the caller so that one threshold fits every coordinate
(eccentricities by the clearance, rates by clearance × crank speed, link speeds by the crank
speed): the default :data:`PERIODICITY_THRESHOLD` of 1e-2 then means "repeats within 1 % of
the clearance", far above the integration error of the positions (atol 1e-10 m against a
21 µm clearance is 5e-6) and far below the size of a rattle. A coordinate whose integration
tolerance is coarser than that (a rate at low speed in a small clearance: atol 1e-6 m/s
against c·ω = 1.6e-5 m/s at 30 rpm and 5 µm) gets a threshold of ten times its tolerance
instead (:func:`thresholds`), so the verdict never hinges on the integrator's noise.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any, NoReturn

import numpy as np
from numpy.typing import NDArray

from jointplay.errors import ConfigError, SettingError

FloatArray = NDArray[np.float64]

#: Start-up revolutions that studies of the running mechanism leave out by default: from a
#: steady start with centred pins the contact transient of the paper's four-bar dies out within
#: two revolutions (the conventional set's per-revolution peaks are flat from the third on).
DEFAULT_SETTLE = 2


def analysed_revolutions(value: Any, name: str = "revolutions") -> float:
    """``value`` as a number of analysed crank revolutions (a finite number > 0).

    Args:
        name: what the message calls it (the command line passes its option's name).

    Raises:
        ConfigError: it is not a number, or not > 0 — the one check of every engine, study
            and command; a :class:`~jointplay.errors.SettingError` when ``name`` is a
            setting's (an identifier, as the default), which each caller names its own way.
    """
    if isinstance(value, bool) or not isinstance(value, int | float | np.integer | np.floating):
        _refuse(name, "{name} must be a number, got {got!r}", value)
    if not (math.isfinite(value) and value > 0):
        _refuse(name, "{name} must be > 0, got {got:g}", value)
    return float(value)


def settle_revolutions(value: Any, name: str = "settle") -> int:
    """``value`` as a number of start-up revolutions left out (a whole number >= 0).

    Args:
        name: what the message calls it (the command line passes its option's name, a
            configuration file its key's place).

    Raises:
        ConfigError: it is not a whole number >= 0 — the one check of every engine, study,
            command and configuration file; a :class:`~jointplay.errors.SettingError` when
            ``name`` is a setting's (an identifier, as the default).
    """
    if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < 0:
        _refuse(name, "{name} must be a whole number of revolutions >= 0, got {got!r}", value)
    return int(value)


def _refuse(name: str, template: str, value: Any) -> NoReturn:
    """Raise the error of ``template`` about ``name``: a SettingError that names the setting
    ``name`` (an identifier), else a ConfigError with ``name`` as given."""
    if name.isidentifier():
        raise SettingError(template.replace("{name}", "{" + name + "}"), got=value)
    raise ConfigError(template.format(name=name, got=value))


#: Largest normalised distance between section points that counts as "the same point".
PERIODICITY_THRESHOLD = 1e-2

#: Longest period looked for, in revolutions.
MAX_PERIOD = 8

#: A coordinate's threshold is at least this many times its normalised integration tolerance.
TOLERANCE_MARGIN = 10.0


def thresholds(tolerances: FloatArray, base: float = PERIODICITY_THRESHOLD) -> FloatArray:
    """Per-coordinate thresholds: ``base``, or :data:`TOLERANCE_MARGIN` × the coordinate's
    normalised integration tolerance where that is larger."""
    return np.maximum(base, TOLERANCE_MARGIN * np.asarray(tolerances, dtype=float))


def revolution_statistics(per_revolution: Mapping[str, Sequence[float]]) -> dict[str, Any]:
    """Mean, min, max and (population) std across revolutions of each quantity's peaks.

    Args:
        per_revolution: for each quantity, its peak in each analysed revolution.
    """
    out: dict[str, Any] = {}
    for name, peaks in per_revolution.items():
        values = np.asarray(peaks, dtype=float)
        out[name] = {
            "mean": float(values.mean()),
            "min": float(values.min()),
            "max": float(values.max()),
            "std": float(values.std()),
            "revolution_of_max": int(np.argmax(values)),
        }
    return out


#: The most one step of a converging section may grow over the one before (round-off and the
#: section's sampling make a shrinking sequence wobble by a few per cent).
CONVERGING_GROWTH = 1.1


@dataclass(frozen=True)
class Periodicity:
    """The verdict on a Poincaré section taken once per crank revolution.

    Attributes:
        points: normalised section points, one row per revolution.
        successive_distance: max-norm distance between successive points (n − 1 values).
        period: the smallest k (revolutions) such that every point repeats k revolutions
            later within ``threshold``; ``None`` if no k up to ``max_period`` does.
        threshold: per coordinate, the normalised distance below which two points are the
            same.
        max_period: the longest period looked for.
        coordinates: names of the section coordinates (columns of ``points``).
    """

    points: FloatArray
    successive_distance: FloatArray
    period: int | None
    threshold: FloatArray
    max_period: int
    coordinates: tuple[str, ...]

    @property
    def verdict(self) -> str:
        """``"periodic (period k)"``, ``"not periodic"`` or ``"undetermined"`` (too few
        revolutions to tell)."""
        if self.period is not None:
            return f"periodic (period {self.period})"
        if self.points.shape[0] < 3:
            return "undetermined"
        return "not periodic"

    def settles_after(self) -> int | None:
        """For a section that is not periodic: the fewest first revolutions whose omission
        leaves a periodic section (at least 3 points left) — a start-up transient that the
        analysed revolutions still held; ``None`` if there is none, or the section is
        periodic already."""
        if self.period is not None:
            return None
        for first in range(1, self.points.shape[0] - 2):
            later = periodicity(
                self.points[first:], self.coordinates, threshold=self.threshold,
                max_period=self.max_period,
            )  # fmt: skip
            if later.period is not None:
                return first
        return None

    @property
    def converging(self) -> bool:
        """Whether the steps between successive section points shrink (none grows by more than
        :data:`CONVERGING_GROWTH`, the last is under half the first, over at least 3 steps):
        the motion is still approaching its periodic cycle — a start-up transient, not a
        rattle, which jumps about."""
        steps = self.successive_distance
        if len(steps) < 3 or not steps[0] > 0:
            return False
        grows = steps[1:] > CONVERGING_GROWTH * steps[:-1]
        return bool(not grows.any() and steps[-1] < 0.5 * steps[0])

    def summary(self) -> dict[str, Any]:
        """A JSON-ready description."""
        return {
            "verdict": self.verdict,
            "period_revolutions": self.period,
            "threshold": (
                {n: float(v) for n, v in zip(self.coordinates, self.threshold, strict=True)}
                if self.coordinates
                else [float(v) for v in self.threshold]
            ),
            "threshold_meaning": (
                "largest spread of each normalised section coordinate among the points k "
                "revolutions apart that still counts as the same point: "
                f"{PERIODICITY_THRESHOLD:g}, or {TOLERANCE_MARGIN:g} x the coordinate's "
                "integration tolerance where larger (eccentricities / clearance, eccentricity "
                "rates / (clearance x crank speed), link angular velocities / crank speed)"
            ),
            "max_period_searched": self.max_period,
            "successive_distance": [float(d) for d in self.successive_distance],
            "coordinates": list(self.coordinates),
            "points": [[float(v) for v in row] for row in self.points],
        }


def periodicity(
    points: FloatArray,
    coordinates: Sequence[str] = (),
    *,
    threshold: float | FloatArray = PERIODICITY_THRESHOLD,
    max_period: int = MAX_PERIOD,
) -> Periodicity:
    """Decide whether a once-per-revolution section repeats.

    A period k is accepted when n >= 2k + 1 points exist and, for every residue r, all the
    points x_r, x_{r+k}, x_{r+2k}, … lie within ``threshold`` of each other in every
    coordinate (their spread, max − min, is below it): the section returns to the same k
    points, without drifting.

    Args:
        points: section points, one row per revolution, normalised (see module docstring).
        coordinates: names of the columns.
        threshold: normalised distance below which two points are the same: one for every
            coordinate, or one per coordinate (see :func:`thresholds`).
        max_period: longest period (revolutions) looked for.
    """
    points = np.atleast_2d(np.asarray(points, dtype=float))
    n = points.shape[0]
    limit = np.broadcast_to(np.asarray(threshold, dtype=float), points.shape[1:]).copy()
    successive = np.max(np.abs(np.diff(points, axis=0)), axis=1) if n > 1 else np.zeros(0)
    period = None
    for k in range(1, max_period + 1):
        if n < 2 * k + 1:
            break
        # Every residue class (the points k revolutions apart) must stay within the
        # threshold as a whole, not only from one point to the next, so a slow drift of the
        # section is not mistaken for a period.
        if all(np.all(np.ptp(points[r::k], axis=0) < limit) for r in range(k)):
            period = k
            break
    return Periodicity(
        points=points,
        successive_distance=successive,
        period=period,
        threshold=limit,
        max_period=max_period,
        coordinates=tuple(coordinates),
    )
