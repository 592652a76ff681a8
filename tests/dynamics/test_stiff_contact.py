"""Stiff multi-impact contact at the default tolerances (issue 40, item 2).

Lankarani–Nikravesh and Flores, K 1e10 N/m^1.5, e 0.8, no friction, dry, 21 µm in all four
joints of the paper four-bar, steady start, 0.1 revolution: the pins fly and strike their
bearings 15-16 times. At the default settings every located peak (ω, α, joint forces) keeps the
accuracy contract against a converged reference (rtol 1e-11, atol 1e-15 m and 1e-11 m/s,
onset 2.1 fm; over 18 neighbouring cases it lies within 4.7e-7 of one with the onset ten
times looser: docs/performance.md, "Stiff multi-impact contact:
the onset tolerance"). Before the default onset tolerance became 0.01 % of the smallest
clearance for the laws that read the impact velocity (it was 1 %) the peaks were off by up
to 8.5 % (LN) and 1.5 % (Flores); they now measure 2.7e-4 and 7.7e-5. With the other laws
it stays 1 %. The batch engine takes the same default.
"""

from __future__ import annotations

import numpy as np
import pytest

from _tolerances import contract_rtol
from jointplay._kernels import ids
from jointplay.contact.laws import get_law
from jointplay.dynamics.batch_inputs import BatchSamples, _offset, build_batch
from jointplay.dynamics.clearance import ClearanceJoint
from jointplay.dynamics.simulate import SolverOptions, Start, simulate
from jointplay.dynamics.system import build_system, onset_fraction
from jointplay.errors import SettingError

ALL = ("O2", "A", "B", "O4")
PEAKS = ("omega3", "omega4", "alpha3", "alpha4", "F_O2", "F_A", "F_B", "F_O4")
CLEARANCE = 21e-6
#: Converged: every tolerance far below the defaults (10 000 steps, 0.3 s).
REFERENCE = SolverOptions(
    rtol=1e-11, atol_position=1e-15, atol_velocity=1e-11, onset_tolerance=CLEARANCE * 1e-7
)


def _joints(law_name: str) -> list[ClearanceJoint]:
    extra = {} if law_name == "hertz" else {"restitution": 0.8}
    law = get_law(law_name, stiffness=1e10, exponent=1.5, **extra)
    return [ClearanceJoint(j, CLEARANCE, 5e-3, law) for j in ALL]  # dry, frictionless


def _peaks(paper_fourbar, joints, solver: SolverOptions) -> tuple[dict[str, float], dict]:
    result = simulate(
        paper_fourbar, joints, revolutions=0.1, settle=0, start=Start("steady"), solver=solver
    )
    return {k: result.peaks[k]["value"] for k in PEAKS}, result.solver_stats


@pytest.mark.parametrize("law_name", ["lankarani-nikravesh", "flores"])
def test_stiff_multi_impact_contact_keeps_the_contract_at_the_default_tolerances(
    paper_fourbar, law_name
) -> None:
    joints = _joints(law_name)
    reference, _ = _peaks(paper_fourbar, joints, REFERENCE)
    peaks, stats = _peaks(paper_fourbar, joints, SolverOptions())
    assert sum(stats["impacts"].values()) >= 10  # the pins really fly and strike
    error = {k: abs(peaks[k] / reference[k] - 1) for k in PEAKS}
    assert all(error[k] < contract_rtol(k) for k in PEAKS), error


@pytest.mark.parametrize(("law_name", "fraction"), [("flores", 1e-4), ("hertz", 1e-2)])
def test_the_default_onset_tolerance_is_the_same_fraction_in_both_engines(
    paper_fourbar, law_name, fraction
) -> None:
    """0.01 % of the smallest clearance where a law reads the impact velocity (Flores), 1 %
    where none does (Hertz): the single engine's and, sample by sample, the batch engine's
    (the vectorised builder and the one that builds each sample)."""
    joints = _joints(law_name)
    assert onset_fraction(joints) == fraction
    system = build_system(paper_fourbar, joints)
    assert system.model.settings[ids.S_ONSET_TOL] == pytest.approx(fraction * CLEARANCE)
    samples = BatchSamples(clearances={"A": np.array([15e-6, 30e-6]), "B": np.array([40e-6] * 2)})
    for vectorised in (True, False):
        problem = build_batch(paper_fourbar, joints, samples, vectorised=vectorised)
        onset = problem.rpar[:, _offset(problem.ipar, "settings") + ids.S_ONSET_TOL]
        np.testing.assert_allclose(onset, fraction * np.array([15e-6, 21e-6]), rtol=1e-12)


@pytest.mark.parametrize("onset", [0.0, -1e-9, float("nan"), CLEARANCE, 1e-3])
def test_an_onset_tolerance_not_between_0_and_the_clearance_is_refused(
    paper_fourbar, onset
) -> None:
    with pytest.raises(SettingError, match="onset_tolerance"):
        build_system(paper_fourbar, _joints("flores"), onset_tolerance=onset)
