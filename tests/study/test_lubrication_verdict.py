"""The regime stated where the user reads a study's result (issue 39, item 3): the dynamic
model's description names each joint's lubrication, and the verdict line says it."""

from __future__ import annotations

import pandas as pd

from jointplay.dynamics.settings import RunSettings
from jointplay.dynamics.setup import ContactModel
from jointplay.model.mechanism import Mechanism
from jointplay.study.design import DesignResult
from jointplay.tolerance.response_dynamic import run_model

TABLE = pd.DataFrame(
    {
        "scheme": ["H9/d9 / c"],
        "cost": [30.0],
        "samples": [100],
        "verdict": ["meets"],
        "feasible": [True],
        "samples_to_decide": pd.array([None], dtype="Int64"),
        "yield": [100.0],
    }
)


def _verdict(
    mechanism: Mechanism,
    contact: ContactModel,
    table: pd.DataFrame = TABLE,
    best: str | None = "H9/d9 / c",
) -> str:
    names = ("clearance_O2", "clearance_A", "clearance_B", "clearance_O4")
    model = run_model(mechanism, names, RunSettings(contact))
    settings = {"model": model.describe()}
    binding = None if best else "joint_force <= 150 N"
    result = DesignResult(
        mechanism, "dynamic", (), 0.9973, table, pd.DataFrame(), best, binding, False,
        settings=settings,
    )  # fmt: skip
    return result.verdict


def test_the_verdict_says_the_regime(paper_fourbar: Mechanism) -> None:
    assert _verdict(paper_fourbar, ContactModel()) == (
        "cheapest scheme shown to meet every requirement: H9/d9 / c — lubricated, 0.05 Pa*s oil"
    )
    assert _verdict(paper_fourbar, ContactModel(lubrication="dry")) == (
        "cheapest scheme shown to meet every requirement: H9/d9 / c — dry"
    )
    failed = TABLE.assign(verdict=["fails"], feasible=[False])
    assert _verdict(paper_fourbar, ContactModel(lubrication="dry"), failed, None) == (
        "every scheme fails — dry; binding requirement: joint_force <= 150 N"
    )


def test_the_model_names_each_joints_lubrication(paper_fourbar: Mechanism) -> None:
    names = ("clearance_O2", "clearance_A")
    described = run_model(paper_fourbar, names, RunSettings(ContactModel())).describe()
    assert described["lubrication"]["O2"] == {
        "regime": "oil", "viscosity_Pa_s": 0.05, "film_model": "short-bearing-pi", "declared": "default",
    }  # fmt: skip
    assert described["lubrication_text"] == "lubricated, 0.05 Pa*s oil"
