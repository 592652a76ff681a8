"""The batch engine's Python face: the vectorised builder, the backends, failures as data.

References: the per-sample build (:func:`build_system` + :func:`initial_state`, exact to
round-off: 1e-14 relative), the single engine per sample (issue 14's bounds: 1e-5 on ω, 1e-3
on α, forces and torque), and the engine itself on another backend or chunking (bitwise).
"""

from __future__ import annotations

import numpy as np
import pytest

from _tolerances import SAME_ALGORITHM_RTOL, contract_rtol
from jointplay.dynamics.batch import (
    EXPLICIT_TOLERANCE_SCALE,
    BatchSamples,
    build_batch,
    choose_method,
    simulate_batch,
)
from jointplay.dynamics.clearance import ClearanceJoint
from jointplay.dynamics.setup import DEFAULT_IMPACT
from jointplay.dynamics.simulate import SolverOptions, Start, simulate
from jointplay.errors import ConfigError
from jointplay.model.mechanism import Mechanism
from jointplay.model.templates import with_lengths

JOINTS = ("O2", "A", "B", "O4")


def _joints(clearance: float = 11.75e-6, law=DEFAULT_IMPACT) -> list[ClearanceJoint]:
    return [ClearanceJoint(j, clearance, 0.005, law) for j in JOINTS]


def _random_samples(n: int, seed: int) -> BatchSamples:
    rng = np.random.default_rng(seed)
    nominal = {"crank": 0.108, "coupler": 0.2705, "rocker": 0.2705, "ground": 0.2794}
    return BatchSamples(
        lengths={k: v * (1 + 2e-3 * rng.standard_normal(n)) for k, v in nominal.items()},
        clearances={j: rng.uniform(6e-6, 20e-6, n) for j in JOINTS},
        law={"c_max": rng.uniform(5e3, 2e4, n), "stiffness": rng.uniform(2e8, 4e8, n)},
        angular_velocity=rng.uniform(18.0, 24.0, n),
    )


def _relative_difference(a: np.ndarray, b: np.ndarray) -> float:
    scale = np.maximum(np.abs(b), 1e-300)
    return float(np.max(np.where(a == b, 0.0, np.abs(a - b) / scale)))


@pytest.mark.parametrize("start", ["steady", "rest", "impulsive"])
def test_vectorised_build_equals_the_per_sample_build(paper_fourbar: Mechanism, start) -> None:
    samples = _random_samples(40, seed=3)
    fast = build_batch(paper_fourbar, _joints(), samples, start=Start(start), settle=1)
    slow = build_batch(
        paper_fourbar, _joints(), samples, start=Start(start), settle=1, vectorised=False
    )
    assert fast.vectorised and not slow.vectorised
    assert fast.ok.all() and slow.ok.all()
    assert _relative_difference(fast.rpar, slow.rpar) < 1e-14
    assert _relative_difference(fast.y0, slow.y0) < 1e-14
    np.testing.assert_array_equal(fast.ipar, slow.ipar)
    for name in ("t_settle", "t_end", "max_step"):
        assert _relative_difference(getattr(fast, name), getattr(slow, name)) < 1e-14


def test_vectorised_build_of_a_slider_crank(slider_crank: Mechanism) -> None:
    rng = np.random.default_rng(4)
    spec = slider_crank.template
    n = 25
    samples = BatchSamples(
        lengths={
            "crank": spec.geometry.crank * (1 + 1e-3 * rng.standard_normal(n)),  # type: ignore[union-attr]
            "rod": spec.geometry.rod * (1 + 1e-3 * rng.standard_normal(n)),  # type: ignore[union-attr]
        },
        clearances={"B": rng.uniform(5e-6, 2e-5, n)},
    )
    joints = [ClearanceJoint("B", 1e-5, 0.005, DEFAULT_IMPACT)]
    fast = build_batch(slider_crank, joints, samples)
    slow = build_batch(slider_crank, joints, samples, vectorised=False)
    assert fast.ok.all()
    assert _relative_difference(fast.rpar, slow.rpar) < 1e-14
    assert _relative_difference(fast.y0, slow.y0) < 1e-13


def test_unbuildable_samples_fail_with_the_per_sample_message(paper_fourbar: Mechanism) -> None:
    samples = BatchSamples(
        lengths={"crank": np.array([0.108, 0.3, 0.108])},
        clearances={"A": np.array([1e-5, 1e-5, -1e-6])},
    )
    fast = build_batch(paper_fourbar, _joints(), samples)
    slow = build_batch(paper_fourbar, _joints(), samples, vectorised=False)
    assert fast.ok.tolist() == slow.ok.tolist() == [True, False, False]
    assert fast.errors == slow.errors
    assert fast.errors[1].startswith("AssemblyError") and "turn fully" in fast.errors[1]
    assert fast.errors[2].startswith("ConfigError") and "clearance" in fast.errors[2]


def test_batch_agrees_with_the_single_engine_per_sample(paper_fourbar: Mechanism) -> None:
    samples = _random_samples(3, seed=11)
    result = simulate_batch(paper_fourbar, _joints(), samples, backend="local", settle=0)
    assert result.method == "explicit" and result.ok.all()
    for i in range(len(samples)):
        reference = _single(paper_fourbar, samples, i)
        for key in result.peaks.columns:
            got = result.peaks.loc[i, key]
            assert abs(got / reference.peaks[key]["value"] - 1) < contract_rtol(key), (i, key)


def _single(mechanism: Mechanism, samples: BatchSamples, i: int, **options):
    """The single engine on sample ``i`` of ``samples`` (lengths, clearances and law)."""
    mechanism = with_lengths(mechanism, **{k: float(v[i]) for k, v in samples.lengths.items()})
    mechanism = mechanism.with_driver(speed=float(samples.angular_velocity[i]))  # type: ignore[index]
    law = DEFAULT_IMPACT.__class__(
        stiffness=float(samples.law["stiffness"][i]),
        exponent=DEFAULT_IMPACT.exponent,
        c_max=float(samples.law["c_max"][i]),
        d_max=DEFAULT_IMPACT.d_max,
    )
    joints = [ClearanceJoint(j, float(samples.clearances[j][i]), 0.005, law) for j in JOINTS]
    return simulate(mechanism, joints, start=Start("steady"), **{"settle": 0, **options})


@pytest.mark.parametrize("settle", [0, 2])
def test_batch_is_as_close_to_a_converged_solution_as_issue_14_asks(
    paper_fourbar: Mechanism, settle: int
) -> None:
    # At the default tolerances the explicit lanes (run at EXPLICIT_TOLERANCE_SCALE of them)
    # stay within issue 14's bounds of the exact solution: omega 1e-5, forces and alpha 1e-3
    # (at the solver's own tolerances they missed them on a third of the samples: 2.9e-5 and
    # 5.7e-3). Reference: the single engine at rtol 1e-9.
    samples = _random_samples(4, seed=21 + settle)
    result = simulate_batch(paper_fourbar, _joints(), samples, settle=settle, backend="local")
    assert result.method == "explicit" and result.ok.all()
    converged = SolverOptions(rtol=1e-9, atol_position=1e-12, atol_velocity=1e-9)
    for i in range(len(samples)):
        exact = _single(paper_fourbar, samples, i, settle=settle, solver=converged).peaks
        for key in result.peaks.columns:
            error = abs(result.peaks.loc[i, key] / exact[key]["value"] - 1)
            assert error < contract_rtol(key), (i, key)


@pytest.mark.parametrize(("start", "settle"), [(None, 2), (Start("steady"), 2), (Start("rest"), 0)])
def test_the_batch_settles_by_default_as_simulate_and_the_cli_do(
    paper_fourbar: Mechanism, monkeypatch: pytest.MonkeyPatch, start, settle: int
) -> None:
    """Without ``settle``, the steady start leaves 2 start-up revolutions out (as
    ``simulate()`` and ``jointplay simulate``); the other starts, whose start-up is what they
    show, none. (The batch took 0 for every start before.)"""
    import inspect

    from jointplay.dynamics import batch

    seen: list[int] = []

    def build(*args, **kwargs):
        seen.append(kwargs["settle"])
        raise KeyboardInterrupt  # stop before any integration

    monkeypatch.setattr(batch, "build_batch", build)
    with pytest.raises(KeyboardInterrupt):
        simulate_batch(paper_fourbar, _joints(), BatchSamples(size=1), start=start)
    assert seen == [settle]
    for function in (simulate, simulate_batch):  # one default, stated where it is read
        assert inspect.signature(function).parameters["settle"].default is None
        assert "default: 2 with the steady start" in " ".join((function.__doc__ or "").split())


@pytest.fixture(scope="module")
def reference(paper_fourbar: Mechanism):
    samples = _random_samples(9, seed=5)
    return samples, simulate_batch(paper_fourbar, _joints(), samples, backend="local", settle=0)


def _same(a, b) -> None:
    np.testing.assert_array_equal(a.peaks.to_numpy(), b.peaks.to_numpy())
    np.testing.assert_array_equal(a.statistics.to_numpy(), b.statistics.to_numpy())
    np.testing.assert_array_equal(a.counters.to_numpy(), b.counters.to_numpy())
    assert a.errors == b.errors


@pytest.mark.parametrize("chunk_size", [1, 7, 9])
def test_chunking_does_not_change_results(paper_fourbar: Mechanism, reference, chunk_size) -> None:
    samples, expected = reference
    result = simulate_batch(paper_fourbar, _joints(), samples, chunk_size=chunk_size, settle=0)
    _same(result, expected)


def test_worker_processes_give_the_same_bits(paper_fourbar: Mechanism, reference) -> None:
    samples, expected = reference
    result = simulate_batch(
        paper_fourbar, _joints(), samples, backend="processes", workers=2, chunk_size=4, settle=0
    )
    assert result.backend == "processes" and result.workers == 2
    _same(result, expected)


def test_a_dask_cluster_gives_the_same_bits_in_chunks_sized_by_the_cluster(
    paper_fourbar: Mechanism, reference, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Three single-thread workers get ~4 chunks each, however many cores this machine has;
    one connection serves every batch of the process."""
    import os

    from distributed import LocalCluster

    from jointplay.execution import dask

    samples, expected = reference
    monkeypatch.setattr(os, "cpu_count", lambda: 1)  # a small client, a larger cluster
    with LocalCluster(
        n_workers=3, threads_per_worker=1, processes=False, dashboard_address=":0"
    ) as cluster:
        address = cluster.scheduler_address
        results = [
            simulate_batch(
                paper_fourbar, _joints(), samples, backend="dask", scheduler=address, settle=0
            )
            for _ in range(2)
        ]
        client = dask._CLIENTS[address]
        assert client.status == "running"
        dask.close_clients()
    for result in results:
        assert result.backend == "dask" and result.workers == 3
        assert result.chunk_size == 1  # 9 lanes over 4 x 3 chunks, not 4 x 1
        _same(result, expected)


@pytest.mark.slow  # JAX compiles the batch for ~10 s
def test_the_gpu_backend_agrees_with_the_cpu(paper_fourbar: Mechanism, reference) -> None:
    pytest.importorskip("jax")
    samples, expected = reference
    result = simulate_batch(
        paper_fourbar, _joints(), samples, backend="gpu", method="explicit", settle=0
    )
    assert result.ok.all()
    for key in expected.peaks.columns:  # measured: alpha3 3.6e-9, the others <= 4.6e-10
        np.testing.assert_allclose(
            result.peaks[key], expected.peaks[key], rtol=SAME_ALGORITHM_RTOL, err_msg=key
        )


def test_the_gpu_backend_without_jax_says_what_to_install(
    paper_fourbar: Mechanism, monkeypatch
) -> None:
    import sys

    import jointplay._kernels

    monkeypatch.setitem(sys.modules, "jointplay._kernels.jax_batch", None)  # import fails
    monkeypatch.delattr(jointplay._kernels, "jax_batch", raising=False)
    with pytest.raises(ConfigError, match=r"jointplay\[gpu\]"):
        simulate_batch(paper_fourbar, _joints(), BatchSamples(size=1), backend="gpu", settle=0)


def test_failed_samples_keep_their_inputs_and_do_not_stop_the_others(
    paper_fourbar: Mechanism,
) -> None:
    samples = BatchSamples(
        law={"stiffness": np.array([3e8, 1e300, 3e8])},  # the middle one overflows
        lengths={"crank": np.array([0.108, 0.108, 0.3])},  # the last cannot turn
    )
    result = simulate_batch(paper_fourbar, _joints(), samples, settle=0)
    assert result.ok.tolist() == [True, False, False]
    failures = result.failures
    assert failures.index.tolist() == [1, 2]
    assert failures.loc[1, "law_stiffness"] == 1e300
    assert failures.loc[1, "error"].startswith("IntegrationError: simulation stopped at")
    assert failures.loc[2, "error"].startswith("AssemblyError")
    assert np.isnan(result.peaks.loc[1:]).all(axis=None)
    few = simulate_batch(
        paper_fourbar,
        _joints(),
        BatchSamples(size=2),
        solver=SolverOptions(max_steps=400),
        settle=0,
    )
    assert not few.ok.any() and "max_steps = 400" in few.errors[0]
    frame = few.to_frame()
    assert frame["status"].tolist() == ["too_many_steps"] * 2


def test_method_choice_follows_the_stiffness(paper_fourbar: Mechanism) -> None:
    from jointplay.study.methods import method_law

    explicit = choose_method(paper_fourbar, _joints())
    assert explicit.method == "explicit"
    assert f"at {EXPLICIT_TOLERANCE_SCALE:g} times the solver's rtol" in explicit.reason
    for name in (
        "ifm-ecs-cylindrical",
        "ifm-ecs-spherical",
        "rm-ecs-cylindrical",
        "rm-conventional",
    ):
        law, _ = method_law(name, paper_fourbar)
        choice = choose_method(paper_fourbar, _joints(law=law))
        assert choice.method == "implicit", name
        assert "stiff" in choice.reason


def test_bad_arguments_name_the_fix(paper_fourbar: Mechanism) -> None:
    with pytest.raises(ConfigError, match="backend must be one of"):
        simulate_batch(paper_fourbar, _joints(), BatchSamples(size=1), backend="threads", settle=0)
    with pytest.raises(ConfigError, match="no parameter 'k'"):
        build_batch(paper_fourbar, _joints(), BatchSamples(law={"k": [1.0]}))
    with pytest.raises(ConfigError, match="not a clearance joint"):
        build_batch(paper_fourbar, _joints()[:2], BatchSamples(clearances={"B": [1e-5]}))
    with pytest.raises(ConfigError, match="one value per sample"):
        BatchSamples(lengths={"crank": [0.1, 0.1]}, clearances={"A": [1e-5]})


def test_the_explicit_method_tightens_rtol_and_the_velocity_atol_only(
    paper_fourbar: Mechanism,
) -> None:
    problem = build_batch(paper_fourbar, _joints(), BatchSamples(size=2))
    tight = problem.scaled_tolerances(0.2)
    assert tight.rtol == pytest.approx(0.2 * problem.rtol)
    n = 9  # three moving bodies: positions, then velocities
    np.testing.assert_array_equal(tight.atol[:n], problem.atol[:n])
    np.testing.assert_allclose(tight.atol[n : 2 * n], 0.2 * problem.atol[n : 2 * n])
    np.testing.assert_array_equal(tight.atol[2 * n :], problem.atol[2 * n :])


#: The paper's RM (Hunt-Crossley family) set at the default tolerances misses the accuracy
#: contract (1e-5 on omega, 1e-3 on the rest): the damping divided by the impact velocity makes
#: grazing contacts stiff. Against rtol 1e-9 (its contact onset within 0.6 pm) on the samples of
#: seed 31: omega 4.8e-3, forces and torque 1.4e-4, alpha 9.4e-4. With the onset tolerance at
#: 1 % of the clearance (its default before issue 40, now 0.01 % for the laws that read the
#: impact velocity): omega 4.2e-4, forces 1.7e-3, alpha 2.0e-2 (a spike); with the contact
#: memory v0 read at the end of the step entering contact (before 6016863), 5.6e-3, 2.3e-2 and
#: 0.51. These bounds are 2-3x the measurement. Not a bound for every sample: seed 32 is off
#: by 5.4e-3 (omega3) and 3.3e-2 (F_A) with either onset tolerance; seed 33 by 2.6e-5 and
#: 1.2e-4 (1.3e-4 and 6.6e-4 at 1 %).
RM_OMEGA_RTOL_LOOSER_THAN_CONTRACT = 1e-2
RM_FORCE_RTOL_LOOSER_THAN_CONTRACT = 5e-4
RM_ALPHA_RTOL_LOOSER_THAN_CONTRACT = 2e-3


def test_an_rm_set_runs_implicit_and_converges(paper_fourbar: Mechanism) -> None:
    from jointplay.study.methods import method_law

    law, _ = method_law("rm-conventional", paper_fourbar)
    samples = _random_samples(4, seed=31)
    samples = BatchSamples(lengths=samples.lengths, clearances=samples.clearances)
    result = simulate_batch(paper_fourbar, _joints(law=law), samples, backend="local", settle=0)
    assert result.method == "implicit" and result.ok.all()
    converged = SolverOptions(
        rtol=1e-9, atol_position=1e-12, atol_velocity=1e-9, onset_tolerance=6e-13
    )
    exact = simulate_batch(
        paper_fourbar, _joints(law=law), samples, backend="local", solver=converged, settle=0
    )
    for key in result.peaks.columns:
        bound = {
            "omega": RM_OMEGA_RTOL_LOOSER_THAN_CONTRACT,
            "alpha": RM_ALPHA_RTOL_LOOSER_THAN_CONTRACT,
        }.get(key.rstrip("0123456789"), RM_FORCE_RTOL_LOOSER_THAN_CONTRACT)
        error = np.max(np.abs(result.peaks[key] / exact.peaks[key] - 1))
        assert error < bound, (key, error)


@pytest.fixture
def interrupt_after_first_chunk(monkeypatch: pytest.MonkeyPatch) -> None:
    """SIGINT to this process as soon as the first chunk of lanes has finished (the readiness
    signal: the engine's progress callback), as Ctrl-C would send it."""
    import os
    import signal
    from contextlib import contextmanager

    from jointplay.execution import progress

    @contextmanager
    def bar(total: int, description: str):
        def advance(count: int) -> None:
            os.kill(os.getpid(), signal.SIGINT)

        yield advance

    monkeypatch.setattr(progress, "progress_bar", bar)


@pytest.mark.parametrize("backend", ["local", "processes", "dask"])
def test_an_interrupt_keeps_the_finished_lanes(
    paper_fourbar: Mechanism, reference, interrupt_after_first_chunk, backend: str
) -> None:
    """Ctrl-C stops the batch on every CPU backend, and the lanes that had finished come back
    with the interrupt, bit for bit what an uninterrupted run gives; the others are marked
    not run."""
    from distributed import LocalCluster

    from jointplay.dynamics.batch import NOT_RUN, BatchInterrupted
    from jointplay.dynamics.integrate import IntegrationStatus
    from jointplay.execution import dask

    samples, expected = reference
    options = {"chunk_size": 2}
    with (
        LocalCluster(n_workers=1, threads_per_worker=1, processes=False, dashboard_address=":0")
        if backend == "dask"
        else _nothing() as cluster
    ):
        if backend == "processes":
            options["workers"] = 2
        if backend == "dask":
            options["scheduler"] = cluster.scheduler_address
        with pytest.raises(BatchInterrupted) as stopped:
            simulate_batch(
                paper_fourbar,
                _joints(),
                samples,
                backend=backend,
                progress=True,
                **options,
                settle=0,
            )
        dask.close_clients()
    result = stopped.value.result
    assert isinstance(stopped.value, KeyboardInterrupt)
    finished = result.status != IntegrationStatus.INTERRUPTED
    assert 2 <= finished.sum() < len(samples)  # at least the first chunk, not everything
    assert all(e == NOT_RUN for e in np.asarray(result.errors)[~finished])
    assert not result.ok[~finished].any() and np.isnan(result.peaks.to_numpy()[~finished]).all()
    np.testing.assert_array_equal(
        result.peaks.to_numpy()[finished], expected.peaks.to_numpy()[finished]
    )
    np.testing.assert_array_equal(
        result.statistics.to_numpy()[finished], expected.statistics.to_numpy()[finished]
    )


@pytest.mark.slow  # JAX compiles the batch for ~10 s
def test_an_interrupt_on_the_gpu_backend_keeps_the_finished_chunks(
    paper_fourbar: Mechanism, reference, interrupt_after_first_chunk
) -> None:
    """The GPU backend (here on JAX's CPU backend) runs its chunks one XLA call each, so
    Ctrl-C after the first chunk keeps that chunk's lanes (status ok, the values of the CPU
    run) and marks the others not run. It used to give all the lanes to one call, and an
    interrupt lost them all."""
    pytest.importorskip("jax")
    from jointplay.dynamics.batch import NOT_RUN, BatchInterrupted
    from jointplay.dynamics.integrate import IntegrationStatus

    samples, expected = reference
    with pytest.raises(BatchInterrupted) as stopped:
        simulate_batch(
            paper_fourbar, _joints(), samples, backend="gpu", method="explicit",
            chunk_size=2, progress=True, settle=0,
        )  # fmt: skip
    result = stopped.value.result
    finished = result.status != IntegrationStatus.INTERRUPTED
    assert finished.tolist() == [True] * 2 + [False] * (len(samples) - 2)
    assert result.ok[finished].all()
    assert all(e == NOT_RUN for e in np.asarray(result.errors)[~finished])
    assert np.isnan(result.peaks.to_numpy()[~finished]).all()
    np.testing.assert_allclose(
        result.peaks.to_numpy()[finished], expected.peaks.to_numpy()[finished],
        rtol=SAME_ALGORITHM_RTOL,
    )  # fmt: skip


@pytest.mark.parametrize("stage", ["_merged", "_names"], ids=["outputs-merged", "tables-built"])
def test_an_interrupt_while_the_batch_result_is_put_together_keeps_every_lane(
    paper_fourbar: Mechanism, reference, monkeypatch: pytest.MonkeyPatch, stage: str
) -> None:
    """Ctrl-C after every lane ran, just as the chunks' outputs are put in lane order (that
    stretch raised the interrupt bare and lost every finished lane) or while the engine builds
    the result's tables: the result comes back with the interrupt (BatchInterrupted, every
    lane ok), not lost with it."""
    import os
    import signal

    import jointplay.dynamics.batch as batch
    from jointplay.dynamics.batch import BatchInterrupted

    samples, expected = reference
    original = getattr(batch, stage)

    def interrupted(*args, **kwargs):
        os.kill(os.getpid(), signal.SIGINT)
        return original(*args, **kwargs)

    monkeypatch.setattr(batch, stage, interrupted)
    with pytest.raises(KeyboardInterrupt) as stopped:
        simulate_batch(paper_fourbar, _joints(), samples, backend="local", settle=0)
    assert isinstance(stopped.value, BatchInterrupted), "the finished lanes were lost"
    assert stopped.value.result.ok.all()
    _same(stopped.value.result, expected)


def _nothing():
    from contextlib import nullcontext

    return nullcontext()


def test_a_dask_cluster_without_workers_is_a_clear_error(
    paper_fourbar: Mechanism, reference, monkeypatch: pytest.MonkeyPatch
) -> None:
    """It used to wait 30 s and end with a bare TimeoutError (exit 3)."""
    from distributed import LocalCluster

    from jointplay.execution import dask

    monkeypatch.setattr(dask, "DASK_NO_WORKERS_S", 0.5)
    samples, _ = reference
    with LocalCluster(n_workers=0, processes=False, dashboard_address=":0") as cluster:
        address = cluster.scheduler_address
        with pytest.raises(ConfigError, match=r"has no workers \(none joined within 0.5 s\)"):
            simulate_batch(
                paper_fourbar, _joints(), samples, backend="dask", scheduler=address, settle=0
            )


_LOSES_ITS_WORKERS = """
import json
from contextlib import contextmanager

import numpy as np
from distributed import LocalCluster

from jointplay.dynamics.batch import BatchSamples, simulate_batch
from jointplay.dynamics.clearance import ClearanceJoint
from jointplay.execution import dask, progress
from jointplay.dynamics.setup import DEFAULT_IMPACT
from jointplay.io.config import load_preset

if __name__ == "__main__":
    samples = BatchSamples(clearances={j: np.linspace(6e-6, 20e-6, 9) for j in ("A", "B")})
    joints = [ClearanceJoint(j, 11.75e-6, 0.005, DEFAULT_IMPACT) for j in ("A", "B")]
    mechanism = load_preset("paper-fourbar")
    reference = simulate_batch(mechanism, joints, samples, settle=0)
    dask.DASK_NO_WORKERS_S = 1.0
    with LocalCluster(
        n_workers=1, threads_per_worker=1, processes=False, dashboard_address=":0"
    ) as cluster:

        @contextmanager
        def bar(total, description):
            yield lambda count: cluster.scale(0)  # the workers go after the first chunk

        progress.progress_bar = bar
        result = simulate_batch(
            mechanism, joints, samples, backend="dask", scheduler=cluster.scheduler_address,
            chunk_size=2, progress=True, settle=0,
        )
        dask.close_clients()
    ok = result.ok
    same = np.array_equal(result.peaks.to_numpy()[ok], reference.peaks.to_numpy()[ok])
    print(json.dumps({"ok": int(ok.sum()), "n": len(ok), "same": bool(same),
                      "errors": [e for e in result.errors if e]}))
"""


def test_a_dask_cluster_that_loses_its_workers_keeps_the_finished_lanes(tmp_path) -> None:
    """The workers go away after the first chunk: the batch ends in bounded time (it used to
    wait for ever), the finished lanes kept, the others failed with the reason. It runs in
    its own interpreter: the cluster that lost its workers leaves threads behind that upset
    the test session (CPython 3.11's parser state is shared between threads)."""
    import json
    import subprocess
    import sys

    script = tmp_path / "loses.py"
    script.write_text(_LOSES_ITS_WORKERS, encoding="utf-8")
    done = subprocess.run(
        [sys.executable, str(script)], capture_output=True, text=True, timeout=120, check=False
    )
    assert done.returncode == 0, done.stderr[-2000:]
    found = json.loads(done.stdout.strip().splitlines()[-1])
    assert 2 <= found["ok"] < found["n"] and found["same"], found
    # the chunks still to run, and those whose results died with the worker before they
    # were fetched (each waited at most DASK_NO_WORKERS_S for a worker)
    reasons = ("has had no worker for 1 s", "had no worker to compute it again within 1 s")
    lost = found["errors"]
    assert lost and all(e.startswith("ClusterLost: the Dask cluster at") for e in lost), lost
    assert all(any(reason in e for reason in reasons) for e in lost), lost
