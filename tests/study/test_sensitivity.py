"""The model sensitivity of a design's choice: the contact model's ends, one at a time."""

from __future__ import annotations

import dataclasses

import pytest

from jointplay.dynamics.setup import DEFAULT_IMPACT, ContactModel, ContactSettings
from jointplay.model.mechanism import Mechanism
from jointplay.study.design import design_study
from jointplay.study.sensitivity import (
    FILM_DAMPING_RANGE,
    FRICTION_RANGE,
    RESTITUTION_RANGE,
    VISCOSITY_RANGE,
    ModelSensitivity,
    SensitivityRow,
    model_cases,
    model_sensitivity,
)
from jointplay.tolerance.execution import Backend

FAST = {"settle": 0, "revolutions": 0.25, "samples": 2, "seed": 3, "backend": Backend("serial")}
#: 2 failure-free samples show a yield of at least 0.025^(1/2) = 15.8 % (95 %): a level they
#: can decide, so that a scheme is chosen
LEVEL = 0.1


def test_each_case_changes_one_parameter_to_an_end_of_its_range() -> None:
    default = ContactModel()
    cases = model_cases(default)
    assert [(c.parameter, c.value) for c in cases] == [
        ("restitution", RESTITUTION_RANGE[0]),
        ("restitution", RESTITUTION_RANGE[1]),
        ("friction", FRICTION_RANGE[0]),
        ("friction", FRICTION_RANGE[1]),
        ("lubrication", "dry"),
        ("lubricant_viscosity", VISCOSITY_RANGE[0]),
        ("lubricant_viscosity", VISCOSITY_RANGE[1]),
        ("stiffness_law", "hertz"),
    ]
    for case in cases:
        changed = {
            name
            for part in ("settings", "friction")
            for name, value in vars(getattr(case.contact, part)).items()
            if value != getattr(getattr(default, part), name)
        }
        changed |= {
            name
            for name in ("film_damping", "lubricant_viscosity")
            if getattr(case.contact, name) != getattr(default, name)
        }
        expected = {
            "stiffness_law": {"stiffness_law"},
            "friction": {"coefficient"},
            "lubrication": {"film_damping"},  # fixed at 0: dry
            "lubricant_viscosity": {"lubricant_viscosity"},
        }
        assert changed == expected.get(case.parameter, {"restitution"}), case
    dry = next(c.contact for c in cases if c.value == "dry")
    assert not dry.lubricated and "dry joints" in dry.describe()["text"]
    fixed = ContactModel(film_damping="1e5 N*s/m")  # a fixed film: its own range
    assert [(c.parameter, c.value) for c in model_cases(fixed) if "film" in c.parameter] == [
        ("film_damping", FILM_DAMPING_RANGE[0]),
        ("film_damping", FILM_DAMPING_RANGE[1]),
    ]
    assert model_cases(ContactModel(law=DEFAULT_IMPACT, method="ifm-conventional")) == ()
    impact = ContactModel(ContactSettings(law="impact"))  # no restitution, a fixed stiffness
    assert [c.parameter for c in model_cases(impact)] == [  # a law named: dry, oil beside it
        *("friction", "friction"),
        *("lubricant_viscosity", "lubricant_viscosity"),
    ]
    oiled = ContactModel(ContactSettings(law="impact"), lubrication="oil")
    assert [c.parameter for c in model_cases(oiled)] == [
        *("friction", "friction"),
        *("lubrication", "lubricant_viscosity", "lubricant_viscosity"),
    ]


def test_the_chosen_scheme_is_re_evaluated_under_each_case(paper_fourbar: Mechanism) -> None:
    contact = ContactModel()
    requirements = ["joint_force <= 1 kN"]
    result = design_study(
        paper_fourbar, ["H8/g7"], ["m"], requirements, contact=contact, confidence=LEVEL, **FAST
    )
    sensitivity = model_sensitivity(paper_fourbar, result, contact, **FAST)
    assert sensitivity is not None and sensitivity.scheme == result.best == "H8/g7 / m"
    assert [r.parameter for r in sensitivity.rows] == ["as chosen"] + [
        c.parameter for c in model_cases(contact)
    ]
    chosen = sensitivity.rows[0]
    assert chosen.yields == {"joint_force <= 1 kN": result.best_row["yield_joint_force <= 1 kN"]}
    # one case, run on its own: the same yields (the same samples and seed)
    rough = dataclasses.replace(
        contact, friction=dataclasses.replace(contact.friction, coefficient=0.2)
    )
    alone = design_study(
        paper_fourbar, ["H8/g7"], ["m"], requirements, contact=rough, confidence=LEVEL, **FAST
    )
    row = next(r for r in sensitivity.rows if (r.parameter, r.value) == ("friction", 0.2))
    assert row.yields["joint_force <= 1 kN"] == alone.table.iloc[0]["yield_joint_force <= 1 kN"]
    assert sensitivity.holds and "holds" in sensitivity.verdict
    record = sensitivity.as_dict()
    assert record["holds"] is True and len(record["rows"]) == len(sensitivity.rows)


def test_a_failing_end_is_named() -> None:
    rows = (
        SensitivityRow("as chosen", "", {"r": 100.0}, True),
        SensitivityRow("friction", 0.2, {"r": 80.0}, False),
    )
    sensitivity = ModelSensitivity("H8/f7 / c", rows)
    assert not sensitivity.holds
    assert sensitivity.verdict == "the choice H8/f7 / c does not hold with friction = 0.2"


@pytest.mark.parametrize("best", [None])
def test_no_choice_no_table(paper_fourbar: Mechanism, best) -> None:
    result = design_study(
        paper_fourbar, ["H8/g7"], ["m"], ["joint_force <= 1 N"], contact=ContactModel(), **FAST
    )
    assert result.best is best
    assert model_sensitivity(paper_fourbar, result, ContactModel(), **FAST) is None
