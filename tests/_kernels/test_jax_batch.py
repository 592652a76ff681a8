"""The JAX batch kernel (GPU backend) equals the Numba kernels and the single engine.

Run on JAX's CPU backend (CI has no GPU), with a few lanes:

* the equations of motion of :mod:`jointplay._kernels.jax.eom` against the Numba ones of
  :mod:`jointplay._kernels.eom` at random states: ẏ (``rhs``), the peak quantities (against
  ``eom.diagnostics``, as ``simulate._columns`` reads them), the contact-onset factor
  (``step_check``) and the contact memory and projection (``after_step``); every normal-force
  law id and friction id, all joints clear and ideal joints left (four-bar), and the
  slider-crank (a prismatic joint);
* whole integrations: the explicit method against the Numba batch kernel (same algorithm and
  peak rule, so the same steps and the same numbers up to round-off) and against
  :func:`jointplay.dynamics.simulate.simulate` (Radau, peaks located on its continuous
  solution), at tolerances tight enough that the two integrators' own errors are far below
  the comparison's; the implicit method against the single engine on a stiff (ECS) set;
* a failed lane is reported as such and does not disturb the others; chunking does not
  change any lane's result.

Named tolerances:

* ``SAME_ARITHMETIC``: both sides evaluate the same expressions in float64 (only the order of
  a few operations and libm's sin/cos/pow differ): round-off, measured ≤ 3e-14 relative to the
  largest entry of each block; a wrong term shows as O(1).
* ``SAME_ALGORITHM_RTOL`` (``tests/_tolerances.py``, shared with the GPU/CPU backend tests):
  the explicit JAX and Numba batch kernels take the same steps; their peaks differ by
  round-off carried through ~2000 steps, measured ≤ 4e-11 here.
* ``contract_rtol`` (``tests/_tolerances.py``): the batch contract's agreement with the single
  engine.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from typing import Any

import numpy as np
import numpy.typing as npt
import pytest

from _tolerances import CONTRACT_OTHER_RTOL, SAME_ALGORITHM_RTOL, contract_rtol

jax = pytest.importorskip("jax")

# the JAX backend is experimental and each test compiles its own XLA programs (~40 s of the
# suite): the slow tier, which CI runs
pytestmark = pytest.mark.slow

import _generic_hooks as hooks  # noqa: E402
from jointplay._kernels import eom, ids  # noqa: E402
from jointplay._kernels.ids import STATUS_NON_FINITE, STATUS_SUCCESS  # noqa: E402
from jointplay._kernels.jax.eom import JaxModel, read_layout  # noqa: E402
from jointplay._kernels.jax_batch import cache_dir, padded_size, run_batch  # noqa: E402
from jointplay.contact.friction import AdamsFriction, AmbrosioFriction, FrictionLaw  # noqa: E402
from jointplay.contact.laws import CONTACT_LAWS, ContactLaw, get_law  # noqa: E402
from jointplay.dynamics.clearance import ClearanceJoint  # noqa: E402
from jointplay.dynamics.setup import DEFAULT_IMPACT  # noqa: E402
from jointplay.dynamics.simulate import SolverOptions, Start, initial_state, simulate  # noqa: E402
from jointplay.dynamics.system import System, build_system  # noqa: E402
from jointplay.errors import ConfigError  # noqa: E402
from jointplay.io.config import load_preset  # noqa: E402
from jointplay.model.mechanism import Mechanism  # noqa: E402

FloatArray = npt.NDArray[np.float64]

SAME_ARITHMETIC = 1e-12
#: Penetrations |e| − c (m) of the two kernels: |e| is a difference of positions ~0.3 m, so
#: round-off carried over ~2000 steps (measured ≤ 1e-13 m, 5e-9 of a 21 µm clearance).
PENETRATION_ATOL = 1e-12

#: One set of parameters per law (the test_eom constructors); δ ~ 1e-4 m below d_max.
LAW_PARAMETERS: dict[str, dict[str, float]] = {
    "impact": {"stiffness": 1e10, "exponent": 1.5, "c_max": 1e4, "d_max": 3e-4},
    "hertz": {"stiffness": 1e10, "exponent": 1.5},
    "kelvin-voigt": {"stiffness": 1e7, "damping": 1e3},
    "restitution": {"penalty": 1e9, "restitution": 0.6, "exponent": 1.0},
}
FRICTIONS: tuple[FrictionLaw | None, ...] = (
    None,
    AmbrosioFriction(mu=0.1, v0=1e-4, v1=1e-3),
    AdamsFriction(mu_static=0.15, mu_dynamic=0.1, v_static=1e-3, v_dynamic=1e-2),
)
FOURBAR_JOINTS = ("O2", "A", "B", "O4")


def _law(name: str) -> ContactLaw:
    return get_law(name, **LAW_PARAMETERS.get(name, {"stiffness": 1e10, "restitution": 0.8}))


def _law_groups() -> list[list[str]]:
    """Every registered law, four to a four-bar (one per clearance joint)."""
    names = list(CONTACT_LAWS)
    return [names[i : i + 4] for i in range(0, len(names), 4)]


def _fourbar() -> Mechanism:
    return load_preset("paper-fourbar")


def _system(mechanism: Mechanism, joints: Sequence[str], laws: Sequence[ContactLaw]) -> System:
    clearances = [
        ClearanceJoint(j, 1e-4, 5e-3, law, FRICTIONS[k % len(FRICTIONS)])
        for k, (j, law) in enumerate(zip(joints, laws, strict=True))
    ]
    return build_system(mechanism, clearances)


def _random_states(system: System, seed: int, count: int = 8) -> FloatArray:
    """States near the nominal assembly, pins off-centre by up to ~3 clearances (most joints
    in contact, some free), velocities of the mechanism's size, impact memory set or unset."""
    rng = np.random.default_rng(seed)
    y0 = initial_state(system, Start())
    n = system.n_coordinates
    nc = len(system.clearances)
    states = np.tile(y0, (count, 1))
    states[:, :n] += np.tile([1.5e-4, 1.5e-4, 1.5e-3], n // 3) * rng.standard_normal((count, n))
    states[:, n : 2 * n] += np.tile([1.0, 1.0, 10.0], n // 3) * rng.standard_normal((count, n))
    states[:, 2 * n : 2 * n + 2] = rng.standard_normal((count, 2))
    memory = np.where(rng.random((count, nc)) < 0.5, 0.0, rng.uniform(0.01, 1.0, (count, nc)))
    states[:, 2 * n + 2 :] = memory
    return states


def _jax_model(system: System) -> tuple[JaxModel, FloatArray]:
    rpar, ipar = eom.pack(system.model)
    return JaxModel(read_layout(ipar, rpar[None])), rpar


def _assert_blocks_close(got: FloatArray, expected: FloatArray, n: int) -> None:
    """ẏ equal block by block (q̇, q̈, work rates), relative to each block's largest entry."""
    for block in (slice(0, n), slice(n, 2 * n), slice(2 * n, 2 * n + 2)):
        scale = np.max(np.abs(expected[..., block]))
        np.testing.assert_allclose(got[..., block], expected[..., block], rtol=0, atol=SAME_ARITHMETIC * scale)  # fmt: skip
    np.testing.assert_array_equal(got[..., 2 * n + 2 :], 0.0)


def _systems() -> list[tuple[str, System]]:
    fourbar = _fourbar()
    cases = [
        (f"four-bar, laws {'/'.join(group)}", _system(fourbar, FOURBAR_JOINTS[: len(group)], [_law(g) for g in group]))
        for group in _law_groups()
    ]  # fmt: skip
    cases.append(("four-bar, A and O4 clear", _system(fourbar, ("A", "O4"), [_law("impact"), _law("flores")])))  # fmt: skip
    slider = load_preset("flores-slider-crank")
    pin = [c.joint for c in jointplay_clearances(slider)]
    cases.append(("slider-crank", _system(slider, pin, [_law("lankarani-nikravesh")] * len(pin))))
    return cases


def jointplay_clearances(mechanism: Mechanism) -> list[ClearanceJoint]:
    """The fits' clearance joints with the conventional IMPACT set (the default before issue
    22: these explicit-method comparisons were made for it; the stiff physical default runs
    implicit)."""
    from jointplay import clearance_joints

    return clearance_joints(mechanism, law=DEFAULT_IMPACT)


SYSTEMS = _systems()


def test_every_law_is_covered() -> None:
    """The random-state tests below meet every normal-force and friction law id."""
    laws = {int(i) for _, s in SYSTEMS for i in s.model.law_id}
    frictions = {int(i) for _, s in SYSTEMS for i in s.model.fric_id}
    assert laws == set(range(ids.HC_LAST + 1))
    assert frictions == {ids.FRICTION_NONE, ids.FRICTION_AMBROSIO, ids.FRICTION_ADAMS}
    assert any(s.model.active.sum() > 0 for _, s in SYSTEMS)  # ideal joints left


@pytest.mark.parametrize(("label", "system"), SYSTEMS, ids=[label for label, _ in SYSTEMS])
def test_equations_of_motion_equal_numba(label: str, system: System) -> None:
    """ẏ, the peak quantities, step_check and after_step equal the Numba kernels'."""
    model, rpar = _jax_model(system)
    states = _random_states(system, seed=len(label))
    n = system.n_coordinates
    times = 1e-3 * np.arange(states.shape[0])
    args = system.kernel_args()
    with jax.enable_x64(True):
        rhs = jax.jit(jax.vmap(model.rhs, in_axes=(0, 0, None)))
        outputs = jax.jit(jax.vmap(model.outputs, in_axes=(0, 0, None)))
        check = jax.jit(jax.vmap(model.step_check, in_axes=(None, 0, None)))
        after = jax.jit(jax.vmap(model.after_step, in_axes=(0, 0, None, None)))
        got_rhs = np.asarray(rhs(times, states, rpar))
        _, got_q, got_pen = (np.asarray(a) for a in outputs(times, states, rpar))
        got_theta = np.asarray(check(states[0], states, rpar))
        got_after = np.asarray(after(times, states, rpar, states[0]))  # steps from states[0]
    expected = np.array([eom.state_rhs(t, y, args) for t, y in zip(times, states, strict=True)])
    _assert_blocks_close(got_rhs, expected, n)
    # The quantities, as simulate._columns computes them from eom.diagnostics.
    qdd, torque, contacts, reactions, _ = eom.diagnostics(times, states, *eom.pack(system.model))
    nb = n // 3
    forces = []
    clear = {int(j): c for c, j in enumerate(system.model.clear_joint)}
    for j in range(len(system.model.active)):
        if j in clear:
            forces.append(np.hypot(contacts[:, clear[j], 0], contacts[:, clear[j], 1]))
        elif system.model.joint_int[3 * j] == 0:
            forces.append(np.hypot(reactions[:, j, 0], reactions[:, j, 1]))
        else:
            forces.append(np.abs(reactions[:, j, 1]))
    want = np.column_stack([states[:, n + 2 : 2 * n : 3], qdd[:, 2::3], *forces, torque])
    assert want.shape[1] == 2 * nb + len(system.model.active) + 1
    scale = np.max(np.abs(want), axis=0)  # per quantity; α relative to the largest α
    scale[nb : 2 * nb] = np.max(scale[nb : 2 * nb])
    assert np.all(np.abs(got_q - want) <= SAME_ARITHMETIC * scale), np.max(
        np.abs(got_q - want) / np.maximum(scale, 1e-300), axis=0
    )
    np.testing.assert_allclose(got_pen, contacts[:, :, 2], rtol=0, atol=1e-18)
    assert np.any(got_pen > 0) and np.any(got_pen <= 0)  # contact and free joints both met
    for k in range(states.shape[0]):
        theta = hooks.step_check(0.0, states[0], 1e-3, states[k], args)
        assert got_theta[k] == pytest.approx(theta, rel=1e-12)
        y = states[k].copy()
        step = system.kernel_args()  # a step from states[0] (contact memory interpolates)
        hooks.start_workspace(states[0], step)
        hooks.after_step(times[k], y, step)
        scale = np.maximum(np.abs(y), 1e-12)
        np.testing.assert_allclose(got_after[k], y, rtol=0, atol=1e-9 * np.max(scale))


# ---- whole integrations -------------------------------------------------------------------
def _inputs(
    systems: Sequence[System], start: Start, t_end: float, solver: SolverOptions
) -> tuple:  # fmt: skip
    """run_batch's arguments for one lane per system (the single engine's settings)."""
    packed = [eom.pack(s.model) for s in systems]
    ipar = packed[0][1]
    rpar = np.array([p[0] for p in packed])
    y0 = np.array([initial_state(s, start) for s in systems])
    n = systems[0].n_coordinates
    nc = len(systems[0].clearances)
    atol = np.concatenate(
        [np.full(n, solver.atol_position), np.full(n, solver.atol_velocity), np.full(2, 1e-6), np.ones(nc)]
    )  # fmt: skip
    period = systems[0].mechanism.driver.period
    lanes = len(systems)
    return (
        ipar, rpar, y0, np.zeros(lanes), np.full(lanes, t_end), np.full(lanes, period / 360.0),
        solver.rtol, atol, solver.max_steps,
    )  # fmt: skip


def _peak_names(system: System) -> list[str]:
    """The single engine's names of the QUANTITY ORDER's columns (None: not reported)."""
    from jointplay.model.columns import rotating_links

    numbers = dict(rotating_links(system.mechanism))
    bodies = system.flat.link_names
    assert [system.flat.body_index(b) for b in bodies] == list(range(len(bodies)))
    names = [f"omega{numbers.get(b, '?')}" for b in bodies]
    names += [f"alpha{numbers.get(b, '?')}" for b in bodies]
    names += [f"F_{j}" for j in system.flat.joint_names]
    return [*names, "torque"]


def _assert_matches_single_engine(
    peaks: FloatArray, system: System, start: Start, revolutions: float, solver: SolverOptions
) -> Any:
    result = simulate(system.mechanism, list(system.clearances), revolutions=revolutions,
                      settle=0, start=start, solver=solver)  # fmt: skip
    checked = 0
    for value, name in zip(peaks, _peak_names(system), strict=True):
        if name not in result.peaks:
            continue  # the crank's ω and α (driven) are not reported by the single engine
        reference = result.peaks[name]["value"]
        assert value == pytest.approx(reference, rel=contract_rtol(name)), name
        checked += 1
    assert checked >= 5
    return result


#: Tight enough that both integrators' errors are far below the contract's ω bound (single engine:
#: its peaks move by < 1e-7 relative from rtol 1e-8 to 1e-10 on these cases).
TIGHT = SolverOptions(rtol=1e-8, atol_position=1e-12, atol_velocity=1e-8)


def test_explicit_fourbar_matches_numba_and_single_engine() -> None:
    """All clear, the paper's conventional set, one steady revolution: the JAX explicit
    kernel takes the Numba batch kernel's steps and agrees with the single engine; a lane
    with a non-finite initial state fails alone; chunking changes nothing."""
    fourbar = _fourbar()
    systems = [
        build_system(fourbar, [ClearanceJoint(j, c, 5e-3, DEFAULT_IMPACT) for j in FOURBAR_JOINTS])
        for c in (2.1e-5, 1.2e-5)
    ]  # fmt: skip
    start = Start("steady")
    period = fourbar.driver.period
    args = list(_inputs(systems, start, period, TIGHT))
    args[1] = np.vstack([args[1], args[1][:1]])  # a third lane that cannot start
    args[2] = np.vstack([args[2], args[2][:1]])
    args[2][2, 0] = np.nan
    for k in (3, 4, 5):
        args[k] = np.append(args[k], args[k][0])
    out = run_batch(*args, "explicit")
    assert out.status.tolist() == [STATUS_SUCCESS, STATUS_SUCCESS, STATUS_NON_FINITE]
    assert np.all(np.isnan(out.peaks[2])) and np.all(np.isnan(out.stats[2]))
    assert np.all(out.t_reached[:2] == period)
    chunked = run_batch(*args, "explicit", chunk_size=2)
    for field in out._fields:
        np.testing.assert_array_equal(getattr(chunked, field), getattr(out, field), err_msg=field)
    try:
        from jointplay._kernels.batch import run_batch as numba_batch
    except ImportError:  # pragma: no cover - the CPU batch kernel is part of the package
        pytest.fail("jointplay._kernels.batch is missing")
    theirs = numba_batch(*args, "explicit")
    np.testing.assert_array_equal(out.status, theirs.status)
    np.testing.assert_array_equal(out.n_steps[:2], theirs.n_steps[:2])
    np.testing.assert_array_equal(out.n_rejected[:2], theirs.n_rejected[:2])
    np.testing.assert_allclose(
        out.peaks[:2], theirs.peaks[:2], rtol=SAME_ALGORITHM_RTOL, atol=1e-300
    )
    nb = systems[0].n_coordinates // 3
    np.testing.assert_allclose(
        out.stats[:2, : 2 * nb], theirs.stats[:2, : 2 * nb], rtol=SAME_ALGORITHM_RTOL
    )
    # penetrations |e| − c: round-off of positions ~0.3 m carried over the steps, absolute
    np.testing.assert_allclose(
        out.stats[:2, 2 * nb :],
        theirs.stats[:2, 2 * nb : out.stats.shape[1]],  # the lanes' regimes follow (no film)
        rtol=0,
        atol=PENETRATION_ATOL,
    )
    for lane, system in enumerate(systems):
        result = _assert_matches_single_engine(out.peaks[lane], system, start, 1.0, TIGHT)
        # the window is the whole run here, as the single engine's largest penetrations
        deepest = result.solver_stats["max_penetration_per_joint_m"]
        want = [deepest[j] for j in FOURBAR_JOINTS]
        np.testing.assert_allclose(out.stats[lane, 2 * nb :], want, rtol=CONTRACT_OTHER_RTOL)
    # the crank's mean speed is the driver's (it is held by the driver constraint)
    assert out.stats[0, 0] == pytest.approx(fourbar.driver.speed, rel=1e-9)


def test_explicit_slider_crank_matches_single_engine() -> None:
    """Ideal joints (a prismatic one among them) with a clearance pin: projection and the
    Lagrange-multiplier forces in the loop; one steady revolution after one settling one."""
    slider = load_preset("flores-slider-crank")
    system = build_system(slider, jointplay_clearances(slider))
    start = Start("steady")
    period = slider.driver.period
    solver = SolverOptions(rtol=1e-8, atol_position=1e-12, atol_velocity=1e-8)
    args = list(_inputs([system], start, 2 * period, solver))
    args[3] = np.array([period])  # t_settle: one revolution
    out = run_batch(*args, "explicit")
    assert out.status.tolist() == [STATUS_SUCCESS]
    result = simulate(slider, list(system.clearances), revolutions=1, settle=1, start=start,
                      solver=solver)  # fmt: skip
    checked = 0
    for value, name in zip(out.peaks[0], _peak_names(system), strict=True):
        if name in result.peaks:
            assert value == pytest.approx(result.peaks[name]["value"], rel=contract_rtol(name)), (
                name
            )
            checked += 1
    assert checked >= 4


def test_implicit_stiff_set_matches_single_engine() -> None:
    """Radau IIA on the paper's spherical ECS set (IMPACT with d_max = 37 nm: stiff)."""
    from jointplay.study.ecs import ecs_parameters

    fourbar = _fourbar()
    law = ecs_parameters(fourbar, "spherical", "paper").impact_law()
    system = build_system(fourbar, [ClearanceJoint(j, 2.1e-5, 5e-3, law) for j in FOURBAR_JOINTS])
    start = Start("steady")
    out = run_batch(*_inputs([system], start, fourbar.driver.period, TIGHT), "implicit")
    assert out.status.tolist() == [STATUS_SUCCESS]
    _assert_matches_single_engine(out.peaks[0], system, start, 1.0, TIGHT)


# ---- inputs and settings ----------------------------------------------------------------------
def test_unknown_law_is_refused() -> None:
    system = _system(_fourbar(), ("A",), [_law("impact")])
    rpar, ipar = eom.pack(system.model)
    ipar = ipar.copy()
    length = dict(zip(ids.MODEL_FIELDS, ipar, strict=False))
    law_slot = len(ids.MODEL_FIELDS) + sum(
        int(length[name]) for name in ("joint_int", "active", "clear_joint")
    )
    ipar[law_slot] = 99
    with pytest.raises(ConfigError, match="normal-force law id 99 runs on no engine"):
        read_layout(ipar, rpar[None])


def test_lanes_must_share_the_driven_body() -> None:
    system = _system(_fourbar(), ("A",), [_law("impact")])
    rpar, ipar = eom.pack(system.model)
    rows = np.tile(rpar, (2, 1))
    length = dict(zip(ids.MODEL_FIELDS, ipar, strict=False))
    driver = sum(int(length[name]) for name in ("mass", "gravity", "joint_f"))
    rows[1, driver] = -1.0
    with pytest.raises(ConfigError, match="same body"):
        read_layout(ipar, rows)


def test_bad_inputs_are_refused() -> None:
    system = _system(_fourbar(), ("A",), [_law("impact")])
    args = list(_inputs([system], Start("steady"), 0.1, SolverOptions()))
    with pytest.raises(ConfigError, match="method"):
        run_batch(*args, "euler")
    args[4] = np.array([-1.0])
    with pytest.raises(ConfigError, match="t_end"):
        run_batch(*args, "explicit")


def test_padded_sizes_share_compilations() -> None:
    assert padded_size(3, 200_000) == 4
    assert padded_size(1000, 200_000) == 1024
    assert padded_size(1500, 200_000) == 2048
    assert padded_size(100_000, 200_000) == 100_352
    assert padded_size(1000, 200_000, minimum=16_384) == 16_384  # a GPU's small batches
    assert padded_size(1000, 4096, minimum=16_384) == 4096  # never above the chunk
    assert padded_size(1_000_000, 200_000) == 200_000
    assert padded_size(3, 2) == 2


def test_cache_folder_from_environment(monkeypatch: pytest.MonkeyPatch, tmp_path) -> None:  # type: ignore[no-untyped-def]
    monkeypatch.setenv("JOINTPLAY_JAX_CACHE", str(tmp_path))
    assert cache_dir() == tmp_path
    monkeypatch.setenv("JOINTPLAY_JAX_CACHE", "off")
    assert cache_dir() is None
    monkeypatch.delenv("JOINTPLAY_JAX_CACHE")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    assert cache_dir() == tmp_path / "jointplay" / "jax"


def test_a_later_process_compiles_the_saved_program_to_the_same_numbers(
    monkeypatch: pytest.MonkeyPatch, tmp_path
) -> None:  # type: ignore[no-untyped-def]
    """The lowered program is kept (jax.export) beside the compilation cache and read back
    instead of tracing the kernel again; its numbers are the traced program's, bit for bit.
    A damaged file reads as none (so the kernel is traced afresh and the file rewritten)."""
    from jointplay._kernels import jax_batch

    pytest.importorskip("flatbuffers")
    system = build_system(
        _fourbar(), [ClearanceJoint(j, 2.1e-5, 5e-3, DEFAULT_IMPACT) for j in ("A", "B")]
    )
    args = _inputs([system], Start("steady"), system.mechanism.driver.period / 8, SolverOptions())

    def fresh_run() -> Any:  # as a new process would: nothing compiled in memory
        monkeypatch.setattr(jax_batch, "_executables", {})
        return run_batch(*args, "explicit")

    monkeypatch.setenv("JOINTPLAY_JAX_CACHE", "off")
    traced = fresh_run()
    monkeypatch.setenv("JOINTPLAY_JAX_CACHE", str(tmp_path))
    saved = fresh_run()
    (program,) = (tmp_path / "exported").iterdir()
    monkeypatch.setattr(jax_batch, "_batch_function", None)  # reading back must not trace
    read_back = fresh_run()
    for result in (saved, read_back):
        for field in traced._fields:
            np.testing.assert_array_equal(getattr(result, field), getattr(traced, field), field)
    program.write_bytes(b"not a program")  # damaged: traced afresh, then overwritten
    assert jax_batch._read_exported(jax, program) is None
    assert traced.status.tolist() == [STATUS_SUCCESS]


def test_the_program_cache_is_private_and_verified(tmp_path) -> None:  # type: ignore[no-untyped-def]
    """A shared or tampered cache could hand this process a program to run: the folder must
    be this user's alone, and a kept program is read only if it is this user's regular file,
    unwritable by others, with the digest written with it."""
    from jointplay._kernels import jax_batch

    pytest.importorskip("flatbuffers")
    folder = tmp_path / "cache"
    folder.mkdir(mode=0o777)
    os.chmod(folder, 0o777)
    assert jax_batch.private_folder(folder) and (folder.stat().st_mode & 0o777) == 0o700
    (tmp_path / "elsewhere").mkdir()
    (tmp_path / "link").symlink_to(tmp_path / "elsewhere")
    assert not jax_batch.private_folder(tmp_path / "link")

    x = jax.numpy.arange(3.0)
    exported = jax.export.export(jax.jit(lambda v: 2 * v))(x)
    path = folder / "program.bin"
    jax_batch._write_exported(exported, path)
    assert (path.stat().st_mode & 0o777) == 0o600
    assert sorted(p.name for p in folder.iterdir()) == ["program.bin"]
    assert jax_batch._read_exported(jax, path) is not None
    link = folder / "linked.bin"
    link.symlink_to(path)
    assert jax_batch._read_exported(jax, link) is None  # not followed
    os.chmod(path, 0o666)
    assert jax_batch._read_exported(jax, path) is None  # others could have written it
    os.chmod(path, 0o600)
    data = path.read_bytes()
    path.write_bytes(data[:-1] + bytes([data[-1] ^ 1]))  # one bit changed
    assert jax_batch._read_exported(jax, path) is None
