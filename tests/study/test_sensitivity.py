"""The model sensitivity of a design's choice: the contact model's ends, one at a time."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import pytest

from jointplay.dynamics.clearance import DEFAULT_ROUGHNESS
from jointplay.dynamics.setup import DEFAULT_IMPACT, ContactModel, ContactSettings
from jointplay.model.mechanism import Mechanism
from jointplay.report.design import write_design
from jointplay.study.design import design_study, design_units
from jointplay.study.sensitivity import (
    FILM_DAMPING_RANGE,
    FRICTION_RANGE,
    RESTITUTION_RANGE,
    ROUGHNESS_FACTORS,
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
        ("film_model", "short-bearing-full"),
        ("roughness", f"{0.5 * DEFAULT_ROUGHNESS * 1e6:.3g} µm (×0.5)"),
        ("roughness", f"{2 * DEFAULT_ROUGHNESS * 1e6:.3g} µm (×2)"),
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
            for name in ("film_damping", "lubricant_viscosity", "film_model", "roughness")
            if getattr(case.contact, name) != getattr(default, name)
        }
        expected = {
            "stiffness_law": {"stiffness_law"},
            "friction": {"coefficient"},
            "lubrication": {"film_damping"},  # fixed at 0: dry
            "lubricant_viscosity": {"lubricant_viscosity"},
            "film_model": {"film_model"},
            "roughness": {"roughness"},
        }
        assert changed == expected.get(case.parameter, {"restitution"}), case
    # the roughness at half and twice each joint's default σ (none given)
    assert [c.contact.roughness for c in cases if c.parameter == "roughness"] == [
        pytest.approx(factor * DEFAULT_ROUGHNESS, rel=1e-12) for factor in ROUGHNESS_FACTORS
    ]
    full = ContactModel(film_model="short-bearing-full", roughness="2 um")  # the other way
    assert [(c.parameter, c.contact.film_model, c.contact.roughness) for c in model_cases(full)
            if c.parameter in ("film_model", "roughness")] == [
        ("film_model", "short-bearing-pi", pytest.approx(2e-6)),
        ("roughness", "short-bearing-full", pytest.approx(1e-6)),
        ("roughness", "short-bearing-full", pytest.approx(4e-6)),
    ]  # fmt: skip
    smooth = ContactModel(roughness=0.0)  # no roughness to scale: the film model only
    assert [c.parameter for c in model_cases(smooth) if c.parameter == "roughness"] == []
    graded = ContactModel(lubrication="oil ISO VG 46")  # the grade gives way to each case's
    assert [c.contact.viscosity for c in model_cases(graded)
            if c.parameter in ("lubrication", "lubricant_viscosity")] == [0.0, *VISCOSITY_RANGE]  # fmt: skip
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
        *("film_model", "roughness", "roughness"),
    ]


def test_the_chosen_scheme_is_re_evaluated_under_each_case(
    paper_fourbar: Mechanism, monkeypatch: pytest.MonkeyPatch
) -> None:
    import jointplay.study.design as design_module

    contact = ContactModel()
    requirements = ["joint_force <= 1 kN"]
    result = design_study(
        paper_fourbar, ["H8/g7"], ["m"], requirements, contact=contact, confidence=LEVEL, **FAST
    )
    checked: list[object] = []  # the re-runs report yields only: no convergence check
    monkeypatch.setattr(design_module, "convergence_finding", lambda *a: checked.append(a))
    sensitivity = model_sensitivity(paper_fourbar, result, contact, **FAST)
    assert checked == []
    monkeypatch.undo()
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
    # each row carries the required response at the level, as its own study computes it
    assert chosen.values == {"joint_force": result.best_row["joint_force_at_confidence"]}
    for parameter, changed in (
        ("film_model", dataclasses.replace(contact, film_model="short-bearing-full")),
        ("roughness", dataclasses.replace(contact, roughness=2 * DEFAULT_ROUGHNESS)),
    ):
        alone = design_study(
            paper_fourbar, ["H8/g7"], ["m"], requirements, contact=changed, confidence=LEVEL,
            **FAST,
        )  # fmt: skip
        row = [r for r in sensitivity.rows if r.parameter == parameter][-1]
        assert row.values["joint_force"] == alone.table.iloc[0]["joint_force_at_confidence"]
    film = next(r for r in sensitivity.rows if r.parameter == "film_model")
    assert film.values["joint_force"] != chosen.values["joint_force"]  # the film moves it
    assert record["rows"][0]["at_confidence"] == chosen.values


def test_the_table_is_on_the_reports_first_screen(paper_fourbar: Mechanism, tmp_path: Path) -> None:
    """Right under the answer and its evidence, before the study's settings and schemes; with
    the film model's and the roughness's rows."""
    contact = ContactModel()
    requirements = ["joint_force <= 1 kN"]
    result = design_study(
        paper_fourbar, ["H8/g7"], ["m"], requirements, contact=contact, confidence=LEVEL, **FAST
    )
    sensitivity = model_sensitivity(paper_fourbar, result, contact, **FAST)
    assert sensitivity is not None
    write_design(result, tmp_path, design_units(paper_fourbar, "dynamic"), plots=False,
                 sensitivity=sensitivity)  # fmt: skip
    html = (tmp_path / "report.html").read_text()
    answer = html.index("<p>Answer: ")
    table = html.index('<h3 id="model-sensitivity">')
    assert answer < table < html.index("requirement: joint_force") < html.index("Schemes by cost")
    for cell in ("film_model", "short-bearing-full", "roughness", "(×0.5)", "(×2)",
                 "joint_force at 10 % (N)", "95 % interval (%)", "parts worse",
                 "verdict at 2 samples", "on 2 of its 2 samples"):  # fmt: skip
        assert cell in html[table:], cell
    summary = json.loads((tmp_path / "summary.json").read_text())["model_sensitivity"]
    assert summary["ranges"]["film_model"] == ["short-bearing-pi", "short-bearing-full"]
    assert summary["ranges"]["roughness_factors"] == [0.5, 2.0]


def test_a_failing_end_is_named() -> None:
    rows = (
        SensitivityRow("as chosen", "", {"r": 100.0}, True, samples=200, verdict="meets"),
        SensitivityRow("friction", 0.2, {"r": 80.0}, False, samples=200, verdict="fails",
                       worse={"r": 40}),
        SensitivityRow("restitution", 0.6, {"r": 99.5}, False, samples=200,
                       verdict="undecided", worse={"r": 1}),
        SensitivityRow("restitution", 0.95, {"r": 100.0}, True, samples=200, verdict="meets"),
    )  # fmt: skip
    sensitivity = ModelSensitivity("H8/f7 / c", rows, 200, 1600)
    assert not sensitivity.holds
    assert sensitivity.verdict == (
        "the choice H8/f7 / c does not hold with friction = 0.2; moves with restitution = 0.6 "
        "(1 on 'r' of 200 parts) (on 200 of its 1,600 samples)"
    )
    held = ModelSensitivity("H8/f7 / c", (rows[0], rows[3]), 200, 1600)
    assert held.holds and held.verdict.endswith(
        "(on 200 of its 1,600 samples): no part fails a requirement it met as chosen"
    )


def test_the_table_runs_a_bounded_stated_number_of_samples(
    paper_fourbar: Mechanism, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Each row re-runs the first ``first`` of the chosen scheme's samples, not all the study
    took: the rows' samples, the table's statement and the simulations run say so."""
    import jointplay.study.design as design_module

    contact = ContactModel()
    requirements = ["joint_force <= 1 kN"]
    options = {**FAST, "samples": 3}
    result = design_study(
        paper_fourbar, ["H8/g7"], ["m"], requirements, contact=contact, confidence=LEVEL,
        **options,
    )  # fmt: skip
    assert result.best == "H8/g7 / m" and result.best_row["samples"] == 3
    real, ran = design_module.run, []

    def run(model, x, **kwargs):
        ran.append(len(x))
        return real(model, x, **kwargs)

    monkeypatch.setattr(design_module, "run", run)
    sensitivity = model_sensitivity(paper_fourbar, result, contact, first=2, **options)
    assert sensitivity is not None
    assert (sensitivity.samples, sensitivity.study_samples) == (2, 3)
    assert all(row.samples == 2 for row in sensitivity.rows)
    assert ran == [2] * len(sensitivity.rows)  # rows x first, whatever the study took
    assert "(on 2 of its 3 samples)" in sensitivity.verdict
    record = sensitivity.as_dict()
    assert (record["samples"], record["study_samples"]) == (2, 3)
    chosen = record["rows"][0]
    assert chosen["samples"] == 2 and chosen["parts_worse"] == {"joint_force <= 1 kN": 0}
    low, high = chosen["yield_ci95_percent"]["joint_force <= 1 kN"]
    assert (low, high) == pytest.approx((100 * 0.025 ** (1 / 2), 100.0))  # 2 of 2, exact
    assert chosen["verdict"] == "meets"  # 2 failure-free samples show 15.8 % >= 10 %


@pytest.mark.parametrize("best", [None])
def test_no_choice_no_table(paper_fourbar: Mechanism, best) -> None:
    result = design_study(
        paper_fourbar, ["H8/g7"], ["m"], ["joint_force <= 1 N"], contact=ContactModel(), **FAST
    )
    assert result.best is best
    assert model_sensitivity(paper_fourbar, result, ContactModel(), **FAST) is None
