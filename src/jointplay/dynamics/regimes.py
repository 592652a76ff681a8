"""The lubrication regime of each clearance joint over a simulation: full film, mixed or
boundary, by the film-thickness ratio λ = h_min / σ (docs/contact.md, "The film-to-contact
transition").

h_min = c − |e| is the thinnest film of the joint (m; negative: the pin in the wall), σ its
composite RMS roughness (:attr:`~jointplay.dynamics.clearance.ClearanceJoint.roughness`).
The thresholds are the kernels' (:data:`~jointplay._kernels.ids.LAMBDA_FULL_FILM`,
:data:`~jointplay._kernels.ids.LAMBDA_BOUNDARY`): full film for λ ≥ 3, mixed for 1 ≤ λ < 3,
boundary below (the Stribeck reading of Hamrock, Schmid & Jacobson, *Fundamentals of Machine
Elements*, the λ-ratio chapter). A dry joint has no film: no regime. With σ = 0 every film
thicker than 0 counts as full film, and the pin at or in the wall as boundary.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from jointplay._kernels import ids
from jointplay._kernels.ids import LAMBDA_BOUNDARY, LAMBDA_FULL_FILM
from jointplay._kernels.lanes.build import lane_layout
from jointplay._kernels.lanes.source import LY_GEOM
from jointplay.dynamics.clearance import ClearanceJoint

__all__ = ["JointRegime", "asperity_play", "joint_regime", "regime_line", "regimes_of"]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class JointRegime:
    """The lubrication regimes of one joint over a stretch of time.

    Attributes:
        joint: the joint's name.
        roughness: its composite roughness σ, m.
        full_film, mixed, boundary: the fractions of the time in each regime (sum 1).
        h_min: the thinnest film over the time, m (negative: the pin in the wall).
    """

    joint: str
    roughness: float
    full_film: float
    mixed: float
    boundary: float
    h_min: float

    def describe(self) -> dict[str, Any]:
        """For ``summary.json``."""
        return {
            "roughness_m": self.roughness,
            "thresholds_lambda": {"full_film": LAMBDA_FULL_FILM, "boundary": LAMBDA_BOUNDARY},
            "full_film": self.full_film,
            "mixed": self.mixed,
            "boundary": self.boundary,
            "h_min_m": self.h_min,
        }


def joint_regime(
    joint: ClearanceJoint, t: FloatArray, ex: FloatArray, ey: FloatArray
) -> JointRegime:
    """The regimes of ``joint`` over the times ``t`` (s, increasing) with its eccentricity
    (``ex``, ``ey``) (m) there: each interval between two times counts by λ at its midpoint
    (the mean of its ends' h_min)."""
    t = np.asarray(t, dtype=float)
    h = joint.clearance - np.hypot(np.asarray(ex, dtype=float), np.asarray(ey, dtype=float))
    dt = np.diff(t)
    mid = 0.5 * (h[1:] + h[:-1])
    sigma = joint.roughness
    full = mid >= LAMBDA_FULL_FILM * sigma if sigma > 0 else mid > 0.0
    boundary = mid < LAMBDA_BOUNDARY * sigma if sigma > 0 else mid <= 0.0
    span = float(dt.sum())
    if not span > 0:
        raise ValueError("the regimes need a stretch of time")
    f_full = float(dt[full].sum()) / span
    f_boundary = float(dt[boundary].sum()) / span
    return JointRegime(
        joint=joint.joint,
        roughness=sigma,
        full_film=f_full,
        mixed=max(1.0 - f_full - f_boundary, 0.0),
        boundary=f_boundary,
        h_min=float(h.min()),
    )


def regimes_of(
    joints: tuple[ClearanceJoint, ...] | list[ClearanceJoint],
    steps: Mapping[str, Any],
    t0: float,
) -> dict[str, JointRegime | None]:
    """Each joint's regimes over the steps at ``t`` ≥ ``t0`` (s) of a simulation's step table
    ``steps`` (its ``t``, ``ex_<J>``, ``ey_<J>`` columns); ``None`` for a dry joint."""
    t = np.asarray(steps["t"], dtype=float)
    keep = t >= t0 - 1e-12
    out: dict[str, JointRegime | None] = {}
    for joint in joints:
        if not joint.film_damping > 0:
            out[joint.joint] = None
            continue
        ex = np.asarray(steps[f"ex_{joint.joint}"], dtype=float)[keep]
        ey = np.asarray(steps[f"ey_{joint.joint}"], dtype=float)[keep]
        out[joint.joint] = joint_regime(joint, t[keep], ex, ey)
    return out


def regime_line(name: str, regime: JointRegime | None) -> str:
    """One line of a joint's regimes: "O2: full film 100 %, mixed 0 %, boundary 0 %
    (h_min 3.2 µm, σ 1.12 µm)", or that it runs dry."""
    if regime is None:
        return f"{name}: dry (no lubricant)"
    h = regime.h_min * 1e6
    return (
        f"{name}: full film {100 * regime.full_film:.0f} %, mixed {100 * regime.mixed:.0f} %, "
        f"boundary {100 * regime.boundary:.0f} % (h_min {h:.2f} µm, σ "
        f"{regime.roughness * 1e6:.2f} µm; λ ≥ {LAMBDA_FULL_FILM:g} full film, < "
        f"{LAMBDA_BOUNDARY:g} boundary)"
    )


def full_film_throughout(regime: JointRegime | None) -> bool:
    """Whether a joint ran in full film all the time (no asperity contact)."""
    return regime is not None and math.isclose(regime.full_film, 1.0)


def asperity_play(rpar: FloatArray, ipar: NDArray[np.int64], n_clear: int) -> FloatArray:
    """How much sooner than the wall each clearance joint's dry law acts, m, per sample
    (``rpar``: (n, R), ``ipar``: the packed model's integers; (n, ``n_clear``) out): λ_t σ
    (at most c) under a Reynolds film, whose asperities touch at h_min = λ_t σ, 0 for a dry
    joint or the linear damper (the kernels' ``contact_clearance``). The kernels' δ of a joint
    minus this is its wall penetration |e| − c, the δ every output reports."""
    if n_clear == 0:
        return np.zeros((rpar.shape[0], 0))
    lay = lane_layout(ipar)
    start = int(lay[LY_GEOM])
    geom = rpar[:, start : start + ids.N_GEOM * n_clear].reshape(-1, n_clear, ids.N_GEOM)
    reynolds = (geom[..., ids.G_FILM] > 0.0) & (geom[..., ids.G_FILM_MODEL] != ids.FILM_LINEAR)
    play = np.minimum(LAMBDA_FULL_FILM * geom[..., ids.G_ROUGHNESS], geom[..., ids.G_CLEARANCE])
    return np.where(reynolds, play, 0.0)
