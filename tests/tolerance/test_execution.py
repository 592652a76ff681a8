"""Execution backends: identical results in-process, on local processes and on Dask."""

from __future__ import annotations

import dataclasses
import operator
import pickle
from typing import ClassVar

import numpy as np
import pytest

from jointplay.errors import ConfigError, PartialInterrupt
from jointplay.model.mechanism import Mechanism
from jointplay.tolerance.analysis import tolerance_study
from jointplay.tolerance.execution import Backend, run, run_tasks
from jointplay.tolerance.responses import Evaluation, FourBarKinematics, LinearModel
from jointplay.tolerance.sampling import sample
from jointplay.tolerance.spec import ToleranceSpec


@pytest.fixture(scope="module")
def kinematics(paper_fourbar: Mechanism) -> tuple[FourBarKinematics, np.ndarray]:
    spec = ToleranceSpec.from_mechanism(paper_fourbar).only("length")
    model = FourBarKinematics.from_mechanism(paper_fourbar, spec.names)
    return model, sample(spec, 3000, 5).values


def _summary_without_execution(study) -> dict:
    summary = study.summary()
    summary.pop("execution")  # backend, workers and wall time differ by design
    return summary


def test_local_processes_give_the_serial_numbers() -> None:
    model = LinearModel(("a", "b"), ((1.0, 2.0), (3.0, -1.0)), chunk_size=500)
    x = np.random.default_rng(5).normal(size=(3000, 2))
    serial = run(model, x, backend=Backend("serial"))
    parallel = run(model, x, backend=Backend("processes", workers=2))
    assert parallel.backend == "processes" and parallel.workers == 2
    np.testing.assert_array_equal(parallel.values, serial.values)
    np.testing.assert_array_equal(parallel.status, serial.status)
    assert parallel.errors == serial.errors
    assert serial.n_ok == 3000 and not serial.interrupted


def test_cheap_kinematics_stay_in_process_with_the_same_numbers(kinematics) -> None:
    """Starting workers (~3 s each here) would cost more than 3000 vectorised samples
    (~0.1 s): the process backend keeps them in this process; the numbers are the same."""
    model, x = kinematics
    serial = run(model, x, backend=Backend("serial", chunk_size=500))
    default = run(model, x, backend=Backend("processes", chunk_size=500))
    assert default.backend == "local" and default.workers == 1
    np.testing.assert_array_equal(default.values, serial.values)


def test_default_workers_are_started_only_when_the_work_pays_for_them(
    kinematics, monkeypatch
) -> None:
    import os

    from jointplay.tolerance import execution

    monkeypatch.setattr(os, "cpu_count", lambda: 8)
    model, _ = kinematics
    per_worker = int(execution.WORKER_START_S / model.seconds_per_sample) + 1
    for n, expected in [
        (3000, ("local", None)),
        (3 * per_worker, ("processes", 3)),
        (100 * per_worker, ("processes", None)),  # all 8
    ]:
        _, backend = execution._placed(model, Backend("processes"), n)
        assert (backend.kind, backend.workers) == expected
    _, backend = execution._placed(model, Backend("processes", workers=2), 3000)
    assert (backend.kind, backend.workers) == ("processes", 2)  # asked for: started


def test_early_worker_start_follows_the_same_rule(monkeypatch) -> None:
    # the command line starts the batch engine's workers before its model exists: exactly
    # those that the run will use (prepare/_placed), none for a run kept in this process
    import os

    from jointplay.execution import pool
    from jointplay.tolerance import execution

    monkeypatch.setattr(os, "cpu_count", lambda: 8)
    started: list[int | None] = []
    monkeypatch.setattr(pool, "start_workers", started.append)
    cost = 0.015
    per_worker = int(execution.WORKER_START_S / cost) + 1
    for n, backend, expected in [
        (per_worker, Backend("processes"), []),  # one worker's worth: stays here
        (3 * per_worker, Backend("processes"), [3]),
        (100 * per_worker, Backend("processes"), [None]),  # one per CPU
        (10, Backend("processes", workers=2), [2]),  # asked for
        (100 * per_worker, Backend("local"), []),
    ]:
        started.clear()
        execution.start_batch_workers(backend, n, cost)
        assert started == expected, (n, backend)


def test_results_do_not_depend_on_the_chunk_size(kinematics) -> None:
    model, x = kinematics
    small = run(model, x[:300], backend=Backend("serial", chunk_size=7))
    large = run(model, x[:300], backend=Backend("serial", chunk_size=1000))
    np.testing.assert_array_equal(small.values, large.values)


def test_a_single_chunk_stays_in_process(kinematics) -> None:
    model, x = kinematics
    result = run(model, x[:10], backend=Backend("processes", workers=2))
    assert result.backend == "local" and result.workers == 1


def test_dask_cluster_gives_identical_samples_and_summaries(paper_fourbar: Mechanism) -> None:
    from distributed import LocalCluster

    spec = ToleranceSpec.from_mechanism(paper_fourbar)
    reference = tolerance_study(
        paper_fourbar, spec, samples=2000, seed=9, backend=Backend("serial", chunk_size=400)
    )
    # One worker process: the model really travels through the scheduler (pickled).
    with LocalCluster(
        n_workers=1, threads_per_worker=1, processes=True, dashboard_address=":0"
    ) as cluster:
        on_dask = tolerance_study(
            paper_fourbar,
            spec,
            samples=2000,
            seed=9,
            backend=Backend.dask(cluster.scheduler_address, chunk_size=400),
        )
    assert on_dask.result.run.backend == "dask"
    assert on_dask.to_dataframe().equals(reference.to_dataframe())
    assert _summary_without_execution(on_dask) == _summary_without_execution(reference)


class _InterruptedAfter:
    """A model whose second block is 'interrupted' by the user (Ctrl-C)."""

    input_names = ("x",)
    response_names = ("y",)
    units: ClassVar[dict[str, str]] = {"y": ""}
    chunk_size = 10

    def __init__(self) -> None:
        self.calls = 0

    def evaluate(self, x: np.ndarray) -> Evaluation:
        self.calls += 1
        if self.calls > 1:
            raise KeyboardInterrupt
        return Evaluation(x.copy(), np.ones(len(x), dtype=bool), ("",) * len(x))

    def describe(self) -> dict:
        return {}


def test_ctrl_c_keeps_the_finished_samples() -> None:
    result = run(_InterruptedAfter(), np.arange(35.0)[:, None], backend=Backend("serial"))
    assert result.interrupted
    np.testing.assert_array_equal(result.values[:10, 0], np.arange(10.0))
    assert (result.status[:10] == 0).all() and (result.status[10:] == 2).all()
    assert result.n_ok == 10 and result.n_not_run == 25 and result.n_failed == 0
    assert result.errors[10].startswith("not run")


class _InterruptedMidBlock(_InterruptedAfter):
    """A model whose second block is interrupted after its first 4 samples finished (what a
    batch-engine model raises: :class:`PartialInterrupt` with the block's partial result)."""

    def evaluate(self, x: np.ndarray) -> Evaluation:
        self.calls += 1
        if self.calls == 1:
            return Evaluation(x.copy(), np.ones(len(x), dtype=bool), ("",) * len(x))
        finished = np.arange(len(x)) < 4
        errors = tuple("" if f else "not run (interrupted)" for f in finished)
        values = np.where(finished[:, None], x, np.nan)
        raise PartialInterrupt(Evaluation(values, finished.copy(), errors, finished=finished))


def test_ctrl_c_keeps_the_finished_samples_of_the_block_it_stopped() -> None:
    result = run(_InterruptedMidBlock(), np.arange(35.0)[:, None], backend=Backend("serial"))
    assert result.interrupted
    np.testing.assert_array_equal(result.values[:14, 0], np.arange(14.0))
    assert (result.status[:14] == 0).all() and (result.status[14:] == 2).all()
    assert result.n_ok == 14 and result.n_not_run == 21
    assert np.isnan(result.values[14:]).all()


def test_models_with_mechanisms_can_be_sent_to_workers(paper_fourbar: Mechanism) -> None:
    from jointplay.contact.laws import get_law
    from jointplay.tolerance.responses import dynamic_model

    spec = ToleranceSpec.from_mechanism(paper_fourbar)
    law = get_law("impact", stiffness=3.16e8, exponent=1.5, c_max=1e4, d_max=1e-4)
    model = dynamic_model(paper_fourbar, spec.names, law)
    copy = pickle.loads(pickle.dumps(model))
    assert copy.mechanism == paper_fourbar
    assert copy.clearance_joints == ("O2", "A", "B", "O4")
    assert copy.response_names == model.response_names


def test_progress_bar_runs(capsys) -> None:
    model = LinearModel(("a",), ((2.0,),), chunk_size=5)
    result = run(model, np.ones((12, 1)), backend=Backend("serial"), progress=True)
    assert result.n_ok == 12
    assert "12/12" in capsys.readouterr().err


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"kind": "threads"}, "backend must be one of"),
        ({"workers": 0}, "positive integer"),
        ({"chunk_size": 0}, "positive integer"),
        ({"kind": "dask"}, "scheduler's address"),
        ({"kind": "serial", "scheduler": "tcp://x:1"}, "dask backend only"),
    ],
)
def test_backend_validation(kwargs: dict, message: str) -> None:
    with pytest.raises(ConfigError, match=message):
        Backend(**kwargs)


def test_wrong_input_shape_is_refused() -> None:
    model = LinearModel(("a", "b"), ((1.0, 1.0),))
    with pytest.raises(ConfigError, match=r"shape \(n, 2\)"):
        run(model, np.ones((3, 3)), backend=Backend("serial"))


@pytest.mark.parametrize("backend", [Backend("serial"), Backend("processes", workers=2)])
def test_run_tasks_keeps_item_order_and_records_failures(backend: Backend) -> None:
    done: list[int] = []
    result = run_tasks(
        operator.truediv,
        [1.0, 0.0, 4.0, 16.0],
        backend,
        shared=8.0,
        on_done=lambda index, value: done.append(index),
    )
    assert result.results == (8.0, None, 2.0, 0.5)
    assert result.status.tolist() == [0, 1, 0, 0]
    assert result.errors[1].startswith("ZeroDivisionError:")
    assert result.errors[0] == ""
    assert sorted(done) == [0, 2, 3] and not result.interrupted
    assert result.backend == backend.kind


def test_a_block_that_raises_marks_its_samples_failed() -> None:
    broken = run(_Raising(), np.ones((5, 1)), backend=Backend("serial"))
    assert broken.status.tolist() == [0, 0, 1, 1, 0]
    assert broken.errors[2] == broken.errors[3] == "RuntimeError: block 2"
    assert np.isnan(broken.values[2:4]).all() and not broken.interrupted


class _Raising:
    """A model whose second block raises (a bug, say): its samples are failures, not a crash."""

    input_names = ("x",)
    response_names = ("y",)
    units: ClassVar[dict[str, str]] = {"y": ""}
    chunk_size = 2

    def __init__(self) -> None:
        self.calls = 0

    def evaluate(self, x: np.ndarray) -> Evaluation:
        self.calls += 1
        if self.calls == 2:
            raise RuntimeError(f"block {self.calls}")
        return Evaluation(x.copy(), np.ones(len(x), dtype=bool), ("",) * len(x))

    def describe(self) -> dict:
        return {}


def _ctrl_c() -> None:
    """SIGINT to this process, as Ctrl-C sends it."""
    import os
    import signal

    os.kill(os.getpid(), signal.SIGINT)


class _CtrlCWhileRead:
    """An evaluation whose results are read (by :func:`run`, putting the blocks together)
    just as Ctrl-C arrives."""

    def __init__(self, x: np.ndarray) -> None:
        self._values, self.ok, self.errors = x.copy(), np.ones(len(x), bool), ("",) * len(x)
        self.finished = self.checks = None

    @property
    def values(self) -> np.ndarray:
        _ctrl_c()
        return self._values


class _LastBlockReadUnderCtrlC(_InterruptedAfter):
    def evaluate(self, x: np.ndarray):  # type: ignore[override]
        return _CtrlCWhileRead(x)


def test_ctrl_c_while_the_blocks_are_put_together_keeps_every_finished_sample() -> None:
    """Every block had finished when Ctrl-C came, while :func:`run` put their results
    together: the run is interrupted and keeps them all (it used to lose them all)."""
    try:
        result = run(
            _LastBlockReadUnderCtrlC(), np.arange(25.0)[:, None], backend=Backend("serial")
        )
    except KeyboardInterrupt:
        pytest.fail("the interrupt went through and the finished samples were lost")
    assert result.interrupted and result.n_ok == 25
    np.testing.assert_array_equal(result.values[:, 0], np.arange(25.0))


def test_ctrl_c_while_a_dynamic_block_is_post_processed_keeps_the_block(
    paper_fourbar: Mechanism, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Ctrl-C after the batch engine ran a block, while its responses are computed from the
    batch result: the block comes back with the interrupt (a PartialInterrupt whose samples
    all finished), not lost with it."""
    from jointplay.contact.laws import get_law
    from jointplay.tolerance.response_dynamic import DynamicResponses
    from jointplay.tolerance.responses import dynamic_model

    spec = ToleranceSpec.from_mechanism(paper_fourbar)
    law = get_law("impact", stiffness=3.16e8, exponent=1.5, c_max=1e4, d_max=1e-4)
    model = dynamic_model(paper_fourbar, spec.names, law, revolutions=0.25, settle=0)
    model = dataclasses.replace(model, backend=Backend("local"))
    x = np.repeat(spec.nominal[None, :], 2, axis=0)
    expected = model.evaluate(x)
    original = DynamicResponses._evaluation

    def post_processing(self, *args, **kwargs):
        _ctrl_c()
        return original(self, *args, **kwargs)

    monkeypatch.setattr(DynamicResponses, "_evaluation", post_processing)
    with pytest.raises(KeyboardInterrupt) as stopped:
        model.evaluate(x)
    assert isinstance(stopped.value, PartialInterrupt), "the block was lost"
    kept = stopped.value.partial
    assert kept.ok.all() and kept.finished is None
    np.testing.assert_array_equal(kept.values, expected.values)


def test_an_interrupted_block_of_the_design_model_keeps_whole_rows(
    paper_fourbar: Mechanism, monkeypatch
) -> None:
    """The design's peak model adds the joint force and contact pressure to the batch
    engine's peaks: an interrupted block's finished samples carry them too, so that run()
    can keep the block (the base peaks alone, 9 columns of 11, made run() fail with a
    broadcast error when Ctrl-C came during a dynamic design)."""
    from jointplay.contact.laws import get_law
    from jointplay.tolerance.response_dynamic import DynamicResponses, PeakResponses
    from jointplay.tolerance.responses import dynamic_model

    spec = ToleranceSpec.from_mechanism(paper_fourbar)
    law = get_law("impact", stiffness=3.16e8, exponent=1.5, c_max=1e4, d_max=1e-4)
    base = dynamic_model(paper_fourbar, spec.names, law, revolutions=0.25, settle=0)
    fields = {f.name: getattr(base, f.name) for f in dataclasses.fields(base)}
    model = PeakResponses(**fields)
    x = sample(spec, 6, 3).values
    finished = np.array([True, True, True, False, False, False])

    def interrupted(self, x):
        m, r = len(x), len(self.peak_keys)
        values = np.where(finished[:, None], 100.0, np.nan) * np.ones((m, r))
        checks = np.zeros((m, len(self.check_names)))
        errors = tuple("" if f else "not run (interrupted)" for f in finished)
        raise PartialInterrupt(Evaluation(values, finished.copy(), errors, checks, finished))

    monkeypatch.setattr(DynamicResponses, "evaluate", interrupted)
    with pytest.raises(PartialInterrupt) as stopped:
        model.evaluate(x)
    partial = stopped.value.partial
    assert partial.values.shape == (6, len(model.response_names))
    np.testing.assert_array_equal(partial.finished, finished)
    assert (partial.values[:3, model.response_names.index("joint_force")] == 100.0).all()
    result = run(model, x, backend=Backend("serial"))
    assert result.interrupted and result.n_ok == 3
