"""The lane source's running reductions (issue 42, item 1) against the NumPy functions they
stream: the wear spread over the Hertz arc (:func:`jointplay.dynamics.wear._spread`) and the
ideal output speed's periodic table (:meth:`OutputSpeedReference.at`); the capability row.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from jointplay._kernels import ids
from jointplay._kernels.capabilities import refusal
from jointplay._kernels.lanes import source
from jointplay._kernels.lanes.build import output_widths, running_layout
from jointplay._kernels.lanes.contract import lane_outputs
from jointplay._kernels.lanes.cpu import DRIVERS, compiled
from jointplay.dynamics.wear import OutputSpeedReference, _spread
from jointplay.model.mechanism import Mechanism


@pytest.mark.parametrize("bins", [8, 36, 720])
def test_spread_wear_is_the_profiles_spread(bins: int) -> None:
    # one step's amount spread about its angle, normalised, an arc narrower than a bin in the
    # nearest bin, wrapped around 2π: the same bins as the NumPy spread of cycle_wear
    rng = np.random.default_rng(bins)
    spread = compiled["spread_wear"]
    angles = np.concatenate([rng.uniform(0, 2 * math.pi, 40), [0.0, 2 * math.pi - 1e-12]])
    amounts = rng.uniform(0.1, 2.0, len(angles))
    halves = np.concatenate([rng.uniform(1e-4, 0.6, 40), [3.0, 1e-6]])
    for angle, amount, half in zip(angles, amounts, halves, strict=True):
        stats = np.zeros(bins + 3)
        spread(stats, 3, bins, angle, amount, half)
        expected = _spread(np.array([angle]), np.array([amount]), np.array([half]), bins)
        np.testing.assert_allclose(stats[3:], expected, rtol=1e-12, atol=1e-15 * amount)
        assert stats[:3].tolist() == [0.0, 0.0, 0.0]
        assert math.isclose(stats.sum(), amount, rel_tol=1e-12)


def test_reference_speed_is_the_periodic_table(paper_fourbar: Mechanism) -> None:
    reference = OutputSpeedReference.of(paper_fourbar)
    crank = np.asarray(reference.crank)
    keep = np.concatenate([[True], np.diff(crank) > 0])
    tail = np.concatenate([[0.0, keep.sum(), 8.0], crank[keep], np.asarray(reference.omega)[keep]])
    lay = np.zeros(source.N_LAY, dtype=np.int64)
    lay[source.LY_SETTINGS] = -ids.N_SETTINGS  # the tail at rp[0] (running_base)
    angles = np.concatenate(
        [np.linspace(-7.0, 13.0, 997), crank[:5], [crank[0] - 1e-9, crank[-1] + 1e-9]]
    )
    got = np.array([compiled["reference_speed"](tail, lay, a) for a in angles])
    np.testing.assert_allclose(got, reference.at(angles), rtol=1e-12, atol=1e-12 * reference.peak)


def test_the_running_tail_widens_the_outputs_only_when_given() -> None:
    # lanes without the tail keep the model's quantities and statistics (bit-identical
    # peaks: the fingerprint tests); with it one more quantity and the running slots
    from jointplay.dynamics.batch import BatchSamples, build_batch
    from jointplay.dynamics.clearance import ClearanceJoint
    from jointplay.dynamics.setup import DEFAULT_IMPACT
    from jointplay.io.config import load_preset

    mechanism = load_preset("paper-fourbar")
    joints = [ClearanceJoint(j, 2.5e-4, 5e-3, DEFAULT_IMPACT) for j in ("A", "B")]
    problem = build_batch(mechanism, joints, BatchSamples(size=2), revolutions=1.0, settle=0)
    lay = running_layout(problem.ipar, problem.rpar)
    n_q, n_stats = output_widths(lay, problem.rpar)
    nb, nj, nc = int(lay[source.LY_N]) // 3, int(lay[source.LY_NJ]), int(lay[source.LY_NC])
    assert (n_q, n_stats) == (2 * nb + nj + 1, 2 * nb + 4 * nc)
    bins = 16
    tail = np.array([[2.0, 3.0, bins, 0.0, 2.0, 4.0, 1.0, 1.0, 1.0, *([1.0] * 3 * nc)]] * 2)
    wide = np.hstack([problem.rpar, tail])
    lay = running_layout(problem.ipar, wide)
    assert output_widths(lay, wide) == (n_q + 1, n_stats + 5 * nc + 1 + 2 * bins * nc)


# compiles all four explicit drivers (~60 CPU-s on a cold cache, most of them no other
# default-tier test needs): the slow tier
@pytest.mark.slow
def test_the_explicit_drivers_run_their_own_compilation_of_the_lane() -> None:
    # the explicit drivers, one source over both compilations of the lane: the running ones
    # run source.RUNNING's lane (the wear rates closed at the window's end), the plain ones
    # the lane without it (the running slots as start_outputs left them: rates NaN)
    from jointplay.dynamics.batch import BatchSamples, build_batch
    from jointplay.dynamics.clearance import ClearanceJoint
    from jointplay.dynamics.setup import DEFAULT_IMPACT
    from jointplay.io.config import load_preset

    mechanism = load_preset("paper-fourbar")
    joints = [ClearanceJoint(j, 2.5e-4, 5e-3, DEFAULT_IMPACT) for j in ("A", "B")]
    problem = build_batch(mechanism, joints, BatchSamples(size=2), revolutions=0.1, settle=0)
    nc = len(joints)
    bins = 16
    joint = [5e-3, 1e11, 1e-12]  # width m, E* Pa, k/H 1/Pa
    tail = np.array([[2.0, 3.0, bins, 0.0, 2.0, 4.0, 1.0, 1.0, 1.0, *(joint * nc)]] * 2)
    rpar = np.hstack([problem.rpar, tail])
    lay = running_layout(problem.ipar, rpar)
    width = output_widths(lay, rpar)
    rates = slice(int(source.running_stats(lay)), int(source.running_stats(lay)) + nc)
    for (running, _), drivers in DRIVERS["explicit"].items():
        peaks, stats, status, t_reached, counts = lane_outputs(2, *width)
        drivers(
            problem.ipar, rpar, lay, problem.y0, problem.t_settle, problem.t_end,
            problem.max_step, problem.rtol, problem.atol, problem.max_steps,
            np.zeros(1, dtype=np.uint8), peaks, stats, status, t_reached, counts,
        )  # fmt: skip
        assert (status == ids.STATUS_SUCCESS).all()
        if running:
            assert np.isfinite(stats[:, rates]).all() and (stats[:, rates] > 0.0).all()
        else:
            assert np.isnan(stats[:, rates]).all()


def test_the_jax_backend_refuses_the_running_responses() -> None:
    assert refusal("batch-implicit", ["running_responses"]) is None
    assert refusal("lanes-implicit", ["running_responses"]) is None
    message = refusal("jax", ["running_responses"])
    assert message is not None and "no running responses" in message
    assert "cuda" in message and "CPU backends" in message
