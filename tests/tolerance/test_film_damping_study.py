"""A dynamic tolerance study carries the film damping of its contact
(:func:`jointplay.tolerance.responses.contact_parts`) to every sample's clearance joints,
and runs it on the batch engine's implicit lanes."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from jointplay.dynamics.setup import ContactModel
from jointplay.model.mechanism import Mechanism
from jointplay.tolerance.execution import Backend
from jointplay.tolerance.responses import contact_parts, dynamic_model
from jointplay.tolerance.spec import ToleranceSpec


def test_a_dynamic_study_runs_the_film_on_the_implicit_lanes(paper_fourbar: Mechanism) -> None:
    spec = ToleranceSpec.from_mechanism(paper_fourbar)
    models = {}
    for film in (0.0, 100.0):  # dry joints, and a thin film
        parts = contact_parts(paper_fourbar, ContactModel(film_damping=film))
        assert parts["film_damping"] == film
        model = dynamic_model(paper_fourbar, spec.names, revolutions=0.5, settle=0, **parts)
        models[film] = dataclasses.replace(model, backend=Backend("local"))
    on = models[100.0]
    assert {j.film_damping for j in on._nominal_joints(None)} == {100.0}
    x = np.repeat(spec.nominal[None, :], 2, axis=0)
    assert {j.film_damping for j in on._nominal_joints(None)} == {100.0}
    assert on.method_choice().method == "implicit"
    assert on.describe()["film_damping_N_s_m"] == 100.0
    assert "film_damping_N_s_m" not in models[0.0].describe()
    with_film, without = on.evaluate(x), models[0.0].evaluate(x)
    assert with_film.ok.all() and without.ok.all()
    assert not np.array_equal(with_film.values, without.values)  # the film took effect


def test_the_jax_gpu_backend_refuses_a_lubricated_study_up_front(paper_fourbar: Mechanism) -> None:
    """One clear error before any sample runs (it used to fail every sample), naming the
    option that runs the joints dry; dry joints are accepted."""
    from jointplay.errors import SettingError

    spec = ToleranceSpec.from_mechanism(paper_fourbar)
    lubricated = contact_parts(paper_fourbar, ContactModel())
    assert lubricated["film_from"]
    with pytest.raises(SettingError, match="lubricant_viscosity"):
        dynamic_model(paper_fourbar, spec.names, backend=Backend("gpu"), **lubricated)
    dry = contact_parts(paper_fourbar, ContactModel(lubricant_viscosity=0))
    assert not dry["film_from"] and dry["film_damping"] == 0.0
    dynamic_model(paper_fourbar, spec.names, backend=Backend("gpu"), **dry)


def test_the_default_studys_scatter_is_the_mechanisms_not_the_integrators(
    paper_fourbar: Mechanism,
) -> None:
    """The lubricated default's dynamic study passes its own convergence check at the
    default tolerances: 8 samples run again 100× tighter move every response by less than
    a tenth of its spread. Measured (200 samples, seed 1): largest share 0.006 (α3) with
    the three-point quintic between steps; 1.25 (α3) and 0.64 (F_B) with the derivative of
    q's cubic, which this fails."""
    from jointplay.tolerance.analysis import CONVERGENCE_LIMIT, tolerance_study

    result = tolerance_study(paper_fourbar, responses="dynamic", samples=48, seed=1)
    check = result.convergence
    assert check is not None and check.samples == 8
    assert check.finding is None, check.as_dict()
    assert check.share < CONVERGENCE_LIMIT / 5, check.as_dict()
