"""The compiled batch kernel against the single engine, lane by lane.

Reference: :func:`jointplay.dynamics.simulate.simulate` (compiled Radau IIA, peaks located on
its continuous solution by zooming). Tolerances, each with its reason:

- explicit vs single engine: the accuracy contract (``_tolerances.contract_rtol``: 1e-5
  relative on ω and 1e-3 on α, forces and torque) — two different integrators at rtol = 1e-6
  (issue 14's acceptance bounds); measured on the three lanes: ω 7.2e-6, forces 7.3e-5,
  α 7.0e-5, torque 2.9e-5;
- implicit vs single engine: the same Radau steps, so only the peak search differs (five
  samples and a parabola per refined step against a converged zoom):
  ``PEAK_SEARCH_OMEGA_RTOL`` and ``PEAK_SEARCH_OTHER_RTOL``.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest

from _tolerances import contract_rtol
from jointplay._kernels import batch as kb
from jointplay._kernels import eom, ids
from jointplay._kernels.lanes import build as lane_build
from jointplay._kernels.lanes import source as lane_source
from jointplay._kernels.lanes.cpu import compiled as lane_compiled
from jointplay._kernels.lanes.source_radau import RULE_CUBIC_DERIVATIVE, RULE_QUINTIC, RULE_RATES
from jointplay.dynamics.clearance import ClearanceJoint
from jointplay.dynamics.setup import DEFAULT_IMPACT, ContactModel
from jointplay.dynamics.simulate import Start, _interpolate, initial_state, simulate
from jointplay.dynamics.system import build_system
from jointplay.model.mechanism import Mechanism
from jointplay.model.templates import with_lengths

JOINTS = ("O2", "A", "B", "O4")
#: The batch kernel's peak search against the single engine's zoom on the same steps; measured
#: on the three lanes: ω 6.2e-8; α 1.1e-4, forces 2.1e-5, torque 2.5e-7 (one bound for the
#: others, set by α, the peak the parabola fits worst).
PEAK_SEARCH_OMEGA_RTOL = 6e-7
PEAK_SEARCH_OTHER_RTOL = 2e-4
KEYS = ("omega3", "omega4", "alpha3", "alpha4", "F_O2", "F_A", "F_B", "F_O4", "torque")
#: QUANTITY ORDER columns of KEYS for the paper's four-bar (3 bodies, 4 joints).
COLUMNS = (1, 2, 4, 5, 6, 7, 8, 9, 10)


def _lane(mechanism: Mechanism, clearance: float):
    joints = [ClearanceJoint(j, clearance, 0.005, DEFAULT_IMPACT) for j in JOINTS]
    system = build_system(mechanism, joints)
    rpar, ipar = eom.pack(system.model)
    y0 = initial_state(system, Start("steady"))
    n = system.n_coordinates
    atol = np.concatenate([np.full(n, 1e-10), np.full(n, 1e-6), np.full(2, 1e-6), np.ones(4)])
    return joints, rpar, ipar, y0, atol


@pytest.fixture(scope="module")
def lanes(paper_fourbar: Mechanism):
    """Three samples: the nominal four-bar and two with other lengths and clearances."""
    cases = [
        (paper_fourbar, 11.75e-6),
        (with_lengths(paper_fourbar, crank=0.1085, coupler=0.2702), 14e-6),
        (with_lengths(paper_fourbar, rocker=0.2711, ground=0.2789), 9e-6),
    ]
    built = [_lane(m, c) for m, c in cases]
    period = paper_fourbar.driver.period
    rpar = np.stack([b[1] for b in built])
    y0 = np.stack([b[3] for b in built])
    args = (built[0][2], rpar, y0, 0.0, period, period / 360.0, 1e-6, built[0][4], 200_000)
    references = [
        simulate(m, b[0], revolutions=1, settle=0, start=Start("steady"))
        for (m, _), b in zip(cases, built, strict=True)
    ]
    return args, references


def _relative(value: float, reference: float) -> float:
    return abs(value - reference) / abs(reference)


def test_explicit_lanes_agree_with_the_single_engine(lanes) -> None:
    args, references = lanes
    out = kb.run_batch(*args, "explicit")
    assert (out.status == ids.STATUS_SUCCESS).all()
    for lane, reference in enumerate(references):
        for key, column in zip(KEYS, COLUMNS, strict=True):
            got = out.peaks[lane, column]
            assert _relative(got, reference.peaks[key]["value"]) < contract_rtol(key), (lane, key)


def test_implicit_lanes_take_the_single_engines_steps(lanes) -> None:
    args, references = lanes
    out = kb.run_batch(*args, "implicit")
    for lane, reference in enumerate(references):
        assert out.n_steps[lane] == reference.solver_stats["steps"]
        for key, column in zip(KEYS, COLUMNS, strict=True):
            omega = key.startswith("omega")
            bound = PEAK_SEARCH_OMEGA_RTOL if omega else PEAK_SEARCH_OTHER_RTOL
            got = out.peaks[lane, column]
            assert _relative(got, reference.peaks[key]["value"]) < bound, (lane, key)


def test_implicit_lanes_on_threads_give_the_same_bits(lanes) -> None:
    """The compiled Radau driver releases the GIL and each lane writes its own rows: the
    thread pool of ``parallel=True`` changes nothing but the wall time."""
    args, _ = lanes
    one = kb.run_batch(*args, "implicit", parallel=False)
    threads = kb.run_batch(*args, "implicit", parallel=True)
    for field in ("peaks", "stats", "status", "n_steps", "n_rejected", "n_rhs"):
        np.testing.assert_array_equal(getattr(threads, field), getattr(one, field), err_msg=field)


def test_statistics_agree_with_the_single_engines_solution(lanes) -> None:
    """Mean and RMS of ω from the single engine's dense time series (trapezoids on 0.5°
    samples: 1e-4 of the RMS), the deepest penetration from its steps (1e-3)."""
    args, references = lanes
    out = kb.run_batch(*args, "explicit")
    for lane, reference in enumerate(references):
        series = reference.timeseries
        t = series["t"].to_numpy()
        for k, key in enumerate(("omega3", "omega4")):
            w = series[key].to_numpy()
            span = t[-1] - t[0]
            mean = np.trapezoid(w, t) / span
            rms = math.sqrt(np.trapezoid(w * w, t) / span)
            body = k + 1
            assert abs(out.stats[lane, body] - mean) < 1e-4 * rms
            assert _relative(out.stats[lane, 3 + body], rms) < 1e-4
        for c, joint in enumerate(JOINTS):
            deepest = reference.solver_stats["max_penetration_per_joint_m"][joint]
            assert _relative(out.stats[lane, 6 + c], deepest) < 1e-3


def test_lanes_do_not_depend_on_their_neighbours_or_threads(lanes) -> None:
    args, _ = lanes
    together = kb.run_batch(*args, "explicit", parallel=True)
    ipar, rpar, y0, *rest = args
    for lane in range(len(rpar)):
        alone = kb.run_batch(ipar, rpar[lane : lane + 1], y0[lane : lane + 1], *rest, "explicit",
                             parallel=False)  # fmt: skip
        for name in kb.BatchKernelOutput._fields:
            np.testing.assert_array_equal(getattr(alone, name)[0], getattr(together, name)[lane])


def test_a_failing_lane_does_not_stop_the_others(lanes) -> None:
    (ipar, rpar, y0, *rest), _ = lanes
    broken = rpar.copy()
    offset = int(lane_build.lane_layout(ipar)[lane_source.LY_LAW_P])  # first law parameter: k
    broken[1, offset] = 1e308  # an absurd stiffness: the force overflows
    out = kb.run_batch(ipar, broken, y0, *rest, "explicit")
    assert out.status.tolist() == [ids.STATUS_SUCCESS, ids.STATUS_NON_FINITE, ids.STATUS_SUCCESS]
    assert np.isnan(out.peaks[1]).all() and np.isfinite(out.peaks[[0, 2]]).all()
    few = kb.run_batch(ipar, rpar, y0, *rest[:-1], 50, "explicit")
    assert (few.status == ids.STATUS_TOO_MANY_STEPS).all() and (few.n_steps == 50).all()


def test_dopri5_tableau_satisfies_the_order_conditions() -> None:
    """Order 5 of the propagated weights, order 4 of the embedded ones (b − E), row sums
    equal to the nodes — independent of the code that uses them (exact fractions)."""
    c = [0, Fraction(1, 5), Fraction(3, 10), Fraction(4, 5), Fraction(8, 9), 1, 1]
    a = [
        [],
        [Fraction(1, 5)],
        [Fraction(3, 40), Fraction(9, 40)],
        [Fraction(44, 45), Fraction(-56, 15), Fraction(32, 9)],
        [Fraction(19372, 6561), Fraction(-25360, 2187), Fraction(64448, 6561),
         Fraction(-212, 729)],
        [Fraction(9017, 3168), Fraction(-355, 33), Fraction(46732, 5247), Fraction(49, 176),
         Fraction(-5103, 18656)],
    ]  # fmt: skip
    b = [Fraction(35, 384), 0, Fraction(500, 1113), Fraction(125, 192), Fraction(-2187, 6784),
         Fraction(11, 84), 0]  # fmt: skip
    e = [Fraction(71, 57600), 0, Fraction(-71, 16695), Fraction(71, 1920),
         Fraction(-17253, 339200), Fraction(22, 525), Fraction(-1, 40)]  # fmt: skip
    for row, node in zip(a[1:], c[1:6], strict=True):
        assert sum(row) == node
    floats = [
        lane_source.B1,
        0.0,
        lane_source.B3,
        lane_source.B4,
        lane_source.B5,
        lane_source.B6,
        0.0,
    ]
    assert floats == [float(v) for v in b]
    assert [float(v) for v in e] == [
        lane_source.E1,
        0.0,
        lane_source.E3,
        lane_source.E4,
        lane_source.E5,
        lane_source.E6,
        lane_source.E7,
    ]
    hat = [bi - ei for bi, ei in zip(b, e, strict=True)]
    for weights, order in ((b, 5), (hat, 4)):
        for p in range(1, order + 1):
            assert sum(w * ci ** (p - 1) for w, ci in zip(weights, c, strict=True)) == Fraction(
                1, p
            )
    # the dense output reproduces the step's end: Σ_m P[j, m] = b_j
    np.testing.assert_allclose(kb.DENSE.sum(axis=1), [float(v) for v in b], atol=1e-15)


def test_the_parabolic_refinement_finds_a_parabolas_vertex() -> None:
    """Samples of 5 − (θ − 0.4)² at θ = 0, 1/8, …, 1: the vertex 5 is found exactly."""
    theta = np.concatenate([[0.0], kb.REFINE_POINTS, [1.0]])
    samples = (5.0 - (theta - 0.4) ** 2)[:, None]
    peaks = np.array([0.0])
    lane_compiled["refine_peaks"](samples, peaks, 0, peaks.shape[0])
    assert peaks[0] == pytest.approx(5.0, rel=1e-15)


@pytest.mark.parametrize("every", [False, True])
def test_the_refinement_takes_every_quantity_or_the_last_alone(every: bool) -> None:
    """One refinement for both rules: every quantity (the peak rule) or the last alone (the
    running responses' speed deviation, refined on every step); the others are left as they
    were, their samples unread."""
    theta = np.concatenate([[0.0], kb.REFINE_POINTS, [1.0]])
    last = 5.0 - (theta - 0.4) ** 2
    samples = np.full((len(theta), 2), np.nan)
    samples[1:-1, 0] = 9.0 - (theta[1:-1] - 0.5) ** 2  # a larger bump in the first quantity
    samples[1:-1, 1] = last[1:-1]
    qa = np.array([8.75, last[0]])
    qb = np.array([8.75, last[-1]])
    peaks = np.zeros(2)
    first = lane_compiled["refine_start"](qa, qb, samples, every, 2)
    assert first == (0 if every else 1)
    assert samples[[0, -1], 1].tolist() == [last[0], last[-1]]
    assert np.isnan(samples[[0, -1], 0]).all() != every
    lane_compiled["refine_peaks"](samples, peaks, first, 2)
    assert peaks[1] == pytest.approx(5.0, rel=1e-15)
    assert peaks[0] == (pytest.approx(9.0, rel=1e-15) if every else 0.0)


@pytest.mark.parametrize("film", [0.0, 1e5])
def test_the_implicit_lanes_interpolate_as_the_single_engine(
    paper_fourbar: Mechanism, film: float
) -> None:
    """The lane source's ``hermite`` with its rule (the implicit lanes' interpolant) is the
    single engine's ``_interpolate``: q̇ the Hermite of q̇ with q̈ without the film; with it
    the quintic through q and q̇ at three step ends in steps away from a contact's start or
    end, and the derivative of q's cubic in the others and the first (``smooth_steps``: here
    a joint starts touching in step 2, so steps 0, 2 and 3 take the cubic's derivative). To round-off (measured: a few ulps where NumPy's ``s**3`` is
    ``pow`` and Numba's a product)."""
    joints = ContactModel(film_damping=film).joints(paper_fourbar, JOINTS, clearance=21e-6)
    system = build_system(paper_fourbar, joints)
    n = system.n_coordinates
    rng = np.random.default_rng(7)
    t = np.cumsum(rng.uniform(1e-4, 1e-3, 7))
    y = rng.standard_normal((t.size, 2 * n + 2 + len(JOINTS)))
    qdd = rng.standard_normal((t.size, n))
    touching = np.zeros((t.size, len(JOINTS)), dtype=bool)
    touching[3:, 1] = True
    bits = [lane_compiled["touching"](np.where(row, 1e-7, -1e-7), len(JOINTS)) for row in touching]
    f = np.zeros_like(y)  # the lane source takes q̈ in f[n:2n]
    f[:, n : 2 * n] = qdd
    samples = np.sort(rng.uniform(t[0], t[-1], 60))
    expected = _interpolate(system, t, y, qdd, touching, samples)
    got = np.empty(y.shape[1])
    rules = set()
    for k, tau in enumerate(samples):
        i = min(int(np.searchsorted(t, tau, side="right")) - 1, t.size - 2)
        b = max(i - 1, 0)
        rule = lane_compiled["interpolation_rule"](film > 0, i >= 1, bits[b], bits[i], bits[i + 1])
        rules.add(rule)
        lane_compiled["hermite"](t[b], y[b], t[i], y[i], f[i], t[i + 1], y[i + 1], f[i + 1], n, y.shape[1],
                         tau, got, rule)  # fmt: skip
        np.testing.assert_allclose(got, expected[k], rtol=1e-13, atol=1e-13)
    expected_rules = {RULE_QUINTIC, RULE_CUBIC_DERIVATIVE} if film > 0 else {RULE_RATES}
    assert rules == expected_rules
