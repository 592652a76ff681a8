"""The six simulation methods of the paper's Table 2, as named presets.

==========================  =====================================================================
name                        contact law and parameters
==========================  =====================================================================
``ifm-conventional``        IMPACT with Table 3: k = 1e4 N/mm^1.5, e = 1.5, c_max = 10 N·s/mm,
                            d = 0.1 mm
``rm-conventional``         Restitution Method: penalty p = 1e4 N/mm (Table 3's stiffness number
                            used as a linear penalty — the paper gives no RM parameters), ε = 0.8
``ifm-ecs-cylindrical``     IMPACT with the ECS cylindrical-contact K, δ, D (Table 4 or ours)
``rm-ecs-cylindrical``      RM with penalty p = ECS cylindrical K, ε = 0.8
``ifm-ecs-spherical``       IMPACT with the ECS spherical-contact K, δ, D (Table 5 or ours)
``rm-ecs-spherical``        RM with penalty p = ECS spherical K, ε = 0.8
==========================  =====================================================================

Each method also names the integrator it runs with (:attr:`Method.integrator`): RODAS4 for the
two IFM ECS methods, whose damping, full at a negligible penetration (δ of 3.7e-5 mm and
2.7e-10 mm against a 0.021 mm clearance), keeps failing Radau's simplified Newton iteration;
DOPRI5 (explicit) for the IFM conventional method, whose soft contact is not stiff at the
accuracy step; Radau IIA for the three RM methods, whose damping divided by the impact
velocity makes slow contacts stiff. Measured on the paper four-bar (docs/performance.md,
"From rest: a Rosenbrock method for the paper's ECS sets" and "From rest: DOPRI5 for the
conventional set"): RODAS4 runs the IFM ECS methods 1.6–2.8× faster from rest and steady,
DOPRI5 the IFM conventional one 1.4–2.5× faster, each at the accuracy contract; neither is
faster on the RM methods. RODAS4 holds only with every joint clear
(:func:`jointplay.dynamics.simulate.preferred_integrator`: with ideal joints beside it is
2–30× slower); DOPRI5 holds with ideal joints too.

Table 3 is :data:`jointplay.study.published.TABLE3_IMPACT`. ECS parameters come from
:func:`jointplay.study.ecs.ecs_parameters` with ``source="computed"`` (our ECS estimate for the
mechanism at its crank speed) or ``"paper"`` (the published Tables 4 and 5). In IMPACT the ECS
δ is the full-damping depth d and D is c_max; the ECS K, a linear stiffness quoted in N/mm, is
read as N/mm^1.5 as the paper's ADAMS runs did (docs/ecs.md, "The IFM unit leap"). ε = 0.8 is
steel on steel as the paper cites.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from jointplay.contact.ecs import EcsConventions
from jointplay.contact.laws import ContactLaw, RestitutionLaw
from jointplay.errors import ConfigError, SettingError
from jointplay.model.mechanism import Mechanism
from jointplay.study.ecs import ecs_parameters
from jointplay.study.published import TABLE3_IMPACT

#: The paper's coefficient of restitution for steel on steel.
PAPER_RESTITUTION = 0.8
#: Penalty of the conventional RM: Table 3's stiffness number as a linear stiffness, N/m.
RM_CONVENTIONAL_PENALTY = 1e4 * 1e3


@dataclass(frozen=True)
class Method:
    """One row of the paper's Table 2."""

    name: str
    title: str
    family: str  # "IFM" or "RM"
    parameters: str  # "conventional", "cylindrical" or "spherical"

    @property
    def integrator(self) -> str:
        """The integrator this method runs with (``SolverOptions.integrator``): ``"rodas4"``
        for IFM with ECS parameters, ``"dopri5"`` for IFM with the conventional set,
        ``"radau"`` for RM (module docstring)."""
        if self.family != "IFM":
            return "radau"
        return "rodas4" if self.uses_ecs else "dopri5"

    @property
    def uses_ecs(self) -> bool:
        return self.parameters != "conventional"


METHODS: dict[str, Method] = {
    m.name: m
    for m in (
        Method("ifm-conventional", "Conventional approach by IFM", "IFM", "conventional"),
        Method("rm-conventional", "Conventional approach by RM", "RM", "conventional"),
        Method(
            "ifm-ecs-cylindrical", "ECS approach by IFM - cylindrical contact", "IFM", "cylindrical"
        ),
        Method(
            "rm-ecs-cylindrical", "ECS approach by RM - cylindrical contact", "RM", "cylindrical"
        ),
        Method("ifm-ecs-spherical", "ECS approach by IFM - spherical contact", "IFM", "spherical"),
        Method("rm-ecs-spherical", "ECS approach by RM - spherical contact", "RM", "spherical"),
    )
}

ECS_SOURCES = ("computed", "paper")


def get_method(name: str) -> Method:
    try:
        return METHODS[name]
    except KeyError:
        raise ConfigError(
            f"unknown method {name!r}; the paper's Table 2 methods are: {', '.join(METHODS)}"
        ) from None


def method_law(
    name: str,
    mechanism: Mechanism,
    *,
    ecs_source: str = "computed",
    restitution: float = PAPER_RESTITUTION,
    conventions: EcsConventions | None = None,
) -> tuple[ContactLaw, dict[str, Any]]:
    """The contact law of method ``name`` for ``mechanism``, with a record of its parameters."""
    method = get_method(name)
    if method.uses_ecs and ecs_source not in ECS_SOURCES:
        raise SettingError("{ecs_source} must be computed or paper, got {got!r}", got=ecs_source)
    record: dict[str, Any] = {
        "method": method.name,
        "title": method.title,
        "integrator": method.integrator,
    }
    law: ContactLaw
    if not method.uses_ecs:
        record["parameters"] = (
            "Table 3" if method.family == "IFM" else "Table 3 stiffness as RM penalty"
        )
        if method.family == "IFM":
            law = TABLE3_IMPACT
        else:
            law = RestitutionLaw(
                penalty=RM_CONVENTIONAL_PENALTY, restitution=restitution, exponent=1.0
            )
    else:
        params = ecs_parameters(mechanism, method.parameters, ecs_source, conventions)
        record["ecs_source"] = ecs_source
        record["ecs"] = params.as_dict()
        law = params.impact_law() if method.family == "IFM" else params.restitution_law(restitution)
    record["law"] = {
        "name": law.name,
        **{k: v for k, v in vars(law).items() if not k.startswith("_")},
    }
    return law, record
