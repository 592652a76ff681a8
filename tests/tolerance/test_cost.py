"""Cost–tolerance models: monotone in the tolerance, overridable from a table."""

from __future__ import annotations

import itertools
import math

import pytest

from jointplay.errors import ConfigError
from jointplay.tolerance import iso286
from jointplay.tolerance.cost import CostModel, fit_cost, length_class_cost

FITS = ("H7/h6", "H7/g6", "H8/g7", "H8/f7", "H9/d9", "H11/c11", "C11/h11")
LENGTHS = {"crank": 0.108, "coupler": 0.2705, "rocker": 0.2705, "ground": 0.2794}


@pytest.mark.parametrize("model", [CostModel(), CostModel(model="exponential", k=0.5)])
def test_looser_fits_never_cost_more(model: CostModel) -> None:
    by_looseness = sorted(FITS, key=lambda f: iso286.fit(f, 0.010).clearance_max)
    costs = [fit_cost(f, 0.010, model) for f in by_looseness]
    assert all(b <= a for a, b in itertools.pairwise(costs))
    assert costs[0] > costs[-1]


def test_coarser_length_classes_never_cost_more() -> None:
    costs = [length_class_cost(c, LENGTHS) for c in "fmcv"]
    assert costs == sorted(costs, reverse=True) and costs[0] > costs[-1]


def test_reciprocal_power_by_hand() -> None:
    # C(T) = a + b (T_ref/T)^k: a feature at 10 µm with T_ref = 0.1 mm, k = 1 costs 1 + 10
    assert CostModel().feature_cost(10e-6) == pytest.approx(11.0, rel=1e-12)
    assert CostModel(k=2).feature_cost(50e-6) == pytest.approx(5.0, rel=1e-12)
    # exponential: a + b exp(-m (T - T_ref)/T_ref)
    model = CostModel(model="exponential", k=1.0)
    assert model.feature_cost(2e-4) == pytest.approx(1 + math.exp(-1), rel=1e-12)


def test_fit_cost_is_its_two_it_grades() -> None:
    model = CostModel()
    expected = model.feature_cost(iso286.standard_tolerance(7, 0.01)) + model.feature_cost(
        iso286.standard_tolerance(6, 0.01)
    )
    assert fit_cost("H7/g6", 0.01, model) == pytest.approx(expected, rel=1e-12)


def test_table_overrides_grades_classes_and_parameters() -> None:
    model = CostModel.from_table(
        {"model": "reciprocal-power", "k": 0.5, "reference": "0.05 mm", "it": {"IT7": 9.0},
         "iso2768": {"m": 0.25}}
    )  # fmt: skip
    assert model.k == 0.5 and model.reference == pytest.approx(5e-5)
    assert model.grade_cost(7, 0.01) == 9.0
    assert model.length_cost("medium", 0.1) == 0.25
    assert fit_cost("H7/h7", 0.01, model) == 18.0


@pytest.mark.parametrize(
    ("table", "message"),
    [
        ({"colour": 1}, "unknown key"),
        ({"model": "linear"}, "model must be one of"),
        ({"k": -1}, "k must be finite and > 0"),
        ({"it": {"seven": 1}}, "IT grade"),
        ({"a": "x"}, "must be a number"),
        ({"reference": 0.1}, r"\[cost\] reference: 0.1 has no unit"),  # 0.1 mm or 0.1 m?
    ],
)
def test_table_errors_name_the_field(table: dict, message: str) -> None:
    with pytest.raises(ConfigError, match=message):
        CostModel.from_table(table)
