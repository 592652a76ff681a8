"""Lubrication, a declared property of each joint (issue 39, item 3): the regime of every
joint from the command's override, else the mechanism's declaration, else the default (oil of
0.05 Pa·s for the physical contact, dry with a contact law named)."""

from __future__ import annotations

import dataclasses

import pytest

from jointplay.dynamics.setup import (
    DEFAULT_IMPACT,
    DEFAULT_VISCOSITY,
    ContactModel,
    ContactSettings,
    FrictionSettings,
)
from jointplay.errors import ConfigError, SettingError
from jointplay.model.mechanism import Lubrication, Mechanism
from jointplay.settings.simulation import contact_model


def _regimes(contact: ContactModel, mechanism: Mechanism) -> dict[str, str]:
    table = contact.joint_lubrication(mechanism, contact.joints(mechanism))
    return {name: entry["regime"] for name, entry in table.items()}


def test_a_named_dry_law_runs_dry_unless_the_lubrication_is_named(
    paper_fourbar: Mechanism,
) -> None:
    # the command line's --contact lankarani-nikravesh --friction 0: dry, as the Python API
    named = contact_model({"contact": "lankarani-nikravesh", "friction": 0.0}, paper_fourbar)
    assert named.regime == "dry" and not named.lubricated
    assert all(j.film_damping == 0.0 for j in named.joints(paper_fourbar))
    api = ContactModel(ContactSettings(law="lankarani-nikravesh"), FrictionSettings())
    assert api.joints(paper_fourbar) == named.joints(paper_fourbar)
    # named together: the law in the film
    oiled = contact_model({"contact": "lankarani-nikravesh", "lubrication": "oil"}, paper_fourbar)
    assert oiled.regime == "oil" and oiled.viscosity == DEFAULT_VISCOSITY
    assert all(j.film_damping > 0 for j in oiled.joints(paper_fourbar))
    thick = contact_model({"contact": "hertz", "lubricant_viscosity": "0.1 Pa*s"}, paper_fourbar)
    assert thick.regime == "oil" and thick.viscosity == pytest.approx(0.1)
    # the physical default (no law named, or its own law named) stays lubricated
    for values in ({}, {"contact": "restitution"}):
        default = contact_model(values, paper_fourbar)
        assert default.regime == "oil" and default.viscosity == DEFAULT_VISCOSITY
    # the paper's methods run dry, unless a lubricant is named with them
    assert contact_model({"method": "ifm-conventional"}, paper_fourbar).regime == "dry"
    method_oiled = contact_model(
        {"method": "ifm-conventional", "lubrication": "oil"}, paper_fourbar
    )
    assert method_oiled.regime == "oil"
    assert not ContactModel(law=DEFAULT_IMPACT).lubricated


def test_each_joint_runs_in_its_declared_lubrication(paper_fourbar: Mechanism) -> None:
    declared = dataclasses.replace(
        paper_fourbar,
        lubrication=Lubrication("oil", 0.1),
        joint_lubrication={"O2": Lubrication("dry"), "A": Lubrication("grease", 0.15)},
    )
    contact = ContactModel()
    joints = {j.joint: j for j in contact.joints(declared)}
    assert joints["O2"].film_damping == 0.0 and joints["O2"].film_from is None
    assert joints["A"].film_from is not None and joints["A"].film_from.viscosity == 0.15
    assert joints["B"].film_from is not None and joints["B"].film_from.viscosity == 0.1
    table = contact.joint_lubrication(declared, list(joints.values()))
    assert table["O2"] == {
        "regime": "dry", "viscosity_Pa_s": None, "film_model": None,
        "film_damping_N_s_m": 0.0, "declared": "mechanism",
    }  # fmt: skip
    assert table["A"]["regime"] == "grease" and table["A"]["film_model"] == "short-bearing-pi"
    # a named dry law keeps the joints' declarations (the file names their lubricant)
    named = ContactModel(ContactSettings(law="hertz"))
    assert _regimes(named, declared) == {"O2": "dry", "A": "grease", "B": "oil", "O4": "oil"}
    # the command's lubrication holds at every joint
    assert set(_regimes(ContactModel(lubrication="dry"), declared).values()) == {"dry"}
    assert set(_regimes(ContactModel(film_damping=0), declared).values()) == {"dry"}
    every = ContactModel(lubricant_viscosity="0.02 Pa*s")
    assert {j.film_from.viscosity for j in every.joints(declared) if j.film_from} == {0.02}
    # an oil declared without a viscosity: the default's
    plain = dataclasses.replace(paper_fourbar, lubrication=Lubrication("oil"))
    named_plain = ContactModel(ContactSettings(law="hertz")).joints(plain)
    assert {j.film_from.viscosity for j in named_plain if j.film_from} == {DEFAULT_VISCOSITY}
    words = contact.regime_words(declared, list(joints))
    assert words == (
        "O2 dry; A lubricated, 0.15 Pa*s grease base oil; B, O4 lubricated, 0.1 Pa*s oil"
    )
    assert contact.regime_words(paper_fourbar, ["O2", "A", "B", "O4"]) == (
        "lubricated, 0.05 Pa*s oil"
    )


@pytest.mark.parametrize(
    ("given", "message"),
    [
        ({"lubrication": "wet"}, "lubrication must be one of dry, oil, grease, got 'wet'"),
        (
            {"lubrication": "dry", "lubricant_viscosity": "0.05 Pa*s"},
            "lubrication dry runs the joints without a film: drop lubricant_viscosity",
        ),
        (
            {"lubrication": "dry", "film_damping": "100 N*s/m"},
            "lubrication dry runs the joints without a film: drop film_damping",
        ),
        ({"lubrication": "grease"}, "lubrication grease needs its base oil's viscosity"),
        (
            {"lubrication": "oil", "lubricant_viscosity": 0},
            "lubrication oil needs a lubricant",
        ),
        ({"lubricant_viscosity": "-1 Pa*s"}, "lubricant_viscosity must be >= 0"),
    ],
)
def test_bad_lubrication_is_refused(given: dict[str, object], message: str) -> None:
    with pytest.raises(SettingError, match=message):
        ContactModel(**given)  # type: ignore[arg-type]


def test_a_declaration_is_checked() -> None:
    with pytest.raises(ConfigError, match="one of dry, oil, grease"):
        Lubrication("wet")
    with pytest.raises(ConfigError, match="a dry joint has no lubricant"):
        Lubrication("dry", 0.05)
    with pytest.raises(ConfigError, match="must be > 0 Pa"):
        Lubrication("oil", -0.05)
    with pytest.raises(ConfigError, match="base oil's viscosity"):
        Lubrication("grease")


def test_the_contact_text_defers_to_the_declarations(paper_fourbar: Mechanism) -> None:
    declared = dataclasses.replace(paper_fourbar, joint_lubrication={"A": Lubrication("dry")})
    named = ContactModel(ContactSettings(law="hertz"))
    text = named.describe(declared)["text"]
    assert "as the mechanism declares" in text and "undeclared joints dry" in text
    assert "dry joints" in named.describe(paper_fourbar)["text"]  # nothing declared
    assert "dry joints" in ContactModel(lubrication="dry").describe(declared)["text"]
