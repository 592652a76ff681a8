"""The numba-cuda batch kernel (:mod:`jointplay._kernels.lanes.cuda`) on numba-cuda's CUDA
simulator, against the CPU lanes.

The simulator must be switched on before numba's CUDA target is imported, so the GPU side
runs in a subprocess with ``NUMBA_ENABLE_CUDASIM=1``: one thread per lane, the kernel's
local arrays and launch exactly as on a GPU, the device functions executed as Python. Three
lanes of the paper four-bar (conventional contact, explicit): the nominal one over
``WINDOW`` of a revolution from t = 0 (its pins start clear of the bearings and every joint
comes into contact inside the run: the contact onsets, with their rejected steps), another
start whose window opens at ``WINDOW`` of a revolution (already in contact) and runs as long
again, and a lane that fails at once (a NaN state). A fraction of a revolution makes the
same bit-equality check as the full revolution that these tests ran before (33 s warm on
the simulator's Python, under load); ``_onset_and_window`` asserts that the shortened run
still holds a contact onset and the window opening.

Bounds: the simulator runs the same source with the same float64 operations and libm as the
CPU compilation, so it gives the CPU's steps exactly (counters equal) and its peaks and
statistics to ``SAME_ALGORITHM_RTOL`` (``tests/_tolerances.py``: the bound for two
implementations of one algorithm taking the same steps; measured here: equal bits). On a GPU,
libdevice's sin/cos/pow differ from libm in the last bit: that bound, or the contract for a
lane where round-off tips a step's acceptance, applies there.

The implicit (Radau IIA) kernel likewise: two short lanes of the stiff physical default
against the CPU compilation of the same source (the same steps; peaks to round-off), also
with film damping (c_e = 1e5 N·s/m), which the explicit kernel refuses.

Interrupts: a child process running a launch on the simulator with the flags of
``interrupts_watched`` is sent SIGINT; the launch must stop within a bound, not run on
(the explicit kernel, and the implicit one on the mapped flags).
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from _tolerances import SAME_ALGORITHM_RTOL
from jointplay._kernels import batch as kb
from jointplay._kernels import eom, ids
from jointplay._kernels.lanes import cuda as lanes_cuda
from jointplay._kernels.lanes.build import lane_layout
from jointplay._kernels.lanes.source import LY_GEOM
from jointplay.dynamics.clearance import ClearanceJoint
from jointplay.dynamics.setup import DEFAULT_IMPACT
from jointplay.dynamics.simulate import Start, initial_state
from jointplay.dynamics.system import build_system
from jointplay.errors import ConfigError
from jointplay.model.mechanism import Mechanism

pytest.importorskip("numba_cuda")

# numba-cuda's simulator runs the device kernels in Python (~50 s of the suite): the slow tier,
# which CI runs
pytestmark = pytest.mark.slow

JOINTS = ("O2", "A", "B", "O4")
#: The simulator's Python runs each device function call; three lanes of a revolution take
#: about 15 s on a 2-core machine.
SIMULATOR_TIMEOUT_S = 240
#: Revolutions of each explicit lane's window, and where the second lane's window opens. The
#: pins of the steady start are clear of their bearings (penetrations −9 to −5 µm) and all
#: four joints are in contact by 0.01 of a revolution (measured: 164 and 337 steps, 37 and 53
#: of them rejected, against 1 031 and 1 321 steps over the full revolution of before).
WINDOW = 0.05
#: Revolutions of a run too short for any contact: the steady start's own penetrations.
AT_START = 0.002

_GPU_SIDE = """
import sys
import numpy as np
from jointplay._kernels.lanes import cuda as lanes_cuda
assert lanes_cuda.simulated() and lanes_cuda.available()
args = np.load(sys.argv[1], allow_pickle=False)
timings = {}
out = lanes_cuda.run_batch(
    args["ipar"], args["rpar"], args["y0"], args["t_settle"], args["t_end"], args["max_step"],
    float(args["rtol"]), args["atol"], int(args["max_steps"]),
    str(args["method"]) if "method" in args.files else "explicit", timings=timings,
)
np.savez(sys.argv[2], **out._asdict())
"""


def _problem(paper_fourbar: Mechanism) -> dict[str, np.ndarray]:
    joints = [ClearanceJoint(j, 11.75e-6, 0.005, DEFAULT_IMPACT) for j in JOINTS]
    system = build_system(paper_fourbar, joints)
    rpar, ipar = eom.pack(system.model)
    y0 = initial_state(system, Start("steady"))
    n = system.n_coordinates
    atol = np.concatenate([np.full(n, 1e-10), np.full(n, 1e-6), np.full(2, 1e-6), np.ones(4)])
    period = paper_fourbar.driver.period
    ys = np.tile(y0, (3, 1))
    ys[1, n : 2 * n] *= 1.01
    ys[2, 0] = np.nan
    settle = np.array([0.0, WINDOW * period, 0.0])
    return {
        "ipar": ipar, "rpar": np.tile(rpar, (3, 1)), "y0": ys, "t_settle": settle,
        "t_end": settle + WINDOW * period, "max_step": np.full(3, period / 360.0),
        "rtol": np.array(1e-6), "atol": atol, "max_steps": np.array(200_000),
    }  # fmt: skip


def _on_the_simulator(problem: dict[str, np.ndarray], tmp_path: Path) -> Any:
    """The GPU kernel's outputs for ``problem``, run on numba-cuda's simulator in a
    subprocess (the simulator must be on before numba.cuda is imported)."""
    np.savez(tmp_path / "in.npz", **problem)
    env = {**os.environ, "NUMBA_ENABLE_CUDASIM": "1"}
    subprocess.run(
        [sys.executable, "-c", _GPU_SIDE, str(tmp_path / "in.npz"), str(tmp_path / "out.npz")],
        env=env, check=True, timeout=SIMULATOR_TIMEOUT_S,
    )  # fmt: skip
    return np.load(tmp_path / "out.npz")


def _onset_and_window(problem: dict[str, np.ndarray], cpu: Any, nc: int) -> None:
    """Assert that the shortened explicit run still holds what the full revolution did: in
    the first lane every clearance joint comes into contact (its largest penetration over the
    window, the ``nc`` statistics after the bodies' 2 nb, is negative over the first ``AT_START`` of a
    revolution and positive over the run), with rejected steps; the second lane's window
    opens inside the run, after some steps, and the lane runs to its end."""
    lanes = problem["y0"].shape[0]
    period = (problem["t_end"][0] - problem["t_settle"][0]) / WINDOW
    start = kb.run_batch(
        problem["ipar"], problem["rpar"], problem["y0"], np.zeros(lanes),
        np.full(lanes, AT_START * period), problem["max_step"], 1e-6, problem["atol"], 200_000,
        "explicit", parallel=False,
    )  # fmt: skip
    nb = (start.stats.shape[1] - 4 * nc) // 2  # STATS ORDER: 2 nb, nc penetrations, 3 nc regimes
    penetrations = slice(2 * nb, 2 * nb + nc)
    assert (start.stats[0, penetrations] < 0.0).all()  # the pins start clear of their bearings
    assert (cpu.stats[0, penetrations] > 0.0).all()  # ... and every joint's contact begins
    assert np.isnan(cpu.stats[0, 2 * nb + nc :]).all()  # no film: no lubrication regimes
    assert cpu.n_rejected[0] > 0
    assert 0.0 < problem["t_settle"][1] < cpu.t_reached[1] == problem["t_end"][1]
    assert cpu.n_steps[1] > cpu.n_steps[0] > 50  # the steps before the window; not a stub


def test_the_simulated_gpu_lanes_are_the_cpu_lanes(paper_fourbar: Mechanism, tmp_path: Path):
    problem = _problem(paper_fourbar)
    gpu = _on_the_simulator(problem, tmp_path)
    cpu = kb.run_batch(
        problem["ipar"], problem["rpar"], problem["y0"], problem["t_settle"], problem["t_end"],
        problem["max_step"], 1e-6, problem["atol"], 200_000, "explicit", parallel=False,
    )  # fmt: skip
    assert list(cpu.status) == [ids.STATUS_SUCCESS, ids.STATUS_SUCCESS, ids.STATUS_NON_FINITE]
    for name in ("status", "n_steps", "n_rejected", "n_rhs"):
        np.testing.assert_array_equal(gpu[name], getattr(cpu, name), err_msg=name)
    for name in ("peaks", "stats", "t_reached"):
        np.testing.assert_allclose(
            gpu[name], getattr(cpu, name), rtol=SAME_ALGORITHM_RTOL, atol=0.0, err_msg=name
        )
    assert np.isnan(gpu["peaks"][2]).all() and np.isnan(gpu["stats"][2]).all()
    _onset_and_window(problem, cpu, len(JOINTS))


def test_the_simulated_gpu_lanes_with_the_running_reductions_are_the_cpu_lanes(
    paper_fourbar: Mechanism, tmp_path: Path
) -> None:
    # the running tail after each lane's model (issue 42): the speed deviation as one more
    # refined quantity, the wear profiles and rates in the statistics, on the GPU lanes as on
    # the CPU's running compilation of the same source (the second lane's window opens late)
    from jointplay.dynamics.batch_running import RunningOutputs
    from jointplay.dynamics.wear import OutputSpeedReference, WearSettings

    problem = _problem(paper_fourbar)
    joints = [ClearanceJoint(j, 11.75e-6, 0.005, DEFAULT_IMPACT) for j in JOINTS]
    running = RunningOutputs(OutputSpeedReference.of(paper_fourbar), WearSettings(bins=36))
    tail = running.tail(paper_fourbar, build_system(paper_fourbar, joints))
    problem["rpar"] = np.hstack([problem["rpar"], np.tile(tail, (3, 1))])
    gpu = _on_the_simulator(problem, tmp_path)
    cpu = kb.run_batch(
        problem["ipar"], problem["rpar"], problem["y0"], problem["t_settle"], problem["t_end"],
        problem["max_step"], 1e-6, problem["atol"], 200_000, "explicit", parallel=False,
    )  # fmt: skip
    nb, nj, nc, _ = kb.layout(problem["ipar"])
    assert cpu.peaks.shape[1] == 2 * nb + nj + 2
    rates = cpu.stats[:2, 2 * nb + 4 * nc : 2 * nb + 5 * nc]
    assert (rates > 0).all() and (cpu.peaks[:2, -1] > 0).all()
    for name in ("status", "n_steps", "n_rejected", "n_rhs"):
        np.testing.assert_array_equal(gpu[name], getattr(cpu, name), err_msg=name)
    for name in ("peaks", "stats", "t_reached"):
        np.testing.assert_allclose(
            gpu[name], getattr(cpu, name), rtol=SAME_ALGORITHM_RTOL, atol=0.0, err_msg=name
        )


#: Penetrations |e| − c (m): |e| is a difference of positions ~0.3 m, so round-off carried
#: through the steps (measured ≤ 1.4e-14 m here, as tests/_kernels/test_jax_batch.py's bound).
PENETRATION_ATOL = 1e-12


def test_the_simulated_gpu_lanes_with_ideal_joints_agree_with_the_cpu_lanes(
    paper_fourbar: Mechanism, tmp_path: Path
) -> None:
    """The four-bar with one clearance joint (A) and three ideal ones: the GPU projects onto
    the ideal constraints by its own Cholesky solve where the CPU calls LAPACK, so the lanes
    agree to round-off (measured: the same steps, peaks ≤ 1.2e-9 relative, mean ω ≤ 1e-11
    rad/s of an RMS of 7 rad/s, penetrations ≤ 1.4e-14 m, over a revolution), not bit for
    bit. Windows as above: ``WINDOW`` of a revolution from t = 0, the steady start's pin in A
    clear of its bearing and in contact within it (measured: 64 and 112 steps, 21 and 34
    rejected), and one opening at ``WINDOW``."""
    system = build_system(paper_fourbar, [ClearanceJoint("A", 11.75e-6, 0.005, DEFAULT_IMPACT)])
    rpar, ipar = eom.pack(system.model)
    y0 = initial_state(system, Start("steady"))
    n = system.n_coordinates
    atol = np.concatenate([np.full(n, 1e-10), np.full(n, 1e-6), np.full(2, 1e-6), np.ones(1)])
    period = paper_fourbar.driver.period
    ys = np.tile(y0, (2, 1))
    ys[1, n : 2 * n] *= 1.01
    settle = np.array([0.0, WINDOW * period])
    problem = {
        "ipar": ipar, "rpar": np.tile(rpar, (2, 1)), "y0": ys, "t_settle": settle,
        "t_end": settle + WINDOW * period, "max_step": np.full(2, period / 360.0),
        "rtol": np.array(1e-6), "atol": atol, "max_steps": np.array(200_000),
    }  # fmt: skip
    gpu = _on_the_simulator(problem, tmp_path)
    cpu = kb.run_batch(
        ipar, problem["rpar"], ys, settle, problem["t_end"], problem["max_step"], 1e-6, atol,
        200_000, "explicit", parallel=False,
    )  # fmt: skip
    assert (cpu.status == ids.STATUS_SUCCESS).all()
    _onset_and_window(problem, cpu, 1)
    for name in ("status", "n_steps", "n_rejected", "n_rhs"):
        np.testing.assert_array_equal(gpu[name], getattr(cpu, name), err_msg=name)
    nb = n // 3
    # the driven crank's α (column nb) is prescribed 0: its peak is round-off (~5e-12 rad/s²
    # in a window this short, where the two Cholesky solves' last bits differ by a third of
    # it; over a whole revolution they happened to agree), compared absolutely as in the
    # implicit ideal-joint test below; every other peak relatively, as before
    crank_alpha = np.arange(cpu.peaks.shape[1]) == nb
    np.testing.assert_allclose(gpu["peaks"][:, ~crank_alpha], cpu.peaks[:, ~crank_alpha],
                               rtol=SAME_ALGORITHM_RTOL, atol=0.0)  # fmt: skip
    np.testing.assert_allclose(gpu["peaks"][:, crank_alpha], cpu.peaks[:, crank_alpha],
                               rtol=0.0, atol=1e-9)  # fmt: skip
    rms = cpu.stats[:, nb : 2 * nb]
    np.testing.assert_allclose(gpu["stats"][:, : 2 * nb], cpu.stats[:, : 2 * nb],
                               rtol=SAME_ALGORITHM_RTOL, atol=SAME_ALGORITHM_RTOL * rms.max())  # fmt: skip
    np.testing.assert_allclose(gpu["stats"][:, 2 * nb :], cpu.stats[:, 2 * nb :],
                               rtol=SAME_ALGORITHM_RTOL, atol=PENETRATION_ATOL)  # fmt: skip


def test_without_a_gpu_the_backend_says_what_is_missing(paper_fourbar: Mechanism) -> None:
    if lanes_cuda.available():
        pytest.skip("a GPU (or the simulator) is present")
    p = _problem(paper_fourbar)
    args = [p[k] for k in ("ipar", "rpar", "y0", "t_settle", "t_end", "max_step")]
    with pytest.raises(ConfigError, match="no usable NVIDIA GPU"):
        lanes_cuda.run_batch(*args, 1e-6, p["atol"], 200_000, "explicit")


def test_numba_cuda_gets_back_the_numpy_alias_it_compiles_against(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """numba-cuda 0.30.4 overloads ``np.row_stack`` when it compiles its first kernel, and
    NumPy 2.5 removed that alias of ``np.vstack``: on the H200 machine (NumPy 2.5.2) every
    launch failed with AttributeError until the backend gave it back."""
    alias = "row_stack"
    monkeypatch.delattr(np, alias, raising=False)  # as NumPy 2.5
    lanes_cuda.available()
    assert getattr(np, alias) is np.vstack


def _implicit_on_both(
    mechanism: Mechanism, joints: list[ClearanceJoint], revolutions: float, tmp_path: Path
) -> tuple[Any, dict[str, np.ndarray]]:
    """Two implicit lanes (the steady start, its window opening inside a step; a NaN state)
    on the simulated GPU and on the CPU compilation of the same source."""
    from jointplay._kernels.lanes import cpu

    system = build_system(mechanism, joints)
    rpar, ipar = eom.pack(system.model)
    y0 = initial_state(system, Start("steady"))
    n = system.n_coordinates
    atol = np.concatenate(
        [np.full(n, 1e-10), np.full(n, 1e-6), np.full(2, 1e-6), np.ones(len(joints))]
    )
    period = mechanism.driver.period
    ys = np.tile(y0, (2, 1))
    ys[1, 0] = np.nan
    settle = np.array([0.3 * revolutions * period, 0.0])
    problem = {
        "ipar": ipar, "rpar": np.tile(rpar, (2, 1)), "y0": ys, "t_settle": settle,
        "t_end": settle + revolutions * period, "max_step": np.full(2, period / 360.0),
        "rtol": np.array(1e-6), "atol": atol, "max_steps": np.array(200_000),
        "method": np.array("implicit"),
    }  # fmt: skip
    gpu = _on_the_simulator(problem, tmp_path)
    nb, nj, nc, _ = kb.layout(ipar)
    cpu_out = {
        "peaks": np.full((2, 2 * nb + nj + 1), np.nan), "stats": np.full((2, 2 * nb + 4 * nc), np.nan),
        "status": np.full(2, ids.STATUS_RUNNING, dtype=np.int64), "t_reached": np.zeros(2),
        "counts": np.zeros((2, 3), dtype=np.int64),
    }  # fmt: skip
    cpu.implicit_lanes(
        ipar, problem["rpar"], lane_layout(ipar), ys, settle, problem["t_end"],
        problem["max_step"], 1e-6, atol, 200_000, np.zeros(1, dtype=np.uint8),
        *cpu_out.values(),
    )  # fmt: skip
    assert list(cpu_out["status"]) == [ids.STATUS_SUCCESS, ids.STATUS_NON_FINITE]
    np.testing.assert_array_equal(gpu["status"], cpu_out["status"])
    for column, name in enumerate(("n_steps", "n_rejected", "n_rhs")):
        np.testing.assert_array_equal(gpu[name], cpu_out["counts"][:, column], err_msg=name)
    assert np.isnan(gpu["peaks"][1]).all() and np.isnan(gpu["stats"][1]).all()
    np.testing.assert_array_equal(gpu["t_reached"], cpu_out["t_reached"])
    return gpu, cpu_out


def test_the_simulated_gpu_implicit_lanes_are_the_cpu_lanes(
    paper_fourbar: Mechanism, tmp_path: Path
) -> None:
    """The implicit (Radau IIA) kernel on the simulator against the CPU compilation of the
    same source (:mod:`jointplay._kernels.lanes.source_radau`, itself equal to the production
    implicit lanes: ``test_lanes_radau.py``): the stiff physical default contact, 0.02 of a
    revolution from the steady start (the contacts' first transient: ~530 steps, ~110
    rejections), the window opening inside a step; and a lane that fails at once. Measured:
    the same steps, rejections and evaluations, statistics equal, peaks ≤ 1.8e-12 relative
    (the simulator's Python ``**`` in the Hermite interpolant is not Numba's)."""
    from jointplay.dynamics.setup import ContactModel

    joints = ContactModel(film_damping=0).joints(paper_fourbar)  # dry: the stiff case
    gpu, cpu_out = _implicit_on_both(paper_fourbar, joints, 0.02, tmp_path)
    assert cpu_out["counts"][0, 0] > 300 and cpu_out["counts"][0, 1] > 50  # not a stub
    for name in ("peaks", "stats"):
        np.testing.assert_allclose(
            gpu[name][0], cpu_out[name][0], rtol=SAME_ALGORITHM_RTOL, atol=0.0, err_msg=name
        )


def test_the_simulated_gpu_implicit_lanes_with_film_damping_are_the_cpu_lanes(
    paper_fourbar: Mechanism, tmp_path: Path
) -> None:
    """The implicit kernel with film damping (the physical default, c_e = 1e5 N·s/m, the
    film's force, Jacobian terms, reported force and interpolant; ``test_lanes_radau.py``
    for the CPU compilation against the production lanes), 0.1 of a revolution from the
    steady start, the window opening inside a step: the same steps, rejections and
    evaluations as the CPU compilation, peaks and statistics to round-off. Measured: the
    same 55 steps, 1 rejection and 508 evaluations, statistics equal, peaks ≤ 5.7e-13
    relative (the simulator's Python ``**`` in the interpolant, as above); 3 s."""
    from jointplay.dynamics.setup import ContactModel

    joints = ContactModel(film_damping=1e5).joints(paper_fourbar)
    gpu, cpu_out = _implicit_on_both(paper_fourbar, joints, 0.1, tmp_path)
    assert cpu_out["counts"][0, 0] > 40
    for name in ("peaks", "stats"):
        np.testing.assert_allclose(
            gpu[name][0], cpu_out[name][0], rtol=SAME_ALGORITHM_RTOL, atol=0.0, err_msg=name
        )


def test_the_simulated_gpu_implicit_lanes_with_a_reynolds_film_are_the_cpu_lanes(
    paper_fourbar: Mechanism, tmp_path: Path
) -> None:
    """The implicit kernel with the physical default contact, the Reynolds film (the
    short-bearing film force, its film-to-contact transition, the lubrication regimes'
    statistics), 0.05 of a revolution from the steady start, the window opening inside a
    step: the same steps, rejections and evaluations as the CPU compilation, peaks and
    statistics (regime fractions included) to round-off."""
    from jointplay.dynamics.setup import ContactModel

    joints = ContactModel().joints(paper_fourbar)
    assert joints[0].film_model != "linear" and joints[0].film_damping > 0  # a Reynolds film
    gpu, cpu_out = _implicit_on_both(paper_fourbar, joints, 0.05, tmp_path)
    assert cpu_out["counts"][0, 0] > 20
    assert np.isfinite(cpu_out["stats"][0]).all()  # the regimes of a lubricated joint
    for name in ("peaks", "stats"):
        np.testing.assert_allclose(
            gpu[name][0], cpu_out[name][0], rtol=SAME_ALGORITHM_RTOL, atol=0.0, err_msg=name
        )


def test_the_simulated_gpu_implicit_lanes_with_ideal_joints_agree_with_the_cpu_lanes(
    paper_fourbar: Mechanism, tmp_path: Path
) -> None:
    """The implicit kernel with ideal joints (the four-bar with one conventional clearance
    joint, A): the Jacobian differenced, the GPU's projection by Cholesky where the CPU's
    calls LAPACK (as the explicit lanes'), 0.1 of a revolution. Measured: the same steps
    (287), rejections and evaluations; peaks ≤ 3.2e-9 relative, mean ω ≤ 6e-9 rad/s (of
    11 rad/s), penetration 7e-14 m (bounds: ``SAME_ALGORITHM_RTOL``, ``PENETRATION_ATOL``)."""
    joints = [ClearanceJoint("A", 11.75e-6, 0.005, DEFAULT_IMPACT)]
    gpu, cpu_out = _implicit_on_both(paper_fourbar, joints, 0.1, tmp_path)
    assert cpu_out["counts"][0, 0] > 100
    # the driven crank's α is prescribed 0: its peak is round-off (~6e-12 rad/s²), compared
    # absolutely
    np.testing.assert_allclose(
        gpu["peaks"][0], cpu_out["peaks"][0], rtol=SAME_ALGORITHM_RTOL, atol=1e-9
    )
    np.testing.assert_allclose(
        gpu["stats"][0][:-1], cpu_out["stats"][0][:-1], rtol=SAME_ALGORITHM_RTOL, atol=1e-9
    )
    np.testing.assert_allclose(gpu["stats"][0][-1], cpu_out["stats"][0][-1], rtol=0.0,
                               atol=PENETRATION_ATOL)  # fmt: skip


def test_a_lane_without_work_shapes_gets_no_gpu_kernel() -> None:
    """The kernel allocates a method's work by its record: a record without the shapes (RODAS4's:
    it has no GPU engine) is refused by name when its kernel is built (on the simulator)."""
    script = (
        "from jointplay._kernels.lanes import cuda_kernel\n"
        "try:\n    cuda_kernel._kernel('rodas_lane')\n"
        "except ValueError as error:\n    print(error)\n"
    )
    env = {**os.environ, "NUMBA_ENABLE_CUDASIM": "1"}
    run = subprocess.run([sys.executable, "-c", script], env=env, capture_output=True, text=True,
                         check=True, timeout=SIMULATOR_TIMEOUT_S)  # fmt: skip
    assert (
        run.stdout.strip()
        == "rodas_lane: its record gives no shapes, arrays and dtypes of its work"
    )


def test_what_the_gpu_lanes_do_not_cover_yet_is_a_clear_error(paper_fourbar: Mechanism):
    p = _problem(paper_fourbar)
    args = [p[k] for k in ("ipar", "rpar", "y0", "t_settle", "t_end", "max_step")]
    with pytest.raises(ConfigError, match="methods are"):
        lanes_cuda.run_batch(*args, 1e-6, p["atol"], 200_000, "rodas")
    captured = p["rpar"].copy()
    lay = lane_layout(p["ipar"])
    captured[:, int(lay[LY_GEOM]) + ids.G_CAPTURE] = 1e-4  # the first joint's
    for method in lanes_cuda.METHODS:
        with pytest.raises(ConfigError, match="sustained-contact"):
            lanes_cuda.run_batch(p["ipar"], captured, *args[2:], 1e-6, p["atol"], 200_000, method)
    damped = p["rpar"].copy()
    damped[:, int(lay[LY_GEOM]) + ids.G_FILM] = 100.0
    with pytest.raises(ConfigError, match="film damping"):
        lanes_cuda.run_batch(p["ipar"], damped, *args[2:], 1e-6, p["atol"], 200_000, "explicit")
    with pytest.raises(ConfigError, match="at most 8 clearance joints"):
        ipar = p["ipar"].copy()
        ipar[ids.MODEL_FIELDS.index("clear_joint")] = 9
        lanes_cuda.run_batch(ipar, *args[1:], 1e-6, p["atol"], 200_000, "explicit")
    with pytest.raises(ConfigError, match="at most 12 coordinates"):  # the Newton matrices
        ipar = p["ipar"].copy()
        ipar[ids.MODEL_FIELDS.index("mass")] = 15  # five bodies
        lanes_cuda.run_batch(ipar, *args[1:], 1e-6, p["atol"], 200_000, "implicit")


_ENGINE_SIDE = """
import sys
import numpy as np
from jointplay.dynamics.batch import BatchSamples, simulate_batch
from jointplay.dynamics.clearance import ClearanceJoint
from jointplay.dynamics.setup import DEFAULT_IMPACT
from jointplay.io.config import load_preset

mechanism = load_preset("paper-fourbar")
joints = [ClearanceJoint(j, 11.75e-6, 0.005, DEFAULT_IMPACT) for j in ("O2", "A", "B", "O4")]
samples = BatchSamples(clearances={j: np.array([10e-6, 14e-6]) for j in ("O2", "A", "B", "O4")})
for backend in ("cuda", "local"):
    result = simulate_batch(mechanism, joints, samples, backend=backend, method="explicit",
                            settle=0, revolutions=0.3)
    assert result.ok.all(), result.backend
    assert result.backend == backend
    np.save(f"{sys.argv[1]}/{backend}.npy", result.peaks.to_numpy())
"""


def test_the_cuda_backend_runs_the_batch_engine_on_the_simulator(tmp_path: Path) -> None:
    """``simulate_batch(backend="cuda")``, through the executor's chunks, on the simulator:
    the CPU backend's peaks (bound as above; measured: equal bits)."""
    env = {**os.environ, "NUMBA_ENABLE_CUDASIM": "1"}
    subprocess.run([sys.executable, "-c", _ENGINE_SIDE, str(tmp_path)], env=env, check=True,
                   timeout=SIMULATOR_TIMEOUT_S)  # fmt: skip
    cuda, local = np.load(tmp_path / "cuda.npy"), np.load(tmp_path / "local.npy")
    assert cuda.shape == local.shape == (2, 9) and np.isfinite(local).all()
    np.testing.assert_allclose(cuda, local, rtol=SAME_ALGORITHM_RTOL, atol=0.0)


_ENGINE_IMPLICIT_SIDE = """
import sys
import numpy as np
from jointplay.dynamics.batch import BatchSamples, simulate_batch
from jointplay.dynamics.setup import ContactModel
from jointplay.io.config import load_preset

mechanism = load_preset("paper-fourbar")
joints = ContactModel(film_damping=0).joints(mechanism)
samples = BatchSamples(clearances={j: np.array([10e-6, 14e-6]) for j in ("O2", "A", "B", "O4")})
for backend in ("cuda", "local"):
    result = simulate_batch(mechanism, joints, samples, backend=backend, method="implicit",
                            settle=0, revolutions=0.01)
    assert result.ok.all(), result.backend
    assert result.backend == backend
    np.save(f"{sys.argv[1]}/{backend}.npy", result.peaks.to_numpy())
"""


def test_the_cuda_backend_runs_the_implicit_method_on_the_simulator(tmp_path: Path) -> None:
    """``simulate_batch(backend="cuda", method="implicit")`` with the stiff physical default,
    two samples of 0.01 of a revolution, on the simulator: the implicit kernel against the
    CPU backend's production implicit lanes (bound as above; measured ≤ 7.1e-11 relative:
    the simulator's Python arithmetic in the interpolant, as in the test above)."""
    env = {**os.environ, "NUMBA_ENABLE_CUDASIM": "1"}
    subprocess.run([sys.executable, "-c", _ENGINE_IMPLICIT_SIDE, str(tmp_path)], env=env,
                   check=True, timeout=SIMULATOR_TIMEOUT_S)  # fmt: skip
    cuda, local = np.load(tmp_path / "cuda.npy"), np.load(tmp_path / "local.npy")
    assert cuda.shape == local.shape == (2, 9) and np.isfinite(local).all()
    np.testing.assert_allclose(cuda, local, rtol=SAME_ALGORITHM_RTOL, atol=0.0)


def test_the_cuda_backend_without_a_gpu_says_so_before_building(
    paper_fourbar: Mechanism,
) -> None:
    from jointplay.dynamics.batch import BatchSamples, simulate_batch

    if lanes_cuda.available():
        pytest.skip("a GPU (or the simulator) is present")
    joints = [ClearanceJoint(j, 11.75e-6, 0.005, DEFAULT_IMPACT) for j in JOINTS]
    with pytest.raises(ConfigError, match="no usable NVIDIA GPU"):
        simulate_batch(paper_fourbar, joints, BatchSamples(size=1), backend="cuda", settle=0)


_INTERRUPTED_SIDE = """
import sys
import numpy as np
from jointplay._kernels.lanes import cuda as lanes_cuda
from jointplay.execution.interrupts import interrupts_watched
assert lanes_cuda.simulated() and lanes_cuda.available()
lanes_cuda.MAP_HOST_FLAGS = sys.argv[3] == "mapped"
args = np.load(sys.argv[1], allow_pickle=False)
raised = False
print("launching", flush=True)
try:
    with interrupts_watched() as flags:
        assert flags is not None
        out = lanes_cuda.run_batch(
            args["ipar"], args["rpar"], args["y0"], args["t_settle"], args["t_end"],
            args["max_step"], float(args["rtol"]), args["atol"], int(args["max_steps"]),
            sys.argv[4], interrupt=flags,
        )
except KeyboardInterrupt:
    raised = True
np.savez(sys.argv[2], raised=raised, **out._asdict())
"""
#: Seconds between the child's "launching" and the SIGINT: the short lane (a few dozen steps,
#: ~0.2 s on the simulator) has finished, the long ones (5 revolutions, over a minute) run.
#: 3 s were too few once on a loaded 2-core machine (CI beside a second full test run: the
#: short implicit lane still running at the signal).
SIGNAL_AFTER_S = 8.0
#: Seconds the child may take from the SIGINT to its exit (measured: well under 1 s; a flag
#: the kernel cannot see lets the long lanes run on, over a minute).
RETURN_BOUND_S = 15.0


@pytest.mark.parametrize(
    ("flags", "method"), [("mapped", "explicit"), ("copied", "explicit"), ("mapped", "implicit")]
)
def test_ctrl_c_stops_the_simulated_gpu_lanes_inside_the_launch(
    paper_fourbar: Mechanism, tmp_path: Path, flags: str, method: str
) -> None:
    """SIGINT to a process running the kernel (on the simulator) with the flags of
    ``interrupts_watched``: the launch returns at once, the lanes still running end
    ``STATUS_INTERRUPTED`` after some steps (they were stopped inside the launch, not before
    it), the lane that had finished keeps the CPU's result, and KeyboardInterrupt reaches the
    caller. ``mapped``: the flags' own page is the kernel's; ``copied``: the fallback, a copy
    that a host thread refreshes. ``implicit``: the Radau kernel, which polls the same flags
    once per step."""
    problem = _problem(paper_fourbar)
    period = paper_fourbar.driver.period
    problem["y0"][2] = problem["y0"][0]
    problem["t_settle"] = np.zeros(3)
    problem["t_end"] = np.array([0.01, 5.0, 5.0]) * period
    np.savez(tmp_path / "in.npz", **problem)
    env = {**os.environ, "NUMBA_ENABLE_CUDASIM": "1"}
    command = [sys.executable, "-c", _INTERRUPTED_SIDE, str(tmp_path / "in.npz"),
               str(tmp_path / "out.npz"), flags, method]  # fmt: skip
    with subprocess.Popen(command, env=env, stdout=subprocess.PIPE, text=True) as child:
        try:
            assert child.stdout is not None and child.stdout.readline().strip() == "launching"
            time.sleep(SIGNAL_AFTER_S)
            child.send_signal(signal.SIGINT)
            sent = time.perf_counter()
            code = child.wait(timeout=RETURN_BOUND_S)
        finally:
            child.kill()
    assert code == 0 and time.perf_counter() - sent < RETURN_BOUND_S
    gpu = np.load(tmp_path / "out.npz")
    assert bool(gpu["raised"])  # KeyboardInterrupt reached the caller
    assert list(gpu["status"]) == [
        ids.STATUS_SUCCESS,
        ids.STATUS_INTERRUPTED,
        ids.STATUS_INTERRUPTED,
    ]
    assert (gpu["n_steps"][1:] > 0).all()  # stopped during the launch
    assert (gpu["t_reached"][1:] < problem["t_end"][1:]).all()
    assert np.isnan(gpu["peaks"][1:]).all() and np.isnan(gpu["stats"][1:]).all()
    cpu = kb.run_batch(
        problem["ipar"], problem["rpar"][:1], problem["y0"][:1], problem["t_settle"][:1],
        problem["t_end"][:1], problem["max_step"][:1], 1e-6, problem["atol"], 200_000,
        method, parallel=False,
    )  # fmt: skip
    for name in ("status", "n_steps", "n_rejected", "n_rhs"):
        np.testing.assert_array_equal(gpu[name][:1], getattr(cpu, name), err_msg=name)
    for name in ("peaks", "stats", "t_reached"):
        np.testing.assert_allclose(gpu[name][:1], getattr(cpu, name), rtol=SAME_ALGORITHM_RTOL,
                                   atol=0.0, err_msg=name)  # fmt: skip


_ENGINE_INTERRUPTED_SIDE = """
import sys
import time
import numpy as np
from jointplay.dynamics.batch import BatchInterrupted, BatchSamples, simulate_batch
from jointplay.dynamics.clearance import ClearanceJoint
from jointplay.dynamics.setup import DEFAULT_IMPACT
from jointplay.io.config import load_preset

mechanism = load_preset("paper-fourbar")
joints = [ClearanceJoint(j, 11.75e-6, 0.005, DEFAULT_IMPACT) for j in ("O2", "A", "B", "O4")]
samples = BatchSamples(clearances={j: np.array([10e-6, 14e-6]) for j in ("O2", "A", "B", "O4")})
print("launching", flush=True)
try:
    simulate_batch(mechanism, joints, samples, backend="cuda", method="explicit", settle=0,
                   revolutions=5.0)
    statuses = np.array([], dtype="U16")
except BatchInterrupted as stopped:
    statuses = np.array(stopped.result.to_frame()["status"], dtype="U16")
np.save(sys.argv[1], statuses)
"""


def test_ctrl_c_stops_the_cuda_backend_of_the_batch_engine_inside_its_launch(
    tmp_path: Path,
) -> None:
    """``simulate_batch(backend="cuda")`` on the simulator, SIGINT during its one launch
    (two samples of 5 revolutions: over a minute on the simulator): the engine hands the
    kernel the interrupt flags, so it stops within the bound and raises BatchInterrupted with
    every sample's status kept (interrupted), instead of running the launch to its end."""
    env = {**os.environ, "NUMBA_ENABLE_CUDASIM": "1"}
    command = [sys.executable, "-c", _ENGINE_INTERRUPTED_SIDE, str(tmp_path / "status.npy")]
    with subprocess.Popen(command, env=env, stdout=subprocess.PIPE, text=True) as child:
        try:
            assert child.stdout is not None and child.stdout.readline().strip() == "launching"
            time.sleep(SIGNAL_AFTER_S + 2.0)  # the engine's imports and set-up come first
            child.send_signal(signal.SIGINT)
            sent = time.perf_counter()
            code = child.wait(timeout=RETURN_BOUND_S)
        finally:
            child.kill()
    assert code == 0 and time.perf_counter() - sent < RETURN_BOUND_S
    assert list(np.load(tmp_path / "status.npy")) == ["interrupted", "interrupted"]
