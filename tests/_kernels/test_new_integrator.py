"""A new integrator is one file (issue 38): a lane source module with its steps, its work
(the CPU's allocator, and the shapes, dtypes and ``arrays`` the GPU kernel allocates by) and
its ``LANE`` record. The tables that name integrators — the records
(``INTEGRATORS``), the lanes (``build.LANES``), the single engine's traced lanes
(``cpu.traced``), the capability table, ``SolverOptions``' choices, ``jointplay.integrate``'s
methods — are read from the modules, so dropping the file into
``jointplay/_kernels/lanes/`` is the whole change.

The test's integrator is DOPRI5 again under another name (its steps call DOPRI5's): what it
shows is the wiring, and that the new lane is a lane like the others, the same bits as
DOPRI5's.
"""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

from jointplay._kernels import eom, integrators
from jointplay._kernels.lanes import SOURCES, build, cpu
from jointplay._kernels.lanes.limits import MAX_COORDS, MAX_STATE, MAX_WORK_ARRAYS
from jointplay.dynamics.setup import ContactModel
from jointplay.dynamics.system import build_system
from jointplay.model.mechanism import Mechanism

#: The new integrator's module, as a user would write it (its steps forward to DOPRI5's).
NEW_MODULE = '''
"""DOPRI5 under another name: a new integrator in one file."""
from jointplay._kernels.lanes.source import LANE as _DOPRI5

LANE = {
    **_DOPRI5,
    "integrator": {**_DOPRI5["integrator"], "name": "dopri5_copy", "engines": ("single",)},
    "lane": "copy_lane", "steps": "copy", "work": "copy_work",
}


def copy_work(lay):
    return dopri_work(lay)


def copy_start(ws, t, y, f, t_end, max_step, rtol, atol, rp, ip, lay, pen, f_mid, record_mid,
               phi_q, schur, lam, counts):
    return dopri_start(ws, t, y, f, t_end, max_step, rtol, atol, rp, ip, lay, pen, f_mid,
                       record_mid, phi_q, schur, lam, counts)


def copy_begin(ws, t, y, f, h, max_step, min_step, rtol, atol, size):
    return dopri_begin(ws, t, y, f, h, max_step, min_step, rtol, atol, size)


def copy_land(t, h, target):
    return dopri_land(t, h, target)


def copy_attempt(ws, t, y, f, h, t_new, y_new, t_old, y_old, rtol, atol, rp, ip, lay,
                 record_new, qb, pen, f_mid, record_mid, phi_q, schur, lam, counts):
    return dopri_attempt(ws, t, y, f, h, t_new, y_new, t_old, y_old, rtol, atol, rp, ip, lay,
                         record_new, qb, pen, f_mid, record_mid, phi_q, schur, lam, counts)


def copy_retry(ws):
    return dopri_retry(ws)


def copy_refresh(ws, t_new, y_new, f_new, changed, rp, ip, lay, record, qb, pen, phi_q, schur,
                 lam, counts):
    return dopri_refresh(ws, t_new, y_new, f_new, changed, rp, ip, lay, record, qb, pen, phi_q,
                         schur, lam, counts)


def copy_accept(ws, t_new, y_new, f_new, h, changed, atol, rp, ip, lay, pen, f_mid,
                record_mid, phi_q, schur, lam, counts):
    return dopri_accept(ws, t_new, y_new, f_new, h, changed, atol, rp, ip, lay, pen, f_mid,
                        record_mid, phi_q, schur, lam, counts)


def copy_dense(ws, t_old, y_old, t, y, f, t_new, y_new, f_new, h, tau, theta, out, lay):
    return dopri_dense(ws, t_old, y_old, t, y, f, t_new, y_new, f_new, h, tau, theta, out, lay)
'''

#: Run in a fresh interpreter whose ``jointplay._kernels.lanes`` also searches the folder of
#: the new module (as if it had been saved beside the others).
SCRIPT = """
import importlib.util, json, sys
spec = importlib.util.find_spec("jointplay._kernels.lanes")
spec.submodule_search_locations.append(sys.argv[1])
package = importlib.util.module_from_spec(spec)
sys.modules[spec.name] = package
spec.loader.exec_module(package)

import numpy as np
from jointplay import load_preset
from jointplay._kernels.capabilities import ENGINES
from jointplay._kernels.integrators import INTEGRATORS
from jointplay._kernels.lanes import build, cpu
from jointplay.dynamics.setup import ContactModel
from jointplay.dynamics.simulate import SolverOptions, Start, simulate

mechanism = load_preset("paper-fourbar")
joints = ContactModel(film_damping=0).joints(mechanism, ["A", "B"])
runs = {
    name: simulate(mechanism, joints, revolutions=0.05, start=Start("steady"),
                   solver=SolverOptions(integrator=name))
    for name in ("dopri5", "dopri5_copy")
}
a, b = runs["dopri5"], runs["dopri5_copy"]
import numba
from jointplay import integrate  # the generic loop runs every integrator's steps too


@numba.njit
def oscillator(t, y, args):
    return np.array([y[1], -args[0][0] * y[0]])


generic = {
    name: integrate(oscillator, (0.0, 2.0), [1.0, 0.0], args=(np.array([4.0]),), method=name)
    for name in ("dopri5", "dopri5_copy")
}
print(json.dumps({
    "integrators": list(INTEGRATORS),
    "lanes": list(build.LANES),
    "traced": sorted(cpu.traced),
    "single": list(ENGINES["single"].integrators),
    "same_bits": bool(np.array_equal(a.t, b.t) and np.array_equal(a.y, b.y)),
    "steps": int(a.t.size),
    "stats": b.solver_stats["integrator"],
    "generic_same_bits": bool(
        np.array_equal(generic["dopri5"].y, generic["dopri5_copy"].y)
        and generic["dopri5"].n_steps == generic["dopri5_copy"].n_steps > 5
    ),
}))
"""


def test_every_table_is_read_from_the_lane_modules() -> None:
    """Nothing lists the integrators by hand: each record, lane and work allocator is its
    module's, and each module with a record is one integrator."""
    records = [module.LANE for module in SOURCES if hasattr(module, "LANE")]
    assert sorted(r["integrator"]["name"] for r in records) == sorted(integrators.INTEGRATORS)
    assert {r["lane"]: r for r in records} == build.LANES
    for record in records:
        assert record["work"] in build.FUNCTIONS  # allocated by a function of the source
    assert next(iter(integrators.INTEGRATORS)) == integrators.DEFAULT


@pytest.mark.parametrize("engine", ["lanes-explicit", "lanes-implicit"])
def test_the_gpu_kernel_makes_each_methods_work_from_its_record(
    engine: str, paper_fourbar: Mechanism
) -> None:
    """The cuda kernel of a batch method has only its integrator's record to allocate the
    method's work (``cuda_kernel._kernel``): the shapes at the GPU's limits, the dtypes, and
    the module's ``arrays``. Those give a ``ws`` of the same members as the CPU's allocator,
    each member of the same kind and at least as large as the paper four-bar's."""
    record = build.LANES[build.lane_for(engine)]
    shapes = build.source_function(record["shapes"])(MAX_STATE, MAX_COORDS, MAX_COORDS)
    assert len(shapes) == len(record["dtypes"]) <= MAX_WORK_ARRAYS
    arrays = [np.empty(shape, dtype) for shape, dtype in zip(shapes, record["dtypes"], strict=True)]
    on_gpu = build.source_function(record["arrays"])(*arrays)  # plain Python
    system = build_system(paper_fourbar, ContactModel().joints(paper_fourbar, ["A", "B"]))
    on_cpu = cpu.compiled[record["work"]](build.lane_layout(eom.pack(system.model)[1]))
    on_gpu, on_cpu = (w if isinstance(w, tuple) else (w,) for w in (on_gpu, on_cpu))
    assert len(on_gpu) == len(on_cpu)
    for gpu_member, cpu_member in zip(on_gpu, on_cpu, strict=True):
        assert (gpu_member.ndim, gpu_member.dtype) == (cpu_member.ndim, cpu_member.dtype)
        assert all(g >= c for g, c in zip(gpu_member.shape, cpu_member.shape, strict=True))
    engines = ("lanes-explicit", "batch-implicit", "lanes-implicit")
    assert [build.lane_for(e) for e in engines] == ["explicit_lane", *["implicit_lane"] * 2]


def test_a_batch_engine_runs_one_integrators_lane(monkeypatch: pytest.MonkeyPatch) -> None:
    """Two records claiming one batch engine, or none, is an error that names the lanes."""
    dopri5 = build.LANES["explicit_lane"]
    monkeypatch.setitem(build.LANES, "copy_lane", dopri5)
    with pytest.raises(ValueError, match=r"lanes-explicit .*\['explicit_lane', 'copy_lane'\]"):
        build.lane_for("lanes-explicit")
    with pytest.raises(ValueError, match=r"no-such-engine .*\[\]"):
        build.lane_for("no-such-engine")


@pytest.mark.slow
def test_a_new_integrator_is_one_file(tmp_path: Path) -> None:
    (tmp_path / "source_zz_copy.py").write_text(textwrap.dedent(NEW_MODULE))
    run = subprocess.run(
        [sys.executable, "-c", SCRIPT, str(tmp_path)],
        capture_output=True, text=True, timeout=900, check=False,
    )  # fmt: skip
    assert run.returncode == 0, run.stderr[-3000:]
    seen = json.loads(run.stdout.strip().splitlines()[-1])
    assert seen["integrators"] == ["radau", "rodas4", "dopri5", "dopri5_copy"]
    assert seen["lanes"] == ["explicit_lane", "implicit_lane", "rodas_lane", "copy_lane"]
    assert seen["traced"] == ["dopri5", "dopri5_copy", "radau", "rodas4"]
    assert "dopri5_copy" in seen["single"]
    assert seen["stats"] == "dopri5_copy"
    assert seen["steps"] > 20 and seen["same_bits"]
    assert seen["generic_same_bits"]  # jointplay.integrate has it too
