"""What each engine integrates, as data (:data:`ENGINES`), and the one reader of it
(:func:`refusal`): every place that refuses a setting on an engine asks it, so a message
says the same thing everywhere and a new capability is one row changed.

The engines:

- ``"single"``: the single engine (:func:`jointplay.dynamics.simulate.simulate`, Radau IIA,
  RODAS4 or DOPRI5), on the CPU backends; the only one that keeps each sample's trajectory;
- ``"lanes-explicit"``: the explicit lanes of the single source (DOPRI5,
  :func:`jointplay._kernels.lanes.source.lane` with DOPRI5's steps), on the CPU and ``cuda`` backends;
- ``"batch-implicit"``: the CPU backends' implicit lanes (:func:`jointplay._kernels.batch.run_batch`:
  the lanes' loop with Radau IIA's steps, the same source as ``"lanes-implicit"``, compiled
  for the CPU with the single engine's hooks, which add the sustained-contact mode);
- ``"lanes-implicit"``: the implicit lanes of the single source (Radau IIA,
  :mod:`jointplay._kernels.lanes.source_radau`), the ``cuda`` backend's implicit method;
- ``"jax"``: the ``gpu`` backend's lanes (:mod:`jointplay._kernels.jax_batch`, DOPRI5 and
  Radau IIA in JAX).

A need is a feature of :data:`FEATURES` (``"film_damping"``, ``"film_model"``, ``"sustained_contact"``,
``"ideal_joints"``, ``"trajectories"``, ``"running_responses"``), ``"law:NAME"`` (a normal-force law family of
:data:`LAW_FORMS`) or ``"friction:NAME"`` (:data:`FRICTION_FORMS`). Plain Python: nothing is
imported, nothing compiled.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass

from jointplay._kernels.integrators import integrators_of

#: The features a run may need, and how a message names them.
FEATURES = {
    "sustained_contact": "the sustained-contact mode",
    "film_damping": "film damping",
    "film_model": "a Reynolds film",
    "ideal_joints": "ideal joints",
    "trajectories": "each sample's trajectory",
    "running_responses": "the running responses (speed error, wear rate)",
}
#: The normal-force law families of :mod:`jointplay._kernels.contact`.
LAW_FORMS = frozenset({"impact", "hertz", "kelvin-voigt", "hunt-crossley family"})
#: The friction laws of :mod:`jointplay._kernels.contact`.
FRICTION_FORMS = frozenset({"none", "ambrosio", "adams"})
#: The CPU backends (the words of messages).
CPU_BACKENDS = "the CPU backends (local, processes, dask)"


@dataclass(frozen=True)
class Engine:
    """What one engine integrates.

    Attributes:
        words: how a message names it (its subject: "the explicit lanes").
        where: where it runs and how it is chosen, for the advice of a refusal.
        film_damping: the pins' lubricant film (a stiff damping force).
        film_model: a Reynolds film (the short-bearing π-film or full film, in place of the
            linear damper: :mod:`jointplay._kernels.lanes.source`'s ``reynolds_force``), with
            its film-to-contact transition (``film_share``, ``contact_clearance``: the same
            source, so an engine without the film refuses both in the one line).
        sustained_contact: the sustained-contact mode (a capture speed).
        ideal_joints: joints without clearance (the constraints' projection).
        trajectories: it keeps each sample's trajectory (not only peaks and statistics).
        running_responses: it computes the running responses (the output speed's error
            against the ideal linkage, the Archard wear rates: the lane source's
            ``running_*``, :mod:`jointplay.dynamics.batch_running`).
        integrators: the integrators it runs (:attr:`Integrator.engines
            <jointplay._kernels.integrators.Integrator.engines>` read back).
        laws: the normal-force law families it integrates.
        frictions: the friction laws it integrates.
    """

    words: str
    where: str
    film_damping: bool
    film_model: bool
    sustained_contact: bool
    ideal_joints: bool
    trajectories: bool
    integrators: tuple[str, ...]
    running_responses: bool = True
    laws: frozenset[str] = LAW_FORMS
    frictions: frozenset[str] = FRICTION_FORMS

    def has(self, need: str) -> bool:
        """Whether it integrates ``need`` (a feature, ``"law:NAME"`` or ``"friction:NAME"``)."""
        kind, _, name = need.partition(":")
        if kind == "law" and name:
            return name in self.laws
        if kind == "friction" and name:
            return name in self.frictions
        if need not in FEATURES:
            raise ValueError(
                f"unknown need {need!r}; needs are {sorted(FEATURES)}, law:, friction:"
            )
        return bool(getattr(self, need))


#: What each engine integrates (the module docstring names them).
ENGINES = {
    "single": Engine(
        "the single engine", f"the single engine on {CPU_BACKENDS}",
        film_damping=True, film_model=True, sustained_contact=True,
        ideal_joints=True, trajectories=True,
        integrators=integrators_of("single"),
    ),
    "lanes-explicit": Engine(
        "the explicit lanes", "the explicit method",
        film_damping=False, film_model=False, sustained_contact=False,
        ideal_joints=True, trajectories=False,
        integrators=integrators_of("lanes-explicit"),
    ),
    "batch-implicit": Engine(
        "the CPU backends' implicit lanes", f"the implicit method on {CPU_BACKENDS}",
        film_damping=True, film_model=True, sustained_contact=True,
        ideal_joints=True, trajectories=False,
        integrators=integrators_of("batch-implicit"),
    ),
    "lanes-implicit": Engine(
        "the single source's implicit lanes (the cuda backend's)",
        "the implicit method on the cuda backend",
        film_damping=True, film_model=True, sustained_contact=False,
        ideal_joints=True, trajectories=False,
        integrators=integrators_of("lanes-implicit"),
    ),
    "jax": Engine(
        "the gpu backend (JAX)", "the gpu backend",
        film_damping=False, film_model=False, sustained_contact=False,
        ideal_joints=True, trajectories=False, running_responses=False,
        integrators=integrators_of("jax"),
    ),
}  # fmt: skip


#: The engines of each backend, by method: ``"explicit"``, ``"implicit"`` (``"auto"`` reads as
#: it: what needs the implicit method gets it) and ``"single"`` (the single engine, one
#: simulation per sample; ``None``: the backend runs the batch engine only).
BACKENDS: dict[str, dict[str, str | None]] = {
    **{
        kind: {"explicit": "lanes-explicit", "implicit": "batch-implicit", "single": "single"}
        for kind in ("local", "serial", "processes", "dask")
    },
    "cuda": {"explicit": "lanes-explicit", "implicit": "lanes-implicit", "single": None},
    "gpu": {"explicit": "jax", "implicit": "jax", "single": None},
}


def engine_of(backend: str, method: str) -> str:
    """The engine that ``backend`` (a backend kind) runs for ``method`` (``"explicit"``,
    ``"implicit"``, ``"auto"`` or ``"single"``); for ``"single"`` on a backend without the
    single engine, its implicit lanes (what it would run instead)."""
    engines = BACKENDS[backend]
    chosen = engines["implicit" if method == "auto" else method]
    return chosen if chosen is not None else str(engines["implicit"])


def _name(need: str) -> str:
    """``need`` in a message's words."""
    kind, _, name = need.partition(":")
    if kind == "law" and name:
        return f"the normal-force law {name}"
    if kind == "friction" and name:
        return f"the friction law {name}"
    return FEATURES[need]


def _bare(words: str) -> str:
    """A feature's words without article and " mode" ("the sustained-contact mode" →
    "sustained contact"), for "no ..." in a refusal."""
    return words.removeprefix("the ").removeprefix("a ").removesuffix(" mode").replace("-", " ")


def refusal(engine: str, needs: Iterable[str], named: Callable[[str], str] = _name) -> str | None:
    """Why ``engine`` (a key of :data:`ENGINES`; a backend's: :func:`engine_of`) cannot run
    what ``needs``, or ``None``: the one reader of :data:`ENGINES`.

    The message names the engine with what it lacks (the contact features, the law families,
    the trajectories: those of ``needs``' kinds), the needs it cannot run (``named``: how to
    write one; e.g. ``"{film_damping}"`` for a :class:`~jointplay.errors.SettingError` that
    the command line names as its option) and where they run: the batch engines that run
    them all, else the single engine where it does. E.g. "the explicit lanes integrate
    compliant contacts only (no sustained contact, no film damping): {film_damping} needs
    the implicit method on the CPU backends (local, processes, dask) or the implicit method
    on the cuda backend: choose one, or turn it off".
    """
    own = ENGINES[engine]
    missing = [need for need in dict.fromkeys(needs) if not own.has(need)]
    if not missing:
        return None
    s = "" if "lanes" in own.words else "s"  # "the explicit lanes integrate", "the ... integrates"
    kinds = {need.partition(":")[0] if ":" in need else need for need in missing}
    clauses = []
    if kinds & {"sustained_contact", "film_damping", "film_model", "ideal_joints"}:
        lacks = [
            "no " + _bare(FEATURES[f])
            for f in ("sustained_contact", "film_damping", "film_model", "ideal_joints")
            if not own.has(f) and (f != "film_model" or f in kinds)
        ]
        clauses.append(f"integrate{s} compliant contacts only ({', '.join(lacks)})")
    if "law" in kinds:
        clauses.append(f"integrate{s} the normal-force laws {', '.join(sorted(own.laws))} only")
    if "friction" in kinds:
        clauses.append(f"integrate{s} the friction laws {', '.join(sorted(own.frictions))} only")
    if "trajectories" in kinds:
        clauses.append(f"keep{s} peaks only, no trajectory")
    if "running_responses" in kinds:
        clauses.append(f"compute{s} no running responses")
    able = [k for k, e in ENGINES.items() if k != engine and all(e.has(n) for n in missing)]
    where = [ENGINES[k].where for k in able if k != "single"] or [
        ENGINES[k].where for k in able if k == "single"
    ]
    them = "it" if len(missing) == 1 else "them"
    advice = (
        f"{'needs' if len(missing) == 1 else 'need'} {' or '.join(where)}: "
        f"{'choose one' if len(where) > 1 else 'use it'}, or turn {them} off"
        if where
        else f"{'runs' if len(missing) == 1 else 'run'} on no engine of jointplay: turn {them} off"
    )
    return (
        f"{own.words} {' and '.join(clauses)}: {' and '.join(named(n) for n in missing)} {advice}"
    )
