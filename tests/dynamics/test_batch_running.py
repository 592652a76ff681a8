"""The running responses of :func:`simulate_batch` (``running=``, issue 42) on every CPU
backend: the same bits in this process's threads, in chunks, in worker processes and on a
Dask cluster (lanes are independent; the running tail travels in each lane's ``rpar``)."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from jointplay.dynamics.batch import BatchSamples, RunningOutputs, simulate_batch
from jointplay.dynamics.clearance import ClearanceJoint
from jointplay.dynamics.setup import DEFAULT_IMPACT
from jointplay.dynamics.wear import OutputSpeedReference, WearSettings
from jointplay.model.mechanism import Mechanism

JOINTS = ("O2", "A", "B", "O4")
FAST = {"settle": 0, "revolutions": 0.25}


def _running(mechanism: Mechanism) -> RunningOutputs:
    return RunningOutputs(OutputSpeedReference.of(mechanism), WearSettings(bins=90))


def _samples() -> BatchSamples:
    rng = np.random.default_rng(5)
    return BatchSamples(clearances={j: rng.uniform(6e-6, 21e-6, 5) for j in JOINTS})


@pytest.fixture(scope="module")
def reference(paper_fourbar: Mechanism):
    joints = [ClearanceJoint(j, 11.75e-6, 0.005, DEFAULT_IMPACT) for j in JOINTS]
    result = simulate_batch(
        paper_fourbar, joints, _samples(), running=_running(paper_fourbar), **FAST
    )
    return joints, result


def _same(result, expected) -> None:
    pd.testing.assert_frame_equal(result.peaks, expected.peaks, check_exact=True)
    pd.testing.assert_frame_equal(result.statistics, expected.statistics, check_exact=True)


def test_the_running_columns(paper_fourbar: Mechanism, reference) -> None:
    joints, result = reference
    assert result.ok.all()
    assert "omega4_deviation" in result.peaks and result.units["omega4_deviation"] == "rad/s"
    rates = result.statistics[[f"wear_rate_{j}" for j in JOINTS]]
    assert (rates.to_numpy() > 0).all() and result.units["wear_rate_A"] == "m/s"
    # without running the columns are absent and the statistics the same
    plain = simulate_batch(paper_fourbar, joints, _samples(), **FAST)
    assert "omega4_deviation" not in plain.peaks and "wear_rate_A" not in plain.statistics
    pd.testing.assert_frame_equal(
        plain.statistics, result.statistics[plain.statistics.columns], check_exact=True
    )


@pytest.mark.parametrize("method", ["explicit", "implicit"])
def test_the_peaks_are_those_without_the_running_responses(
    paper_fourbar: Mechanism, method: str
) -> None:
    # the speed deviation never triggers the other quantities' refinement: the model's peaks
    # and statistics are bit for bit those of a batch without the running responses
    joints = [ClearanceJoint(j, 11.75e-6, 0.005, DEFAULT_IMPACT) for j in JOINTS]
    run = simulate_batch(
        paper_fourbar, joints, _samples(), running=_running(paper_fourbar), method=method, **FAST
    )
    plain = simulate_batch(paper_fourbar, joints, _samples(), method=method, **FAST)
    assert run.ok.all() and run.method == method
    pd.testing.assert_frame_equal(plain.peaks, run.peaks[plain.peaks.columns], check_exact=True)
    pd.testing.assert_frame_equal(
        plain.statistics, run.statistics[plain.statistics.columns], check_exact=True
    )
    pd.testing.assert_frame_equal(plain.counters, run.counters, check_exact=True)


@pytest.mark.parametrize("chunk_size", [1, 2])
def test_chunks_and_worker_processes_give_the_same_bits(
    paper_fourbar: Mechanism, reference, chunk_size: int
) -> None:
    joints, expected = reference
    running = _running(paper_fourbar)
    _same(
        simulate_batch(
            paper_fourbar, joints, _samples(), running=running, chunk_size=chunk_size, **FAST
        ),
        expected,
    )
    if chunk_size == 2:
        result = simulate_batch(
            paper_fourbar, joints, _samples(), running=running, backend="processes",
            workers=2, chunk_size=chunk_size, **FAST,
        )  # fmt: skip
        assert result.backend == "processes"
        _same(result, expected)


def test_a_dask_cluster_gives_the_same_bits(paper_fourbar: Mechanism, reference) -> None:
    from distributed import LocalCluster

    from jointplay.execution import dask

    joints, expected = reference
    with LocalCluster(
        n_workers=2, threads_per_worker=1, processes=False, dashboard_address=":0"
    ) as cluster:
        result = simulate_batch(
            paper_fourbar, joints, _samples(), running=_running(paper_fourbar), backend="dask",
            scheduler=cluster.scheduler_address, **FAST,
        )  # fmt: skip
        dask.close_clients()
    assert result.backend == "dask"
    _same(result, expected)
