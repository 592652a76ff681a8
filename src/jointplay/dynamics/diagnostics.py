"""Plausibility diagnostics: plain warnings when a simulated result is not physical.

Every simulation is checked, and each finding is a :class:`Diagnostic` — level, code, joint,
value, limit and a sentence — that the summary lists, the console prints (one line each) and
reports show in a callout. The checks, their codes and limits:

=====================================  ==========================================================
code                                   fires when
=====================================  ==========================================================
``penetration-exceeds-clearance``      a pin sinks deeper into its bearing than the radial
                                       clearance: the contact stiffness is far too low for the
                                       load, and the "clearance joint" is a soft spring
``penetration-exceeds-elastic``        a pin sinks deeper than :data:`ELASTIC_FACTOR` times
                                       the elastic approach that the joint's own Hertz law
                                       gives at its peak force: the contact is far softer than
                                       the joint's materials (raised even when the clearance
                                       is larger than the penetration)
``hertz-validity``                     the Hertz line-contact half-width at the peak force
                                       exceeds :data:`HERTZ_VALIDITY` of the pin radius: the
                                       half-space theory behind Hertz's stiffness, the paper's
                                       ECS estimates and the contact pressure no longer holds
``contact-pressure-exceeds-allowable``  the peak Hertz pressure of the line contact (force over
                                       the joint's bearing width) exceeds the material's
                                       allowable pressure
``contact-pressure-unchecked``         (info) the material has no yield strength or allowable
                                       pressure, so the pressure could not be checked
``force-far-above-ideal``              (info) a joint force peaks above
                                       :data:`IDEAL_FORCE_FACTOR` times the ideal-joint force
``start-transient-dominates``          the reported peak is a start-up artefact (only when no
                                       start-up revolution was left out): it lies in the first
                                       revolution and exceeds the later revolutions' peaks by
                                       more than :data:`TRANSIENT_RATIO`, or only one revolution
                                       was simulated from a non-steady start and the peak lies
                                       in its first :data:`START_WINDOW_DEG`
``not-periodic``                       (info) the once-per-revolution Poincaré section does not
                                       repeat (see :mod:`jointplay.dynamics.cycles`)
``dry-undetermined``                   (info) dry joints, and too few analysed revolutions for
                                       the periodicity check: the peaks may be draws of an
                                       irregular motion
``not-settled``                        the start-up has not died out: the first analysed
                                       revolution's peak lies outside the range of the later
                                       ones by more than :data:`SETTLED_CHANGE` of their mean
``transmission-angle-low``             the four-bar's transmission angle leaves 40°–140° (the
                                       design guideline, :data:`~jointplay.kinematics.fourbar.MIN_TRANSMISSION_ANGLE_DEG`):
                                       the coupler pushes the rocker along its length, joint
                                       forces grow and clearance matters more
``energy-drift``                       the energy balance (kinetic + potential − motor work +
                                       contact work) drifts by more than
                                       :data:`ENERGY_TOLERANCE` of the largest energy: the
                                       integration is not accurate enough
=====================================  ==========================================================

The elastic approach is Hertz's for the joint's radii and materials,
δ_H = (F / K)^(2/3), K = (4/3) E* √R (docs/contact-laws.md §3.1): the stiffness law
``hertz`` uses; the other geometric laws give approaches within a factor of
about 1.3 of it at µm clearances (docs/contact.md), so :data:`ELASTIC_FACTOR` leaves room
for them and for the damping.

The contact pressure is Hertz's for two parallel cylinders in internal (conformal) contact:
line load f = F / L, equivalent radius R = R_J R_B / (R_B − R_J), half-width
b = √(4 f R / (π E*)) and peak pressure p₀ = 2 f / (π b) = √(f E* / (π R)) (Johnson,
*Contact Mechanics*, 1985, eqs. 4.43–4.45; docs/contact-laws.md §3.2).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import asdict, dataclass, field, replace
from typing import Any, Literal

from jointplay.contact.hertz import (
    conformal_radius,
    effective_modulus,
    line_contact_half_width,
    point_contact_stiffness,
)
from jointplay.errors import name_settings
from jointplay.kinematics import fourbar
from jointplay.model.mechanism import Material, Mechanism
from jointplay.model.templates import FourBarGeometry, TemplateSpec

Level = Literal["info", "warning"]

#: A joint force this many times the ideal-joint peak is reported (information).
IDEAL_FORCE_FACTOR = 10.0
#: The first revolution's peak beyond this ratio to the later ones' is a start-up artefact.
TRANSIENT_RATIO = 1.5
#: With a single revolution from a non-steady start, a peak this early is a start-up artefact.
START_WINDOW_DEG = 30.0
#: How far (relative to the later revolutions' mean) the first analysed revolution's peak may
#: lie outside their range before the motion counts as "not settled".
SETTLED_CHANGE = 0.05
#: A penetration beyond this many times the joint's Hertz approach at its peak force is not
#: elastic (the geometric laws sit within ~1.3 of Hertz's at µm clearances: docs/contact.md).
ELASTIC_FACTOR = 3.0
#: Largest contact half-width, as a share of the pin radius, at which Hertz theory is used:
#: the half-space idealisation needs a contact small against the radii (Johnson 1985, §4.1);
#: at b = 0.3 R the contact arc already spans ±17°.
HERTZ_VALIDITY = 0.3
#: Largest acceptable drift of the energy balance, relative to the largest energy.
ENERGY_TOLERANCE = 1e-3


@dataclass(frozen=True)
class Diagnostic:
    """One finding about a simulated result.

    Attributes:
        level: ``"warning"`` (the result is not physical or not what it seems) or ``"info"``.
        code: stable identifier (see the module docstring).
        joint: the joint concerned, or ``None`` for the whole mechanism.
        value: the offending value (the unit is in the message).
        limit: the limit it was compared with (same unit).
        message: one sentence saying what is wrong and what to do; the settings it advises
            on by their names in the Python API (``settle``, ``rtol``).
        template: the message with each setting it names as a ``{setting}`` field
            (:func:`~jointplay.errors.name_settings`), ``None`` when it names none: each
            caller shows its own names for them (:meth:`named`; the command line its
            options'), as :class:`~jointplay.errors.SettingError`.
    """

    level: Level
    code: str
    joint: str | None
    value: float
    limit: float
    message: str
    template: str | None = field(default=None, compare=False, repr=False)

    @classmethod
    def advising(
        cls, level: Level, code: str, joint: str | None, value: float, limit: float, template: str
    ) -> Diagnostic:
        """A finding whose advice names settings: ``template`` with ``{setting}`` fields."""
        return cls(level, code, joint, value, limit, name_settings(template), template)

    def named(self, names: Mapping[str, str]) -> Diagnostic:
        """The same finding, its settings called by ``names`` (setting → name) where given."""
        if self.template is None:
            return self
        return replace(self, message=name_settings(self.template, names))

    def as_dict(self) -> dict[str, Any]:
        record = asdict(self)
        del record["template"]
        return record

    def line(self, names: Mapping[str, str] | None = None) -> str:
        """One console line; ``names``: what to call the settings it advises on."""
        where = f" [{self.joint}]" if self.joint else ""
        message = self.named(names).message if names else self.message
        return f"{self.level}: {self.code}{where}: {message}"


def line_contact_pressure(
    force: float,
    width: float,
    journal_radius: float,
    clearance: float,
    bearing: Material,
    pin: Material,
) -> float:
    """Peak Hertz pressure p₀ of a pin loaded against its bearing, Pa.

    Args:
        force: normal contact force, N (>= 0).
        width: length of the contact line (the bearing width), m.
        journal_radius: pin radius R_J, m.
        clearance: radial clearance R_B − R_J, m (> 0).
        bearing, pin: the two materials.
    """
    if force <= 0.0:
        return 0.0
    modulus = effective_modulus(
        bearing.youngs_modulus, bearing.poisson_ratio, pin.youngs_modulus, pin.poisson_ratio
    )
    radius = conformal_radius(journal_radius, journal_radius + clearance)
    line_load = force / width
    half_width = line_contact_half_width(line_load, radius, modulus)
    return 2.0 * line_load / (math.pi * half_width)  # Johnson (1985) eq. 4.45


def check_penetration(joint: str, penetration: float, clearance: float) -> Diagnostic | None:
    """``penetration-exceeds-clearance`` when the deepest penetration exceeds the clearance."""
    if penetration <= clearance:
        return None
    return Diagnostic(
        "warning",
        "penetration-exceeds-clearance",
        joint,
        penetration,
        clearance,
        f"the pin penetrates its bearing by {penetration * 1e6:.3g} µm, more than the "
        f"{clearance * 1e6:.3g} µm radial clearance: the contact stiffness is far too low "
        "for the load; use a stiffness from the joint's geometry (e.g. a stiffness law)",
    )


def hertz_approach(
    force: float, journal_radius: float, clearance: float, bearing: Material, pin: Material
) -> float:
    """The elastic approach δ_H = (F / K)^(2/3) of the joint's Hertz law at ``force`` (N), m,
    K = (4/3) E* √R with the conformal radius R (docs/contact-laws.md §3.1)."""
    if force <= 0.0:
        return 0.0
    modulus = effective_modulus(
        bearing.youngs_modulus, bearing.poisson_ratio, pin.youngs_modulus, pin.poisson_ratio
    )
    radius = conformal_radius(journal_radius, journal_radius + clearance)
    return float((force / point_contact_stiffness(radius, modulus)) ** (2.0 / 3.0))


def check_elastic(
    joint: str, penetration: float, approach: float, force: float
) -> Diagnostic | None:
    """``penetration-exceeds-elastic`` when the deepest penetration exceeds
    :data:`ELASTIC_FACTOR` times the Hertz approach ``approach`` (m) at the peak ``force``."""
    if not approach > 0.0 or penetration <= ELASTIC_FACTOR * approach:
        return None
    return Diagnostic(
        "warning",
        "penetration-exceeds-elastic",
        joint,
        penetration,
        ELASTIC_FACTOR * approach,
        f"the pin penetrates its bearing by {penetration * 1e6:.3g} µm, "
        f"{penetration / approach:.3g} times the {approach * 1e6:.3g} µm elastic approach of "
        f"the joint's own Hertz law at its peak force {force:.4g} N: the contact is far "
        "softer than the joint's materials; use a stiffness from the joint's geometry "
        "(the default contact, or a stiffness law)",
    )


def check_hertz_validity(
    joint: str, force: float, width: float, journal_radius: float, clearance: float,
    bearing: Material, pin: Material,
) -> Diagnostic | None:  # fmt: skip
    """``hertz-validity`` when the line-contact half-width at ``force`` (N) over ``width``
    (m) exceeds :data:`HERTZ_VALIDITY` of the pin radius."""
    if force <= 0.0:
        return None
    modulus = effective_modulus(
        bearing.youngs_modulus, bearing.poisson_ratio, pin.youngs_modulus, pin.poisson_ratio
    )
    radius = conformal_radius(journal_radius, journal_radius + clearance)
    half_width = line_contact_half_width(force / width, radius, modulus)
    share = half_width / journal_radius
    if share <= HERTZ_VALIDITY:
        return None
    return Diagnostic(
        "warning",
        "hertz-validity",
        joint,
        share,
        HERTZ_VALIDITY,
        f"at its peak force {force:.4g} N the contact half-width is {half_width * 1e3:.3g} mm, "
        f"{share:.2g} of the pin radius (Hertz theory holds to about {HERTZ_VALIDITY:g}): "
        "Hertz's stiffness, the ECS estimates and the contact pressure are outside their "
        "validity here",
    )


def check_pressure(
    joint: str, pressure: float, material: Material, force: float
) -> Diagnostic | None:
    """``contact-pressure-exceeds-allowable`` (or ``-unchecked`` without a limit)."""
    limit = material.contact_pressure_limit
    if limit is None:
        return Diagnostic(
            "info",
            "contact-pressure-unchecked",
            joint,
            pressure,
            math.nan,
            f"peak contact pressure {pressure / 1e6:.4g} MPa not checked: material "
            f"{material.name!r} has no yield_strength or allowable_contact_pressure",
        )
    if pressure <= limit:
        return None
    return Diagnostic(
        "warning",
        "contact-pressure-exceeds-allowable",
        joint,
        pressure,
        limit,
        f"peak Hertz contact pressure {pressure / 1e6:.4g} MPa (at {force:.4g} N) exceeds the "
        f"allowable {limit / 1e6:.4g} MPa of {material.name!r}: the surfaces would yield",
    )


def check_force_against_ideal(joint: str, peak: float, ideal: float) -> Diagnostic | None:
    """``force-far-above-ideal`` when a joint's peak force is far above the ideal joint's."""
    if not ideal > 0.0 or peak <= IDEAL_FORCE_FACTOR * ideal:
        return None
    return Diagnostic(
        "info",
        "force-far-above-ideal",
        joint,
        peak,
        IDEAL_FORCE_FACTOR * ideal,
        f"the force peaks at {peak:.4g} N, {peak / ideal:.3g} times the ideal joint's "
        f"{ideal:.4g} N: impacts in the clearance dominate",
    )


def check_start_transient(
    quantity: str,
    per_revolution: Sequence[float],
    *,
    steady_start: bool,
    first_peak_crank_deg: float | None = None,
) -> Diagnostic | None:
    """``start-transient-dominates`` for a quantity whose peak is a start-up artefact.

    Args:
        quantity: the column (e.g. ``"F_A"``).
        per_revolution: its peak in every simulated revolution, the start-up included.
        steady_start: the motion started from the steady (ideal-joint) state.
        first_peak_crank_deg: with a single revolution, the crank angle turned since the
            start when its peak occurred, deg.
    """
    if len(per_revolution) >= 2:
        first, later = per_revolution[0], max(per_revolution[1:])
        if later > 0.0 and first > TRANSIENT_RATIO * later:
            return Diagnostic.advising(
                "warning",
                "start-transient-dominates",
                None,
                first,
                TRANSIENT_RATIO * later,
                f"{quantity} peaks at {first:.4g} in the first revolution, "
                f"{first / later:.3g} times its later peaks ({later:.4g}): a start-up "
                "artefact; read the steady-running statistics ({settle})",
            )
        return None
    if (
        not steady_start
        and first_peak_crank_deg is not None
        and first_peak_crank_deg < START_WINDOW_DEG
    ):
        return Diagnostic.advising(
            "warning",
            "start-transient-dominates",
            None,
            first_peak_crank_deg,
            START_WINDOW_DEG,
            f"{quantity} peaks {first_peak_crank_deg:.3g}° after the start of a single "
            "revolution: likely a start-up artefact; simulate more start-up revolutions "
            "({settle})",
        )
    return None


def check_settled(quantity: str, per_revolution: Sequence[float]) -> Diagnostic | None:
    """``not-settled`` when a quantity's first analysed revolution stands out of the rest.

    A running mechanism with clearance need not repeat, so revolution-to-revolution scatter
    is no sign of a start-up; a start-up that has not died out is: the first analysed
    revolution's peak lies outside the range of the later ones by more than
    :data:`SETTLED_CHANGE` of their mean. Needs three analysed revolutions.
    """
    if len(per_revolution) < 3:
        return None
    first, later = per_revolution[0], per_revolution[1:]
    low, high = min(later), max(later)
    outside = max(first - high, low - first, 0.0)
    mean = sum(later) / len(later)
    change = outside / max(abs(mean), 1e-300)
    if change <= SETTLED_CHANGE:
        return None
    return Diagnostic.advising(
        "warning",
        "not-settled",
        None,
        change,
        SETTLED_CHANGE,
        f"{quantity}'s peak in the first analysed revolution ({first:.4g}) lies "
        f"{change:.1%} outside the range of the later ones ({low:.4g} to {high:.4g}): the "
        "motion is still changing from its start; raise {settle}",
    )


def check_periodic(
    verdict: str,
    period: int | None,
    revolutions: int,
    *,
    settles_after: int | None = None,
    converging: bool = False,
) -> Diagnostic | None:
    """``not-periodic`` (information) when the Poincaré section does not repeat.

    The message tells a start-up transient from rattling: ``settles_after`` (the section is
    periodic once its first revolutions are left out) or ``converging`` (its steps shrink)
    mean the motion is still settling, not rattling (:class:`~jointplay.dynamics.cycles.
    Periodicity`).
    """
    if period is not None or verdict != "not periodic":
        return None
    where = (
        f"the once-per-revolution Poincaré section does not repeat over {revolutions} revolutions"
    )
    if settles_after is not None:
        reason = (
            f"it repeats from revolution {settles_after + 1} on: a start-up transient, not "
            f"rattling; raise {{settle}} by {settles_after}"
        )
    elif converging:
        reason = (
            "its steps shrink from revolution to revolution: a start-up transient still "
            "settling, not rattling; raise {settle}"
        )
    else:
        reason = (
            "the pins rattle differently every revolution: each peak is a draw; read the "
            "distribution of the per-revolution peaks (mean, 95th percentile), and sample the "
            "motion's states with an ensemble of runs (docs/performance.md, \"Accuracy of "
            'irregular (chaotic) running")'
        )
    return Diagnostic.advising(
        "info", "not-periodic", None, float(revolutions), math.nan, f"{where}: {reason}"
    )


#: The fewest analysed revolutions the periodicity check gives a verdict on (three Poincaré
#: points: :attr:`jointplay.dynamics.cycles.Periodicity.verdict`).
PERIODICITY_REVOLUTIONS = 3


def check_dry_undetermined(
    verdict: str, revolutions: int, dry_joints: Sequence[str]
) -> Diagnostic | None:
    """``dry-undetermined`` (information) when dry joints ran too few revolutions for the
    periodicity check: dry pins often rattle irregularly (docs/performance.md, "Accuracy of
    irregular (chaotic) running"), and then every peak is a draw that the run cannot flag."""
    if verdict != "undetermined" or not dry_joints:
        return None
    return Diagnostic.advising(
        "info",
        "dry-undetermined",
        None,
        float(revolutions),
        float(PERIODICITY_REVOLUTIONS),
        f"dry joints ({', '.join(dry_joints)}) and {revolutions} analysed revolution(s): too "
        "few to tell periodic running from rattling; dry pins often rattle, and then each "
        "peak is a draw — run at least 12 revolutions (the per-revolution peak distributions "
        "of irregular running), or an ensemble (--ensemble 12)",
    )


def check_energy(residual: float) -> Diagnostic | None:
    """``energy-drift`` when the energy balance drifts (relative to the largest energy)."""
    if not residual > ENERGY_TOLERANCE:
        return None
    return Diagnostic.advising(
        "warning",
        "energy-drift",
        None,
        residual,
        ENERGY_TOLERANCE,
        f"the energy balance drifts by {residual:.2e} of the largest energy: the "
        "integration is not accurate enough; tighten {rtol}",
    )


def check_transmission_angle(mechanism: Mechanism) -> Diagnostic | None:
    """``transmission-angle-low`` when a four-bar's transmission angle μ leaves the design
    range 40°–140° over the crank turn (Norton, *Design of Machinery*, §3.3; see
    :data:`jointplay.kinematics.fourbar.MIN_TRANSMISSION_ANGLE_DEG`).

    Value and limit are in degrees: the worst of μ_min and 180° − μ_max, and 40°. Other
    mechanisms (slider-crank, general) are not checked.
    """
    spec = mechanism.template
    if not (isinstance(spec, TemplateSpec) and isinstance(spec.geometry, FourBarGeometry)):
        return None
    limit = fourbar.MIN_TRANSMISSION_ANGLE_DEG
    worst = math.degrees(fourbar.transmission_angle_deviation(spec.geometry))
    if worst >= limit:
        return None
    low, high = (math.degrees(v) for v in fourbar.transmission_angle_range(spec.geometry))
    return Diagnostic(
        "warning",
        "transmission-angle-low",
        None,
        worst,
        limit,
        f"the transmission angle runs {low:.1f}°–{high:.1f}°, outside the 40°–140° design "
        f"guideline (Norton, Design of Machinery, §3.3): at {worst:.1f}° the coupler pushes "
        "the rocker mostly along its length, so joint forces grow and clearance and friction "
        "matter more; change the link lengths to widen it",
    )


def collect(findings: Sequence[Diagnostic | None]) -> list[Diagnostic]:
    """The findings that are not ``None``, one per (code, joint), warnings first."""
    seen: dict[tuple[str, str | None], Diagnostic] = {}
    for finding in findings:
        if finding is not None and (finding.code, finding.joint) not in seen:
            seen[(finding.code, finding.joint)] = finding
    return sorted(seen.values(), key=lambda d: (d.level != "warning", d.code, d.joint or ""))


def simulation_findings(
    diagnostics: Sequence[Diagnostic], mechanism: Mechanism
) -> list[Diagnostic]:
    """A simulation's ``diagnostics`` and the mechanism's own (its transmission angle), once
    each, warnings first: what ``jointplay simulate`` and ``jointplay explore`` report."""
    return collect([*diagnostics, check_transmission_angle(mechanism)])


def as_records(diagnostics: Sequence[Diagnostic]) -> list[Mapping[str, Any]]:
    """JSON-ready records ``{"level", "code", "joint", "value", "limit", "message"}``."""
    return [d.as_dict() for d in diagnostics]
