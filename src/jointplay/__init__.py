"""jointplay — planar linkages as they are really built.

Tolerance stacks on link lengths, radial clearance in revolute joints, contact dynamics.
SI units inside; :mod:`jointplay.units` converts quantities with units at the edges.

The public API, importable from the top::

    from jointplay import load_preset, nominal_analysis, get_law, ClearanceJoint, simulate

    mechanism = load_preset("paper-fourbar")          # or load_config("my.toml")
    nominal = nominal_analysis(mechanism)               # kinematics + inverse dynamics
    law = get_law("impact", stiffness=3.16e8, exponent=1.5, c_max=1e4, d_max=1e-4)
    joints = [ClearanceJoint(j, clearance=21e-6, journal_radius=5e-3, law=law)
              for j in ("O2", "A", "B", "O4")]
    result = simulate(mechanism, joints, revolutions=1)   # steady start, 2 revolutions to settle

The names are loaded on first use, so ``import jointplay`` (and the command line's
help) does not pay for NumPy's, SciPy's or Numba's start-up. Where each lives:

===========================  ================================================
name                         module
===========================  ================================================
mechanisms                   :mod:`jointplay.io.config`, :mod:`jointplay.model`
nominal analysis             :mod:`jointplay.dynamics.nominal`
contact and friction laws    :mod:`jointplay.contact`
clearance dynamics           :mod:`jointplay.dynamics.simulate`
many samples at once         :mod:`jointplay.dynamics.batch` (CPU, processes, Dask, JAX/GPU)
tolerance analysis           :mod:`jointplay.tolerance`
design study                 :mod:`jointplay.study.design`
===========================  ================================================
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

from jointplay.errors import (
    AssemblyError,
    ConfigError,
    IntegrationError,
    JointplayError,
    StandardsError,
)

__version__ = "0.1.0"

#: Public name -> module that defines it (imported on first access, PEP 562).
_LAZY: dict[str, str] = {
    # mechanisms
    "Mechanism": "jointplay.model.mechanism",
    "four_bar": "jointplay.model.templates",
    "slider_crank": "jointplay.model.templates",
    "FourBarGeometry": "jointplay.model.templates",
    "SliderCrankGeometry": "jointplay.model.templates",
    "load_preset": "jointplay.io.config",
    "load_config": "jointplay.io.config",
    "list_presets": "jointplay.io.config",
    # kinematics and inverse dynamics
    "analyse": "jointplay.kinematics.analysis",
    "nominal_analysis": "jointplay.dynamics.nominal",
    "inverse_dynamics": "jointplay.dynamics.inverse",
    # contact
    "get_law": "jointplay.contact.laws",
    "CONTACT_LAWS": "jointplay.contact.laws",
    "get_friction": "jointplay.contact.friction",
    "get_stiffness_law": "jointplay.contact.stiffness",
    # clearance dynamics
    "ClearanceJoint": "jointplay.dynamics.clearance",
    "clearance_joints": "jointplay.dynamics.setup",
    "simulate": "jointplay.dynamics.simulate",
    "SimulationResult": "jointplay.dynamics.simulate",
    "Start": "jointplay.dynamics.simulate",
    "SolverOptions": "jointplay.dynamics.simulate",
    "integrate": "jointplay.dynamics.integrate",
    "simulate_batch": "jointplay.dynamics.batch",
    "BatchSamples": "jointplay.dynamics.batch",
    "BatchResult": "jointplay.dynamics.batch",
    # tolerances
    "fit": "jointplay.tolerance.iso286",
    "general_tolerance": "jointplay.tolerance.iso2768",
    "ToleranceSpec": "jointplay.tolerance.spec",
    "tolerance_study": "jointplay.tolerance.analysis",
    # design
    "design_study": "jointplay.study.design",
}

__all__ = [
    "CONTACT_LAWS",
    "AssemblyError",
    "BatchResult",
    "BatchSamples",
    "ClearanceJoint",
    "ConfigError",
    "FourBarGeometry",
    "IntegrationError",
    "JointplayError",
    "Mechanism",
    "SimulationResult",
    "SliderCrankGeometry",
    "SolverOptions",
    "StandardsError",
    "Start",
    "ToleranceSpec",
    "__version__",
    "analyse",
    "clearance_joints",
    "design_study",
    "fit",
    "four_bar",
    "general_tolerance",
    "get_friction",
    "get_law",
    "get_stiffness_law",
    "integrate",
    "inverse_dynamics",
    "list_presets",
    "load_config",
    "load_preset",
    "nominal_analysis",
    "simulate",
    "simulate_batch",
    "slider_crank",
    "tolerance_study",
]


def __getattr__(name: str) -> Any:
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module 'jointplay' has no attribute {name!r}")
    value = getattr(importlib.import_module(module), name)
    globals()[name] = value  # later look-ups skip this function
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_LAZY))


if TYPE_CHECKING:  # the same names, for type checkers and IDEs
    from jointplay.contact.friction import get_friction
    from jointplay.contact.laws import CONTACT_LAWS, get_law
    from jointplay.contact.stiffness import get_stiffness_law
    from jointplay.dynamics.clearance import ClearanceJoint
    from jointplay.dynamics.integrate import integrate
    from jointplay.dynamics.inverse import inverse_dynamics
    from jointplay.dynamics.nominal import nominal_analysis
    from jointplay.dynamics.setup import clearance_joints
    from jointplay.dynamics.simulate import SimulationResult, SolverOptions, Start, simulate
    from jointplay.io.config import list_presets, load_config, load_preset
    from jointplay.kinematics.analysis import analyse
    from jointplay.model.mechanism import Mechanism
    from jointplay.model.templates import (
        FourBarGeometry,
        SliderCrankGeometry,
        four_bar,
        slider_crank,
    )
    from jointplay.study.design import design_study
    from jointplay.tolerance.analysis import tolerance_study
    from jointplay.tolerance.iso286 import fit
    from jointplay.tolerance.iso2768 import general_tolerance
    from jointplay.tolerance.spec import ToleranceSpec
