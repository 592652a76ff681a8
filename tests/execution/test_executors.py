"""The execution room: one list of backend names, one executor per name, the choices it makes."""

from __future__ import annotations

import pytest

from jointplay.errors import ConfigError
from jointplay.execution import ALIASES, BACKENDS, Backend, backend_kind
from jointplay.execution.executors import _EXECUTORS, Executor, executor


def test_every_backend_name_has_one_executor_and_no_more() -> None:
    assert set(_EXECUTORS) == set(BACKENDS)
    for name in BACKENDS:
        assert _EXECUTORS[name].kind == name


def test_an_alias_names_its_backend_and_an_unknown_name_is_refused() -> None:
    for alias, kind in ALIASES.items():
        assert backend_kind(alias) == kind
        assert Backend(alias).kind == kind  # type: ignore[arg-type]
    with pytest.raises(ConfigError, match="backend must be one of local, processes"):
        Backend("threads")  # type: ignore[arg-type]


def test_tasks_that_cannot_use_workers_run_in_this_process() -> None:
    assert executor(Backend("processes", workers=4)).for_tasks(1).kind == "local"
    assert executor(Backend("processes", workers=1)).for_tasks(10).kind == "local"
    assert executor(Backend("gpu")).for_tasks(10).kind == "local"
    two = executor(Backend("processes", workers=8)).for_tasks(2)
    assert two.kind == "processes" and two.lane_slots() == 2


def test_lane_chunks_follow_the_backend_and_a_given_chunk_size_wins() -> None:
    processes = executor(Backend("processes", workers=3))
    assert processes.lane_chunk(1000, 3) == 32  # the default chunk caps ~4 per slot
    assert processes.lane_chunk(12, 3) == 1
    assert executor(Backend("processes", workers=3, chunk_size=7)).lane_chunk(1000, 3) == 7
    gpu = executor(Backend("gpu"))
    assert gpu.on_device and gpu.lane_parts(10, gpu.lane_chunk(10, 1)) == 10


def test_the_gpu_executor_refuses_an_engine_without_a_device_kernel() -> None:
    from jointplay.execution.executors import Lanes, LaneWork

    work = LaneWork(task=print, shared=None, here=lambda *a: None, stopped=lambda o: False)
    with pytest.raises(ConfigError, match="gpu backend runs the batch engine only"):
        executor(Backend("gpu")).run_lanes(Lanes(work, [()], 1, 1, lambda k, o: None))


def test_an_executor_is_chosen_from_the_backend_alone() -> None:
    chosen = executor(Backend("local", chunk_size=5))
    assert isinstance(chosen, Executor) and chosen.kind == "local"
    assert chosen.block(64) == 5 and executor(Backend("local")).block(64) == 64
