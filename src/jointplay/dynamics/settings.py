"""The settings of a run of the clearance dynamics, built once where a run is asked for.

:class:`RunSettings` gathers what every simulating study and command takes: the contact of
the clearance joints (:class:`~jointplay.dynamics.setup.ContactModel`, per joint), how the
motion starts (:class:`~jointplay.dynamics.simulate.Start`), the start-up revolutions left
out (``settle``), the analysed revolutions and the integrator's options
(:class:`~jointplay.dynamics.simulate.SolverOptions`). It is checked once, at construction
(:func:`~jointplay.dynamics.cycles.analysed_revolutions`,
:func:`~jointplay.dynamics.cycles.settle_revolutions`): a bad value is a
:class:`~jointplay.errors.SettingError` that names its field (the command line shows the
option's name instead). The command line builds one from its options
(``jointplay.cli._simulation.run_settings``); the Python API's
:func:`~jointplay.tolerance.analysis.tolerance_study` and
:func:`~jointplay.study.design.design_study` take one as ``run_settings``, or build it from their loose
keywords (:meth:`RunSettings.of`).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from jointplay.dynamics.cycles import DEFAULT_SETTLE, analysed_revolutions, settle_revolutions
from jointplay.dynamics.setup import ContactModel, FrictionSettings, resolve_contact
from jointplay.dynamics.simulate import SolverOptions, Start
from jointplay.errors import SettingError

if TYPE_CHECKING:
    from collections.abc import Sequence

    from jointplay.contact.laws import ContactLaw
    from jointplay.dynamics.clearance import ClearanceJoint
    from jointplay.dynamics.simulate import SimulationResult
    from jointplay.model.mechanism import Mechanism

__all__ = ["RunSettings", "simulate_run"]


def _steady() -> Start:
    return Start("steady")


@dataclass(frozen=True)
class RunSettings:
    """How the clearance dynamics run (SI; frozen, checked at construction).

    Attributes:
        contact: the contact of every clearance joint (default: the physical
            ``ContactModel()`` of every command; ``ContactModel`` with ``law`` for a ready
            law, e.g. :func:`~jointplay.dynamics.setup.conventional_contact`).
        start: how the motion starts (default ``Start("steady")``, the running mechanism;
            a mode's name is read as ``Start(name)``).
        settle: start-up revolutions left out of the results (a whole number >= 0; default
            :data:`~jointplay.dynamics.cycles.DEFAULT_SETTLE`).
        revolutions: analysed crank revolutions after them (> 0).
        solver: the integrator's tolerances, largest step and step budget.

    Raises:
        SettingError: a field of the wrong kind or out of range (named by its field).
    """

    contact: ContactModel = dataclasses.field(default_factory=ContactModel)
    start: Start = dataclasses.field(default_factory=_steady)
    settle: int = DEFAULT_SETTLE
    revolutions: float = 1.0
    solver: SolverOptions = dataclasses.field(default_factory=SolverOptions)

    def __post_init__(self) -> None:
        if not isinstance(self.contact, ContactModel):
            raise SettingError(
                "{contact} must be a ContactModel (jointplay.dynamics.setup), got {got!r}",
                got=self.contact,
            )
        if isinstance(self.start, str):
            object.__setattr__(self, "start", Start(self.start))  # type: ignore[arg-type]
        if not isinstance(self.start, Start):
            raise SettingError(
                "{start} must be a Start or the name of a start mode, got {got!r}", got=self.start
            )
        if not isinstance(self.solver, SolverOptions):
            raise SettingError(
                "{solver} must be SolverOptions (jointplay.dynamics.simulate), got {got!r}",
                got=self.solver,
            )
        object.__setattr__(self, "settle", settle_revolutions(self.settle))
        object.__setattr__(self, "revolutions", analysed_revolutions(self.revolutions))

    @classmethod
    def of(
        cls,
        run: RunSettings | None = None,
        *,
        contact: str | ContactLaw | ContactModel | None = None,
        start: str | Start | None = None,
        settle: int | None = None,
        revolutions: float | None = None,
        solver: SolverOptions | None = None,
    ) -> RunSettings:
        """``run``, or the settings of the Python API's loose keywords (``None``: not
        given, the default): ``contact`` as :func:`~jointplay.dynamics.setup.resolve_contact`
        reads it (a bare law: frictionless). Giving ``run`` and a loose keyword is an error."""
        loose = {
            "contact": contact,
            "start": start,
            "settle": settle,
            "revolutions": revolutions,
            "solver": solver,
        }
        given: dict[str, Any] = {name: value for name, value in loose.items() if value is not None}
        if run is not None:
            if given:
                names = ", ".join(f"{{{name}}}" for name in given)
                raise SettingError(
                    f"give the run settings either as {{run}} or as {names}, not both"
                )
            return run
        if "contact" in given:
            resolved = resolve_contact(given["contact"])
            given["contact"] = (
                resolved
                if isinstance(resolved, ContactModel)
                else ContactModel(friction=FrictionSettings(), law=resolved)
            )
        return cls(**given)

    def describe(self) -> dict[str, Any]:
        """The settings as plain data (summaries)."""
        return {
            "contact": self.contact.describe(),
            "start": self.start.mode,
            "ramp_time_s": self.start.ramp_time,
            "settle_revolutions": self.settle,
            "revolutions": self.revolutions,
            "solver": dataclasses.asdict(self.solver),
        }


def simulate_run(
    mechanism: Mechanism,
    clearances: Sequence[ClearanceJoint] | None,
    run: RunSettings,
    **options: Any,
) -> SimulationResult:
    """:func:`~jointplay.dynamics.simulate.simulate` with ``run``'s start, settle,
    revolutions and solver (its integrator, where not chosen, the one the paper method of
    ``run``'s contact names, where it holds: :attr:`ContactModel.integrator`,
    :func:`~jointplay.dynamics.simulate.preferred_integrator`); ``clearances``: the
    clearance joints (``None``: ``run``'s contact on every joint with a clearance in its fit,
    ``run.contact.joints(mechanism)``); ``options``: simulate's others (``output_step``,
    ``sample_deg``, ``nominal``, …)."""
    from jointplay.dynamics.simulate import preferred_integrator, simulate

    joints = run.contact.joints(mechanism) if clearances is None else clearances
    solver = run.solver
    preferred = preferred_integrator(run.contact.integrator, mechanism, joints)
    if solver.integrator is None and preferred is not None:
        solver = dataclasses.replace(solver, integrator=preferred)
    return simulate(
        mechanism,
        joints,
        revolutions=run.revolutions,
        settle=run.settle,
        start=run.start,
        solver=solver,
        **options,
    )
