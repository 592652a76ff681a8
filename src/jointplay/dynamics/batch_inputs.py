"""The batch engine's inputs: the samples, and the kernels' inputs built from them.

:class:`BatchSamples` holds the per-sample inputs (lengths, clearances, contact-law values,
crank speed); :func:`build_batch` turns them into a :class:`BatchProblem`, the packed model
``(ipar, rpar)`` of :mod:`jointplay._kernels.eom` (``ipar`` shared, ``rpar`` per sample), the
initial state, the analysed window and the largest step. For the four-bar and slider-crank
templates this is vectorised over the samples and equals, to round-off, what
:func:`~jointplay.dynamics.system.build_system` and
:func:`~jointplay.dynamics.simulate.initial_state` give for each sample (tested); any other
mechanism is built one sample at a time with them. :mod:`jointplay.dynamics.batch` runs them.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from types import SimpleNamespace
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from jointplay._kernels import batch as kb
from jointplay._kernels import constraints as ck
from jointplay._kernels import eom, ids
from jointplay.contact.laws import ContactLaw
from jointplay.dynamics.clearance import (
    MIN_CLEARANCE,
    ClearanceJoint,
    film_model_id,
    stiffness_field,
)
from jointplay.dynamics.cycles import analysed_revolutions, settle_revolutions
from jointplay.dynamics.simulate import SolverOptions, Start, initial_state, start_constraints
from jointplay.dynamics.system import PARAMS_WIDTH, System, build_system, onset_fraction
from jointplay.errors import ConfigError, JointplayError
from jointplay.kinematics import fourbar, slidercrank
from jointplay.kinematics.solver import revolute_tree
from jointplay.model.flat import DRV_OMEGA
from jointplay.model.mechanism import GROUND, Mechanism
from jointplay.model.templates import (
    FourBarGeometry,
    LinkBody,
    TemplateSpec,
    with_lengths,
)

__all__ = ["BatchProblem", "BatchSamples", "build_batch"]

FloatArray = NDArray[np.float64]


# --- the samples ---------------------------------------------------------------------------------
def _column(values: Any, name: str) -> FloatArray:
    array = np.array(values, dtype=np.float64)
    if array.ndim != 1:
        raise ConfigError(f"batch samples: {name} must be a 1-D array (one value per sample)")
    return array


@dataclass(frozen=True)
class BatchSamples:
    """Per-sample inputs of :func:`simulate_batch` (SI); anything absent stays nominal.

    Attributes:
        lengths: template length name (``crank``, ``coupler``, ``rocker``, ``ground``;
            ``crank``, ``rod``, ``offset``) → one length per sample, m.
        clearances: clearance joint name → radial clearance per sample, m.
        law: contact-law field name (e.g. ``stiffness``, ``c_max``, ``d_max``,
            ``restitution``) → value per sample (SI), for every clearance joint's law.
        angular_velocity: signed crank angular velocity per sample, rad/s (``None``: nominal).
        size: number of samples (needed only when no input varies: n nominal copies).
    """

    lengths: Mapping[str, FloatArray] = field(default_factory=dict)
    clearances: Mapping[str, FloatArray] = field(default_factory=dict)
    law: Mapping[str, FloatArray] = field(default_factory=dict)
    angular_velocity: FloatArray | None = None
    size: int | None = None

    def __post_init__(self) -> None:
        for group in ("lengths", "clearances", "law"):
            columns = {
                str(k): _column(v, f"{group}[{k!r}]") for k, v in getattr(self, group).items()
            }
            for array in columns.values():
                array.flags.writeable = False
            object.__setattr__(self, group, columns)
        if self.angular_velocity is not None:
            speed = _column(self.angular_velocity, "angular_velocity")
            speed.flags.writeable = False
            object.__setattr__(self, "angular_velocity", speed)
        sizes = {len(a) for a in self._columns().values()}
        if self.size is not None:
            if isinstance(self.size, bool) or not isinstance(self.size, int) or self.size < 0:
                raise ConfigError(f"batch samples: size must be a whole number, got {self.size!r}")
            sizes.add(self.size)
        if len(sizes) > 1:
            raise ConfigError(
                f"batch samples: every input needs one value per sample, got {sorted(sizes)}"
            )
        object.__setattr__(self, "size", sizes.pop() if sizes else 0)

    def _columns(self) -> dict[str, FloatArray]:
        out = {f"length_{k}": v for k, v in self.lengths.items()}
        out.update({f"clearance_{k}": v for k, v in self.clearances.items()})
        out.update({f"law_{k}": v for k, v in self.law.items()})
        if self.angular_velocity is not None:
            out["angular_velocity"] = self.angular_velocity
        return out

    def __len__(self) -> int:
        return int(self.size or 0)

    def take(self, index: NDArray[np.intp] | slice) -> BatchSamples:
        """The samples at ``index`` (a slice or integer array)."""
        return BatchSamples(
            lengths={k: v[index] for k, v in self.lengths.items()},
            clearances={k: v[index] for k, v in self.clearances.items()},
            law={k: v[index] for k, v in self.law.items()},
            angular_velocity=None
            if self.angular_velocity is None
            else self.angular_velocity[index],
            size=len(np.arange(len(self))[index]),
        )

    def to_frame(self) -> pd.DataFrame:
        """One row per sample: ``length_*``, ``clearance_*``, ``law_*``, ``angular_velocity``."""
        columns = self._columns()
        return pd.DataFrame(columns, index=pd.RangeIndex(len(self), name="sample"))


# --- the kernels' inputs ----------------------------------------------------------------------------
@dataclass(frozen=True)
class BatchProblem:
    """What the batch kernels take, for every sample (:mod:`jointplay._kernels.batch`).

    Attributes:
        ipar: the integer structure, shared.
        rpar: (n, R) model floats per sample.
        y0: (n, S) initial states.
        t_settle, t_end: (n,) analysed window, s.
        max_step: (n,) largest step, s.
        rtol, atol, max_steps: integration settings (atol per state component).
        ok: (n,) the sample could be built (the others hold nominal values and are not run).
        errors: n messages, ``""`` where ``ok``.
        vectorised: the template builder was used (else one sample at a time).
    """

    ipar: NDArray[np.int64]
    rpar: FloatArray
    y0: FloatArray
    t_settle: FloatArray
    t_end: FloatArray
    max_step: FloatArray
    rtol: float
    atol: FloatArray
    max_steps: int
    ok: NDArray[np.bool_]
    errors: tuple[str, ...]
    vectorised: bool

    def scaled_tolerances(self, scale: float) -> BatchProblem:
        """This problem with rtol and the velocities' atol times ``scale``."""
        nb = kb.layout(self.ipar)[0]
        atol = self.atol.copy()
        atol[3 * nb : 6 * nb] *= scale
        return dataclasses.replace(self, rtol=self.rtol * scale, atol=atol)

    def take(self, index: NDArray[np.intp]) -> BatchProblem:
        return dataclasses.replace(
            self,
            rpar=self.rpar[index],
            y0=self.y0[index],
            t_settle=self.t_settle[index],
            t_end=self.t_end[index],
            max_step=self.max_step[index],
            ok=self.ok[index],
            errors=tuple(self.errors[i] for i in index),
        )


def _check_settings(revolutions: float, settle: int, start: Any, solver: Any) -> None:
    if not isinstance(start, Start):
        raise ConfigError(f"start must be a Start, e.g. Start('steady'), got {start!r}")
    if not isinstance(solver, SolverOptions):
        raise ConfigError(f"solver must be a SolverOptions, got {type(solver).__name__}")
    analysed_revolutions(revolutions)
    settle_revolutions(settle)


def _settle_time(driver: FloatArray, turns: float) -> FloatArray:
    """Time at which the driven crank has turned ``turns`` revolutions (per sample), s — the
    single engine counts its revolutions by the crank's angle, which a speed ramp delays."""
    omega = np.abs(driver[:, DRV_OMEGA])
    ramp = driver[:, 3]
    angle = 2.0 * math.pi * turns
    out = angle / omega
    for i in np.flatnonzero(ramp > 0.0):
        covered = 0.5 * omega[i] * ramp[i]  # the angle turned during the ramp
        if angle >= covered:
            out[i] = ramp[i] + (angle - covered) / omega[i]
            continue
        low, high = 0.0, float(ramp[i])  # within the ramp: bisection on the STEP5 angle
        for _ in range(200):
            mid = 0.5 * (low + high)
            u = mid / ramp[i]
            if omega[i] * ramp[i] * u**4 * (2.5 - 3.0 * u + u * u) < angle:
                low = mid
            else:
                high = mid
        out[i] = 0.5 * (low + high)
    return np.asarray(out, dtype=float)


def build_batch(
    mechanism: Mechanism,
    clearances: Sequence[ClearanceJoint],
    samples: BatchSamples,
    *,
    revolutions: float = 1.0,
    settle: int = 0,
    start: Start | None = None,
    solver: SolverOptions | None = None,
    vectorised: bool | None = None,
) -> BatchProblem:
    """The kernels' inputs for every sample (see :class:`BatchProblem`).

    Args:
        vectorised: force (``True``) or refuse (``False``) the vectorised template builder;
            ``None``: vectorised whenever the mechanism is a template.

    Raises:
        ConfigError: a setting is out of range, or an input names nothing of the mechanism.
    """
    start = start or Start("steady")
    solver = solver or SolverOptions()
    _check_settings(revolutions, settle, start, solver)
    clearances = tuple(clearances)
    if not clearances:
        raise ConfigError("the batch engine needs at least one clearance joint")
    names = [c.joint for c in clearances]
    for joint in samples.clearances:
        if joint not in names:
            raise ConfigError(
                f"batch samples: clearance of {joint!r}, which is not a clearance joint; "
                f"clearance joints: {names}"
            )
    laws = {type(c.law) for c in clearances}
    for name in samples.law:
        for law in laws:
            if name not in {f.name for f in dataclasses.fields(law)}:
                raise ConfigError(
                    f"batch samples: {law.__name__} has no parameter {name!r}; its parameters "
                    f"are {[f.name for f in dataclasses.fields(law)]}"
                )
    template = isinstance(mechanism.template, TemplateSpec)
    if samples.lengths and not template:
        raise ConfigError(
            f"mechanism {mechanism.name!r} has no template: its lengths cannot vary per sample"
        )
    if template:
        assert isinstance(mechanism.template, TemplateSpec)
        known = mechanism.template.geometry.length_names
        for name in samples.lengths:
            if name not in known:
                raise ConfigError(
                    f"batch samples: unknown length {name!r}; the template's lengths are "
                    f"{list(known)}"
                )
    use_vector = template if vectorised is None else vectorised
    if use_vector and not template:
        raise ConfigError("the vectorised builder needs a four-bar or slider-crank template")
    system0 = build_system(
        mechanism,
        clearances,
        ramp_time=start.ramp_time,
        onset_tolerance=solver.onset_tolerance,
        driven=start.driven,
    )
    rpar0, ipar = eom.pack(system0.model)
    if use_vector:
        rpar, y0, ok, errors = _build_vectorised(system0, rpar0, samples, start, solver)
    else:
        rpar, y0, ok, errors = _build_each(system0, samples, start, solver)
    n_coord = system0.n_coordinates
    driver = rpar[:, _offset(ipar, "driver") : _offset(ipar, "driver") + 4]
    period = 2.0 * math.pi / np.abs(driver[:, DRV_OMEGA])
    t_settle = _settle_time(driver, float(settle)) if settle else np.zeros(len(rpar))
    t_end = (int(settle) + revolutions) * period
    max_step = np.full(len(rpar), solver.max_step) if solver.max_step else period / 360.0
    fewest = (t_end / max_step)[ok]
    if fewest.size and fewest.max() > solver.max_steps:
        raise ConfigError(
            f"a max step of {solver.max_step:.3g} s needs at least {fewest.max():.3g} steps for "
            f"{int(settle) + revolutions:g} revolution(s), more than max_steps = "
            f"{solver.max_steps}; give a larger max step or fewer revolutions"
        )
    atol = np.concatenate(
        [
            np.full(n_coord, solver.atol_position),
            np.full(n_coord, solver.atol_velocity),
            np.full(2, 1e-6),
            np.full(len(clearances), 1.0),
        ]
    )
    return BatchProblem(
        ipar=np.array(ipar),
        rpar=rpar,
        y0=y0,
        t_settle=t_settle,
        t_end=t_end,
        max_step=max_step,
        rtol=solver.rtol,
        atol=atol,
        max_steps=solver.max_steps,
        ok=ok,
        errors=tuple(errors),
        vectorised=bool(use_vector),
    )


def _offset(ipar: NDArray[np.int64], name: str) -> int:
    """Start of the float field ``name`` in ``rpar`` (:func:`jointplay._kernels.eom.pack`)."""
    offset = 0
    for item in ids.FLOAT_FIELDS:
        if item == name:
            return offset
        offset += int(ipar[ids.MODEL_FIELDS.index(item)])
    raise KeyError(name)


def _sample_mechanism(
    system0: System, samples: BatchSamples, i: int
) -> tuple[Mechanism, list[ClearanceJoint]]:
    """The mechanism and clearance joints of sample ``i`` (the per-sample path)."""
    mechanism = system0.mechanism
    lengths = {k: float(v[i]) for k, v in samples.lengths.items()}
    if lengths:
        mechanism = with_lengths(mechanism, **lengths)
    if samples.angular_velocity is not None:
        omega = float(samples.angular_velocity[i])
        if not (math.isfinite(omega) and omega != 0.0):
            raise ConfigError(f"crank angular velocity must be finite and non-zero, got {omega}")
        mechanism = mechanism.with_driver(speed=abs(omega), direction=1 if omega > 0 else -1)
    law_changes = {k: float(v[i]) for k, v in samples.law.items()}
    joints = []
    for c in system0.clearances:
        change: dict[str, Any] = {}
        if c.joint in samples.clearances:
            c = c.with_clearance(float(samples.clearances[c.joint][i]))
        if law_changes:
            change["law"] = dataclasses.replace(c.law, **law_changes)
        joints.append(dataclasses.replace(c, **change) if change else c)
    return mechanism, joints


def _build_each(
    system0: System, samples: BatchSamples, start: Start, solver: SolverOptions
) -> tuple[FloatArray, FloatArray, NDArray[np.bool_], list[str]]:
    """Per sample: :func:`build_system` and :func:`initial_state` (any mechanism)."""
    rpar0, _ = eom.pack(system0.model)
    y00 = initial_state(system0, start)
    n = len(samples)
    rpar = np.tile(rpar0, (n, 1))
    y0 = np.tile(y00, (n, 1))
    ok = np.ones(n, dtype=bool)
    errors = [""] * n
    for i in range(n):
        try:
            mechanism, joints = _sample_mechanism(system0, samples, i)
            system = build_system(
                mechanism,
                joints,
                ramp_time=start.ramp_time,
                onset_tolerance=solver.onset_tolerance,
                driven=start.driven,
            )
            rpar[i] = eom.pack(system.model)[0]
            y0[i] = initial_state(system, start)
        except (JointplayError, np.linalg.LinAlgError) as exc:
            ok[i] = False
            errors[i] = f"{type(exc).__name__}: {exc}"
    return rpar, y0, ok, errors


#: Per template: each bar link's (length name, start point, end point); ground points as
#: functions of the geometry (see :mod:`jointplay.model.templates`).
_BARS = {
    "four-bar": {"crank": ("crank", "O2", "A"), "coupler": ("coupler", "A", "B"),
                 "rocker": ("rocker", "O4", "B")},
    "slider-crank": {"crank": ("crank", "O2", "A"), "rod": ("rod", "A", "B")},
}  # fmt: skip


def _ground_points(kind: str, g: SimpleNamespace, n: int) -> dict[str, tuple[Any, Any]]:
    zero = np.zeros(n)
    if kind == "four-bar":
        return {"O2": (zero, zero), "O4": (g.ground, zero)}
    return {"O2": (zero, zero), "S0": (zero, g.offset)}


def _geometric_changes(
    clear: ClearanceJoint, samples: BatchSamples, clearance: FloatArray
) -> Mapping[str, FloatArray]:
    """``samples.law`` plus, for a joint whose stiffness follows its geometry and whose
    clearance varies, the stiffness and exponent refitted to each sample's clearance (NaN,
    so the sample fails, where the stiffness law does not apply)."""
    rule = clear.stiffness_from
    if rule is None or clear.joint not in samples.clearances:
        return samples.law
    k, n = rule.fits(clear.journal_radius, clearance)
    return {stiffness_field(clear.law): k, "exponent": n, **samples.law}


def _law_columns(
    law: ContactLaw, changes: Mapping[str, FloatArray], n: int
) -> tuple[FloatArray, NDArray[np.bool_], list[str]]:
    """(n, PARAMS_WIDTH) packed parameters of ``law`` with ``changes`` per sample, validity
    and messages. Fields the law packs as they are (its declared ``packing``) go straight into
    their column; others (e.g. a restitution, packed as its hysteresis factor) are packed once
    per distinct row."""
    base = np.zeros(PARAMS_WIDTH)
    packed = law.params()
    base[: len(packed)] = packed
    out = np.tile(base, (n, 1))
    ok = np.ones(n, dtype=bool)
    errors = [""] * n
    if not changes:
        return out, ok, errors
    slots = {name: law.packed_slot(name) for name in changes}  # the law declares them
    direct = {name: slot for name, slot in slots.items() if slot is not None}
    for name, column in direct.items():
        out[:, column] = changes[name]
    rows = np.column_stack([changes[name] for name in changes])
    if len(direct) == len(changes) and np.all(np.isfinite(rows)):
        # packed as given: the laws' checks are ranges, so checking the extremes suffices
        try:
            for extreme in (rows.min(axis=0), rows.max(axis=0)):
                dataclasses.replace(law, **dict(zip(changes, map(float, extreme), strict=True)))
            return out, ok, errors
        except JointplayError:
            pass
    unique, inverse = np.unique(rows, axis=0, return_inverse=True)
    checked: list[tuple[bool, str, FloatArray]] = []
    for values in unique:
        try:
            variant = dataclasses.replace(
                law, **dict(zip(changes, map(float, values), strict=True))
            )
            params = np.zeros(PARAMS_WIDTH)
            params[: len(packed)] = variant.params()
            checked.append((True, "", params))
        except JointplayError as exc:
            checked.append((False, f"{type(exc).__name__}: {exc}", base))
    indirect = [name for name in changes if name not in direct]
    for i, k in enumerate(np.asarray(inverse).ravel()):
        good, message, params = checked[k]
        if not good:
            ok[i], errors[i] = False, message
        elif indirect:
            out[i] = params
    return out, ok, errors


def _build_vectorised(
    system0: System, rpar0: FloatArray, samples: BatchSamples, start: Start, solver: SolverOptions
) -> tuple[FloatArray, FloatArray, NDArray[np.bool_], list[str]]:
    """The template builder: :func:`build_system` + :func:`initial_state` over all samples."""
    mechanism = system0.mechanism
    spec = mechanism.template
    assert isinstance(spec, TemplateSpec)
    kind = spec.geometry.kind
    n = len(samples)
    ok = np.ones(n, dtype=bool)
    errors = [""] * n
    g = SimpleNamespace(
        **{
            name: np.array(samples.lengths[name], dtype=float)
            if name in samples.lengths
            else np.full(n, float(getattr(spec.geometry, name)))
            for name in spec.geometry.length_names
        }
    )
    # assembly: the crank must turn fully (as analyse's check_mobility)
    if kind == "four-bar":
        lengths = np.column_stack([g.crank, g.coupler, g.rocker, g.ground])
        turns = _turns_fully(lengths)
        positive = np.all(lengths > 0, axis=1)
    else:
        turns = g.crank + np.abs(g.offset) < g.rod
        positive = (g.crank > 0) & (g.rod > 0)
    finite = np.all(np.isfinite(np.column_stack(list(vars(g).values()))), axis=1)
    bad = np.flatnonzero(~(turns & positive & finite))
    for i in bad:  # the exact message of the per-sample build
        ok[i] = False
        try:
            _sample_mechanism(system0, samples, int(i))
            values: dict[str, Any] = {k: float(v[i]) for k, v in vars(g).items()}
            if isinstance(spec.geometry, FourBarGeometry):
                fourbar.check_full_rotation(dataclasses.replace(spec.geometry, **values))
            else:
                slidercrank.check_full_rotation(dataclasses.replace(spec.geometry, **values))
            errors[i] = "AssemblyError: the crank cannot turn fully"
        except JointplayError as exc:
            errors[i] = f"{type(exc).__name__}: {exc}"
    for name in vars(g):  # failed samples: nominal geometry, not run
        getattr(g, name)[~ok] = float(getattr(spec.geometry, name))
    driver0 = mechanism.driver
    omega = (
        np.full(n, driver0.angular_velocity)
        if samples.angular_velocity is None
        else np.array(samples.angular_velocity, dtype=float)
    )
    bad_speed = ~(np.isfinite(omega) & (omega != 0.0))
    for i in np.flatnonzero(bad_speed & ok):
        ok[i] = False
        errors[i] = (
            f"ConfigError: crank angular velocity must be finite and non-zero, got {omega[i]}"
        )
    omega[bad_speed] = driver0.angular_velocity
    # masses and inertias: Link.bar's formulas (unless the template gave them)
    flat0 = system0.flat
    nb = flat0.n_bodies
    mass = np.tile(flat0.mass, (n, 1))
    inertia = np.tile(flat0.inertia, (n, 1))
    com = np.tile(flat0.com_local, (n, 1, 1))
    bars = _BARS[kind]
    for k, link in enumerate(mechanism.links):
        if link.name not in bars:
            continue
        length = getattr(g, bars[link.name][0])
        body = spec.bodies.get(link.name, LinkBody())
        m = (
            np.full(n, body.mass)
            if body.mass is not None
            else spec.material.density * length * body.width * float(body.thickness or 0.0)
        )
        mass[:, k] = m
        inertia[:, k] = (
            body.inertia if body.inertia is not None else m * (length**2 + body.width**2) / 12.0
        )
        com[:, k, 0] = length / 2.0
        com[:, k, 1] = 0.0
    # joint points from the centres of mass (flatten's ``local``)
    ground = _ground_points(kind, g, n)
    joint_f = np.tile(flat0.joint_f, (n, 1, 1))

    def local(link: str, point: str) -> tuple[Any, Any]:
        if link == GROUND:
            return ground[point]
        k = flat0.body_index(link)
        if link in bars:
            _, first, last = bars[link]
            length = getattr(g, bars[link][0])
            x, y = (
                (np.zeros(n), np.zeros(n))
                if point == first
                else (length, np.zeros(n))
                if point == last
                else tuple(np.full(n, v) for v in mechanism.link(link).point(point))
            )
        else:
            x, y = (np.full(n, v) for v in mechanism.link(link).point(point))
        return x - com[:, k, 0], y - com[:, k, 1]

    for row, joint in enumerate(mechanism.joints):
        joint_f[:, row, 0], joint_f[:, row, 1] = local(joint.link_a, joint.point_a)
        joint_f[:, row, 2], joint_f[:, row, 3] = local(joint.link_b, joint.point_b)
    driver = np.tile(flat0.driver, (n, 1))
    driver[:, DRV_OMEGA] = omega
    # clearances, laws, settings
    nc = len(system0.clearances)
    geom = np.zeros((n, nc, ids.N_GEOM))
    law_p = np.zeros((n, nc, PARAMS_WIDTH))
    films = np.zeros((n, nc))
    for c, clear in enumerate(system0.clearances):
        clearance = (
            np.array(samples.clearances[clear.joint], dtype=float)
            if clear.joint in samples.clearances
            else np.full(n, clear.clearance)
        )
        with np.errstate(invalid="ignore", divide="ignore"):  # bad clearances fail below
            films[:, c] = (
                clear.film_damping
                if clear.film_from is None
                else clear.film_from.damping(clear.journal_radius, clearance)
            )
        geom[:, c, ids.G_R_BEARING] = clear.journal_radius + clearance
        geom[:, c, ids.G_R_JOURNAL] = clear.journal_radius
        geom[:, c, ids.G_CLEARANCE] = clearance
        geom[:, c, ids.G_FILM] = films[:, c]  # each joint its own c_e, as build_system
        geom[:, c, ids.G_CAPTURE] = clear.capture_speed
        geom[:, c, ids.G_FILM_MODEL] = film_model_id(clear.film_model)
        geom[:, c, ids.G_ROUGHNESS] = clear.roughness  # σ, each joint its own
        law_p[:, c], law_ok, law_errors = _law_columns(
            clear.law, _geometric_changes(clear, samples, clearance), n
        )
        for i in np.flatnonzero(~law_ok & ok):
            ok[i], errors[i] = False, law_errors[i]
        if clear.joint in samples.clearances:  # ClearanceJoint's checks, for the bad ones
            with np.errstate(invalid="ignore"):
                suspect = ~(np.isfinite(clearance) & (clearance >= MIN_CLEARANCE))
            for i in np.flatnonzero(ok & suspect):
                try:
                    dataclasses.replace(clear, clearance=float(clearance[i]))
                except JointplayError as exc:
                    ok[i], errors[i] = False, f"{type(exc).__name__}: {exc}"
    settings = np.tile(system0.model.settings, (n, 1))
    if solver.onset_tolerance is None:  # as build_system: a fraction of the smallest clearance
        fraction = onset_fraction(system0.clearances)  # the laws' kinds are every sample's
        settings[:, ids.S_ONSET_TOL] = fraction * geom[:, :, ids.G_CLEARANCE].min(axis=1)
    mass_vector = np.stack([mass, mass, inertia], axis=2).reshape(n, 3 * nb)
    gravity = np.zeros((n, nb, 3))
    gravity[:, :, 0] = mass * flat0.gravity[0]
    gravity[:, :, 1] = mass * flat0.gravity[1]
    fields = {
        "mass": mass_vector,
        "gravity": gravity.reshape(n, 3 * nb),
        "joint_f": joint_f.reshape(n, -1),
        "driver": driver,
        "geom": geom.reshape(n, -1),
        "law_p": law_p.reshape(n, -1),
        "fric_p": np.tile(system0.model.fric_p, (n, 1)),
        "settings": settings,
    }
    rpar = np.concatenate([fields[name] for name in ids.FLOAT_FIELDS], axis=1)
    assert rpar.shape[1] == rpar0.shape[0]
    y0 = _initial_states(system0, kind, g, omega, joint_f, mass_vector, driver, start)
    return rpar, y0, ok, errors


def _four(row: FloatArray) -> FourBarGeometry:
    crank, coupler, rocker, ground = (float(v) for v in row)
    return FourBarGeometry(crank=crank, coupler=coupler, rocker=rocker, ground=ground)


def _turns_fully(lengths: FloatArray) -> NDArray[np.bool_]:
    """Vectorised :func:`jointplay.kinematics.fourbar.infeasible_crank_ranges` is empty."""
    a, b, c, d = lengths.T
    too_long = (a * a + d * d - (b + c) ** 2) / (2 * a * d)
    too_short = (a * a + d * d - (b - c) ** 2) / (2 * a * d)
    with np.errstate(invalid="ignore"):
        ok = (too_long <= -1) & (too_short >= 1)
    # Ranges narrower than 1e-12 rad count as feasible, as infeasible_crank_ranges drops them.
    edge = ~ok & (too_long <= too_short) & np.isfinite(too_long) & np.isfinite(too_short)
    for i in np.flatnonzero(edge):
        ok[i] = not fourbar.infeasible_crank_ranges(_four(lengths[i]))
    return np.asarray(ok, dtype=bool)


def _rotate(phi: FloatArray, sx: FloatArray, sy: FloatArray) -> FloatArray:
    c, s = np.cos(phi), np.sin(phi)
    return np.column_stack([c * sx - s * sy, s * sx + c * sy])


def _initial_states(
    system0: System,
    kind: str,
    g: SimpleNamespace,
    omega: FloatArray,
    joint_f: FloatArray,
    mass_vector: FloatArray,
    driver: FloatArray,
    start: Start,
) -> FloatArray:
    """:func:`initial_state` for every sample: the closed-form assembly at the start angle
    (:func:`jointplay.kinematics.analysis.analyse`), velocities per ``start``, projected onto
    the ideal constraints, the driver and the lubricated clearance joints
    (:func:`~jointplay.dynamics.simulate.start_constraints`)."""
    mechanism = system0.mechanism
    flat0 = system0.flat
    n = len(omega)
    nb = flat0.n_bodies
    theta2 = np.full(n, mechanism.driver.start_angle)
    phi = np.zeros((n, nb))
    w = np.zeros((n, nb))
    phi[:, 0], w[:, 0] = theta2, omega
    if kind == "four-bar":
        t3, t4 = fourbar.positions(g, theta2, mechanism.branch)  # type: ignore[arg-type]
        w3, w4 = fourbar.velocities(g, theta2, t3, t4, omega)  # type: ignore[arg-type]
        phi[:, 1], phi[:, 2], w[:, 1], w[:, 2] = t3, t4, w3, w4
    else:
        t3, _ = slidercrank.positions(g, theta2, mechanism.branch)  # type: ignore[arg-type]
        w3, _ = slidercrank.velocities(g, theta2, t3, omega)  # type: ignore[arg-type]
        phi[:, 1], w[:, 1] = t3, w3
        slider = next(j for j in mechanism.joints if j.name not in {"O2", "A", "B"})
        phi[:, 2] = slider.axis_angle + slider.relative_angle  # type: ignore[union-attr]
    # gs.state_from_angles, with each sample's joint points
    pos = np.zeros((n, nb, 2))
    vel = np.zeros((n, nb, 2))
    for row, known, new in revolute_tree(flat0):
        a = int(flat0.joint_int[row, 1])
        s_known = joint_f[:, row, 0:2] if known == a else joint_f[:, row, 2:4]
        s_new = joint_f[:, row, 2:4] if known == a else joint_f[:, row, 0:2]
        if known < 0:
            p, v = s_known.copy(), np.zeros((n, 2))
        else:
            rs = _rotate(phi[:, known], s_known[:, 0], s_known[:, 1])
            perp = np.column_stack([-rs[:, 1], rs[:, 0]])
            p, v = pos[:, known] + rs, vel[:, known] + w[:, known][:, None] * perp
        rs = _rotate(phi[:, new], s_new[:, 0], s_new[:, 1])
        perp = np.column_stack([-rs[:, 1], rs[:, 0]])
        pos[:, new] = p - rs
        vel[:, new] = v - w[:, new][:, None] * perp
    q0 = np.concatenate([pos, phi[:, :, None]], axis=2).reshape(n, -1)
    steady = np.concatenate([vel, w[:, :, None]], axis=2).reshape(n, -1)
    crank = flat0.body_index(mechanism.driver.link)
    qd0 = np.zeros_like(steady)
    if start.mode == "steady":
        qd0 = steady
    elif start.mode == "rest":
        qd0[:, 3 * crank : 3 * crank + 3] = steady[:, 3 * crank : 3 * crank + 3]
    # the driver of the packed model (off when not driven), as initial_state projects
    model_driver = driver.copy()
    model_driver[:, 0] = system0.model.driver[0]
    active = start_constraints(system0)  # the ideal joints and the lubricated ones
    _project(q0, qd0, flat0.joint_int, joint_f, active, model_driver, mass_vector)
    nc = len(system0.clearances)
    return np.concatenate([q0, qd0, np.zeros((n, 2 + nc))], axis=1)


def _project(
    q0: FloatArray,
    qd0: FloatArray,
    joint_int: NDArray[np.int64],
    joint_f: FloatArray,
    active: NDArray[np.int64],
    driver: FloatArray,
    mass_vector: FloatArray,
) -> None:
    """q̇ ← q̇ − M⁻¹Φ_qᵀ(Φ_q M⁻¹Φ_qᵀ)⁻¹(Φ_q q̇ − ν) per sample, in place (initial_state's
    impulsive projection). With the driver as the only constraint (every joint clear) it sets
    the crank's rate; otherwise each sample's Jacobian is built and solved."""
    n = len(q0)
    rows = 2 * int(active.sum()) + (1 if driver[0, 0] >= 0 else 0)
    if rows == 0:
        return
    if int(active.sum()) == 0:  # Φ_q = e_k: the crank's rate becomes ν
        k = 3 * int(driver[0, 0]) + 2  # ν = φ̇_d(0): ω, or 0 at the start of a ramp
        qd0[:, k] = np.where(driver[:, 3] > 0.0, 0.0, driver[:, DRV_OMEGA])
        return
    for i in range(n):
        phi_q = ck.jacobian(q0[i], joint_int, joint_f[i], active, driver[i])
        nu = ck.velocity_rhs(0.0, active, driver[i])
        inv_mass = 1.0 / mass_vector[i]
        weighted = phi_q * inv_mass
        qd0[i] -= inv_mass * (phi_q.T @ np.linalg.solve(weighted @ phi_q.T, phi_q @ qd0[i] - nu))
