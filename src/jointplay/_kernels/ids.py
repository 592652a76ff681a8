"""The numbers every kernel dialect shares, defined once: contact-law and friction-law ids and
their packed parameter layouts, the packed model's slots, integration statuses, counters and
the numerical constants of the step and Jacobian rules.

Plain Python, no Numba: the single engine (:mod:`jointplay._kernels.eom`,
:mod:`~jointplay._kernels.contact`, :mod:`~jointplay._kernels.driver`), the lane source
(:mod:`jointplay._kernels.lanes.source`, compiled for the CPU and CUDA by
:mod:`jointplay._kernels.lanes.build`, which reads the source's upper-case globals, so these
names reach every target) and the JAX dialect import them from here; nothing copies them.

Units are SI where a constant has one (m, s, N).
"""

from __future__ import annotations

import signal
import sys

# --- normal-force law ids (jointplay._kernels.contact; docs/contact-laws.md) ------------------
LAW_IMPACT = 0
LAW_HERTZ = 1
LAW_KELVIN_VOIGT = 2
LAW_RESTITUTION = 3
LAW_HUNT_CROSSLEY = 4
LAW_LANKARANI_NIKRAVESH = 5
LAW_FLORES = 6
LAW_GONTHIER = 7
LAW_HU_GUO = 8
LAW_HERBERT_MCWHANNELL = 9
LAW_LEE_WANG = 10
LAW_ZHIYING_QISHAO = 11
#: First and last id of the Hunt–Crossley family (shared layout ``HC_*``).
HC_FIRST = LAW_RESTITUTION
HC_LAST = LAW_ZHIYING_QISHAO

# --- packed layouts of the normal-force laws ---------------------------------------------------
IMPACT_STIFFNESS, IMPACT_EXPONENT, IMPACT_C_MAX, IMPACT_D_MAX, IMPACT_SIZE = 0, 1, 2, 3, 4
HERTZ_STIFFNESS, HERTZ_EXPONENT, HERTZ_SIZE = 0, 1, 2
KV_STIFFNESS, KV_DAMPING, KV_SIZE = 0, 1, 2
HC_STIFFNESS, HC_EXPONENT, HC_CHI, HC_V_FLOOR, HC_SIZE = 0, 1, 2, 3, 4

# --- friction law ids and layouts --------------------------------------------------------------
FRICTION_NONE = 0
FRICTION_AMBROSIO = 1
FRICTION_ADAMS = 2
NONE_SIZE = 0
AMBROSIO_MU, AMBROSIO_V0, AMBROSIO_V1, AMBROSIO_SIZE = 0, 1, 2, 3
ADAMS_MU_STATIC, ADAMS_MU_DYNAMIC, ADAMS_V_STATIC, ADAMS_V_DYNAMIC, ADAMS_SIZE = 0, 1, 2, 3, 4

# --- the packed model (jointplay._kernels.eom.EomModel) ----------------------------------------
#: The packed model's fields in ``EomModel``'s order: the order of the field lengths that open
#: ``ipar`` (:func:`jointplay._kernels.eom.pack`); then the float fields in their order in
#: ``rpar``, the integer fields in theirs in ``ipar``.
MODEL_FIELDS = (
    "mass", "gravity", "joint_int", "joint_f", "active", "driver", "clear_joint", "geom",
    "law_id", "law_p", "fric_id", "fric_p", "settings",
)  # fmt: skip
FLOAT_FIELDS = ("mass", "gravity", "joint_f", "driver", "geom", "law_p", "fric_p", "settings")
INT_FIELDS = ("joint_int", "active", "clear_joint", "law_id", "fric_id")
#: Slots of the ``settings`` block: the contact-onset tolerance (m), the projection tolerance
#: (m or rad), the entry rate that marks a contact event entered at a rate <= 0 (m/s), and the
#: largest capture speed of the joints (m/s; 0: the sustained-contact mode off at every joint),
#: derived from their ``G_CAPTURE`` by the model's builder: the right-hand side's one-comparison
#: gate of the mode (a loop over the joints there cost 6–14 % of ``bench_clearance.py``).
S_ONSET_TOL, S_PROJ_TOL, S_V_MARK, S_CAPTURE_MAX = 0, 1, 2, 3
N_SETTINGS = 4
#: Columns of the ``geom`` table, one row per clearance joint: bearing radius, journal radius,
#: radial clearance (m); the joint's film coefficient (N·s/m; 0: dry): the linear film's c_e,
#: or, for a Reynolds film, C0 = π μ R L³ / c³ (the full film's squeeze coefficient at ε = 0);
#: the capture speed of its sustained-contact mode (m/s; 0: the mode off for this joint); the
#: film's form (``FILM_*``, a float holding the id); the composite RMS roughness σ of the pin
#: and the hole, m (``G_ROUGHNESS``: a Reynolds film's asperity contact, :data:`LAMBDA_FULL_FILM`).
G_R_BEARING, G_R_JOURNAL, G_CLEARANCE, G_FILM, G_CAPTURE, G_FILM_MODEL = 0, 1, 2, 3, 4, 5
G_ROUGHNESS = 6
N_GEOM = 7
#: The film forms (docs/contact.md, "Reynolds films"): the linear isotropic damper −c_e ė
#: (the default), the short-bearing Reynolds film with Gümbel's half-film cavitation (the
#: positive part of the full film's pressure) and the short-bearing full (2π) film.
FILM_LINEAR, FILM_SHORT_PI, FILM_SHORT_FULL = 0, 1, 2
#: The largest eccentricity ratio ε = |e|/c a Reynolds film's coefficients are evaluated at:
#: beyond it (the pin nearer the wall than 0.5 % of c) they are held, so the film force stays
#: finite and continuous where the pin reaches the wall and the contact law takes over.
FILM_EPS_CAP = 0.995
#: The film-thickness ratios λ = h_min / σ (h_min = c − |e|, σ the composite roughness) of
#: the lubrication regimes (docs/contact.md, "The film-to-contact transition"; the Stribeck
#: reading of Hamrock, Schmid & Jacobson): full film for λ ≥ :data:`LAMBDA_FULL_FILM`, mixed
#: down to :data:`LAMBDA_BOUNDARY`, boundary below. Under a Reynolds film the asperities touch
#: where λ falls below LAMBDA_FULL_FILM: the dry law acts on δ_a = |e| − (c − λ_t σ), λ_t =
#: LAMBDA_FULL_FILM, beside the film (load sharing, Johnson, Greenwood & Poon 1972).
LAMBDA_FULL_FILM = 3.0
LAMBDA_BOUNDARY = 1.0
#: The v0 slot of a clearance joint in sustained contact (locked onto |e| = c); any negative
#: value reads as locked.
LOCKED = -1.0
#: Tolerance of the sustained-contact mode's release control: a step whose end has a locked
#: joint's F_N below −RELEASE_TOL · max(F_N at its start, 1 N) is retried, shortened to the
#: sign change.
RELEASE_TOL = 1e-3

# --- integration statuses and counters ---------------------------------------------------------
#: Statuses an integration ends with (``STATUS_RUNNING`` while it goes on).
STATUS_SUCCESS = 0
STATUS_STEP_TOO_SMALL = -1
STATUS_TOO_MANY_STEPS = -2
STATUS_NON_FINITE = -3
#: A SIGINT or SIGTERM arrived during the integration.
STATUS_INTERRUPTED = -4
STATUS_RUNNING = 1
#: The signals that stop an integration, as the bytes Python's C-level signal handler writes
#: to its wakeup file descriptor.
SIGINT, SIGTERM = int(signal.SIGINT), int(signal.SIGTERM)
INTERRUPT_SIGNALS = (SIGINT, SIGTERM)
#: Meaning of the entries of a single-engine integration's ``counters`` array.
COUNTER_NAMES = (
    "nfev", "njev", "nlu", "n_steps", "n_rejected_error", "n_rejected_newton", "n_rejected_check",
)  # fmt: skip
NFEV, NJEV, NLU, NSTEPS, NREJ_ERROR, NREJ_NEWTON, NREJ_CHECK = range(7)
#: Counters per batch lane: accepted steps, rejected steps, right-hand side evaluations.
K_STEPS, K_REJECTED, K_RHS = 0, 1, 2
#: A traced lane's (the single engine's, ``source.RECORD``) further counters: Jacobians, LU
#: factorisations (two per Newton matrix: real and complex), the rejections by a Newton
#: iteration that did not converge and by the contact-onset control (those by the error test
#: are the rest of ``K_REJECTED``).
K_JAC, K_LU, K_REJ_NEWTON, K_REJ_CHECK = 3, 4, 5, 6
N_TRACE_COUNTS = 7

# --- numerical constants of the step and Jacobian rules ----------------------------------------
EPS = sys.float_info.epsilon
#: SciPy's finite-difference Jacobian constants (``_ivp/common.py``, ``num_jac``).
NUM_JAC_DIFF_REJECT = EPS**0.875
NUM_JAC_DIFF_SMALL = EPS**0.75
NUM_JAC_DIFF_BIG = EPS**0.25
NUM_JAC_MIN_FACTOR = 1e3 * EPS
NUM_JAC_FACTOR_INCREASE = 10.0
NUM_JAC_FACTOR_DECREASE = 0.1
#: Not in SciPy: the largest relative difference step. SciPy multiplies a column's factor by
#: 10 at every Jacobian in which the column's difference is small, without bound, so a
#: component on which f (nearly) does not depend gets an infinite step after ~300 Jacobians
#: and the Jacobian turns NaN (seen on a slider-crank: its slider angle is held by a
#: constraint). A step as large as the component itself (or its atol) is the cap.
NUM_JAC_MAX_FACTOR = 1.0
#: The contact laws' slopes in the closed-form Jacobian: relative step in δ, and the floor of
#: the rates (m/s) whose relative step is taken.
LAW_STEP = 1.4901161193847656e-08
RATE_FLOOR = 1e-3
#: The fixed-step differences of the Jacobian with ideal joints and film damping: relative
#: step and floor of the state component.
DIFF_STEP = 1.4901161193847656e-08
DIFF_FLOOR = 1e-3

# --- the single engine's workspace (one per integration; the CPU lanes' projection scratch)
#: The largest constraint violation max |Φ| seen after a step (m or rad), the number of
#: projections onto the ideal constraints, whether a step was accepted yet, and from
#: ``N_WORK`` on, per clearance joint, δ and δ̇ at the last accepted step's end.
W_MAX_VIOLATION, W_PROJECTIONS, W_HAS_PREVIOUS = 0, 1, 2
N_WORK = 3
