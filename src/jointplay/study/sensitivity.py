"""Is a design's choice robust to the contact model? (issue 22, item 4)

The contact's uncertain parameters — the coefficient of restitution, the friction
coefficient, the pin-in-hole stiffness law, the lubricant (its viscosity, and dry
joints) and, under a Reynolds film, the film model (full film against the π-film) and the
pins' roughness (σ × 0.5, × 2) — are inputs with documented ranges
(docs/contact.md). :func:`model_sensitivity` re-evaluates the scheme a design study chose
with each of them, one at a time, at the ends of its range (the others as the study had
them), on the first :data:`SENSITIVITY_SAMPLES` samples of the chosen scheme's stream (the
same as-made parts in every row, a sample size fixed in advance: each yield's exact 95 %
interval holds at it), and says which requirements move with the model: per requirement,
how many of those parts fail it under the changed model that met it as chosen, and whether
the yield is shown to fail the level there.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from jointplay.dynamics.setup import ContactModel
    from jointplay.model.mechanism import Mechanism
    from jointplay.study.design import DesignResult

#: The documented ranges (docs/contact.md): their ends are the cases re-evaluated.
RESTITUTION_RANGE = (0.6, 0.95)
FRICTION_RANGE = (0.01, 0.2)
#: The stiffness laws for conformal pin-in-hole contact valid at every clearance: the default
#: (Liu's) and Hertz's point-contact convention of the revolute-clearance literature.
STIFFNESS_LAWS = ("liu", "hertz")
#: The lubricant's viscosity, Pa·s (docs/contact.md): a thin, hot oil to a grease's base oil;
#: the table also runs the joints dry (0). A fixed film damping takes FILM_DAMPING_RANGE.
VISCOSITY_RANGE = (0.005, 0.5)
FILM_DAMPING_RANGE = (1e4, 1e6)
#: The Reynolds films compared (docs/contact.md, "Reynolds films"): the π-film default, whose
#: film carries no suction, against the full film, whose does (an upper bound on the film's
#: force); each design re-runs with the other one.
FILM_MODELS = ("short-bearing-pi", "short-bearing-full")
#: The joints' composite roughness σ re-run at these multiples of the study's: where the
#: asperities start to carry load (h_min = 3σ) is the transition's least known input.
ROUGHNESS_FACTORS = (0.5, 2.0)
#: The chosen scheme's samples each contact model re-runs: the first of its stream (the
#: study's own parts), at most this many — the table's cost is bounded (rows × this), not the
#: study's sample count (a failure-free 99.73 % scheme is decided at 1 600).
SENSITIVITY_SAMPLES = 200


@dataclass(frozen=True)
class ModelCase:
    """One contact model of the sensitivity table: ``parameter`` set to ``value``."""

    parameter: str
    value: float | str
    contact: ContactModel


def model_cases(contact: ContactModel) -> tuple[ModelCase, ...]:
    """Each uncertain parameter of ``contact`` at the ends of its range, one at a time: the
    restitution (laws that take one), the friction coefficient, dry joints and the lubricant's
    viscosity (or a fixed film damping) and the other stiffness law (a stiffness from the geometry). None for one of the
    paper's methods (fixed by name)."""
    from jointplay.dynamics.setup import DEFAULT_RESTITUTION

    if contact.law is not None:
        return ()
    settings, friction = contact.settings, contact.friction
    cases = []
    if settings.law not in ("impact", "hertz", "kelvin-voigt"):  # the restitution family
        given = DEFAULT_RESTITUTION if settings.restitution is None else settings.restitution
        for e in RESTITUTION_RANGE:
            if e != given:
                changed = dataclasses.replace(settings, restitution=e)
                cases.append(
                    ModelCase("restitution", e, dataclasses.replace(contact, settings=changed))
                )
    for mu in FRICTION_RANGE:
        if mu != friction.coefficient:
            changed_friction = dataclasses.replace(friction, coefficient=mu)
            cases.append(
                ModelCase("friction", mu, dataclasses.replace(contact, friction=changed_friction))
            )
    if contact.lubricated:
        named = None if contact.lubrication is None else "dry"
        dry = dataclasses.replace(contact, film_damping=0.0, lubrication=named, grade=None)
        cases.append(ModelCase("lubrication", "dry", dry))
    if contact.fixed_film is None:  # from the geometry: the lubricant's range
        regime = None if contact.lubrication == "dry" else contact.lubrication
        for viscosity in VISCOSITY_RANGE:
            if viscosity != contact.viscosity:
                changed_contact = dataclasses.replace(
                    contact, lubricant_viscosity=viscosity, lubrication=regime, grade=None
                )
                cases.append(ModelCase("lubricant_viscosity", viscosity, changed_contact))
        cases += _film_cases(contact)
    else:
        for film in FILM_DAMPING_RANGE:
            if film != contact.fixed_film:
                changed_contact = dataclasses.replace(contact, film_damping=film)
                cases.append(ModelCase("film_damping", film, changed_contact))
    if settings.geometry_law is not None:
        for law in STIFFNESS_LAWS:
            if law != settings.geometry_law:
                changed = dataclasses.replace(settings, stiffness_law=law)
                cases.append(
                    ModelCase("stiffness_law", law, dataclasses.replace(contact, settings=changed))
                )
    return tuple(cases)


def _film_cases(contact: ContactModel) -> list[ModelCase]:
    """A Reynolds film's own model choices (docs/contact.md, "Reynolds films" and "The
    film-to-contact transition"): the other short-bearing film (:data:`FILM_MODELS`: the
    full film against the π-film) and the joints' composite roughness σ at
    :data:`ROUGHNESS_FACTORS` times the study's (each joint's default
    :data:`~jointplay.dynamics.clearance.DEFAULT_ROUGHNESS` where none is given; none for
    smooth joints, σ = 0). None for dry joints or the linear damper."""
    from jointplay.dynamics.clearance import DEFAULT_ROUGHNESS, MAX_ROUGHNESS

    if not contact.lubricated or contact.film_model not in FILM_MODELS:
        return []
    other = next(model for model in FILM_MODELS if model != contact.film_model)
    cases = [ModelCase("film_model", other, dataclasses.replace(contact, film_model=other))]
    base = DEFAULT_ROUGHNESS if contact.roughness is None else float(contact.roughness)
    if base > 0:
        for factor in ROUGHNESS_FACTORS:
            sigma = min(base * factor, MAX_ROUGHNESS)
            label = f"{sigma * 1e6:.3g} µm (×{factor:g})"
            cases.append(
                ModelCase("roughness", label, dataclasses.replace(contact, roughness=sigma))
            )
    return cases


@dataclass(frozen=True)
class SensitivityRow:
    """The chosen scheme under one contact model, on the table's samples.

    Attributes:
        parameter, value: what changed (``"as chosen"`` for the study's own model).
        yields: requirement text → share of the samples meeting it, %.
        meets: the scheme is shown to meet every requirement at the study's confidence on
            the table's samples (exact interval at that fixed n).
        values: each required response → its value at the study's confidence level over
            the samples (SI; the scheme table's ``<response>_at_confidence``): how far the
            model moves the response, where the yields stay at 100 %.
        samples: the samples of the row (the first of the chosen scheme's stream).
        intervals: requirement text → the yield's exact (Clopper–Pearson) 95 % interval at
            ``samples``, %.
        verdict: ``meets``, ``fails`` or ``undecided`` on those intervals (all requirements).
        worse: requirement text → the parts (of the same ``samples``) that fail it under this
            model and met it as chosen (0 in the ``as chosen`` row).
        bases: required response → ``order-statistic`` (a 95 % bound) or ``normal-model``
            (an estimate: too few samples for a bound at the level).
    """

    parameter: str
    value: float | str
    yields: Mapping[str, float]
    meets: bool
    values: Mapping[str, float] = field(default_factory=dict)
    samples: int = 0
    intervals: Mapping[str, tuple[float, float]] = field(default_factory=dict)
    verdict: str = ""
    worse: Mapping[str, int] = field(default_factory=dict)
    bases: Mapping[str, str] = field(default_factory=dict)

    @property
    def fails(self) -> bool:
        """Shown to fail the level on its samples (some requirement's interval below it)."""
        return self.verdict == "fails"

    @property
    def moves(self) -> bool:
        """Some part fails a requirement under this model that it met as chosen."""
        return any(self.worse.values())

    def as_dict(self) -> dict[str, Any]:
        return {
            "parameter": self.parameter,
            "value": self.value,
            "samples": self.samples,
            "yield_percent": dict(self.yields),
            "yield_ci95_percent": {k: list(v) for k, v in self.intervals.items()},
            "parts_worse": dict(self.worse),
            "at_confidence": dict(self.values),
            "at_confidence_basis": dict(self.bases),
            "verdict": self.verdict,
            "meets_every_requirement": self.meets,
        }


@dataclass(frozen=True)
class ModelSensitivity:
    """The model-sensitivity table of a design (``summary.json`` → ``model_sensitivity``).

    Attributes:
        scheme: the chosen scheme.
        rows: ``as chosen`` first, then one per :func:`model_cases`.
        samples: the samples each row ran (the first of the chosen scheme's stream).
        study_samples: the chosen scheme's samples in the study.
    """

    scheme: str
    rows: tuple[SensitivityRow, ...]
    samples: int = 0
    study_samples: int = 0

    @property
    def holds(self) -> bool:
        """At every end of every range, no part fails a requirement it met as chosen, and
        no row is shown to fail."""
        return not any(row.fails or row.moves for row in self.rows)

    @property
    def on(self) -> str:
        """``on 200 of its 1,600 samples`` (empty without the counts)."""
        if not self.samples:
            return ""
        return f"on {self.samples:,} of its {self.study_samples:,} samples"

    @property
    def verdict(self) -> str:
        on = f" ({self.on})" if self.on else ""
        if self.holds:
            return (
                f"the choice {self.scheme} holds at the ends of the contact model's ranges "
                "(restitution, friction, stiffness law, lubricant and dry joints, film model, "
                f"roughness){on}: no part fails a requirement it met as chosen"
            )
        failing = [f"{r.parameter} = {r.value}" for r in self.rows if r.fails]
        moving = [
            f"{r.parameter} = {r.value} ("
            + ", ".join(f"{n} on {t!r}" for t, n in r.worse.items() if n)
            + f" of {r.samples:,} parts)"
            for r in self.rows
            if r.moves and not r.fails
        ]
        parts = []
        if failing:
            parts.append(f"does not hold with {', '.join(failing)}")
        if moving:
            parts.append(f"moves with {', '.join(moving)}")
        return f"the choice {self.scheme} {'; '.join(parts)}{on}"

    def as_dict(self) -> dict[str, Any]:
        return {
            "scheme": self.scheme,
            "holds": self.holds,
            "verdict": self.verdict,
            "samples": self.samples,
            "study_samples": self.study_samples,
            "intervals": "exact (Clopper-Pearson) 95 % interval of each yield at the table's "
            "samples (a sample size fixed in advance); parts_worse: of those same parts, "
            "how many fail the requirement under the row's model that met it as chosen",
            "ranges": {
                "restitution": list(RESTITUTION_RANGE),
                "friction": list(FRICTION_RANGE),
                "stiffness_law": list(STIFFNESS_LAWS),
                "lubricant_viscosity_Pa_s": list(VISCOSITY_RANGE),
                "film_damping_N_s_m": list(FILM_DAMPING_RANGE),
                "lubrication": ["lubricated", "dry"],
                "film_model": list(FILM_MODELS),
                "roughness_factors": list(ROUGHNESS_FACTORS),
            },
            "rows": [row.as_dict() for row in self.rows],
        }


def _met(result: DesignResult) -> dict[str, Any]:
    """Each requirement → which of the (one) scheme's samples meet it (a failed simulation
    does not)."""

    frame = result.samples
    ok = (frame["status"] == "ok").to_numpy()
    return {
        r.text: r.met(frame[r.response].to_numpy(dtype=float)) & ok
        for r in result.requirements
        if r.response in frame
    }


def _row(
    parameter: str, value: float | str, result: DesignResult, chosen: Mapping[str, Any] | None
) -> SensitivityRow:
    table = result.table.iloc[0]
    texts = [r.text for r in result.requirements]
    yields = {t: float(table[f"yield_{t}"]) for t in texts}
    intervals = {
        t: (float(table[f"yield_low_{t}"]), float(table[f"yield_high_{t}"])) for t in texts
    }
    responses = [r.response for r in result.requirements if f"{r.response}_at_confidence" in table]
    values = {name: float(table[f"{name}_at_confidence"]) for name in responses}
    bases = {name: str(table[f"{name}_at_confidence_basis"]) for name in responses}
    met = _met(result)
    worse = {
        t: 0 if chosen is None else int((chosen[t] & ~met[t]).sum()) for t in texts if t in met
    }
    return SensitivityRow(
        parameter, value, yields, bool(table["feasible"]), values, int(table["samples"]),
        intervals, str(table["verdict"]), worse, bases,
    )  # fmt: skip


def model_sensitivity(
    mechanism: Mechanism,
    result: DesignResult,
    contact: ContactModel,
    *,
    first: int = SENSITIVITY_SAMPLES,
    **options: Any,
) -> ModelSensitivity | None:
    """The chosen scheme of ``result`` re-evaluated under every :func:`model_cases` of
    ``contact``, on the first ``first`` samples of its stream; ``None`` without a chosen
    scheme, for kinematic designs and for a paper method.

    Args:
        mechanism: the design's mechanism.
        result: the finished design study (its requirements and confidence are reused).
        contact: the contact model the study ran with.
        first: the samples each row runs (at most the chosen scheme's in the study): the
            first of its stream, the same parts in every row; the table costs
            ``(cases + 1) × first`` simulations whatever the study's sample count.
        **options: the other arguments the study ran with
            (:func:`jointplay.study.design.design_study`: seed, settle, solver, …; its
            ``samples`` and ``max_samples`` give way to ``first``).
    """
    from jointplay.study.design import design_study

    row = result.best_row
    cases = model_cases(contact)
    if row is None or result.responses != "dynamic" or not cases:
        return None
    run = options.pop("run_settings", None)  # the study's run settings: each case's contact
    options.pop("max_samples", None)
    options.pop("samples", None)
    n = max(1, min(int(first), int(row["samples"])))
    joints = [key.removeprefix("fit_") for key in row if key.startswith("fit_")]
    fits = {joint: str(row[f"fit_{joint}"]) for joint in joints}

    def again(model: ContactModel | None) -> DesignResult:
        return design_study(
            mechanism,
            [fits],
            [str(row["length_class"])],
            result.requirements,
            confidence=result.confidence,
            responses="dynamic",
            samples=n,
            check_convergence=False,  # a row reports the yields only
            **(
                {"contact": contact if model is None else model}
                if run is None
                else {
                    "run_settings": run
                    if model is None
                    else dataclasses.replace(run, contact=model)
                }
            ),
            **options,
        )

    base = again(None)  # the study's own model on the table's samples
    if base.interrupted or base.table.empty:
        return None
    chosen = _met(base)
    rows = [_row("as chosen", "", base, None)]
    for case in cases:
        changed = again(case.contact)
        if changed.interrupted or changed.table.empty:
            break
        rows.append(_row(case.parameter, case.value, changed, chosen))
    return ModelSensitivity(str(result.best), tuple(rows), n, int(row["samples"]))
