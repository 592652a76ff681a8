"""The film-to-contact transition of a Reynolds film (:mod:`jointplay._kernels.lanes.source`'s
``contact_clearance``; docs/contact.md, "The film-to-contact transition"): under a Reynolds film
the asperities of a joint with composite roughness σ touch where the film thins to
h_min = c − |e| = λ_t σ (λ_t = :data:`~jointplay._kernels.ids.LAMBDA_FULL_FILM`), and the dry
law acts on the asperity interference δ_a = |e| − (c − λ_t σ) beside the unchanged film
(load sharing, Johnson, Greenwood & Poon 1972). Checked here on one pin spinning in its
bearing (e = the body's position, ω_j = φ̇):

* the dry law starts at h_min = λ_t σ, not at the wall (and at the wall with σ = 0, as before);
* the force and the closed-form Jacobian are continuous across h_min = λ_t σ, and the
  Jacobian equals central differences of the right-hand side in the mixed regime;
* under a growing load (the pin pressed further in, the wedge spinning) the asperities' share
  grows monotonically to the whole load;
* dry joints and the linear film keep their contact at the wall, whatever σ.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import numpy.typing as npt
import pytest

from jointplay._kernels import eom, ids
from jointplay.contact.friction import AmbrosioFriction
from jointplay.contact.laws import get_law
from jointplay.dynamics.clearance import DEFAULT_ROUGHNESS, ClearanceJoint, JointFilm
from jointplay.dynamics.system import System, build_system
from jointplay.errors import ConfigError
from jointplay.model.mechanism import Driver, Ground, JointFit, Link, Mechanism, RevoluteJoint

CLEARANCE = 21e-6  # m
RADIUS = 5e-3  # m
SIGMA = 1e-6  # m: the asperities touch at h_min = 3 µm
SPIN = 20.0  # rad/s: the journal's spin, the film's wedge
LAMBDA_T = ids.LAMBDA_FULL_FILM
JACOBIAN_RTOL = 1e-3


def _spinner() -> Mechanism:
    """One link driven about ground pin O, its centre of mass on the pin."""
    return Mechanism(
        name="spinner",
        ground=Ground({"O": (0.0, 0.0)}),
        links=(Link("crank", {"O": (0.0, 0.0), "P": (0.1, 0.0)}, 1.5, (0.0, 0.0), 0.02),),
        joints=(RevoluteJoint("O", "ground", "O", "crank", "O", fit=JointFit(diameter=0.01)),),
        driver=Driver("crank", "O", speed=10.0),
        gravity=(0.0, 0.0),
    )


def _system(
    roughness: float, film: str | None = "short-bearing-pi", friction: bool = False
) -> System:
    """The spinner's pin, a Hertz-like law (n = 1.5: its slope vanishes at first touch), the
    π-film of 0.05 Pa·s (``film`` None: dry; ``"linear"``: the damper)."""
    law = get_law("restitution", penalty=1e10, restitution=0.8, exponent=1.5)
    fric = AmbrosioFriction(mu=0.1, v0=1e-4, v1=1e-3) if friction else None
    from_film = None if film is None else JointFilm(0.05, 0.01, model=film)
    joint = ClearanceJoint(
        "O", CLEARANCE, RADIUS, law, fric, film_from=from_film, roughness=roughness
    )
    return build_system(_spinner(), [joint])


def _state(system: System, h_min: float, rate: float = 0.0, angle: float = 0.3):
    """The pin at film thickness ``h_min`` (m) along ``angle``, moving out at ``rate`` (m/s),
    spinning at :data:`SPIN`."""
    y = np.zeros(system.n_state)
    n = np.array([math.cos(angle), math.sin(angle)])
    y[0:2] = (CLEARANCE - h_min) * n
    y[3:5] = rate * n
    y[5] = SPIN
    return y


def _contact(system: System, y: npt.NDArray[np.float64]):
    """(F_N, δ, the film's force on the journal (2,), the journal's acceleration (2,))."""
    rpar, ipar = eom.pack(system.model)
    record = np.zeros((1, 7))
    eom.evaluate(0.0, y, rpar, ipar, record)
    film = eom.film_forces(y[None], rpar, ipar, record[None])[0][0]
    f = eom.state_rhs(0.0, y, system.kernel_args())
    n = system.n_coordinates
    return record[0, 0], record[0, 2], film, f[n : n + 2]


def test_the_asperities_touch_where_the_film_thins_to_lambda_t_sigma() -> None:
    """F_N = 0 above h_min = λ_t σ and > 0 just below, δ = |e| − (c − λ_t σ) exactly; with
    σ = 0 the law starts at the wall (h_min = 0), as before the transition."""
    rough = _system(SIGMA)
    threshold = LAMBDA_T * SIGMA
    for h in (1.01 * threshold, 0.99 * threshold, 0.5 * threshold, -0.1e-6):
        y = _state(rough, h)
        f_n, delta, _, _ = _contact(rough, y)
        assert delta == pytest.approx(threshold - h, abs=1e-18)
        assert (f_n > 0) == (h < threshold)
    smooth = _system(0.0)
    for h in (0.99 * threshold, 0.01 * threshold):
        y = _state(smooth, h)
        f_n, delta, _, _ = _contact(smooth, y)
        assert f_n == 0.0 and delta == math.sqrt(y[0] ** 2 + y[1] ** 2) - CLEARANCE
    assert _contact(smooth, _state(smooth, -0.1e-6))[0] > 0


@pytest.mark.parametrize("ratio", [LAMBDA_T, ids.LAMBDA_BOUNDARY])
def test_force_and_jacobian_are_continuous_across_the_transition(ratio: float) -> None:
    """The journal's acceleration and the closed-form Jacobian just above and just below
    h_min = λ_t σ (the asperities touch, the film's share starts to fall) and h_min = λ_b σ
    (the film's share reaches 0) agree (F_N grows as δ_a^1.5, the share as a C¹ step)."""
    system = _system(SIGMA, friction=True)
    size = system.n_state
    n = system.n_coordinates
    args = system.kernel_args()
    sides = []
    for h in (ratio * SIGMA * (1 + 1e-9), ratio * SIGMA * (1 - 1e-9)):
        y = _state(system, h, rate=1e-3)
        jac = np.full((size, size), np.nan)
        assert eom.jacobian_state(0.0, y, eom.state_rhs(0.0, y, args), args, jac)
        sides.append((_contact(system, y)[3], jac[:, : 2 * n]))
    (acc_above, jac_above), (acc_below, jac_below) = sides
    assert np.allclose(acc_above, acc_below, rtol=1e-6, atol=0.0)
    scale = np.maximum(np.max(np.abs(jac_above), axis=0), 1e-300)
    assert np.max(np.abs(jac_above - jac_below) / scale) < 1e-5


def _central_differences(system: System, y: npt.NDArray[np.float64]):
    n = system.n_coordinates
    args = system.kernel_args()
    columns = []
    for j in range(2 * n):
        h = (1e-9 if j < n else 1e-6) * max(abs(y[j]), 1e-1)
        up, down = y.copy(), y.copy()
        up[j] += h
        down[j] -= h
        columns.append((eom.state_rhs(0.0, up, args) - eom.state_rhs(0.0, down, args)) / (2 * h))
    return np.array(columns).T


@pytest.mark.parametrize("film", ["short-bearing-pi", "short-bearing-full"])
def test_the_closed_form_jacobian_in_the_mixed_regime_equals_differences(film: str) -> None:
    """In the mixed regime (0 < h_min < λ_t σ: film and asperities at once, with friction),
    :func:`eom.jacobian_state` equals central differences of the whole right-hand side; the
    asperity law's terms are there (the same state with σ = 0 has none, and differs)."""
    system = _system(SIGMA, film=film, friction=True)
    smooth = _system(0.0, film=film, friction=True)
    size = system.n_state
    n = system.n_coordinates
    for h, rate, angle in ((2.5e-6, 2e-4, 0.3), (1.5e-6, -1e-4, 2.0), (0.5e-6, 3e-4, -1.0)):
        y = _state(system, h, rate, angle)
        y[2 * n + 2] = 1e-3  # a contact event under way: its entry speed
        assert _contact(system, y)[0] > 0
        jac = np.full((size, size), np.nan)
        args = system.kernel_args()
        assert eom.jacobian_state(0.0, y, eom.state_rhs(0.0, y, args), args, jac)
        expected = _central_differences(system, y)
        scale = np.maximum(np.max(np.abs(expected), axis=0), 1e-300)
        np.testing.assert_array_less(np.abs(jac[:, : 2 * n] - expected) / scale, JACOBIAN_RTOL)
        other = np.full((size, size), np.nan)
        smooth_args = smooth.kernel_args()
        eom.jacobian_state(0.0, y, eom.state_rhs(0.0, y, smooth_args), smooth_args, other)
        assert np.max(np.abs(other[:, : 2 * n] - expected) / scale) > 10 * JACOBIAN_RTOL


def test_the_asperity_share_grows_monotonically_to_the_whole_load() -> None:
    """The pin pressed ever further into its spinning film (ė = 0: the load the joint holds
    at rest in that position): the asperities'
    share F_N / (F_N + |F_film|) is 0 in full film (λ ≥ 3), grows monotonically through
    the mixed regime and is 1 in boundary lubrication (λ ≤ 1: the film's share gone)."""
    system = _system(SIGMA)
    heights = np.linspace(6e-6, -3e-6, 181)
    shares, loads = [], []
    for h in heights:
        y = _state(system, h)
        f_n, _, film, _ = _contact(system, y)
        n = y[0:2] / np.hypot(*y[0:2])
        loads.append(np.hypot(*(film - f_n * n)))
        shares.append(f_n / (f_n + np.hypot(*film)))
    shares_a = np.array(shares)
    assert loads[-1] > loads[0]
    full = heights >= LAMBDA_T * SIGMA
    assert np.all(shares_a[full] == 0.0)
    boundary = heights <= ids.LAMBDA_BOUNDARY * SIGMA
    mixed = ~full & ~boundary
    assert mixed.sum() > 30 and np.all(np.diff(shares_a[mixed]) > 0)
    assert np.all(np.diff(shares_a) >= 0)
    assert np.all(shares_a[boundary] == 1.0)  # the film gone: the asperities carry it all


@pytest.mark.parametrize("film", [None, "linear"])
def test_dry_joints_and_the_linear_film_keep_the_contact_at_the_wall(film: str | None) -> None:
    """σ does not move a dry joint's contact nor the linear damper's: the right-hand side is
    the same to the bit with σ = 0 and σ = 5 µm."""
    for h in (10e-6, 1e-6, -0.2e-6):
        y = _state(_system(0.0, film), h, rate=1e-3)
        one = eom.state_rhs(0.0, y, _system(0.0, film).kernel_args())
        other = eom.state_rhs(0.0, y, _system(5e-6, film).kernel_args())
        assert np.array_equal(one, other)


def test_the_roughness_is_checked() -> None:
    """σ ≥ 0 in metres, at most 0.1 mm; the default a ground pin in a reamed hole."""
    law = get_law("restitution", penalty=1e10, restitution=0.8, exponent=1.5)
    assert ClearanceJoint("O", CLEARANCE, RADIUS, law).roughness == DEFAULT_ROUGHNESS
    assert pytest.approx(1.12e-6, rel=0.01) == DEFAULT_ROUGHNESS
    for bad in (-1e-6, 1.1, math.nan, True):
        with pytest.raises(ConfigError, match="roughness"):
            ClearanceJoint("O", CLEARANCE, RADIUS, law, roughness=bad)


@pytest.mark.parametrize("vectorised", [True, False])
def test_the_batch_inputs_carry_each_joints_roughness(vectorised: bool) -> None:
    """The batch engine's packed samples (both builders) hold each joint's own σ, at every
    sample's clearance (``with_clearance`` keeps it)."""
    from jointplay._kernels.lanes import source
    from jointplay._kernels.lanes.build import lane_layout
    from jointplay.dynamics.batch_inputs import BatchSamples, build_batch
    from jointplay.dynamics.setup import ContactModel
    from jointplay.io.config import load_preset

    mechanism = load_preset("paper-fourbar")
    own = {"O2": 0.5e-6, "A": 1e-6, "B": 2e-6, "O4": 0.0}
    joints = [
        dataclasses.replace(j, roughness=own[j.joint])
        for j in ContactModel(film_model="short-bearing-pi").joints(mechanism)
    ]
    assert [j.with_clearance(9e-6).roughness for j in joints] == list(own.values())
    clearances = np.array([8e-6, 21e-6])
    samples = BatchSamples(clearances={j: clearances for j in own})
    problem = build_batch(mechanism, joints, samples, vectorised=vectorised)
    lay = lane_layout(problem.ipar)
    start, nc = int(lay[source.LY_GEOM]), int(lay[source.LY_NC])
    geom = problem.rpar[:, start : start + ids.N_GEOM * nc].reshape(2, nc, ids.N_GEOM)
    for c, joint in enumerate(joints):
        assert np.all(geom[:, c, ids.G_ROUGHNESS] == own[joint.joint])
