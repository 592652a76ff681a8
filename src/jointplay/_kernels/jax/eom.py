"""The equations of motion of :mod:`jointplay._kernels.eom`, for one lane, in JAX.

A line-by-line port of the Numba kernels (same state layout, same formulas, same branch
decisions), written for ``jax.vmap`` over the lanes of a batch: the integer structure of the
mechanism (``ipar``: bodies, joints, which joints are clear, the law and friction ids, the
driven body) is static, read once into a :class:`Layout` in Python, so every loop over bodies,
joints and clearance joints unrolls at trace time and every law is chosen in Python; the
floats (``rpar``: masses, lengths, clearances, law parameters, crank speed) and the state are
traced, one row per lane. Branches on traced values become ``jnp.where`` with guarded
operands (a zero eccentricity gets the fallback normal (1, 0); a law is evaluated at a safe
penetration outside contact), so the functions are differentiable (``jax.jacfwd``, used by
the implicit integrator) and never produce NaN where the Numba kernel does not.

Per lane (module docstring of :mod:`jointplay._kernels.eom` for the physics):

- :meth:`JaxModel.rhs` is :func:`jointplay._kernels.eom.state_rhs` (ẏ);
- :meth:`JaxModel.outputs` is ẏ with the batch engine's peak quantities (ω and α of every
  body, the force of every joint, the motor torque; the QUANTITY ORDER of the batch
  contract, as :func:`jointplay.dynamics.simulate._columns` computes them) and the
  penetration δ of every clearance joint;
- :meth:`JaxModel.step_check` is the lane source's contact-onset control (``onset_check``);
- :meth:`JaxModel.after_step` is what the lanes' loop does after an accepted step (the
  source's ``contact_memory``, then its mass-weighted ``project`` onto the ideal constraints;
  the projection's statistics are not kept).

Every normal-force law id (IMPACT, Hertz, Kelvin–Voigt, the Hunt–Crossley family 3–11) and
friction id (none, Ambrósio, ADAMS) of :mod:`jointplay._kernels.contact` is ported; an unknown
id is refused when the layout is read (:class:`~jointplay.errors.ConfigError`, the message of
:func:`jointplay._kernels.capabilities.refusal`), where the
Numba kernel would return NaN. Symmetric positive definite solves use an unrolled Cholesky
factorisation (the Numba right-hand side does the same; its projection uses an LU solve,
equal to round-off).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import jax.numpy as jnp
import numpy as np

from jointplay._kernels import ids
from jointplay._kernels.capabilities import refusal
from jointplay._kernels.lanes.source import N_LAY
from jointplay.errors import ConfigError

Scalar = Any  # a traced float64 scalar (one lane)

#: Normal-force laws the port knows, by id.
NORMAL_LAWS = {
    ids.LAW_IMPACT: "impact",
    ids.LAW_HERTZ: "hertz",
    ids.LAW_KELVIN_VOIGT: "kelvin-voigt",
    **{law: "hunt-crossley family" for law in range(ids.HC_FIRST, ids.HC_LAST + 1)},
}
#: Friction laws the port knows, by id.
FRICTION_LAWS = {
    ids.FRICTION_NONE: "none",
    ids.FRICTION_AMBROSIO: "ambrosio",
    ids.FRICTION_ADAMS: "adams",
}

#: Joint kinds of joint_int column 0 (jointplay.model.flat).
REVOLUTE, PRISMATIC = 0, 1


@dataclass(frozen=True)
class Layout:
    """The static (integer) structure of a batch, read from ``ipar`` (:func:`eom.pack`).

    Attributes:
        n: number of coordinates, 3 per moving body.
        joints: (kind, body a, body b) per joint (−1 = ground).
        active: 1 per ideal joint, 0 per clearance joint.
        clear_joint: joint row of each clearance joint.
        law_id, fric_id: normal-force and friction law id of each clearance joint.
        crank: driven body (−1: no driver); ``rpar``'s ``driver[0]``, the same in every lane.
        offsets: start of each float field of :class:`eom.EomModel` in ``rpar``.
        plaw, pfric: width of one clearance joint's law and friction parameter rows.
        n_rpar: length of ``rpar``.
    """

    n: int
    joints: tuple[tuple[int, int, int], ...]
    active: tuple[int, ...]
    clear_joint: tuple[int, ...]
    law_id: tuple[int, ...]
    fric_id: tuple[int, ...]
    crank: int
    offsets: tuple[tuple[str, int], ...]
    plaw: int
    pfric: int
    n_rpar: int

    @property
    def nb(self) -> int:
        return self.n // 3

    @property
    def nj(self) -> int:
        return len(self.joints)

    @property
    def nc(self) -> int:
        return len(self.clear_joint)

    @property
    def n_state(self) -> int:
        """q, q̇, the two work integrals, one impact-velocity slot per clearance joint."""
        return 2 * self.n + 2 + self.nc

    @property
    def n_peaks(self) -> int:
        """P = 2 nb + nj + 1: ω and α per body, the force per joint, the torque."""
        return 2 * self.nb + self.nj + 1

    @property
    def n_rows(self) -> int:
        """Constraint rows: 2 per ideal joint, 1 for the driver."""
        return 2 * sum(self.active) + (1 if self.crank >= 0 else 0)

    def offset(self, name: str) -> int:
        return dict(self.offsets)[name]


def read_layout(ipar: np.ndarray, rpar: np.ndarray) -> Layout:
    """The :class:`Layout` of packed models ``ipar`` (int64) and ``rpar`` (float64, (n, R)).

    Raises:
        ConfigError: ``ipar`` is not a packed model, the lanes do not share their driven body,
            or a law or friction id is not one the JAX port knows.
    """
    ipar = np.asarray(ipar, dtype=np.int64)
    rpar = np.atleast_2d(np.asarray(rpar, dtype=np.float64))
    if ipar.ndim != 1 or ipar.shape[0] < len(ids.MODEL_FIELDS):
        raise ConfigError(f"ipar must be a packed model (eom.pack), got shape {ipar.shape}")
    lengths = {name: int(ipar[i]) for i, name in enumerate(ids.MODEL_FIELDS)}
    ints: dict[str, np.ndarray] = {}
    o = len(ids.MODEL_FIELDS)
    for name in ids.INT_FIELDS:
        ints[name] = ipar[o : o + lengths[name]]
        o += lengths[name]
    offsets = []
    r = 0
    for name in ids.FLOAT_FIELDS:
        offsets.append((name, r))
        r += lengths[name]
    o += N_LAY  # the lane source's layout closes ipar (eom.pack)
    if rpar.shape[1] != r or o != ipar.shape[0]:
        raise ConfigError(
            f"rpar rows have {rpar.shape[1]} entries and ipar {ipar.shape[0]}, but the packed "
            f"model says {r} and {o}: pass eom.pack(model) of one mechanism for every lane"
        )
    n = lengths["mass"]
    nc = lengths["clear_joint"]
    driver = dict(offsets)["driver"]
    crank = rpar[:, driver]
    if not np.all(crank == crank[0]):
        raise ConfigError(
            "the lanes of a batch must drive the same body (rpar's driver[0] differs between "
            "lanes); split the batch by mechanism"
        )
    for kind, joint_ids, names in (
        ("law", ints["law_id"], NORMAL_LAWS),
        ("friction", ints["fric_id"], FRICTION_LAWS),
    ):  # the laws the port knows, by their names in the engines' table (an unknown id: none)
        for c, law in enumerate(joint_ids):
            refused = refusal("jax", [f"{kind}:{names.get(int(law), f'id {int(law)}')}"])
            if refused is not None:
                raise ConfigError(f"clearance joint {c}: {refused}")
    joint_int = ints["joint_int"].reshape(-1, 3)
    return Layout(
        n=n,
        joints=tuple((int(k), int(a), int(b)) for k, a, b in joint_int),
        active=tuple(int(v) for v in ints["active"]),
        clear_joint=tuple(int(v) for v in ints["clear_joint"]),
        law_id=tuple(int(v) for v in ints["law_id"]),
        fric_id=tuple(int(v) for v in ints["fric_id"]),
        crank=int(crank[0]) if rpar.shape[0] else -1,
        offsets=tuple(offsets),
        plaw=lengths["law_p"] // max(nc, 1),
        pfric=lengths["fric_p"] // max(nc, 1),
        n_rpar=r,
    )


# ---------------------------------------------------------------------------------------
# Scalar laws (jointplay._kernels.contact and constraints.driver_motion).
# ---------------------------------------------------------------------------------------
def step3(x: Scalar, x0: Scalar, h0: Scalar, x1: Scalar, h1: Scalar) -> Scalar:
    """ADAMS cubic STEP (:func:`jointplay._kernels.contact.step3`)."""
    span = jnp.where(x1 > x0, x1 - x0, 1.0)
    u = (x - x0) / span
    inner = h0 + (h1 - h0) * u * u * (3.0 - 2.0 * u)
    return jnp.where(x <= x0, h0, jnp.where(x >= x1, h1, inner))


def power(d: Scalar, exponent: Scalar) -> Scalar:
    """δ^e (:func:`jointplay._kernels.contact.power`: δ√δ for e = 3/2)."""
    return jnp.where(exponent == 1.5, d * jnp.sqrt(d), d**exponent)


def normal_force(law: int, p: Any, delta: Scalar, delta_dot: Scalar, v0: Scalar) -> Scalar:
    """:func:`jointplay._kernels.contact.normal_force` for the static ``law`` (N; 0 outside
    contact). ``p`` holds the law's packed parameters."""
    inside = delta > 0.0
    d = jnp.where(inside, delta, 1.0)  # a safe penetration outside contact
    if law == ids.LAW_IMPACT:
        damping = step3(d, 0.0, 0.0, p[ids.IMPACT_D_MAX], p[ids.IMPACT_C_MAX])
        force = p[ids.IMPACT_STIFFNESS] * power(d, p[ids.IMPACT_EXPONENT]) + damping * delta_dot
    elif law == ids.LAW_HERTZ:
        force = p[ids.HERTZ_STIFFNESS] * power(d, p[ids.HERTZ_EXPONENT])
    elif law == ids.LAW_KELVIN_VOIGT:
        force = p[ids.KV_STIFFNESS] * d + p[ids.KV_DAMPING] * delta_dot
    elif ids.HC_FIRST <= law <= ids.HC_LAST:
        v_ref = jnp.where(v0 > 0.0, v0, delta_dot)
        v_floor = p[ids.HC_V_FLOOR]
        v_eff = jnp.where(v_ref > v_floor, v_ref, v_floor)
        force = (
            p[ids.HC_STIFFNESS]
            * power(d, p[ids.HC_EXPONENT])
            * (1.0 + p[ids.HC_CHI] * delta_dot / v_eff)
        )
    else:  # read_layout refuses unknown ids
        raise ConfigError(f"normal-force law id {law} is not ported to JAX")
    return jnp.where(inside & (force > 0.0), force, 0.0)


def friction_force(law: int, p: Any, v_t: Scalar, f_n: Scalar) -> Scalar:
    """:func:`jointplay._kernels.contact.friction_force` for the static ``law`` (signed F_T, N)."""
    if law == ids.FRICTION_NONE:
        return jnp.zeros_like(v_t)
    sign = jnp.sign(v_t)
    speed = jnp.abs(v_t)
    if law == ids.FRICTION_AMBROSIO:
        v_lo, v_hi = p[ids.AMBROSIO_V0], p[ids.AMBROSIO_V1]
        span = jnp.where(v_hi > v_lo, v_hi - v_lo, 1.0)
        correction = jnp.where(
            speed <= v_lo, 0.0, jnp.where(speed >= v_hi, 1.0, (speed - v_lo) / span)
        )
        return p[ids.AMBROSIO_MU] * correction * f_n * sign
    if law == ids.FRICTION_ADAMS:
        mu_s, mu_d = p[ids.ADAMS_MU_STATIC], p[ids.ADAMS_MU_DYNAMIC]
        v_s, v_d = p[ids.ADAMS_V_STATIC], p[ids.ADAMS_V_DYNAMIC]
        coefficient = jnp.where(
            speed <= v_s,
            step3(v_t, -v_s, -mu_s, v_s, mu_s),
            jnp.where(speed < v_d, sign * step3(speed, v_s, mu_s, v_d, mu_d), sign * mu_d),
        )
        return coefficient * f_n
    raise ConfigError(f"friction law id {law} is not ported to JAX")


def driver_motion(t: Scalar, driver: Any) -> tuple[Scalar, Scalar, Scalar]:
    """:func:`jointplay._kernels.constraints.driver_motion`: prescribed crank angle (rad),
    speed (rad/s) and acceleration (rad/s²) at ``t``, constant speed or the quintic STEP5 ramp."""
    phi0, omega, ramp = driver[1], driver[2], driver[3]
    ramped = ramp > 0.0
    after = ~ramped | (t >= ramp)
    shift = jnp.where(ramped, 0.5 * omega * ramp, 0.0)
    angle_after = phi0 + shift + omega * (t - jnp.maximum(ramp, 0.0))
    u = t / jnp.where(ramped, ramp, 1.0)
    angle_ramp = phi0 + omega * jnp.where(ramped, ramp, 0.0) * u**4 * (2.5 - 3.0 * u + u * u)
    speed_ramp = omega * u**3 * (10.0 - 15.0 * u + 6.0 * u * u)
    accel_ramp = omega / jnp.where(ramped, ramp, 1.0) * 30.0 * u * u * (1.0 - u) ** 2
    before = t <= 0.0
    angle = jnp.where(after, angle_after, jnp.where(before, phi0, angle_ramp))
    speed = jnp.where(after, omega, jnp.where(before, 0.0, speed_ramp))
    accel = jnp.where(after, 0.0, jnp.where(before, 0.0, accel_ramp))
    return angle, speed, accel


def _cholesky_solve(a: list[list[Scalar]], b: list[Scalar]) -> list[Scalar]:
    """x with a x = b for a small symmetric positive definite ``a`` (lower triangle read),
    unrolled (eom._cholesky_solve's arithmetic)."""
    m = len(b)
    low: list[list[Scalar]] = [[None] * m for _ in range(m)]
    for k in range(m):
        d = a[k][k]
        for p in range(k):
            d = d - low[k][p] * low[k][p]
        d = jnp.sqrt(d)
        low[k][k] = d
        for i in range(k + 1, m):
            s = a[i][k]
            for p in range(k):
                s = s - low[i][p] * low[k][p]
            low[i][k] = s / d
    x = list(b)
    for i in range(m):
        s = x[i]
        for p in range(i):
            s = s - low[i][p] * x[p]
        x[i] = s / low[i][i]
    for i in range(m - 1, -1, -1):
        s = x[i]
        for p in range(i + 1, m):
            s = s - low[p][i] * x[p]
        x[i] = s / low[i][i]
    return x


class JaxModel:
    """The equations of motion of one lane for a static :class:`Layout` (module docstring).

    Every method takes the lane's ``p`` (its ``rpar`` row, shape (R,)) and state ``y``
    (shape (S,)), traced; nothing is stored between calls.
    """

    def __init__(self, layout: Layout) -> None:
        self.layout = layout
        self.n = layout.n
        self._o = dict(layout.offsets)

    # ---- parameters ---------------------------------------------------------------------
    def _mass(self, p: Any, i: int) -> Scalar:
        return p[self._o["mass"] + i]

    def _joint_f(self, p: Any, j: int, k: int) -> Scalar:
        return p[self._o["joint_f"] + 6 * j + k]

    def _driver(self, p: Any) -> Any:
        o = self._o["driver"]
        return p[o : o + 4]

    def _geom(self, p: Any, c: int, k: int) -> Scalar:
        return p[self._o["geom"] + ids.N_GEOM * c + k]

    def _law_row(self, p: Any, c: int) -> Any:
        o = self._o["law_p"] + self.layout.plaw * c
        return p[o : o + self.layout.plaw]

    def _fric_row(self, p: Any, c: int) -> Any:
        o = self._o["fric_p"] + self.layout.pfric * c
        return p[o : o + self.layout.pfric]

    def _setting(self, p: Any, k: int) -> Scalar:
        return p[self._o["settings"] + k]

    # ---- kinematics ---------------------------------------------------------------------
    def _arm(
        self, q: Any, body: int, sx: Scalar, sy: Scalar
    ) -> tuple[Scalar, Scalar, Scalar, Scalar]:
        """(x, y, r_x, r_y) of the local point (sx, sy) of ``body`` (eom._arm_of)."""
        if body < 0:
            return sx, sy, jnp.zeros_like(sx), jnp.zeros_like(sy)
        c = jnp.cos(q[3 * body + 2])
        s = jnp.sin(q[3 * body + 2])
        rx = c * sx - s * sy
        ry = s * sx + c * sy
        return q[3 * body] + rx, q[3 * body + 1] + ry, rx, ry

    def _contact(self, q: Any, qd: Any, p: Any, c: int) -> dict[str, Any]:
        """Kinematics of clearance joint ``c`` (eom._contact_state / add_contact_forces)."""
        j = self.layout.clear_joint[c]
        _, a, b = self.layout.joints[j]
        bx, by, rax, ray = self._arm(q, a, self._joint_f(p, j, 0), self._joint_f(p, j, 1))
        jx, jy, rbx, rby = self._arm(q, b, self._joint_f(p, j, 2), self._joint_f(p, j, 3))
        ex, ey = jx - bx, jy - by
        emag = jnp.sqrt(ex * ex + ey * ey)
        positive = emag > 0.0
        safe = jnp.where(positive, emag, 1.0)
        nx = jnp.where(positive, ex / safe, 1.0)
        ny = jnp.where(positive, ey / safe, 0.0)
        wa = qd[3 * a + 2] if a >= 0 else 0.0
        wb = qd[3 * b + 2] if b >= 0 else 0.0
        edx = -wb * rby + wa * ray
        edy = wb * rbx - wa * rax
        if b >= 0:
            edx = edx + qd[3 * b]
            edy = edy + qd[3 * b + 1]
        if a >= 0:
            edx = edx - qd[3 * a]
            edy = edy - qd[3 * a + 1]
        delta = emag - self._geom(p, c, ids.G_CLEARANCE)
        delta_dot = edx * nx + edy * ny
        r_j = self._geom(p, c, ids.G_R_JOURNAL)
        r_b = self._geom(p, c, ids.G_R_BEARING)
        v_t = -edx * ny + edy * nx + r_j * wb - r_b * wa
        return {
            "a": a, "b": b, "delta": delta, "delta_dot": delta_dot, "v_t": v_t,
            "nx": nx, "ny": ny, "rax": rax, "ray": ray, "rbx": rbx, "rby": rby,
            "r_j": r_j, "r_b": r_b,
        }  # fmt: skip

    def penetration(self, q: Any, p: Any, c: int) -> Scalar:
        """δ = |e| − c of clearance joint ``c``, m (eom._penetration)."""
        j = self.layout.clear_joint[c]
        _, a, b = self.layout.joints[j]
        bx, by, _, _ = self._arm(q, a, self._joint_f(p, j, 0), self._joint_f(p, j, 1))
        jx, jy, _, _ = self._arm(q, b, self._joint_f(p, j, 2), self._joint_f(p, j, 3))
        return jnp.sqrt((jx - bx) ** 2 + (jy - by) ** 2) - self._geom(p, c, ids.G_CLEARANCE)

    # ---- forces -------------------------------------------------------------------------
    def _contact_forces(
        self, y: Any, p: Any, force: list[Scalar]
    ) -> tuple[Scalar, list[tuple[Scalar, Scalar, Scalar]]]:
        """Add every clearance joint's contact force to ``force`` (3 nb, in place);
        return the absorbed power (W) and (F_N, F_T, δ) per joint (eom.add_contact_forces)."""
        n = self.n
        q, qd = y[:n], y[n : 2 * n]
        power = 0.0
        record = []
        for c in range(self.layout.nc):
            k = self._contact(q, qd, p, c)
            v0 = y[2 * n + 2 + c]
            f_n = normal_force(
                self.layout.law_id[c], self._law_row(p, c), k["delta"], k["delta_dot"], v0
            )
            f_t = friction_force(self.layout.fric_id[c], self._fric_row(p, c), k["v_t"], f_n)
            nx, ny = k["nx"], k["ny"]
            fx = -f_n * nx + f_t * ny
            fy = -f_n * ny - f_t * nx
            self._push(force, k["b"], k["rbx"] + k["r_j"] * nx, k["rby"] + k["r_j"] * ny, fx, fy)
            self._push(force, k["a"], k["rax"] + k["r_b"] * nx, k["ray"] + k["r_b"] * ny, -fx, -fy)
            power = power + f_n * k["delta_dot"] + f_t * k["v_t"]
            record.append((f_n, f_t, k["delta"]))
        return power, record

    @staticmethod
    def _push(
        force: list[Scalar], body: int, rx: Scalar, ry: Scalar, fx: Scalar, fy: Scalar
    ) -> None:
        if body < 0:
            return
        force[3 * body] = force[3 * body] + fx
        force[3 * body + 1] = force[3 * body + 1] + fy
        force[3 * body + 2] = force[3 * body + 2] + (rx * fy - ry * fx)

    # ---- constraints (jointplay._kernels.constraints) ------------------------------------
    def _point(self, q: Any, body: int, sx: Scalar, sy: Scalar) -> tuple[Scalar, Scalar]:
        x, y, _, _ = self._arm(q, body, sx, sy)
        return x, y

    def _residual(self, q: Any, t: Scalar, p: Any) -> list[Scalar]:
        """Φ(q, t): 2 rows per ideal joint, then the driver's (constraints.residual)."""
        out: list[Scalar] = []
        for j, (kind, a, b) in enumerate(self.layout.joints):
            if not self.layout.active[j]:
                continue
            pax, pay = self._point(q, a, self._joint_f(p, j, 0), self._joint_f(p, j, 1))
            pbx, pby = self._point(q, b, self._joint_f(p, j, 2), self._joint_f(p, j, 3))
            if kind == REVOLUTE:
                out += [pax - pbx, pay - pby]
            else:
                phi_a = q[3 * a + 2] if a >= 0 else 0.0
                phi_b = q[3 * b + 2] if b >= 0 else 0.0
                angle = phi_a + self._joint_f(p, j, 4)
                nx, ny = -jnp.sin(angle), jnp.cos(angle)
                out += [phi_b - phi_a - self._joint_f(p, j, 5), nx * (pbx - pax) + ny * (pby - pay)]
        if self.layout.crank >= 0:
            out.append(q[3 * self.layout.crank + 2] - driver_motion(t, self._driver(p))[0])
        return out

    def _jacobian(self, q: Any, p: Any) -> list[dict[int, Scalar]]:
        """Φ_q as sparse rows {column: value} (constraints.jacobian)."""
        rows: list[dict[int, Scalar]] = []
        for j, (kind, a, b) in enumerate(self.layout.joints):
            if not self.layout.active[j]:
                continue
            r0: dict[int, Scalar] = {}
            r1: dict[int, Scalar] = {}
            if kind == REVOLUTE:
                for body, sx, sy, sign in (
                    (a, self._joint_f(p, j, 0), self._joint_f(p, j, 1), 1.0),
                    (b, self._joint_f(p, j, 2), self._joint_f(p, j, 3), -1.0),
                ):
                    if body < 0:
                        continue
                    _, _, ax, ay = self._arm(q, body, sx, sy)
                    r0[3 * body] = r0.get(3 * body, 0.0) + sign
                    r1[3 * body + 1] = r1.get(3 * body + 1, 0.0) + sign
                    r0[3 * body + 2] = r0.get(3 * body + 2, 0.0) - sign * ay
                    r1[3 * body + 2] = r1.get(3 * body + 2, 0.0) + sign * ax
            else:
                phi_a = q[3 * a + 2] if a >= 0 else 0.0
                pax, pay = self._point(q, a, self._joint_f(p, j, 0), self._joint_f(p, j, 1))
                pbx, pby = self._point(q, b, self._joint_f(p, j, 2), self._joint_f(p, j, 3))
                angle = phi_a + self._joint_f(p, j, 4)
                nx, ny = -jnp.sin(angle), jnp.cos(angle)
                dx, dy = pbx - pax, pby - pay
                if a >= 0:
                    _, _, sax, say = self._arm(q, a, self._joint_f(p, j, 0), self._joint_f(p, j, 1))
                    r0[3 * a + 2] = -1.0
                    r1[3 * a] = -nx
                    r1[3 * a + 1] = -ny
                    r1[3 * a + 2] = (-ny * dx + nx * dy) - (nx * -say + ny * sax)
                if b >= 0:
                    _, _, sbx, sby = self._arm(q, b, self._joint_f(p, j, 2), self._joint_f(p, j, 3))
                    r0[3 * b + 2] = 1.0
                    r1[3 * b] = nx
                    r1[3 * b + 1] = ny
                    r1[3 * b + 2] = nx * -sby + ny * sbx
            rows += [r0, r1]
        if self.layout.crank >= 0:
            rows.append({3 * self.layout.crank + 2: 1.0})
        return rows

    def _gamma(self, q: Any, qd: Any, t: Scalar, p: Any) -> list[Scalar]:
        """γ with Φ_q q̈ = γ (constraints.acceleration_rhs)."""
        out: list[Scalar] = []
        for j, (kind, a, b) in enumerate(self.layout.joints):
            if not self.layout.active[j]:
                continue
            if kind == REVOLUTE:
                g0: Scalar = 0.0
                g1: Scalar = 0.0
                for body, sx, sy, sign in (
                    (a, self._joint_f(p, j, 0), self._joint_f(p, j, 1), 1.0),
                    (b, self._joint_f(p, j, 2), self._joint_f(p, j, 3), -1.0),
                ):
                    if body < 0:
                        continue
                    _, _, ax, ay = self._arm(q, body, sx, sy)
                    w2 = qd[3 * body + 2] ** 2
                    g0 = g0 + sign * ax * w2
                    g1 = g1 + sign * ay * w2
                out += [g0, g1]
            else:
                phi_a = q[3 * a + 2] if a >= 0 else 0.0
                wa = qd[3 * a + 2] if a >= 0 else 0.0
                wb = qd[3 * b + 2] if b >= 0 else 0.0
                angle = phi_a + self._joint_f(p, j, 4)
                nx, ny = -jnp.sin(angle), jnp.cos(angle)
                pax, pay, sax, say = self._arm(q, a, self._joint_f(p, j, 0), self._joint_f(p, j, 1))
                pbx, pby, sbx, sby = self._arm(q, b, self._joint_f(p, j, 2), self._joint_f(p, j, 3))
                dx, dy = pbx - pax, pby - pay
                vax = (qd[3 * a] if a >= 0 else 0.0) - say * wa
                vay = (qd[3 * a + 1] if a >= 0 else 0.0) + sax * wa
                vbx = (qd[3 * b] if b >= 0 else 0.0) - sby * wb
                vby = (qd[3 * b + 1] if b >= 0 else 0.0) + sbx * wb
                ddx, ddy = vbx - vax, vby - vay
                bnx, bny = -ny, nx
                out += [
                    0.0,
                    (nx * dx + ny * dy) * wa * wa
                    - 2.0 * wa * (bnx * ddx + bny * ddy)
                    + nx * (sbx * wb * wb - sax * wa * wa)
                    + ny * (sby * wb * wb - say * wa * wa),
                ]
        if self.layout.crank >= 0:
            out.append(driver_motion(t, self._driver(p))[2])
        return out

    def _accelerations(
        self, t: Scalar, y: Any, p: Any, force: list[Scalar]
    ) -> tuple[list[Scalar], Scalar, list[Scalar]]:
        """q̈ from the generalised forces, the motor torque and λ (ideal joints' rows, then
        the driver's) (eom.constrained_accelerations)."""
        n = self.n
        crank = self.layout.crank
        mass = [self._mass(p, i) for i in range(n)]
        if sum(self.layout.active) == 0:
            acc = list(force)
            lam: list[Scalar] = []
            torque: Scalar = 0.0
            if crank >= 0:
                k = 3 * crank + 2
                multiplier = acc[k] - mass[k] * driver_motion(t, self._driver(p))[2]
                acc[k] = acc[k] - multiplier
                torque = -multiplier
                lam = [multiplier]
            return [acc[i] / mass[i] for i in range(n)], torque, lam
        q, qd = y[:n], y[n : 2 * n]
        phi_q = self._jacobian(q, p)
        gamma = self._gamma(q, qd, t, p)
        rows = len(phi_q)
        rhs = []
        schur: list[list[Scalar]] = [[0.0] * rows for _ in range(rows)]
        for r in range(rows):
            s = -gamma[r]
            for i, value in phi_q[r].items():
                w = value / mass[i]
                s = s + w * force[i]
                for c in range(r + 1):
                    if i in phi_q[c]:
                        schur[r][c] = schur[r][c] + w * phi_q[c][i]
            rhs.append(s)
        lam = _cholesky_solve(schur, rhs)
        acc = []
        for i in range(n):
            s = force[i]
            for r in range(rows):
                if i in phi_q[r]:
                    s = s - phi_q[r][i] * lam[r]
            acc.append(s / mass[i])
        torque = -lam[rows - 1] if crank >= 0 else 0.0
        return acc, torque, lam

    def _evaluate(self, t: Scalar, y: Any, p: Any) -> dict[str, Any]:
        n = self.n
        force = [p[self._o["gravity"] + i] for i in range(n)]
        power, record = self._contact_forces(y, p, force)
        acc, torque, lam = self._accelerations(t, y, p, force)
        crank = self.layout.crank
        motor = torque * y[n + 3 * crank + 2] if crank >= 0 else 0.0
        tail = [jnp.zeros_like(t)] * self.layout.nc
        ydot = jnp.stack(
            [*(y[n + i] for i in range(n)), *acc, motor + 0.0 * t, power + 0.0 * t, *tail]
        )
        return {"ydot": ydot, "acc": acc, "torque": torque, "lam": lam, "record": record}

    # ---- the integrator's functions -------------------------------------------------------
    def rhs(self, t: Scalar, y: Any, p: Any) -> Any:
        """ẏ (eom.state_rhs), shape (S,)."""
        return self._evaluate(t, y, p)["ydot"]

    def outputs(self, t: Scalar, y: Any, p: Any) -> tuple[Any, Any, Any]:
        """(ẏ, the P peak quantities, the nc penetrations δ (m)) at (t, y).

        Quantities in the batch contract's order: ω_b (rad/s) and α_b (rad/s²) of every
        body, the force of every joint (N: |F_N n + F_T t| of a clearance joint, |λ| of an
        ideal revolute joint's pair, |λ_normal| of an ideal prismatic joint), the motor
        torque −λ_driver (N·m), as :func:`jointplay.dynamics.simulate._columns`.
        """
        n = self.n
        out = self._evaluate(t, y, p)
        values: list[Scalar] = [y[n + 3 * b + 2] for b in range(self.layout.nb)]
        values += [out["acc"][3 * b + 2] for b in range(self.layout.nb)]
        clear = {j: c for c, j in enumerate(self.layout.clear_joint)}
        row = 0
        for j, (kind, _, _) in enumerate(self.layout.joints):
            if j in clear:
                f_n, f_t, _ = out["record"][clear[j]]
                values.append(jnp.hypot(f_n, f_t))
            else:
                lam = out["lam"]
                if kind == REVOLUTE:
                    values.append(jnp.hypot(lam[row], lam[row + 1]))
                else:
                    values.append(jnp.abs(lam[row + 1]))
                row += 2
        values.append(out["torque"] + 0.0 * t)
        pens = [record[2] for record in out["record"]]
        penetration = jnp.stack(pens) if pens else jnp.zeros((0,), dtype=y.dtype)
        return out["ydot"], jnp.stack([v + 0.0 * t for v in values]), penetration

    def step_check(self, y_old: Any, y_new: Any, p: Any) -> Scalar:
        """Contact-onset step factor θ (the source's ``onset_check``): 1 accepts, < 1
        shortens the step."""
        n = self.n
        tolerance = self._setting(p, ids.S_ONSET_TOL)
        theta = jnp.ones_like(tolerance)
        for c in range(self.layout.nc):
            old = self.penetration(y_old[:n], p, c)
            new = self.penetration(y_new[:n], p, c)
            hit = (old <= 0.0) & (new > tolerance)
            span = jnp.where(hit, new - old, 1.0)
            theta = jnp.where(hit, jnp.minimum(theta, (0.5 * tolerance - old) / span), theta)
        return theta

    def after_step(self, t: Scalar, y: Any, p: Any, y_old: Any) -> Any:
        """The state after an accepted step from ``y_old`` to ``y`` (the lanes'): each
        clearance joint's contact memory v0 set at the start of a contact event (max(δ̇ at
        δ = 0, v_mark), eom.impact_rate) and cleared at its end; then, when max |Φ| exceeds
        the projection tolerance, q projected (up to three Newton steps) and q̇ projected,
        mass-weighted, onto the ideal constraints and the driver (Hairer, Lubich & Wanner,
        *Geometric Numerical Integration*, §IV.4)."""
        n = self.n
        q, qd = y[:n], y[n : 2 * n]
        v_mark = self._setting(p, ids.S_V_MARK)
        for c in range(self.layout.nc):
            k = self._contact(q, qd, p, c)
            k_old = self._contact(y_old[:n], y_old[n : 2 * n], p, c)
            slot = 2 * n + 2 + c
            delta, memory = k["delta"], y[slot]
            start = (delta > 0.0) & (memory <= 0.0)
            end = (delta <= 0.0) & (memory > 0.0)
            crossing = (k_old["delta"] <= 0.0) & (delta > k_old["delta"])
            fraction = -k_old["delta"] / jnp.where(crossing, delta - k_old["delta"], 1.0)
            rate = jnp.where(
                crossing,
                k_old["delta_dot"] + (k["delta_dot"] - k_old["delta_dot"]) * fraction,
                k["delta_dot"],
            )
            value = jnp.where(start, jnp.maximum(rate, v_mark), jnp.where(end, 0.0, memory))
            y = y.at[slot].set(value)
        if self.layout.n_rows == 0:
            return y
        tol = self._setting(p, ids.S_PROJ_TOL)
        mass = [self._mass(p, i) for i in range(n)]

        def max_abs(values: list[Scalar]) -> Scalar:
            return jnp.max(jnp.abs(jnp.stack([v + 0.0 * t for v in values])))

        def correction(q_now: Any, residual: list[Scalar]) -> Any:
            """M⁻¹ Φ_qᵀ (Φ_q M⁻¹ Φ_qᵀ)⁻¹ r as a (n,) array."""
            phi_q = self._jacobian(q_now, p)
            rows = len(phi_q)
            schur: list[list[Scalar]] = [[0.0] * rows for _ in range(rows)]
            for r in range(rows):
                for i, value in phi_q[r].items():
                    for c in range(r + 1):
                        if i in phi_q[c]:
                            schur[r][c] = schur[r][c] + value / mass[i] * phi_q[c][i]
            mult = _cholesky_solve(schur, residual)
            out = []
            for i in range(n):
                s: Scalar = 0.0
                for r in range(rows):
                    if i in phi_q[r]:
                        s = s + phi_q[r][i] * mult[r]
                out.append(s / mass[i] + 0.0 * t)
            return jnp.stack(out)

        q0 = y[:n]
        project = max_abs(self._residual(q0, t, p)) > tol
        going = project
        q_now = q0
        for _ in range(3):
            q_next = q_now - correction(q_now, self._residual(q_now, t, p))
            q_now = jnp.where(going, q_next, q_now)
            going = going & ~(max_abs(self._residual(q_now, t, p)) <= 1e-3 * tol)
        qd0 = y[n : 2 * n]
        nu = [0.0] * (self.layout.n_rows - 1)
        if self.layout.crank >= 0:
            nu.append(driver_motion(t, self._driver(p))[1])
        else:
            nu.append(0.0)
        phi_q = self._jacobian(q_now, p)
        drift = []
        for r in range(len(phi_q)):
            s = -nu[r]
            for i, value in phi_q[r].items():
                s = s + value * qd0[i]
            drift.append(s)
        qd_new = qd0 - correction(q_now, drift)
        y = y.at[:n].set(jnp.where(project, q_now, q0))
        return y.at[n : 2 * n].set(jnp.where(project, qd_new, qd0))
