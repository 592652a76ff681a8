"""Compile the lane source (:mod:`jointplay._kernels.lanes.source`) for one target.

The single-source pattern: the source modules (:data:`jointplay._kernels.lanes.SOURCES`:
:mod:`~jointplay._kernels.lanes.source`, the equations, the loop and DOPRI5's steps;
:mod:`~jointplay._kernels.lanes.source_radau`, Radau IIA's;
:mod:`~jointplay._kernels.lanes.source_rodas`, RODAS4's; each integrator's lane declared by
its module's ``LANE`` record) hold plain Python functions written in the subset both Numba
targets compile (scalars and caller-provided arrays, no allocation but the CPU's work
allocators).
:func:`build` makes a fresh namespace for a target — the source's constants and ``math`` —
and compiles every function of :data:`FUNCTIONS` into it with the target's decorator
(``numba.njit(cache=True, error_model="numpy")`` for the CPU,
``numba.cuda.jit(device=True)`` for NVIDIA GPUs), each function's body looking the others up
by name in that namespace. Compilation is lazy (on the first call, or when a kernel that
calls it is compiled), so the order does not matter.

Standard library and NumPy only at import: the targets' decorators are the caller's.
"""

from __future__ import annotations

import math
import types
from collections.abc import Callable, Mapping
from typing import Any

import numpy as np
import numpy.typing as npt

from jointplay._kernels import ids
from jointplay._kernels.capabilities import refusal
from jointplay._kernels.lanes import SOURCES, source

__all__ = [
    "FUNCTIONS", "HOME", "LANES", "all_clear", "build", "closed", "lane_for", "lane_layout",
    "lanes_refusal", "model_width", "output_widths", "rebound", "running_layout",
    "source_function",
]  # fmt: skip

#: A lane method's steps, the names the loop calls (``step_<name>``: ``source.lane``'s
#: docstring); a method defines them as ``<prefix>_<name>``.
STEPS = ("start", "begin", "land", "attempt", "retry", "refresh", "accept", "dense")
#: The lanes by name, each the loop compiled with an integrator's steps and constants: its
#: source module's ``LANE`` record (the prefix of its steps, ``steps``; its work allocator,
#: ``work``; the loop's constants, in capitals).
LANES = {module.LANE["lane"]: module.LANE for module in SOURCES if hasattr(module, "LANE")}
#: The loop's functions (``source``'s), compiled once per lane with its method's names.
LOOP = ("lane",)


def source_function(name: str) -> Callable[..., Any]:
    """The lane source's function ``name`` as its module defines it (not compiled): one of
    :data:`FUNCTIONS`, or the loop's."""
    function: Callable[..., Any] = getattr(HOME.get(name, source), name)
    return function


def lane_for(engine: str) -> str:
    """The lane that ``engine`` runs (a batch engine, ``"lanes-explicit"``, … of
    :data:`jointplay._kernels.capabilities.ENGINES`): the one whose integrator's record names
    the engine."""
    lanes = [lane for lane, record in LANES.items() if engine in record["integrator"]["engines"]]
    if len(lanes) != 1:
        raise ValueError(f"{engine} runs one integrator's lane, the records give it {lanes}")
    return lanes[0]


def _defined(module: types.ModuleType) -> tuple[str, ...]:
    """The functions ``module`` defines (not those it imports or aliases), in its order."""
    return tuple(
        name
        for name, value in vars(module).items()
        if isinstance(value, types.FunctionType)
        and value.__module__ == module.__name__
        and value.__name__ == name
        and name not in LOOP
    )


#: Each function of the source by name: the module that defines it (:data:`SOURCES`).
HOME = {name: module for module in SOURCES for name in _defined(module)}
#: The source's functions, compiled for every target: every function the source modules
#: define, the loop aside (compiled once per lane, with its method's steps).
FUNCTIONS = tuple(HOME)


def build(
    decorate: Callable[[Callable[..., Any]], Any],
    hooks: Mapping[str, Callable[..., Any]] | None = None,
    extras: Mapping[str, Any] | None = None,
    only: tuple[str, ...] = FUNCTIONS,
    own: Mapping[str, Callable[..., Any]] | None = None,
    decorate_own: Callable[[Callable[..., Any]], Any] | None = None,
    tag: str = "",
    decorate_steps: Callable[[Callable[..., Any]], Any] | None = None,
) -> dict[str, Any]:
    """Every function of :data:`FUNCTIONS`, compiled with ``decorate``, in a namespace of its
    own (returned: name → compiled function, with the source's constants beside them).

    Args:
        decorate: the target's decorator.
        hooks: the target's own version of a hook the lane calls, by the name the lane calls
            it (``project``: default :func:`source.project`), in place of the source's; compiled like the
            source's functions, in the same namespace.
        extras: more names for that namespace (what a hook calls: compiled functions).
        only: the functions to compile (a subset closed under the calls among them with
            ``hooks`` and ``own``); all by default.
        own: the target's own functions, written like the source and compiled into the same
            namespace under their names (the single engine's sustained-contact mode,
            :mod:`jointplay._kernels.sustained`), with ``decorate_own`` (default ``decorate``).
        tag: appended to each compiled copy's qualified name, so that a target whose hooks
            differ from another's never shares Numba's on-disk cache entries with it (the
            cache keys a function by its name and code, not by the functions it calls).
        decorate_steps: the decorator of each lane's own copies of its method's steps and
            of the loop's helpers (default ``decorate``): the CPU inlines them into the loop.
    """
    namespace: dict[str, Any] = {
        name: value
        for module in (ids, *SOURCES)
        for name, value in vars(module).items()
        if name.isupper()
    }
    namespace["math"] = math
    namespace.update(extras or {})
    chosen = dict(hooks or {})
    if set(chosen) - set(FUNCTIONS) or set(only) - set(FUNCTIONS):
        raise ValueError(
            "no function of the lane source is called "
            f"{sorted((set(chosen) | set(only)) - set(FUNCTIONS))}"
        )
    functions = [
        (
            name,
            chosen.get(name, source_function(name)),
        )
        for name in FUNCTIONS
        if name in only
    ]
    suffix = f"_{tag}" if tag else ""
    mine = [(name, original, decorate_own or decorate) for name, original in (own or {}).items()]
    for name, original, decorator in [*((n, f, decorate) for n, f in functions), *mine]:
        namespace[name] = decorator(rebound(original, namespace, original.__qualname__ + suffix))
    for name, method in LANES.items():  # the loop, once per lane, with its method's steps
        steps = tuple(f"{method['steps']}_{step}" for step in STEPS)
        if all(step in namespace for step in steps):
            bound = {**namespace, **{k: v for k, v in method.items() if k.isupper()}}
            for function, alias in [*zip(steps, STEPS, strict=True), *((f, "") for f in LOOP)]:
                original = source_function(function)
                use = decorate if function == "lane" else (decorate_steps or decorate)
                copy = use(rebound(original, bound, f"{function}_{name}{suffix}"))
                bound[f"step_{alias}" if alias else function] = copy
            namespace[name] = bound["lane"]
    return namespace


def rebound(original: Callable[..., Any], namespace: dict[str, Any], qualname: str) -> Any:
    """``original`` with ``namespace`` as its globals, under ``qualname`` (Numba's cache key):
    how a target binds the names a function calls."""
    copy = types.FunctionType(
        original.__code__, namespace, original.__name__, original.__defaults__,
        original.__closure__,
    )  # fmt: skip
    copy.__module__ = original.__module__
    copy.__qualname__ = qualname
    copy.__doc__ = original.__doc__
    return copy


def closed(
    names: tuple[str, ...], own: Mapping[str, Callable[..., Any]] | None = None
) -> tuple[str, ...]:
    """``names`` and every function of :data:`FUNCTIONS` they call, directly or not (read from
    the functions' code; ``own``: the target's own functions, followed too): the ``only`` of
    a target that compiles part of the source."""
    mine = dict(own or {})
    for name, method in LANES.items():  # a lane: its method's steps and what the loop calls
        if name in names:
            names = (*names, *LOOP, *(f"{method['steps']}_{step}" for step in STEPS))
    wanted = set(names)
    todo = list(names)
    while todo:
        name = todo.pop()
        if name in LANES:
            continue
        function = mine.get(name) or source_function(name)
        for called in function.__code__.co_names:
            if (called in FUNCTIONS or called in mine) and called not in wanted:
                wanted.add(called)
                todo.append(called)
    return tuple(name for name in FUNCTIONS if name in wanted)


def lane_layout(ipar: npt.NDArray[np.int64]) -> npt.NDArray[np.int64]:
    """The ``lay`` array of the source (``LY_*``): where each field of the packed model starts
    in ``rpar`` (floats) or ``ipar`` (integers), and the model's sizes."""
    lengths = {name: int(ipar[i]) for i, name in enumerate(ids.MODEL_FIELDS)}
    lay = np.zeros(source.N_LAY, dtype=np.int64)
    offset = 0
    floats = range(source.LY_MASS, source.LY_SETTINGS + 1)
    for name, slot in zip(ids.FLOAT_FIELDS, floats, strict=True):
        lay[slot] = offset
        offset += lengths[name]
    offset = len(ids.MODEL_FIELDS)
    ints = range(source.LY_JOINT_INT, source.LY_FRIC_ID + 1)
    for name, slot in zip(ids.INT_FIELDS, ints, strict=True):
        lay[slot] = offset
        offset += lengths[name]
    n = lengths["mass"]
    nj = lengths["active"]
    nc = lengths["clear_joint"]
    active = ipar[lay[source.LY_ACTIVE] : lay[source.LY_ACTIVE] + nj]
    lay[source.LY_N] = n
    lay[source.LY_NJ] = nj
    lay[source.LY_NC] = nc
    lay[source.LY_PLAW] = lengths["law_p"] // max(nc, 1)
    lay[source.LY_PFRIC] = lengths["fric_p"] // max(nc, 1)
    lay[source.LY_NIDEAL] = int(np.sum(active))
    lay[source.LY_SIZE] = 2 * n + 2 + nc
    lay[source.LY_SECOND] = lay[source.LY_KEPT] = n
    lay[source.LY_NQ] = 2 * (n // 3) + nj + 1
    return lay


def model_width(lay: npt.NDArray[np.int64]) -> int:
    """The packed model's floats in one ``rpar`` row (what follows is the running tail)."""
    return int(lay[source.LY_SETTINGS]) + ids.N_SETTINGS


def running_layout(
    ipar: npt.NDArray[np.int64], rpar: npt.NDArray[np.float64]
) -> npt.NDArray[np.int64]:
    """The ``lay`` of lanes whose ``rpar`` rows are ``rpar``'s: :func:`lane_layout`, with one
    more quantity (the running responses asked for: ``source.running_on``) when the rows
    carry a running tail after the packed model (``source.RUN_*``)."""
    lay = lane_layout(ipar)
    if np.atleast_2d(rpar).shape[1] > model_width(lay):
        lay[source.LY_NQ] += 1
    return lay


def output_widths(lay: npt.NDArray[np.int64], rpar: npt.NDArray[np.float64]) -> tuple[int, int]:
    """``(P, M)``: the peaks and the statistics a lane of ``lay`` fills (the running slots
    included when asked: ``source.running_stats``)."""
    nb = int(lay[source.LY_N]) // 3
    nj = int(lay[source.LY_NJ])
    nc = int(lay[source.LY_NC])
    width = 2 * nb + 4 * nc
    n_q = int(lay[source.LY_NQ])
    if n_q > 2 * nb + nj + 1:
        rows = np.atleast_2d(rpar)
        bins = int(rows[0, model_width(lay) + source.RUN_BINS]) if len(rows) else 0
        width += 5 * nc + 1 + 2 * bins * nc
    return n_q, width


def all_clear(ipar: npt.NDArray[np.int64]) -> bool:
    """Whether every joint of the model packed in ``ipar`` is a clearance joint (the driver
    the only constraint; the paper's mechanisms): the GPU lanes' mechanisms so far."""
    return int(lane_layout(ipar)[source.LY_NIDEAL]) == 0


def lanes_refusal(
    ipar: npt.NDArray[np.int64], rpar: npt.NDArray[np.float64], method: str
) -> str | None:
    """Why the GPU lanes of ``method`` (``"explicit"`` or ``"implicit"``) cannot run these
    lanes, or ``None`` (:func:`jointplay._kernels.capabilities.refusal` of what they need):
    they cover every mechanism outside the contact options of :mod:`eom` they do not
    implement: the sustained-contact mode (neither method: its hooks are the CPU's), film damping (the
    implicit method only: at a c_e of the order of 1e5 N·s/m the film's time constant m/c_e
    is microseconds, and an explicit method's steps with it)."""
    lay = lane_layout(ipar)
    nc = int(lay[source.LY_NC])
    start = int(lay[source.LY_GEOM])
    geom = np.atleast_2d(rpar)[:, start : start + ids.N_GEOM * nc]
    needs = []
    if np.any(geom[:, ids.G_CAPTURE :: ids.N_GEOM] > 0.0):
        needs.append("sustained_contact")
    films = geom[:, ids.G_FILM :: ids.N_GEOM] > 0.0
    if np.any(films):
        needs.append("film_damping")
    if np.any(films & (geom[:, ids.G_FILM_MODEL :: ids.N_GEOM] != ids.FILM_LINEAR)):
        needs.append("film_model")
    return refusal("lanes-explicit" if method != "implicit" else "lanes-implicit", needs)
