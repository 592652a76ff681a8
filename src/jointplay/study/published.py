"""The paper's published constants: Table 3 (conventional IMPACT) and Tables 4–5 (ECS values).

Akhadkar, Deoghare & Vaidya print the contact parameters of their conventional approach
(Table 3) and the results of their Equivalent Contact Stiffness estimate at 200 RPM (Table 4,
cylindrical contact; Table 5, spherical contact). They are data, kept here in the paper's
units with SI accessors; :mod:`jointplay.study.ecs` offers Tables 4–5 as a parameter source and
``docs/ecs.md`` discusses why our estimate does not reproduce them. Table 2 (the six methods)
is :mod:`jointplay.study.methods`.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any

from jointplay.contact.ecs import MM
from jointplay.contact.laws import ImpactLaw
from jointplay.dynamics.setup import DEFAULT_IMPACT

#: The paper's conventional IMPACT parameters (Table 3): k = 1e4 N/mm^1.5, e = 1.5,
#: c_max = 10 N·s/mm, d = 0.1 mm. They are jointplay's default IMPACT law, which owns the
#: numbers (:data:`jointplay.dynamics.setup.DEFAULT_IMPACT`); this is their paper name.
TABLE3_IMPACT: ImpactLaw = DEFAULT_IMPACT


@dataclass(frozen=True)
class PublishedEcs:
    """ECS values published in the paper, in its units.

    Attributes:
        contact: ``"spherical"`` or ``"cylindrical"``.
        table: where they are printed.
        crank_speed_rpm: crank speed they were estimated for, rev/min.
        stiffness_n_per_mm: K, N/mm.
        penetration_mm: δ, mm (as printed; docs/ecs.md discusses Table 4's unit).
        damping_n_s_per_mm: D, N·s/mm.
    """

    contact: str
    table: str
    crank_speed_rpm: float
    stiffness_n_per_mm: float
    penetration_mm: float
    damping_n_s_per_mm: float

    @property
    def stiffness(self) -> float:
        """K, N/m."""
        return self.stiffness_n_per_mm / MM

    @property
    def penetration(self) -> float:
        """δ, m."""
        return self.penetration_mm * MM

    @property
    def damping(self) -> float:
        """D, N·s/m."""
        return self.damping_n_s_per_mm / MM

    @property
    def damping_ratio(self) -> float:
        """D/K, s (0.01 for both tables, to 4 significant figures)."""
        return self.damping_n_s_per_mm / self.stiffness_n_per_mm

    def as_dict(self) -> dict[str, Any]:
        """JSON-ready: the printed values and their SI equivalents."""
        return {
            "source": f"Akhadkar et al., {self.table}",
            "crank_speed_rpm": self.crank_speed_rpm,
            "paper_units": {
                "stiffness_N_per_mm": self.stiffness_n_per_mm,
                "penetration_mm": self.penetration_mm,
                "damping_N_s_per_mm": self.damping_n_s_per_mm,
            },
            "si": {
                "stiffness_N_per_m": self.stiffness,
                "penetration_m": self.penetration,
                "damping_N_s_per_m": self.damping,
            },
        }


#: The paper's ECS results at 200 RPM: Table 4 (cylindrical) and Table 5 (spherical).
PAPER_PUBLISHED: Mapping[str, PublishedEcs] = MappingProxyType(
    {
        "cylindrical": PublishedEcs("cylindrical", "Table 4", 200.0, 242348.0, 2.69e-10, 2423.0),
        "spherical": PublishedEcs("spherical", "Table 5", 200.0, 2500.0, 3.67e-5, 25.0),
    }
)
