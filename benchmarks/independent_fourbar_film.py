"""An independent recomputation of the paper four-bar with a Reynolds film in all four pins.

Issue 39 asks that the lubricated joint-force peaks at 85 and 130 µm be "within the range a
Reynolds film gives", stated beside an independent computation. This script is that
computation: NumPy and SciPy only — it does not import jointplay's model, kernels or film
code. It reads the preset's numbers from its TOML file, writes the equations of motion of the
three moving links itself (Newton–Euler in the plane, the crank's rotation prescribed, every
pin a force element), and takes the film force from the short-bearing Reynolds equation by
integrating the pressure numerically over the film angle, not from closed forms:

    h³ ∂²p/∂z² = 12 μ (w sin θ − ė_r cos θ),  h = c (1 − ε cos θ),
    w = |e| ((ω_j + ω_b)/2 − γ̇) = |e| (ω_j + ω_b)/2 − ė·t

(θ from the line of centres n = e/|e|, t = ẑ × n; derived from the short-bearing equation
∂/∂z(h³ ∂p/∂z) = 6 μ U ∂h/∂x + 12 μ ∂h/∂t with U = R (ω_j + ω_b), the angle measured in a
fixed frame: Pinkus & Sternlicht, *Theory of Hydrodynamic Lubrication*, 1961; Frêne et al.,
*Hydrodynamic Lubrication*, 1997). With p = 0 at z = ±L/2, ∫p dz = (μ L³ / h³)(ė_r cos θ −
w sin θ), and the force on the journal is F = −R ∫ (∫p dz)(cos θ n + sin θ t) dθ over

- ``full``: the whole film, 0 ≤ θ < 2π (uncavitated);
- ``gumbel``: only where the pressure is positive (Gümbel's half-Sommerfeld condition): the
  half-turn where ė_r cos θ − w sin θ > 0, which moves with the ratio of squeeze to wedge;

and, for comparison with the lubricated-joint literature's closed forms,

- ``fixed-half``: the π-film closed forms as Flores, Ambrósio, Claro & Lankarani (Mech. Mach.
  Theory 41, 2006) write them after Pinkus & Sternlicht, the squeeze integrated over the
  wedge's fixed half (not a solution of the equation above when both act).

The integrals use composite Gauss–Legendre quadrature (64 panels × 8 points over the
interval), checked against the full film's closed forms at ε = 0.97 when the script starts.
SciPy's Radau integrates (rtol 1e-10); the peaks of the analysed revolution are located on
the dense output (a 20 000-point grid, then a bounded search around the largest points).

Run: ``python benchmarks/independent_fourbar_film.py`` (a few minutes on 2 cores); add
``--compare`` to run jointplay's ``simulate`` with the same settings beside it.
"""

from __future__ import annotations

import argparse
import math
import time
import tomllib
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import minimize_scalar

PRESET = Path(__file__).resolve().parents[1] / "src/jointplay/data/presets/paper-fourbar.toml"
VISCOSITY = 0.05  # Pa·s, the default oil
FILM_LENGTH = 0.010  # m: the bore's length, the links' 10 mm thickness

_GL_X, _GL_W = np.polynomial.legendre.leggauss(8)
_PANELS = 64


def _mm(text: str) -> float:
    value, unit = text.split()
    return float(value) * {"mm": 1e-3, "kg": 1.0}[unit]


def _quadrature(lo: float, hi: float) -> tuple[np.ndarray, np.ndarray]:
    edges = np.linspace(lo, hi, _PANELS + 1)
    half = 0.5 * (edges[1:] - edges[:-1])
    mid = 0.5 * (edges[1:] + edges[:-1])
    nodes = (mid[:, None] + half[:, None] * _GL_X[None, :]).ravel()
    weights = (half[:, None] * _GL_W[None, :]).ravel()
    return nodes, weights


_FULL = _quadrature(0.0, 2.0 * math.pi)
_HALF = _quadrature(-0.5 * math.pi, 0.5 * math.pi)


class WallReached(RuntimeError):
    """A film without a cushion let the pin reach its bearing's wall (ε ≥ 1)."""


def film_force(
    film: str, eps: float, e_r: float, w: float, c: float, r: float
) -> tuple[float, float]:
    """(F_r, F_t) on the journal, N, in the (n, t) frame."""
    k = VISCOSITY * FILM_LENGTH**3 / c**3
    if film == "fixed-half":  # the literature's closed forms (Flores et al. 2006)
        if eps >= 1.0:
            raise WallReached(f"the pin reaches the wall (ε = {eps:.4f})")
        om = w / max(eps * c, 1e-300) if eps > 0 else 0.0  # ω_eff = w / |e|
        de = e_r / c
        g = 1.0 - eps * eps
        base = VISCOSITY * r * FILM_LENGTH**3 / c**2
        f_r = -base * (2 * eps**2 * om / g**2 + math.pi * (1 + 2 * eps**2) * de / (2 * g**2.5))
        f_t = base * (math.pi * eps * om / (2 * g**1.5) + 2 * eps * de / g**2)
        return f_r, f_t
    if film == "full":
        theta, weight = _FULL
    else:  # positive where ė_r cos θ − w sin θ = ρ cos(θ + β) > 0
        beta = math.atan2(w, e_r)
        theta, weight = _HALF[0] - beta, _HALF[1]
    cos, sin = np.cos(theta), np.sin(theta)
    pz = k * (e_r * cos - w * sin) / (1.0 - eps * cos) ** 3
    if film == "gumbel":
        pz = np.maximum(pz, 0.0)  # round-off at the ends only
    return -r * float(np.dot(weight, pz * cos)), -r * float(np.dot(weight, pz * sin))


def _self_check() -> None:
    eps, c, r = 0.97, 130e-6, 0.005
    c0 = math.pi * VISCOSITY * r * FILM_LENGTH**3 / c**3
    f_r, _ = film_force("full", eps, 1e-3, 0.0, c, r)
    _, f_t = film_force("full", eps, 0.0, 1e-3, c, r)
    want_r = -c0 * (1 + 2 * eps**2) * (1 - eps**2) ** -2.5 * 1e-3
    want_t = c0 * (1 - eps**2) ** -1.5 * 1e-3
    assert abs(f_r / want_r - 1) < 1e-9 and abs(f_t / want_t - 1) < 1e-9, (f_r, want_r, f_t, want_t)
    # no squeeze: Gümbel's half is the wedge's half, as the closed forms
    g = film_force("gumbel", eps, 0.0, 1e-3, c, r)
    f = film_force("fixed-half", eps, 0.0, 1e-3, c, r)
    assert abs(g[0] / f[0] - 1) < 1e-9 and abs(g[1] / f[1] - 1) < 1e-9, (g, f)


class FourBar:
    """Crank (prescribed rotation), coupler and rocker, each pin a film force element."""

    def __init__(self, clearance: float, film: str) -> None:
        spec = tomllib.loads(PRESET.read_text())
        geo = {k: _mm(v) for k, v in spec["geometry"].items()}
        self.l2, self.l3, self.l4, self.l1 = (
            geo["crank"],
            geo["coupler"],
            geo["rocker"],
            geo["ground"],
        )
        self.speed = float(spec["driver"]["speed"].split()[0]) * 2 * math.pi / 60
        masses, inertias = [], []
        for name, length in (("crank", self.l2), ("coupler", self.l3), ("rocker", self.l4)):
            link = spec["links"][name]
            m = _mm(link["mass"])
            masses.append(m)
            inertias.append(
                m * (length**2 + _mm(link["width"]) ** 2) / 12
            )  # a bar about its centre
        self.m = np.array(masses)
        self.inertia = np.array(inertias)
        self.radius = {j: 0.5 * _mm(spec["joints"][j]["diameter"]) for j in ("O2", "A", "B", "O4")}
        self.c = clearance
        self.film = film
        # body 0 crank (O2 at 0, A at l2), 1 coupler (A at 0, B at l3), 2 rocker (O4 at 0, B at l4);
        # -1 the ground. (bearing body, its point, journal body, its point) as jointplay's
        # joints list them (link_a the bearing, link_b the journal).
        self.joints = {
            "O2": (-1, (0.0, 0.0), 0, 0.0),
            "A": (0, self.l2, 1, 0.0),
            "B": (1, self.l3, 2, self.l4),
            "O4": (-1, (self.l1, 0.0), 2, 0.0),
        }
        self.com = np.array([0.5 * self.l2, 0.5 * self.l3, 0.5 * self.l4])

    def crank(self, t: float) -> tuple[float, float]:
        return self.speed * t, self.speed

    def _body(self, y: np.ndarray, t: float, body: int):
        """(x, y, θ, vx, vy, ω) of body's centre of mass."""
        if body == 0:
            th, om = self.crank(t)
            return y[0], y[1], th, y[8], y[9], om
        i = 2 + 3 * (body - 1)
        return y[i], y[i + 1], y[i + 2], y[8 + i], y[8 + i + 1], y[8 + i + 2]

    def _point(self, y, t, body, local):
        if body < 0:
            return np.array(local), np.zeros(2), 0.0, np.zeros(2)
        x, yy, th, vx, vy, om = self._body(y, t, body)
        s = local - self.com[body]  # along the link's axis
        arm = np.array([s * math.cos(th), s * math.sin(th)])
        vel = np.array([vx - om * arm[1], vy + om * arm[0]])
        return np.array([x, yy]) + arm, vel, om, arm

    def joint_forces(self, y: np.ndarray, t: float):
        """{joint: (force on the journal (2,), bearing body, its arm, journal body, its arm)}."""
        out = {}
        for name, (a, pa, b, pb) in self.joints.items():
            ra, va, oa, arm_a = self._point(y, t, a, pa)
            rb, vb, ob, arm_b = self._point(y, t, b, pb)
            e = rb - ra
            ed = vb - va
            size = math.hypot(*e)
            n = e / size if size > 0 else np.array([1.0, 0.0])
            tv = np.array([-n[1], n[0]])
            e_r = float(ed @ n)
            w = size * 0.5 * (oa + ob) - float(ed @ tv)
            f_r, f_t = film_force(self.film, size / self.c, e_r, w, self.c, self.radius[name])
            out[name] = (f_r * n + f_t * tv, a, arm_a, b, arm_b, size / self.c)
        return out

    def rhs(self, t: float, y: np.ndarray) -> np.ndarray:
        force = np.zeros(8)  # crank x, y; coupler x, y, θ; rocker x, y, θ
        for f, a, arm_a, b, arm_b, _ in self.joint_forces(y, t).values():
            for body, arm, sign in ((b, arm_b, 1.0), (a, arm_a, -1.0)):
                if body < 0:
                    continue
                fx, fy = sign * f
                if body == 0:
                    force[0] += fx
                    force[1] += fy
                else:
                    i = 2 + 3 * (body - 1)
                    force[i] += fx
                    force[i + 1] += fy
                    force[i + 2] += arm[0] * fy - arm[1] * fx
        mass = np.array([self.m[0], self.m[0], self.m[1], self.m[1], self.inertia[1],
                         self.m[2], self.m[2], self.inertia[2]])  # fmt: skip
        return np.concatenate([y[8:], force / mass])

    def steady_start(self) -> np.ndarray:
        """The nominal linkage at crank angle 0 moving with its nominal velocities, pins centred."""
        a = np.array([self.l2, 0.0])
        o4 = np.array([self.l1, 0.0])
        d = math.hypot(*(o4 - a))
        # B on the circles |B − A| = l3, |B − O4| = l4, above the line A–O4 (branch 1)
        along = (self.l3**2 - self.l4**2 + d**2) / (2 * d)
        height = math.sqrt(self.l3**2 - along**2)
        u = (o4 - a) / d
        b = a + along * u + height * np.array([-u[1], u[0]])
        th3 = math.atan2(*(b - a)[::-1])
        th4 = math.atan2(*(b - o4)[::-1])
        va = self.speed * np.array([-a[1], a[0]])
        # v_A + ω3 ẑ×(B − A) = ω4 ẑ×(B − O4)
        ab, ob = b - a, b - o4
        mat = np.array([[-ab[1], ob[1]], [ab[0], -ob[0]]])
        om3, om4 = np.linalg.solve(mat, -va)
        y = np.zeros(16)
        y[0:2] = 0.5 * a
        y[8:10] = 0.5 * va
        y[2:5] = [*(a + 0.5 * ab), th3]
        y[10:13] = [*(va + om3 * 0.5 * np.array([-ab[1], ab[0]])), om3]
        y[5:8] = [*(o4 + 0.5 * ob), th4]
        y[13:16] = [*(om4 * 0.5 * np.array([-ob[1], ob[0]])), om4]
        return y


def peaks(clearance: float, film: str, settle: int = 2, rtol: float = 1e-10) -> dict[str, float]:
    model = FourBar(clearance, film)
    period = 2 * math.pi / model.speed
    t_end = (settle + 1) * period
    atol = np.concatenate([np.full(8, 1e-13), np.full(8, 1e-9)])
    atol[[4, 7]] = 1e-12  # angles, rad
    started = time.perf_counter()
    sol = solve_ivp(model.rhs, (0.0, t_end), model.steady_start(), method="Radau", rtol=rtol,
                    atol=atol, dense_output=True)  # fmt: skip
    if not sol.success:
        raise RuntimeError(sol.message)

    def magnitude(t: float, joint: str) -> float:
        return float(np.hypot(*model.joint_forces(sol.sol(t), t)[joint][0]))

    grid = np.linspace(settle * period, t_end, 20_001)
    result = {"eps_max": max(max(v[5] for v in model.joint_forces(sol.sol(t), t).values())
                             for t in grid[::10])}  # fmt: skip
    for joint in model.joints:
        values = np.array([magnitude(t, joint) for t in grid])
        best = 0.0
        for k in np.argsort(values)[-3:]:
            lo, hi = grid[max(k - 1, 0)], grid[min(k + 1, grid.size - 1)]
            found = minimize_scalar(lambda t, j=joint: -magnitude(t, j), bounds=(lo, hi),
                                    method="bounded", options={"xatol": 1e-12})  # fmt: skip
            best = max(best, values[k], -found.fun)
        result[joint] = best
    result["steps"] = float(sol.t.size - 1)
    result["seconds"] = time.perf_counter() - started
    return result


def _jointplay(clearance: float, film: str, rtol: float | None = None) -> dict[str, float]:
    """jointplay's ``simulate`` (the command, as a user runs it) with the same settings."""
    import json
    import subprocess
    import sys
    import tempfile

    name = {"gumbel": "short-bearing-pi", "full": "short-bearing-full"}[film]
    with tempfile.TemporaryDirectory() as folder:
        command = [sys.executable, "-m", "jointplay", "simulate", "--preset", "paper-fourbar",
                   "--clearance", f"{clearance * 1e6:g} um", "--film-model", name, "--settle", "2",
                   "--revolutions", "1", "--no-plots", "--out", f"{folder}/run"]  # fmt: skip
        if rtol is not None:
            command += ["--rtol", f"{rtol:g}"]
        subprocess.run(command, check=True, capture_output=True)
        summary = json.loads(Path(f"{folder}/run/summary.json").read_text())
    return {j: summary["peaks"][f"F_{j}"]["value"] for j in ("O2", "A", "B", "O4")}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--clearances", default="85,130", help="µm, comma-separated")
    parser.add_argument("--films", default="gumbel,full,fixed-half")
    parser.add_argument("--compare", action="store_true", help="run jointplay beside it")
    args = parser.parse_args()
    _self_check()
    print("clearance  film          F_O2     F_A      F_B      F_O4  (N, peaks of revolution 3)")
    for um in (float(v) for v in args.clearances.split(",")):
        for film in args.films.split(","):
            try:
                got = peaks(um * 1e-6, film)
            except WallReached as wall:
                print(f"{um:6.0f} µm  {film:10s} no answer: {wall}")
                continue
            row = " ".join(f"{got[j]:8.3f}" for j in ("O2", "A", "B", "O4"))
            print(
                f"{um:6.0f} µm  {film:10s} {row}   (largest ε {got['eps_max']:.4f}; "
                f"{got['steps']:.0f} steps, {got['seconds']:.0f} s)"
            )
            if args.compare and film != "fixed-half":
                for rtol in (None, 1e-9):
                    theirs = _jointplay(um * 1e-6, film, rtol)
                    row = " ".join(f"{theirs[j]:8.3f}" for j in ("O2", "A", "B", "O4"))
                    label = "jointplay" if rtol is None else f"rtol {rtol:g}"
                    print(f"{'':9s}  {label:10s} {row}")


if __name__ == "__main__":
    main()
