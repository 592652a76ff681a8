"""Clearance revolute joints: which joints rattle, by how much, and with which laws."""

from __future__ import annotations

import math
from dataclasses import dataclass

from jointplay.contact.friction import FrictionLaw
from jointplay.contact.laws import ContactLaw
from jointplay.errors import ConfigError

#: The smallest radial clearance modelled, m (1 nm): below it the joint is ideal in practice
#: and the contact arithmetic (onset tolerance, eccentricity ratios) underflows.
MIN_CLEARANCE = 1e-9


@dataclass(frozen=True)
class ClearanceJoint:
    """A revolute joint modelled as a pin moving freely in its bearing until it hits the wall.

    Attributes:
        joint: name of a revolute joint of the mechanism (its ``link_a`` carries the bearing,
            its ``link_b`` the journal).
        clearance: radial clearance c = R_bearing − R_journal, m (> 0).
        journal_radius: pin radius R_J, m (> 0); the bearing radius is R_J + c.
        law: normal contact force law (an instance from :mod:`jointplay.contact.laws`).
        friction: friction law, or ``None`` (frictionless, the default).
    """

    joint: str
    clearance: float
    journal_radius: float
    law: ContactLaw
    friction: FrictionLaw | None = None

    def __post_init__(self) -> None:
        where = f"clearance joint {self.joint!r}"
        if not isinstance(self.joint, str) or not self.joint:
            raise ConfigError(f"ClearanceJoint.joint must be a joint name, got {self.joint!r}")
        for field in ("clearance", "journal_radius"):
            value = getattr(self, field)
            if isinstance(value, bool) or not isinstance(value, int | float):
                raise ConfigError(
                    f"{where}: {field} must be a number in metres, got {value!r}; convert "
                    "text with units first, e.g. jointplay.units.parse_quantity('21 um', 'm', "
                    f"field='{field}')"
                )
            object.__setattr__(self, field, float(value))
        if not math.isfinite(self.clearance) or self.clearance < 0:
            raise ConfigError(
                f"{where}: radial clearance must be positive, got {self.clearance * 1e3:g} mm "
                "(a negative value would be an interference fit, which jointplay does not model)"
            )
        if 0 < self.clearance < MIN_CLEARANCE:
            raise ConfigError(
                f"{where}: a radial clearance of {self.clearance:.3g} m is below "
                f"{MIN_CLEARANCE:g} m (1 nm), smaller than any machined fit: leave the joint "
                "ideal instead, or check the unit (e.g. '0.021 mm')"
            )
        if self.clearance == 0:
            raise ConfigError(
                f"{where}: zero clearance — leave the joint ideal instead (omit it from --joints)"
            )
        if not (math.isfinite(self.journal_radius) and self.journal_radius > 0):
            raise ConfigError(
                f"{where}: journal (pin) radius must be > 0 m, got {self.journal_radius}"
            )
        if not isinstance(self.law, ContactLaw):
            raise ConfigError(
                f"{where}: law must be a ContactLaw instance, got {type(self.law).__name__}"
            )
        if self.friction is not None and not isinstance(self.friction, FrictionLaw):
            raise ConfigError(
                f"{where}: friction must be a FrictionLaw instance or None, got "
                f"{type(self.friction).__name__}"
            )

    @property
    def bearing_radius(self) -> float:
        """R_B = R_J + c, m."""
        return self.journal_radius + self.clearance
