"""A Dask cluster that loses its workers in the middle of a study (docs/cli.md, "Workers that
die mid-run"): the study stops waiting once the cluster has had no worker for
``DASK_NO_WORKERS_S`` — once, not once per block of samples — and says so in words."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

pytestmark = pytest.mark.slow

#: The study loses its workers after 48 of its 120 samples (blocks of 8): 9 blocks and the
#: convergence check's are left. Printed: the seconds from the loss to the study's end, the
#: samples kept and the warnings that NumPy or jointplay raised.
_STUDY_LOSES_ITS_WORKERS = """
import json
import time
import warnings
from contextlib import contextmanager

if __name__ == "__main__":
    try:
        from distributed import LocalCluster

        cluster = LocalCluster(
            n_workers=1, threads_per_worker=1, processes=False, dashboard_address=":0"
        )
    except Exception as exc:  # no cluster here: nothing to test
        print(json.dumps({"skip": f"{type(exc).__name__}: {exc}"}))
        raise SystemExit(0)

    from jointplay.execution import Backend, dask, progress
    from jointplay.io.config import load_preset
    from jointplay.tolerance.analysis import tolerance_study

    dask.DASK_NO_WORKERS_S = 1.0
    dask.DASK_WORKER_CHECK_S = 0.1
    lost = {}

    @contextmanager
    def bar(total, description):
        done = [0]

        def advance(count):
            done[0] += count
            if done[0] >= 48 and not lost:
                cluster.scale(0)
                lost["at"] = time.monotonic()

        yield advance

    progress.progress_bar = bar
    with cluster, warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        study = tolerance_study(
            load_preset("paper-fourbar"), responses="dynamic", samples=120, revolutions=1,
            settle=0, seed=1, progress=True,
            backend=Backend("dask", scheduler=cluster.scheduler_address, chunk_size=8),
        )
        took = time.monotonic() - lost["at"]
        dask.close_clients()
    run = study.result.run
    print(json.dumps({
        "after_loss_s": took,
        "ok": int((run.status == 0).sum()),
        "errors": sorted({e for e in run.errors if e}),
        "warnings": [f"{w.filename}: {w.message}" for w in caught
                     if "jointplay" in w.filename or "numpy" in w.filename],
    }))
"""


def test_a_study_whose_cluster_loses_its_workers_gives_up_once(tmp_path: Path) -> None:
    """It waited ``DASK_NO_WORKERS_S`` for every block left (and again in the convergence
    check, which then printed NumPy's raw "All-NaN slice encountered"): 94 s for a
    30 s limit, hours for a large study."""
    script = tmp_path / "loses.py"
    script.write_text(_STUDY_LOSES_ITS_WORKERS, encoding="utf-8")
    done = subprocess.run(
        [sys.executable, str(script)], capture_output=True, text=True, timeout=300, check=False
    )
    assert done.returncode == 0, done.stderr[-3000:]
    found = json.loads(done.stdout.strip().splitlines()[-1])
    if "skip" in found:
        pytest.skip(f"no Dask LocalCluster here: {found['skip']}")
    # the limit (1 s) once, and a little for the blocks that then fail at once
    assert found["after_loss_s"] < 1.0 + 3.0, found
    assert 48 <= found["ok"] < 120, found
    assert found["errors"], found
    assert all(e.startswith("ClusterLost: the Dask cluster at") for e in found["errors"]), found
    assert all("no worker" in e for e in found["errors"]), found
    assert found["warnings"] == [], found
