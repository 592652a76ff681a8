"""The single-source lanes (:mod:`jointplay._kernels.lanes`) on the CPU.

* The source's copies of the kernels' constants equal their homes (law and friction ids,
  settings columns, statuses, the DOPRI5 tableau and dense output, the peak rule's margin and
  the onset retries), and its layout finds every field that :func:`eom.pack` wrote.
* The CPU's explicit lanes are the source's compilation. (Before the old explicit lane of
  :mod:`jointplay._kernels.batch` was deleted, the source's gave its bits, field by field:
  every law id and friction law all-clear, a late window, a failing lane, ideal joints left
  on the four-bar and the slider-crank; see the history of this file.)
"""

from __future__ import annotations

import numpy as np

from jointplay._kernels import batch as kb
from jointplay._kernels import driver, eom, ids
from jointplay._kernels.lanes import build, cpu, source, source_radau
from jointplay.contact.friction import AdamsFriction, AmbrosioFriction, FrictionLaw
from jointplay.contact.laws import ContactLaw, get_law
from jointplay.dynamics.clearance import ClearanceJoint
from jointplay.dynamics.system import System, build_system
from jointplay.model.mechanism import Mechanism

JOINTS = ("O2", "A", "B", "O4")
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


def _law(name: str) -> ContactLaw:
    return get_law(name, **LAW_PARAMETERS.get(name, {"stiffness": 1e10, "restitution": 0.8}))


def _system(mechanism: Mechanism, laws: list[str], shift: int) -> System:
    joints = [
        ClearanceJoint(j, 2e-5, 5e-3, _law(name), FRICTIONS[(k + shift) % len(FRICTIONS)])
        for k, (j, name) in enumerate(zip(JOINTS, laws, strict=True))
    ]
    return build_system(mechanism, joints)


def test_the_sources_method_constants_are_the_kernels() -> None:
    assert source.MAX_CHECK_REJECTIONS == driver.MAX_CHECK_REJECTIONS
    assert source.REFINE_MARGIN == kb.REFINE_MARGIN
    np.testing.assert_array_equal(np.arange(1, source.N_REFINE + 1) / 8.0, kb.REFINE_POINTS)
    np.testing.assert_array_equal(np.reshape(source.DENSE, (7, 4)), kb.DENSE)


def test_the_layout_finds_every_field_that_pack_wrote(paper_fourbar: Mechanism) -> None:
    """Bit for bit, each field where ``lay`` says; the packed fields are ``ids``' (one home:
    :class:`eom.EomModel`'s, each a float or an integer field)."""
    assert eom.EomModel._fields == ids.MODEL_FIELDS
    assert sorted(ids.FLOAT_FIELDS + ids.INT_FIELDS) == sorted(ids.MODEL_FIELDS)
    system = _system(paper_fourbar, ["impact", "hertz", "flores", "lee-wang"], 1)
    rpar, ipar = eom.pack(system.model)
    model = system.model
    lay = build.lane_layout(ipar)
    floats = {"mass": source.LY_MASS, "gravity": source.LY_GRAVITY, "joint_f": source.LY_JOINT_F,
              "driver": source.LY_DRIVER, "geom": source.LY_GEOM, "law_p": source.LY_LAW_P,
              "fric_p": source.LY_FRIC_P, "settings": source.LY_SETTINGS}  # fmt: skip
    for name, slot in floats.items():
        field = getattr(model, name)
        np.testing.assert_array_equal(rpar[lay[slot] : lay[slot] + len(field)], field, name)
    ints = {"joint_int": source.LY_JOINT_INT, "active": source.LY_ACTIVE,
            "clear_joint": source.LY_CLEAR, "law_id": source.LY_LAW_ID,
            "fric_id": source.LY_FRIC_ID}  # fmt: skip
    for name, slot in ints.items():
        field = getattr(model, name)
        np.testing.assert_array_equal(ipar[lay[slot] : lay[slot] + len(field)], field, name)
    nb, nj, nc, size = kb.layout(ipar)
    assert (lay[source.LY_N], lay[source.LY_NJ], lay[source.LY_NC]) == (3 * nb, nj, nc)
    assert lay[source.LY_SIZE] == size and lay[source.LY_NQ] == 2 * nb + nj + 1
    assert lay[source.LY_NIDEAL] == 0 and build.all_clear(ipar)


def test_a_mechanism_with_ideal_joints_is_not_all_clear(paper_fourbar: Mechanism) -> None:
    system = build_system(paper_fourbar, [ClearanceJoint("A", 2e-5, 5e-3, _law("impact"))])
    _, ipar = eom.pack(system.model)
    assert build.lane_layout(ipar)[source.LY_NIDEAL] == 3 and not build.all_clear(ipar)


def test_the_cpu_lane_is_the_sources_compilation() -> None:
    # both lanes are the one loop of the source, each with its method's steps bound to it
    assert cpu.explicit_lane.py_func.__code__ is source.lane.__code__
    assert cpu.implicit_lane.py_func.__code__ is source.lane.__code__
    explicit, implicit = (
        cpu.explicit_lane.py_func.__globals__,
        cpu.implicit_lane.py_func.__globals__,
    )
    assert explicit["step_attempt"].py_func.__code__ is source.dopri_attempt.__code__
    assert implicit["step_attempt"].py_func.__code__ is source_radau.radau_attempt.__code__
    assert (explicit["LAND_SETTLE"], implicit["LAND_SETTLE"]) == (True, False)


def test_a_borrowed_array_stays_valid_while_its_owner_is_used_after() -> None:
    # the CPU lanes get their arrays borrowed (no reference counts): Numba frees a variable
    # after its last use, so the owner must be used after the borrowing call; a large array
    # is returned to the system when freed, so reading it after that would crash
    import numba

    @numba.njit
    def read_after_allocating() -> float:
        owner = np.ones(200_000)
        view = cpu.borrowed(owner)
        other = np.zeros(200_000)
        total = view[0] + view[-1] + other[0]
        cpu._alive(owner)
        return total

    assert read_after_allocating() == 2.0


def test_the_lane_driver_keeps_every_work_array_alive_until_the_lane_returns() -> None:
    import ast
    import inspect

    body = ast.parse(inspect.getsource(cpu._one).lstrip()).body[0].body
    owners = set()
    for statement in body:
        if isinstance(statement, ast.Assign):
            for target in statement.targets:
                names = target.elts if isinstance(target, ast.Tuple) else [target]
                owners |= {name.id for name in names if isinstance(name, ast.Name)}
    calls = [n.func.id for s in body for n in ast.walk(s) if isinstance(n, ast.Call)
             and isinstance(n.func, ast.Name)]  # fmt: skip
    assert calls.index("_alive") > calls.index("method_lane")
    alive = next(n for s in body for n in ast.walk(s)
                 if isinstance(n, ast.Call) and getattr(n.func, "id", "") == "_alive")  # fmt: skip
    kept = {arg.id for arg in alive.args}
    assert owners - {"b", "code", "t"} <= kept, owners - kept
