"""The integrators, as data: one :class:`Integrator` record each (:data:`INTEGRATORS`), read
wherever an integrator is named, listed or chosen.

A record says what an integrator is (its order, whether it is explicit), how the engines run
it (the fraction of the tolerances, the engines that have it) and where its steps are (their
prefix in the lane source, run by the lanes and by :func:`jointplay.integrate`'s loop,
:mod:`jointplay._kernels.driver`). Each record is declared once, in the lane source module
that holds the integrator's steps (its ``LANE["integrator"]``, the prefix its ``LANE["steps"]``:
:data:`jointplay._kernels.lanes.SOURCES`), beside the lane's name and work allocator that
:mod:`jointplay._kernels.lanes.build` and :mod:`jointplay._kernels.lanes.cpu` read: a new
integrator is one file. The batch engines' two methods, ``"explicit"`` and ``"implicit"``,
are the integrators their lanes have, named by :attr:`Integrator.lane_method`
(:func:`lane_methods`). Nothing compiled, no Numba imported (the command line and the JAX
backend read it without Numba).
"""

from __future__ import annotations

from dataclasses import dataclass

from jointplay._kernels.lanes import SOURCES

__all__ = ["DEFAULT", "INTEGRATORS", "Integrator", "integrators_of", "lane_methods"]


@dataclass(frozen=True)
class Integrator:
    """One integrator.

    Attributes:
        name: its name in options and results (``--integrator``, ``SolverOptions``).
        title: how a report names it.
        order: the order of the solution it propagates.
        explicit: no linear algebra in a step (and stable only below a step size).
        tolerance_scale: the fraction of the solver's rtol and velocity atol that the engines
            run it at (DOPRI5's error estimate is less conservative than Radau's, see
            :data:`jointplay.dynamics.simulate.EXPLICIT_TOLERANCE_SCALE`).
        engines: the engines that have it (keys of
            :data:`jointplay._kernels.capabilities.ENGINES`).
        steps: the prefix of its steps in the lane source (``"radau"``, ``"rodas"``,
            ``"dopri"``): its ``LANE`` record's ``steps``
            (:func:`jointplay._kernels.driver.steps_of`).
    """

    name: str
    title: str
    order: int
    explicit: bool
    tolerance_scale: float
    engines: tuple[str, ...]
    steps: str

    @property
    def lane_method(self) -> str:
        """The batch engines' name of it: ``"explicit"`` or ``"implicit"``."""
        return "explicit" if self.explicit else "implicit"


#: The default integrator.
DEFAULT = "radau"
#: Every integrator by name, from the lane source modules' records (``LANE["integrator"]``:
#: :data:`jointplay._kernels.lanes.SOURCES`): the default first, then the implicit ones,
#: then the explicit ones, each in the modules' order.
INTEGRATORS: dict[str, Integrator] = {
    integrator.name: integrator
    for integrator in sorted(
        (
            Integrator(**module.LANE["integrator"], steps=module.LANE["steps"])
            for module in SOURCES
            if hasattr(module, "LANE")
        ),
        key=lambda integrator: (integrator.name != DEFAULT, integrator.explicit),
    )
}


def integrators_of(engine: str) -> tuple[str, ...]:
    """The names of the integrators that ``engine`` has, in :data:`INTEGRATORS`' order."""
    return tuple(name for name, integrator in INTEGRATORS.items() if engine in integrator.engines)


def lane_methods(*engines: str) -> tuple[str, ...]:
    """The batch methods (``"explicit"`` first, then ``"implicit"``) of the integrators that
    any of ``engines`` has: a batch backend's ``method`` values."""
    have = {INTEGRATORS[name].lane_method for engine in engines for name in integrators_of(engine)}
    return tuple(method for method in ("explicit", "implicit") if method in have)
