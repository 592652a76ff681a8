"""jointplay — planar linkages as they are really built.

Tolerance stacks on link lengths, radial clearance in revolute joints, contact dynamics.
SI units inside; see :mod:`jointplay.units` for quantities with units at the edges.
"""

from __future__ import annotations

__version__ = "0.1.0"

from jointplay.errors import (
    AssemblyError,
    ConfigError,
    IntegrationError,
    JointplayError,
    StandardsError,
)

__all__ = [
    "AssemblyError",
    "ConfigError",
    "IntegrationError",
    "JointplayError",
    "StandardsError",
    "__version__",
]
