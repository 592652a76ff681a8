"""Tolerance specifications: which quantities of a mechanism vary, between which limits, how.

A :class:`ToleranceSpec` is a tuple of toleranced *inputs*, each a frozen object with a name,
a nominal value, a :class:`Tolerance` (specification limits plus the distribution of the
manufacturing process) and a source:

* :class:`LinkTolerance` — a template length (``crank``, ``coupler``, ...), with explicit
  limit deviations or an ISO 2768-1 general-tolerance class; input name ``length_<name>``;
* :class:`JointTolerance` — the radial clearance of a revolute joint, from an ISO 286 fit and
  nominal diameter or from explicit clearance limits; input name ``clearance_<joint>``;
* :class:`QuantityTolerance` — any other named quantity (used by verification models).

Distributions (all SI, centre ``m = (lower + upper)/2``, half-width ``h = (upper − lower)/2``):

* ``uniform``: uniform on ``[m + shift − h, m + shift + h]``;
* ``triangular``: symmetric triangle with its mode at ``m + shift`` and support ``±h``;
* ``normal``: mean ``m + shift``; standard deviation ``σ = h/3`` (±3σ at the limits, Cp = 1)
  or, given a process capability index Cpk, ``σ = (h − |shift|)/(3 Cpk)``
  (Cpk = min(USL − μ, μ − LSL)/(3σ), e.g. Montgomery, *Introduction to Statistical Quality
  Control*, §8.3). A normal quantity is truncated to its physical ``bounds`` (a clearance
  cannot be negative; the truncated mass is 1e-4 or less for the default settings).

The mechanism's own data give the default specification (:meth:`ToleranceSpec.from_mechanism`):
its ``tolerances`` (the ``[tolerances.lengths.<name>]`` tables) and the ISO 286 fits of its
joints. The extended TOML form (distributions, shifts, Cpk, general classes, joint clearance
tables) is read by :func:`parse_tolerance_table`; see its docstring for the keys.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import special

from jointplay.errors import ConfigError, JointplayError
from jointplay.model.mechanism import LengthTolerance, Mechanism, RevoluteJoint
from jointplay.model.templates import TemplateSpec
from jointplay.tolerance import iso286, iso2768
from jointplay.units import parse_quantity

__all__ = [
    "DISTRIBUTIONS",
    "Distribution",
    "InputTolerance",
    "JointTolerance",
    "LinkTolerance",
    "QuantityTolerance",
    "Tolerance",
    "ToleranceSpec",
    "load_study_spec",
    "mechanism_tolerances",
    "parse_tolerance_table",
]

FloatArray = NDArray[np.float64]
Distribution = Literal["uniform", "normal", "triangular"]

#: The distributions a toleranced quantity can follow.
DISTRIBUTIONS: tuple[str, ...] = ("uniform", "normal", "triangular")

#: Default distribution of every quantity: a capable process centred in the limits (Cp = 1).
DEFAULT_DISTRIBUTION: Distribution = "normal"


@dataclass(frozen=True)
class Tolerance:
    """Specification limits of one quantity and how the process spreads it (SI).

    Attributes:
        limits: ``(lower, upper)`` specification limits of the quantity itself (not deviations),
            in its SI unit (m for lengths and clearances).
        distribution: ``"uniform"``, ``"normal"`` (±3σ at the limits unless ``cpk`` is given)
            or ``"triangular"``; see the module docstring.
        shift: process mean shift from the centre of the limits, same unit as ``limits``.
        cpk: process capability index Cpk > 0 of a normal process; sets σ (normal only).
        bounds: physical range ``(low, high)`` of the quantity; a normal distribution is
            truncated to it, and no other distribution may leave it.
    """

    limits: tuple[float, float]
    distribution: Distribution = DEFAULT_DISTRIBUTION
    shift: float = 0.0
    cpk: float | None = None
    bounds: tuple[float, float] = (-math.inf, math.inf)

    def __post_init__(self) -> None:
        try:
            lower, upper = (float(v) for v in self.limits)
            low, high = (float(v) for v in self.bounds)
        except (TypeError, ValueError):
            raise ConfigError(
                f"Tolerance: limits and bounds must be pairs of numbers, got {self.limits!r} "
                f"and {self.bounds!r}"
            ) from None
        object.__setattr__(self, "limits", (lower, upper))
        object.__setattr__(self, "bounds", (low, high))
        object.__setattr__(self, "shift", float(self.shift))
        if not (math.isfinite(lower) and math.isfinite(upper) and lower <= upper):
            raise ConfigError(
                f"Tolerance: limits must be finite with lower <= upper, got {self.limits!r}"
            )
        if self.distribution not in DISTRIBUTIONS:
            raise ConfigError(
                f"Tolerance: distribution must be one of {', '.join(DISTRIBUTIONS)}, "
                f"got {self.distribution!r}"
            )
        if not math.isfinite(self.shift):
            raise ConfigError(f"Tolerance: shift must be finite, got {self.shift!r}")
        if self.cpk is not None:
            object.__setattr__(self, "cpk", float(self.cpk))
            if self.distribution != "normal":
                raise ConfigError(
                    f"Tolerance: cpk applies to a normal distribution, not {self.distribution!r}; "
                    "remove cpk or set distribution = 'normal'"
                )
            if not (math.isfinite(self.cpk) and self.cpk > 0):
                raise ConfigError(f"Tolerance: cpk must be > 0, got {self.cpk!r}")
            if abs(self.shift) >= self.half_width:
                raise ConfigError(
                    f"Tolerance: with cpk the process shift |{self.shift:g}| must stay inside "
                    f"the limits (half-width {self.half_width:g})"
                )
        if not low <= high:
            raise ConfigError(f"Tolerance: bounds must have low <= high, got {self.bounds!r}")
        if self.distribution == "normal":
            if not low <= self.mode <= high:
                raise ConfigError(
                    f"Tolerance: the process mean {self.mode:g} lies outside the physical "
                    f"bounds {self.bounds!r}"
                )
        elif not (low <= self.mode - self.half_width and self.mode + self.half_width <= high):
            raise ConfigError(
                f"Tolerance: a {self.distribution} distribution on "
                f"[{self.mode - self.half_width:g}, {self.mode + self.half_width:g}] leaves the "
                f"physical bounds {self.bounds!r}; narrow the limits or reduce the shift"
            )

    @property
    def lower(self) -> float:
        """Lower specification limit."""
        return self.limits[0]

    @property
    def upper(self) -> float:
        """Upper specification limit."""
        return self.limits[1]

    @property
    def centre(self) -> float:
        """Centre of the limits, (lower + upper)/2."""
        return 0.5 * (self.limits[0] + self.limits[1])

    @property
    def half_width(self) -> float:
        """Half the tolerance band, (upper − lower)/2."""
        return 0.5 * (self.limits[1] - self.limits[0])

    @property
    def mode(self) -> float:
        """Most likely value: centre + shift (the mean before any truncation)."""
        return self.centre + self.shift

    @property
    def sigma(self) -> float:
        """Scale of the distribution: σ of the (untruncated) normal, h/√3 or h/√6 otherwise."""
        h = self.half_width
        if self.distribution == "uniform":
            return h / math.sqrt(3.0)
        if self.distribution == "triangular":
            return h / math.sqrt(6.0)
        if self.cpk is None:
            return h / 3.0
        return (h - abs(self.shift)) / (3.0 * self.cpk)

    @property
    def mean(self) -> float:
        """Mean of the distribution (truncation of a normal included)."""
        if self.distribution != "normal" or self.sigma == 0.0:
            return self.mode
        alpha, beta, z = self._truncation()
        return self.mode + self.sigma * (_pdf(alpha) - _pdf(beta)) / z

    @property
    def std(self) -> float:
        """Standard deviation of the distribution (truncation of a normal included)."""
        sigma = self.sigma
        if self.distribution != "normal" or sigma == 0.0:
            return sigma
        alpha, beta, z = self._truncation()
        ratio = (_pdf(alpha) - _pdf(beta)) / z
        spread = (_xpdf(alpha) - _xpdf(beta)) / z
        return sigma * math.sqrt(max(0.0, 1.0 + spread - ratio * ratio))

    def _truncation(self) -> tuple[float, float, float]:
        alpha = (self.bounds[0] - self.mode) / self.sigma
        beta = (self.bounds[1] - self.mode) / self.sigma
        return alpha, beta, float(special.ndtr(beta) - special.ndtr(alpha))

    def ppf(self, u: ArrayLike) -> FloatArray:
        """The quantity at cumulative probabilities ``u`` ∈ (0, 1) (inverse CDF), SI."""
        u = np.asarray(u, dtype=float)
        h, mode = self.half_width, self.mode
        if self.distribution == "uniform":
            return np.asarray(mode - h + 2.0 * h * u, dtype=float)
        if self.distribution == "triangular":
            upper_half = u >= 0.5
            t = np.where(upper_half, 1.0 - u, u)
            offset = h * (np.sqrt(2.0 * t) - 1.0)
            return np.asarray(np.where(upper_half, mode - offset, mode + offset), dtype=float)
        sigma = self.sigma
        if sigma == 0.0:
            return np.full(u.shape, mode)
        alpha, beta, _ = self._truncation()
        lo, hi = float(special.ndtr(alpha)), float(special.ndtr(beta))
        z = special.ndtri(lo + (hi - lo) * u)
        return np.asarray(np.clip(mode + sigma * z, *self.bounds), dtype=float)

    def describe(self) -> dict[str, Any]:
        """JSON-ready description (SI)."""
        return {
            "limits": list(self.limits),
            "distribution": self.distribution,
            "shift": self.shift,
            "cpk": self.cpk,
            "bounds": [_finite_or_none(v) for v in self.bounds],
            "mean": self.mean,
            "std": self.std,
        }


def _pdf(x: float) -> float:
    return 0.0 if math.isinf(x) else math.exp(-0.5 * x * x) / math.sqrt(2.0 * math.pi)


def _xpdf(x: float) -> float:
    return 0.0 if math.isinf(x) else x * _pdf(x)


def _finite_or_none(value: float) -> float | None:
    return value if math.isfinite(value) else None


@dataclass(frozen=True)
class QuantityTolerance:
    """A generic toleranced quantity (e.g. the inputs of a verification model).

    Attributes:
        name: input name (a valid column name).
        nominal: nominal (basic) value, SI.
        tolerance: limits and distribution.
        unit: SI unit of the quantity, for reports.
        source: where the tolerance comes from.
    """

    name: str
    nominal: float
    tolerance: Tolerance
    unit: str = ""
    source: str = ""

    kind: Literal["quantity"] = field(default="quantity", init=False)

    def __post_init__(self) -> None:
        _check_name(self.name)
        object.__setattr__(self, "nominal", float(self.nominal))


@dataclass(frozen=True)
class LinkTolerance:
    """Tolerance of a template length (a link or the ground).

    Attributes:
        length: template length name, e.g. ``"crank"`` (see the template's ``length_names``).
        nominal: basic length, m.
        tolerance: limits (absolute lengths, m) and distribution.
        source: e.g. ``"ISO 2768-1 c"`` or ``"explicit"``.
    """

    length: str
    nominal: float
    tolerance: Tolerance
    source: str = ""

    kind: Literal["length"] = field(default="length", init=False)
    unit: Literal["m"] = field(default="m", init=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "nominal", float(self.nominal))
        _check_name(self.name)

    @property
    def name(self) -> str:
        """Input name, ``length_<length>``."""
        return f"length_{self.length}"

    @classmethod
    def from_deviations(
        cls,
        length: str,
        nominal: float,
        lower: float,
        upper: float,
        *,
        distribution: Distribution = DEFAULT_DISTRIBUTION,
        shift: float = 0.0,
        cpk: float | None = None,
        source: str = "explicit",
    ) -> LinkTolerance:
        """Limits from deviations ``lower <= upper`` (m) about the nominal length ``nominal`` (m)."""
        if not lower <= upper:
            raise ConfigError(
                f"tolerance of {length!r}: lower deviation {lower * 1e3:g} mm exceeds the upper "
                f"{upper * 1e3:g} mm"
            )
        return cls(
            length,
            nominal,
            Tolerance(
                (nominal + lower, nominal + upper),
                distribution,
                shift,
                cpk,
                bounds=(0.0, math.inf),
            ),
            source,
        )

    @classmethod
    def general(
        cls,
        length: str,
        nominal: float,
        tolerance_class: str,
        *,
        distribution: Distribution = DEFAULT_DISTRIBUTION,
        shift: float = 0.0,
        cpk: float | None = None,
    ) -> LinkTolerance:
        """±deviation of ISO 2768-1 Table 1 in class ``tolerance_class`` (f, m, c, v) at ``nominal`` (m)."""
        letter = iso2768.parse_class(tolerance_class)
        deviation = iso2768.general_tolerance(letter, abs(nominal))
        return cls.from_deviations(
            length,
            nominal,
            -deviation,
            deviation,
            distribution=distribution,
            shift=shift,
            cpk=cpk,
            source=f"ISO 2768-1 {letter}",
        )


@dataclass(frozen=True)
class JointTolerance:
    """Radial clearance of a revolute joint: the range the fit allows and its distribution.

    Attributes:
        joint: revolute joint name (``link_a`` carries the bearing, ``link_b`` the pin).
        journal_radius: pin radius used by the dynamics, m (half the nominal diameter).
        tolerance: radial-clearance limits, m (≥ 0) and distribution (bounded below by 0).
        fit: the ISO 286 fit designation, e.g. ``"H8/g7"``, if the limits come from one.
        source: e.g. ``"ISO 286 Ø10 H8/g7"`` or ``"explicit"``.
    """

    joint: str
    journal_radius: float
    tolerance: Tolerance
    fit: str | None = None
    source: str = ""

    kind: Literal["clearance"] = field(default="clearance", init=False)
    unit: Literal["m"] = field(default="m", init=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "journal_radius", float(self.journal_radius))
        if not (math.isfinite(self.journal_radius) and self.journal_radius > 0):
            raise ConfigError(
                f"clearance tolerance of joint {self.joint!r}: journal radius must be > 0 m, "
                f"got {self.journal_radius!r}"
            )
        if self.tolerance.lower < 0:
            raise ConfigError(
                f"clearance tolerance of joint {self.joint!r}: the radial clearance must be "
                f">= 0, got a lower limit of {self.tolerance.lower * 1e6:g} µm (an interference "
                "fit, which jointplay does not model)"
            )
        _check_name(self.name)

    @property
    def name(self) -> str:
        """Input name, ``clearance_<joint>``."""
        return f"clearance_{self.joint}"

    @property
    def nominal(self) -> float:
        """Nominal radial clearance: the centre of the limits (the mean clearance of the fit), m."""
        return self.tolerance.centre

    @classmethod
    def from_fit(
        cls,
        joint: str,
        fit: str,
        diameter: float,
        *,
        distribution: Distribution = DEFAULT_DISTRIBUTION,
        shift: float = 0.0,
        cpk: float | None = None,
    ) -> JointTolerance:
        """Radial clearance limits of the ISO 286 fit ``fit`` (e.g. ``"H8/g7"``) at ``diameter`` (m).

        Raises:
            StandardsError: the fit is not defined at that size.
            ConfigError: the fit is not a clearance fit.
        """
        result = iso286.fit(fit, diameter)
        if result.fit_type != "clearance":
            raise ConfigError(
                f"joint {joint!r}: {result.designation} is a {result.fit_type} fit at "
                f"Ø{diameter * 1e3:g} mm (radial clearance {result.radial_clearance_min * 1e6:g} "
                f"… {result.radial_clearance_max * 1e6:g} µm); jointplay models clearance fits only"
            )
        return cls(
            joint,
            diameter / 2.0,
            Tolerance(
                (result.radial_clearance_min, result.radial_clearance_max),
                distribution,
                shift,
                cpk,
                bounds=(0.0, math.inf),
            ),
            fit=result.designation,
            source=f"ISO 286 Ø{diameter * 1e3:g} {result.designation}",
        )

    @classmethod
    def from_limits(
        cls,
        joint: str,
        lower: float,
        upper: float,
        *,
        journal_radius: float,
        distribution: Distribution = DEFAULT_DISTRIBUTION,
        shift: float = 0.0,
        cpk: float | None = None,
        source: str = "explicit",
    ) -> JointTolerance:
        """Explicit radial-clearance limits ``lower <= upper`` (m) and pin radius (m)."""
        return cls(
            joint,
            journal_radius,
            Tolerance((lower, upper), distribution, shift, cpk, bounds=(0.0, math.inf)),
            source=source,
        )


#: Any toleranced input.
InputTolerance = LinkTolerance | JointTolerance | QuantityTolerance


@dataclass(frozen=True)
class ToleranceSpec:
    """The toleranced inputs of a study, in a fixed order (their column order everywhere).

    Attributes:
        inputs: the toleranced quantities; names must be unique.
    """

    inputs: tuple[InputTolerance, ...]

    def __post_init__(self) -> None:
        object.__setattr__(self, "inputs", tuple(self.inputs))
        names = self.names
        duplicates = sorted({n for n in names if names.count(n) > 1})
        if duplicates:
            raise ConfigError(f"tolerance specification: inputs {duplicates} are given twice")
        for item in self.inputs:
            if not isinstance(item, LinkTolerance | JointTolerance | QuantityTolerance):
                raise ConfigError(
                    "tolerance specification: inputs must be LinkTolerance, JointTolerance or "
                    f"QuantityTolerance objects, got {type(item).__name__}"
                )

    @property
    def names(self) -> tuple[str, ...]:
        """Input names in order."""
        return tuple(item.name for item in self.inputs)

    def __len__(self) -> int:
        return len(self.inputs)

    def __getitem__(self, name: str) -> InputTolerance:
        for item in self.inputs:
            if item.name == name:
                return item
        raise ConfigError(f"no toleranced input {name!r}; inputs: {list(self.names)}")

    @property
    def nominal(self) -> FloatArray:
        """Nominal values, (k,) SI: basic lengths, mid-range clearances."""
        return np.array([item.nominal for item in self.inputs], dtype=float)

    @property
    def centre(self) -> FloatArray:
        """Centres of the limits, (k,)."""
        return np.array([item.tolerance.centre for item in self.inputs], dtype=float)

    @property
    def lower(self) -> FloatArray:
        """Lower limits, (k,)."""
        return np.array([item.tolerance.lower for item in self.inputs], dtype=float)

    @property
    def upper(self) -> FloatArray:
        """Upper limits, (k,)."""
        return np.array([item.tolerance.upper for item in self.inputs], dtype=float)

    @property
    def mean(self) -> FloatArray:
        """Means of the input distributions, (k,)."""
        return np.array([item.tolerance.mean for item in self.inputs], dtype=float)

    @property
    def std(self) -> FloatArray:
        """Standard deviations of the input distributions, (k,)."""
        return np.array([item.tolerance.std for item in self.inputs], dtype=float)

    def only(self, *kinds: str) -> ToleranceSpec:
        """The inputs of the given kinds (``"length"``, ``"clearance"``, ``"quantity"``)."""
        return ToleranceSpec(tuple(item for item in self.inputs if item.kind in kinds))

    def with_distribution(
        self, distribution: Distribution, *, cpk: float | None = None
    ) -> ToleranceSpec:
        """Every input with ``distribution`` (shifts kept; ``cpk`` for normal inputs)."""
        return ToleranceSpec(
            tuple(
                replace(
                    item,
                    tolerance=replace(
                        item.tolerance,
                        distribution=distribution,
                        cpk=cpk if distribution == "normal" else None,
                    ),
                )
                for item in self.inputs
            )
        )

    def describe(self) -> dict[str, dict[str, Any]]:
        """JSON-ready description of every input (SI)."""
        out: dict[str, dict[str, Any]] = {}
        for item in self.inputs:
            entry: dict[str, Any] = {"kind": item.kind, "unit": item.unit, "nominal": item.nominal}
            if isinstance(item, LinkTolerance):
                entry["length"] = item.length
            if isinstance(item, JointTolerance):
                entry["joint"] = item.joint
                entry["journal_radius"] = item.journal_radius
                entry["fit"] = item.fit
            entry.update(item.tolerance.describe())
            entry["source"] = item.source
            out[item.name] = entry
        return out

    @classmethod
    def from_mechanism(
        cls,
        mechanism: Mechanism,
        *,
        distribution: Distribution = DEFAULT_DISTRIBUTION,
        general_class: str | None = None,
        fits: bool = True,
    ) -> ToleranceSpec:
        """The specification the mechanism's own data give.

        Args:
            mechanism: a template mechanism for length tolerances (any mechanism for fits).
            distribution: distribution of every input.
            general_class: ISO 2768-1 class (f, m, c, v) for every template length that has
                no tolerance of its own (lengths under 0.5 mm, e.g. a zero offset, are skipped).
            fits: give every revolute joint with an ISO 286 fit designation a clearance input.
        """
        lengths: list[InputTolerance] = []
        nominal = _template_lengths(mechanism)
        given = {t.length for t in mechanism.tolerances}
        for item in mechanism.tolerances:
            if item.length not in nominal:
                raise ConfigError(
                    f"tolerance on unknown length {item.length!r}; the mechanism's template "
                    f"lengths are {sorted(nominal) or 'none (not a template mechanism)'}"
                )
            lengths.append(
                LinkTolerance.from_deviations(
                    item.length,
                    nominal[item.length],
                    item.lower,
                    item.upper,
                    distribution=distribution,
                    source=item.source or "explicit",
                )
            )
        if general_class is not None:
            for name, value in nominal.items():
                if name not in given and abs(value) >= 0.5e-3:
                    lengths.append(
                        LinkTolerance.general(name, value, general_class, distribution=distribution)
                    )
        joints: list[InputTolerance] = []
        if fits:
            for joint in mechanism.revolute_joints:
                if joint.fit is not None and joint.fit.fit:
                    joints.append(
                        JointTolerance.from_fit(
                            joint.name,
                            joint.fit.fit,
                            joint.fit.diameter,
                            distribution=distribution,
                        )
                    )
        return cls(tuple(_ordered(lengths, nominal)) + tuple(joints))


def _ordered(items: list[InputTolerance], nominal: Mapping[str, float]) -> list[InputTolerance]:
    order = {name: i for i, name in enumerate(nominal)}
    return sorted(items, key=lambda t: order.get(getattr(t, "length", ""), len(order)))


def _template_lengths(mechanism: Mechanism) -> dict[str, float]:
    spec = mechanism.template
    if isinstance(spec, TemplateSpec):
        return dict(spec.geometry.lengths)
    return {}


def _check_name(name: str) -> None:
    if not name or not all(ch.isalnum() or ch == "_" for ch in name):
        raise ConfigError(
            f"input name {name!r} must be non-empty and use only letters, digits and '_'"
        )


# --- the [tolerances] table of a configuration file -------------------------------------------

_TOP_KEYS = ("general", "distribution", "fits", "lengths", "joints")
_SHARED_KEYS = ("distribution", "shift", "cpk", "source")
_LENGTH_KEYS = ("lower", "upper", "class", *_SHARED_KEYS)
_JOINT_KEYS = ("fit", "diameter", "clearance_min", "clearance_max", *_SHARED_KEYS)


def parse_tolerance_table(table: Mapping[str, Any] | None, mechanism: Mechanism) -> ToleranceSpec:
    """Build the specification from a configuration's parsed ``[tolerances]`` table.

    Keys (quantities are strings with units, as everywhere in configuration files)::

        [tolerances]
        general = "c"              # ISO 2768-1 class for every length without its own entry
        distribution = "normal"    # default of every quantity: uniform | normal | triangular
        fits = true                # joints with an ISO 286 fit in [joints.<name>] get a
                                   # clearance input (default true)

        [tolerances.lengths.crank] # either explicit deviations ...
        lower = "-0.8 mm"
        upper = "0.8 mm"
        source = "ISO 2768-1 c"    # free text, recorded
        distribution = "normal"    # optional, per quantity
        shift = "0.1 mm"           # optional process mean shift
        cpk = 1.33                 # optional (normal only)

        [tolerances.lengths.coupler]
        class = "m"                # ... or an ISO 2768-1 class

        [tolerances.joints.A]      # clearance: a fit (diameter defaults to [joints.A]) ...
        fit = "H7/g6"
        diameter = "10 mm"
        [tolerances.joints.B]      # ... or explicit radial clearance limits
        clearance_min = "5 um"
        clearance_max = "30 um"

    A joint table with neither a fit nor limits only sets the distribution of the clearance
    that ``[joints.<name>]``'s fit gives.

    Args:
        table: the parsed TOML table (``None``: no ``[tolerances]`` table).
        mechanism: the mechanism it belongs to (nominal lengths, joint fits and diameters).

    Raises:
        ConfigError: unknown keys, missing units, contradictory entries; the message names
            the table and key.
    """
    raw = _mapping(table or {}, "tolerances")
    _reject_unknown(raw, _TOP_KEYS, "tolerances")
    default = _distribution(raw.get("distribution", DEFAULT_DISTRIBUTION), "tolerances")
    general = raw.get("general")
    if general is not None and not isinstance(general, str):
        raise ConfigError(f"tolerances.general must be an ISO 2768-1 class letter, got {general!r}")
    use_fits = raw.get("fits", True)
    if not isinstance(use_fits, bool):
        raise ConfigError(f"tolerances.fits must be true or false, got {use_fits!r}")
    nominal = _template_lengths(mechanism)
    inputs: list[InputTolerance] = []
    length_tables = _mapping(raw.get("lengths", {}), "tolerances.lengths")
    for name, entry_raw in length_tables.items():
        where = f"tolerances.lengths.{name}"
        if name not in nominal:
            raise ConfigError(
                f"{where}: unknown length {name!r}; the mechanism's template lengths are "
                f"{sorted(nominal) or 'none (not a template mechanism)'}"
            )
        inputs.append(
            _length_entry(_mapping(entry_raw, where), where, name, nominal[name], default)
        )
    if general is not None:
        for name, value in nominal.items():
            if name not in length_tables and abs(value) >= 0.5e-3:
                inputs.append(
                    _with_context(
                        lambda n=name, v=value: LinkTolerance.general(
                            n, v, general, distribution=default
                        ),
                        "tolerances.general",
                    )
                )
    inputs = _ordered(inputs, nominal)
    joint_tables = _mapping(raw.get("joints", {}), "tolerances.joints")
    revolute = {j.name: j for j in mechanism.revolute_joints}
    for name in joint_tables:
        if name not in revolute:
            raise ConfigError(
                f"tolerances.joints.{name}: unknown revolute joint {name!r}; revolute joints: "
                f"{sorted(revolute)}"
            )
    for name, joint in revolute.items():
        if name in joint_tables:
            where = f"tolerances.joints.{name}"
            inputs.append(_joint_entry(_mapping(joint_tables[name], where), where, joint, default))
        elif use_fits and joint.fit is not None and joint.fit.fit:
            fit, diameter = joint.fit.fit, joint.fit.diameter
            inputs.append(
                _with_context(
                    lambda n=name, f=fit, d=diameter: JointTolerance.from_fit(
                        n, f, d, distribution=default
                    ),
                    f"joints.{name}",
                )
            )
    return ToleranceSpec(tuple(inputs))


def _length_entry(
    entry: Mapping[str, Any], where: str, name: str, nominal: float, default: Distribution
) -> LinkTolerance:
    _reject_unknown(entry, _LENGTH_KEYS, where)
    distribution, shift, cpk, source = _shared(entry, where, default)
    if "class" in entry:
        if "lower" in entry or "upper" in entry:
            raise ConfigError(f"{where}: give either class or lower/upper, not both")
        return _with_context(
            lambda: LinkTolerance.general(
                name,
                nominal,
                str(entry["class"]),
                distribution=distribution,
                shift=shift,
                cpk=cpk,
            ),
            where,
        )
    if "lower" not in entry or "upper" not in entry:
        raise ConfigError(
            f'{where}: give lower and upper deviations (e.g. lower = "-0.8 mm") or an '
            'ISO 2768-1 class (class = "c")'
        )
    lower = parse_quantity(entry["lower"], "m", field=f"{where}.lower")
    upper = parse_quantity(entry["upper"], "m", field=f"{where}.upper")
    return _with_context(
        lambda: LinkTolerance.from_deviations(
            name,
            nominal,
            lower,
            upper,
            distribution=distribution,
            shift=shift,
            cpk=cpk,
            source=source or "explicit",
        ),
        where,
    )


def _joint_entry(
    entry: Mapping[str, Any], where: str, joint: RevoluteJoint, default: Distribution
) -> JointTolerance:
    _reject_unknown(entry, _JOINT_KEYS, where)
    distribution, shift, cpk, source = _shared(entry, where, default)
    fit_data = joint.fit
    diameter = (
        parse_quantity(entry["diameter"], "m", field=f"{where}.diameter")
        if "diameter" in entry
        else (fit_data.diameter if fit_data is not None else None)
    )
    has_limits = "clearance_min" in entry or "clearance_max" in entry
    if has_limits:
        if "fit" in entry:
            raise ConfigError(f"{where}: give either a fit or clearance_min/max, not both")
        if "clearance_min" not in entry or "clearance_max" not in entry:
            raise ConfigError(f"{where}: give both clearance_min and clearance_max (radial)")
        if diameter is None:
            raise ConfigError(
                f"{where}: the pin diameter is needed for the dynamics; give diameter here or "
                f"in [joints.{joint.name}]"
            )
        lower = parse_quantity(entry["clearance_min"], "m", field=f"{where}.clearance_min")
        upper = parse_quantity(entry["clearance_max"], "m", field=f"{where}.clearance_max")
        return _with_context(
            lambda: JointTolerance.from_limits(
                joint.name,
                lower,
                upper,
                journal_radius=diameter / 2.0,
                distribution=distribution,
                shift=shift,
                cpk=cpk,
                source=source or "explicit",
            ),
            where,
        )
    fit = entry.get("fit", fit_data.fit if fit_data is not None else None)
    if not isinstance(fit, str) or diameter is None:
        raise ConfigError(
            f"{where}: needs an ISO 286 fit and a diameter (here or in [joints.{joint.name}]) "
            "or clearance_min and clearance_max"
        )
    result = _with_context(
        lambda: JointTolerance.from_fit(
            joint.name, fit, diameter, distribution=distribution, shift=shift, cpk=cpk
        ),
        where,
    )
    return replace(result, source=source) if source else result


def _shared(
    entry: Mapping[str, Any], where: str, default: Distribution
) -> tuple[Distribution, float, float | None, str]:
    distribution = _distribution(entry.get("distribution", default), where)
    shift = parse_quantity(entry["shift"], "m", field=f"{where}.shift") if "shift" in entry else 0.0
    cpk = entry.get("cpk")
    if cpk is not None and (isinstance(cpk, bool) or not isinstance(cpk, int | float)):
        raise ConfigError(f"{where}.cpk must be a number, got {cpk!r}")
    source = entry.get("source", "")
    if not isinstance(source, str):
        raise ConfigError(f"{where}.source must be a string, got {source!r}")
    return distribution, shift, None if cpk is None else float(cpk), source


def _distribution(value: Any, where: str) -> Distribution:
    if value not in DISTRIBUTIONS:
        raise ConfigError(
            f"{where}.distribution must be one of {', '.join(DISTRIBUTIONS)}, got {value!r}"
        )
    return value


def _mapping(value: Any, where: str) -> Mapping[str, Any]:
    if not isinstance(value, Mapping):
        raise ConfigError(f"{where} must be a table, got {type(value).__name__}")
    return value


def _reject_unknown(entry: Mapping[str, Any], known: Sequence[str], where: str) -> None:
    unknown = sorted(set(entry) - set(known))
    if unknown:
        raise ConfigError(f"{where}: unknown key(s) {unknown}; expected some of {list(known)}")


def _with_context(build: Any, where: str) -> Any:
    """Call ``build()``; prefix any jointplay error with the table it came from."""
    try:
        return build()
    except JointplayError as exc:
        raise type(exc)(f"{where}: {exc}") from None


def mechanism_tolerances(
    table: Mapping[str, Any], mechanism: Mechanism
) -> tuple[LengthTolerance, ...]:
    """Validate a whole ``[tolerances]`` table and return the mechanism's length tolerances.

    Called by :func:`jointplay.io.config.parse_config`, so every command checks the extended
    keys (classes, distributions, joints) the same way; class entries become explicit limits.
    """
    spec = parse_tolerance_table(table, mechanism)
    return tuple(
        LengthTolerance(
            item.length,
            item.tolerance.lower - item.nominal,
            item.tolerance.upper - item.nominal,
            item.source,
        )
        for item in spec.inputs
        if isinstance(item, LinkTolerance)
    )


def load_study_spec(
    preset: str | None = None, config: Path | str | None = None
) -> tuple[Mechanism, ToleranceSpec]:
    """Load a mechanism (preset or TOML file) and its full tolerance specification."""
    from jointplay.io import config as config_io  # the io layer builds on the model only

    mechanism = config_io.load_mechanism(preset, config)
    # parse_config has validated the table already (with the file's name in any message).
    return mechanism, parse_tolerance_table(config_io.tolerance_table(preset, config), mechanism)
