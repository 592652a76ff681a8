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
  cannot be negative; the truncated mass is 1e-4 or less for the default settings): it is
  the truncated normal with standardised bounds ``(bound − mean)/σ`` (as
  :data:`scipy.stats.truncnorm`, in closed form).

The mechanism's own data give the default specification (:meth:`ToleranceSpec.from_mechanism`):
its ``tolerances`` (the ``[tolerances.lengths.<name>]`` tables) and the ISO 286 fits of its
joints. The extended TOML form of a configuration's ``[tolerances]`` table (distributions,
shifts, Cpk, general classes, joint clearance tables) is read in the file layer, by
:func:`jointplay.io.tolerances.parse_tolerance_table`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any, Literal

from jointplay.errors import ConfigError
from jointplay.model.mechanism import Mechanism
from jointplay.model.templates import TemplateSpec
from jointplay.tolerance import iso286, iso2768

__all__ = [
    "DEFAULT_DISTRIBUTION",
    "DISTRIBUTIONS",
    "Distribution",
    "InputTolerance",
    "JointTolerance",
    "LinkTolerance",
    "QuantityTolerance",
    "Tolerance",
    "ToleranceSpec",
    "in_template_order",
    "template_lengths",
]

if TYPE_CHECKING:  # NumPy is imported where arrays are made: reading a mechanism needs none
    import numpy as np
    from numpy.typing import ArrayLike, NDArray

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
        return self.mode + self.sigma * _truncated_normal_moments(*self._standard_bounds())[0]

    @property
    def std(self) -> float:
        """Standard deviation of the distribution (truncation of a normal included)."""
        sigma = self.sigma
        if self.distribution != "normal" or sigma == 0.0:
            return sigma
        return sigma * _truncated_normal_moments(*self._standard_bounds())[1]

    def _standard_bounds(self) -> tuple[float, float]:
        """``bounds`` in standard deviations of the normal process from its mean."""
        sigma = self.sigma
        return (self.bounds[0] - self.mode) / sigma, (self.bounds[1] - self.mode) / sigma

    def ppf(self, u: ArrayLike) -> FloatArray:
        """The quantity at cumulative probabilities ``u`` ∈ (0, 1) (inverse CDF), SI."""
        import numpy as np

        u = np.asarray(u, dtype=float)
        h, mode = self.half_width, self.mode
        if self.distribution == "uniform":
            return np.asarray(mode - h + 2.0 * h * u, dtype=float)
        if self.distribution == "triangular":
            upper_half = u >= 0.5
            t = np.where(upper_half, 1.0 - u, u)
            offset = h * (np.sqrt(2.0 * t) - 1.0)
            return np.asarray(np.where(upper_half, mode - offset, mode + offset), dtype=float)
        if self.sigma == 0.0:
            return np.full(u.shape, mode)
        values = _truncated_normal_ppf(u, mode, self.sigma, *self.bounds)
        return np.asarray(np.clip(values, *self.bounds), dtype=float)

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


def _truncated_normal_moments(alpha: float, beta: float) -> tuple[float, float]:
    """Mean and standard deviation of the standard normal truncated to [α, β] (Johnson, Kotz &
    Balakrishnan, *Continuous Univariate Distributions* 1, §10.1): with Z = Φ(β) − Φ(α),
    mean = (φ(α) − φ(β))/Z and variance = 1 + (αφ(α) − βφ(β))/Z − mean²; a window above
    the mean is mirrored below it (Φ small and exact there)."""
    from scipy.special import ndtr

    if alpha > 0.0:
        mean, std = _truncated_normal_moments(-beta, -alpha)
        return -mean, std

    def density(x: float) -> float:
        return math.exp(-0.5 * x * x) / math.sqrt(2.0 * math.pi) if math.isfinite(x) else 0.0

    def x_density(x: float) -> float:
        return x * density(x) if math.isfinite(x) else 0.0

    mass = float(ndtr(beta) - ndtr(alpha))
    mean = (density(alpha) - density(beta)) / mass
    variance = 1.0 + (x_density(alpha) - x_density(beta)) / mass - mean * mean
    return mean, math.sqrt(max(variance, 0.0))


def _truncated_normal_ppf(
    u: FloatArray, mean: float, sigma: float, lower: float, upper: float
) -> FloatArray:
    """Inverse CDF of the normal (``mean``, ``sigma``) truncated to [``lower``, ``upper``]:
    x = μ + σ Φ⁻¹(Φ(α) + u (Φ(β) − Φ(α))), α, β the standardised limits — closed form, as
    :data:`scipy.stats.truncnorm` gives it but ~100× faster (``ndtr``/``ndtri`` only). A
    window above the mean is mirrored below it, so that Φ is evaluated where it is small and
    exact.
    """
    import numpy as np
    from scipy.special import ndtr, ndtri

    alpha, beta = (lower - mean) / sigma, (upper - mean) / sigma
    if alpha > 0.0:  # the whole window above the mean: x = μ − σ ppf(1 − u) of the mirror
        return mean - sigma * (_truncated_normal_ppf(1.0 - u, 0.0, 1.0, -beta, -alpha))
    low, high = ndtr(alpha), ndtr(beta)
    return np.asarray(mean + sigma * ndtri(low + u * (high - low)), dtype=float)


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
        import numpy as np

        return np.array([item.nominal for item in self.inputs], dtype=float)

    @property
    def centre(self) -> FloatArray:
        """Centres of the limits, (k,)."""
        import numpy as np

        return np.array([item.tolerance.centre for item in self.inputs], dtype=float)

    @property
    def lower(self) -> FloatArray:
        """Lower limits, (k,)."""
        import numpy as np

        return np.array([item.tolerance.lower for item in self.inputs], dtype=float)

    @property
    def upper(self) -> FloatArray:
        """Upper limits, (k,)."""
        import numpy as np

        return np.array([item.tolerance.upper for item in self.inputs], dtype=float)

    @property
    def mean(self) -> FloatArray:
        """Means of the input distributions, (k,)."""
        import numpy as np

        return np.array([item.tolerance.mean for item in self.inputs], dtype=float)

    @property
    def std(self) -> FloatArray:
        """Standard deviations of the input distributions, (k,)."""
        import numpy as np

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
        nominal = template_lengths(mechanism)
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
        return cls(tuple(in_template_order(lengths, nominal)) + tuple(joints))


def in_template_order(
    items: list[InputTolerance], nominal: Mapping[str, float]
) -> list[InputTolerance]:
    """``items`` with the length inputs in the order of the template lengths ``nominal``."""
    order = {name: i for i, name in enumerate(nominal)}
    return sorted(items, key=lambda t: order.get(getattr(t, "length", ""), len(order)))


def template_lengths(mechanism: Mechanism) -> dict[str, float]:
    """The nominal template lengths of ``mechanism`` by name, m (empty without a template)."""
    spec = mechanism.template
    if isinstance(spec, TemplateSpec):
        return dict(spec.geometry.lengths)
    return {}


def _check_name(name: str) -> None:
    if not name or not all(ch.isalnum() or ch == "_" for ch in name):
        raise ConfigError(
            f"input name {name!r} must be non-empty and use only letters, digits and '_'"
        )
