"""A dynamic tolerance study carries the sustained-contact mode of its contact
(:func:`jointplay.tolerance.responses.contact_parts`) to every sample's clearance joints,
and runs it on the batch engine's implicit lanes."""

from __future__ import annotations

import dataclasses

import numpy as np

from jointplay.dynamics.setup import DEFAULT_CAPTURE_SPEED, ContactModel
from jointplay.model.mechanism import Mechanism
from jointplay.tolerance.execution import Backend
from jointplay.tolerance.responses import contact_parts, dynamic_model
from jointplay.tolerance.spec import ToleranceSpec


def test_a_dynamic_study_runs_the_mode_on_the_implicit_lanes(paper_fourbar: Mechanism) -> None:
    spec = ToleranceSpec.from_mechanism(paper_fourbar)
    models = {}
    for on in (False, True):
        parts = contact_parts(paper_fourbar, ContactModel(sustained_contact=on))
        assert parts["capture_speed"] == (DEFAULT_CAPTURE_SPEED if on else 0.0)
        model = dynamic_model(paper_fourbar, spec.names, revolutions=0.5, settle=0, **parts)
        models[on] = dataclasses.replace(model, backend=Backend("local"))
    on = models[True]
    assert {j.capture_speed for j in on._nominal_joints(None)} == {DEFAULT_CAPTURE_SPEED}
    assert on.method_choice().method == "implicit"
    assert on.describe()["capture_speed_m_s"] == DEFAULT_CAPTURE_SPEED
    assert "capture_speed_m_s" not in models[False].describe()
    x = np.repeat(spec.nominal[None, :], 2, axis=0)
    with_mode, without = on.evaluate(x), models[False].evaluate(x)
    assert with_mode.ok.all() and without.ok.all()
    assert not np.array_equal(with_mode.values, without.values)  # the mode took effect
