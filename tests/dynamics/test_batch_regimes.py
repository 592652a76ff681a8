"""The batch engine's time in each lubrication regime (issue 39, item 4): per lubricated
clearance joint, the kernels' ``full_film_<J>``, ``mixed_<J>``, ``boundary_<J>`` statistics
count each accepted step by λ = h_min/σ at its midpoint, as the single engine's
:attr:`~jointplay.dynamics.simulate.SimulationResult.film_regimes` counts its steps; the two
integrate the same motion with their own steps, so the fractions agree to the steps'
resolution (measured: at most 1.2e-4, O2's full-film share, in the first test below)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from jointplay.contact.laws import get_law
from jointplay.dynamics.batch import BatchSamples, simulate_batch
from jointplay.dynamics.setup import ContactModel
from jointplay.dynamics.simulate import Start, simulate
from jointplay.model.mechanism import Mechanism

JOINTS = ("O2", "A", "B", "O4")
#: The fractions of the two engines: the same motion on different steps (see the docstring).
REGIME_ATOL = 1e-3
REGIMES = ("full_film", "mixed", "boundary")


def test_the_batch_reports_the_single_engines_regimes(paper_fourbar: Mechanism) -> None:
    """A thin oil (1e-4 Pa*s) and σ = 0.1 µm at 21 µm: O2, A and B run partly mixed (their
    asperities touch where the film thins to 0.3 µm); O4 dry."""
    contact = ContactModel(roughness=0.0, lubricant_viscosity=1e-4)
    joints = [
        dataclasses.replace(j.with_clearance(21e-6), roughness=0.1e-6)
        if j.joint != "O4"
        else dataclasses.replace(j.with_clearance(21e-6), film_from=None, film_damping=0.0)
        for j in contact.joints(paper_fourbar)
    ]
    single = simulate(paper_fourbar, joints, revolutions=1, settle=1, start=Start("steady"))
    samples = BatchSamples(clearances={j: np.array([21e-6]) for j in JOINTS})
    batch = simulate_batch(paper_fourbar, joints, samples, backend="local", revolutions=1, settle=1)
    assert batch.method == "implicit" and batch.ok.all()
    stats = batch.statistics.iloc[0]
    for joint in ("O2", "A", "B"):
        regime = single.film_regimes[joint]
        assert regime is not None
        got = [stats[f"{name}_{joint}"] for name in REGIMES]
        want = [regime.full_film, regime.mixed, regime.boundary]
        np.testing.assert_allclose(got, want, rtol=0, atol=REGIME_ATOL, err_msg=joint)
        assert sum(got) == pytest.approx(1.0, abs=1e-12)
        assert 0.05 < stats[f"mixed_{joint}"] < 0.95, joint  # a split worth comparing
    assert batch.units["mixed_O2"] == "1"
    # a dry joint has no regime
    assert single.film_regimes["O4"] is None
    assert np.isnan([stats[f"{name}_O4"] for name in REGIMES]).all()


def test_the_kernels_count_each_step_by_its_midpoint() -> None:
    """The compiled regime integrals of one joint (c = 21 µm, σ = 1 µm, a Reynolds film: its
    kernels' δ = |e| − (c − 3σ)) over a made-up h_min history through all three regimes equal
    :func:`~jointplay.dynamics.regimes.joint_regime` of the same history; a dry joint's stay
    NaN."""
    from jointplay._kernels import ids
    from jointplay._kernels.lanes import cpu
    from jointplay._kernels.lanes.source import LY_GEOM
    from jointplay.dynamics.clearance import ClearanceJoint
    from jointplay.dynamics.regimes import joint_regime

    c, sigma = 21e-6, 1e-6
    rp = np.zeros(2 * ids.N_GEOM)
    for joint, film in enumerate((1e4, 0.0)):  # a lubricated joint, a dry one
        o = ids.N_GEOM * joint
        rp[o + ids.G_CLEARANCE], rp[o + ids.G_ROUGHNESS] = c, sigma
        rp[o + ids.G_FILM], rp[o + ids.G_FILM_MODEL] = film, ids.FILM_SHORT_PI
    lay = np.zeros(32, dtype=np.int64)
    lay[LY_GEOM] = 0
    t = np.linspace(0.0, 1.0, 201) ** 1.3  # uneven steps
    h = 4e-6 * np.cos(7.0 * t) + 2.5e-6  # h_min from 6.5 µm down to −1.5 µm: every regime
    pens = [np.array([(c - hk) - (c - 3 * sigma), 0.0]) for hk in h]
    nb, nc = 1, 2
    stats = np.full(2 * nb + 4 * nc, np.nan)
    f = cpu.compiled
    f["open_regimes"](rp, lay, pens[0], stats, nb, nc)
    for k in range(1, len(t)):
        f["accumulate_regimes"](rp, lay, pens[k], t[k] - t[k - 1], stats, nb, nc)
    f["close_regimes"](stats, nb, nc, t[-1] - t[0])
    law = get_law("hertz", stiffness=1e10, exponent=1.5)  # any: the regimes do not use it
    joint = ClearanceJoint("J", clearance=c, journal_radius=5e-3, law=law, roughness=sigma)
    want = joint_regime(joint, t, c - h, np.zeros_like(h))
    got = stats[2 * nb + nc : 2 * nb + nc + 3]
    np.testing.assert_allclose(got, [want.full_film, want.mixed, want.boundary], atol=1e-12)
    assert min(got) > 0.05  # every regime visited
    assert np.isnan(stats[2 * nb + nc + 3 :]).all()
