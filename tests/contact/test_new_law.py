"""Adding a Hunt–Crossley-type law takes one class and no edit elsewhere (docs/contact-laws.md,
"Adding a law").

The law below is defined here only: a χ(e) that no registered Hunt–Crossley-type law has (the
exact one of §2.3, which the built-in ``restitution`` law uses on a ``penalty`` field), on the
inherited kernel force form and packing. It must run through the compiled kernel, the
simulator and the batch engine's per-sample packing, and reproduce the built-in law exactly.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np
import pytest

from jointplay._kernels import contact as kc
from jointplay._kernels import ids
from jointplay.contact.laws import CONTACT_LAWS, HuntCrossleyTypeLaw, RestitutionLaw
from jointplay.contact.restitution import chi_for_restitution, single_impact
from jointplay.dynamics.batch_inputs import _law_columns
from jointplay.dynamics.clearance import ClearanceJoint
from jointplay.dynamics.simulate import Start, simulate


@dataclass(frozen=True)
class ExactRestitutionLaw(HuntCrossleyTypeLaw):
    """Hunt–Crossley form with the exact χ(e) of docs/contact-laws.md §2.3 (test only)."""

    name: ClassVar[str] = "exact-restitution (test)"
    citation: ClassVar[str] = "docs/contact-laws.md §2.3"
    equation: ClassVar[str] = "F = K δ^n (1 + χ(e) δ̇/v0),  g(χ) = g(-χ e)"

    @staticmethod
    def chi_of(e: float) -> float:
        """Exact χ(e): one impact rebounds with exactly e."""
        return chi_for_restitution(e)


K, N, E = 2e9, 1.0, 0.6
NEW = ExactRestitutionLaw(stiffness=K, restitution=E, exponent=N)
BUILT_IN = RestitutionLaw(penalty=K, restitution=E, exponent=N)


def test_the_new_law_is_not_registered_and_packs_like_the_built_in() -> None:
    assert ExactRestitutionLaw not in CONTACT_LAWS.values()
    assert NEW.law_id == ids.LAW_HUNT_CROSSLEY
    np.testing.assert_array_equal(NEW.params(), BUILT_IN.params())
    assert NEW.params()[ids.HC_CHI] == chi_for_restitution(E)
    others = [cls for cls in CONTACT_LAWS.values() if issubclass(cls, HuntCrossleyTypeLaw)]
    assert all(not np.isclose(cls.chi_of(E), NEW.chi) for cls in others)  # a new χ(e)


def test_single_impact_rebounds_with_exactly_e() -> None:
    """Closed form: with the exact χ(e) the rebound speed is e times the impact speed."""
    result = single_impact(NEW, mass=0.5, impact_speed=0.3)
    assert result.restitution == pytest.approx(E, rel=1e-6)


def test_kernel_equals_the_reference_force() -> None:
    delta = np.linspace(-1e-6, 3e-5, 31)
    for rate, v0 in ((0.2, 0.3), (-0.1, 0.3), (0.05, 0.0)):
        kernel = [kc.normal_force(NEW.law_id, NEW.params(), 0, d, rate, v0) for d in delta]
        np.testing.assert_allclose(kernel, NEW.force(delta, rate, v0), rtol=1e-13, atol=0.0)


def test_simulate_reproduces_the_built_in_law_exactly(paper_fourbar) -> None:
    def run(law):
        joints = [ClearanceJoint(name, 21e-6, 5e-3, law) for name in ("A", "B")]
        return simulate(paper_fourbar, joints, revolutions=0.1, start=Start("steady"), settle=0)

    new, built_in = run(NEW), run(BUILT_IN)
    assert sum(new.solver_stats["impacts"].values()) > 0  # the pins really hit
    np.testing.assert_array_equal(new.y, built_in.y)
    softer = run(ExactRestitutionLaw(stiffness=K, restitution=0.95, exponent=N))
    assert not np.array_equal(softer.y[-1], new.y[-1])  # the restitution reaches the kernel


def test_batch_packing_follows_the_declared_slots() -> None:
    """Per-sample changes: ``stiffness`` goes straight into its slot, ``restitution`` is
    packed as χ(e) — what the batch engine once found by probing the fields."""
    assert NEW.packed_slot("stiffness") == ids.HC_STIFFNESS
    assert NEW.packed_slot("restitution") is None
    changes = {"stiffness": np.array([1e9, 3e9, 1e9]), "restitution": np.array([0.5, 0.9, 2.0])}
    packed, ok, errors = _law_columns(NEW, changes, 3)
    np.testing.assert_array_equal(packed[:2, ids.HC_STIFFNESS], [1e9, 3e9])
    np.testing.assert_array_equal(
        packed[:2, ids.HC_CHI], [chi_for_restitution(0.5), chi_for_restitution(0.9)]
    )
    assert list(ok) == [True, True, False]  # e = 2 is out of range: that sample fails
    assert "restitution" in errors[2]


def test_a_new_force_form_is_written_once() -> None:
    """The single engine, the batch lanes on the CPU and the CUDA kernel compile one
    ``normal_force``, ``friction_force`` and ``law_slopes``, the lane source's: a law with a new
    force form is a branch there and its class in ``contact/laws.py`` — two source files
    (docs/contact-laws.md §2.6; the JAX dialect, a third, refuses the id until it is ported)."""
    import ast
    from pathlib import Path

    import jointplay._kernels
    from jointplay._kernels.lanes import build, cpu, source, source_radau

    originals = {
        "normal_force": source.normal_force,
        "friction_force": source.friction_force,
        "law_slopes": source_radau.law_slopes,
    }
    cuda_like = build.build(lambda f: f)  # the namespace the CUDA kernel compiles
    for name, original in originals.items():
        for compiled in (getattr(kc, name), cpu.compiled[name]):
            assert compiled.py_func.__code__ is original.__code__, name
        assert cuda_like[name].__code__ is original.__code__, name
    kernels = Path(jointplay._kernels.__file__).parent
    defining = sorted(
        str(path.relative_to(kernels))
        for path in kernels.rglob("*.py")
        if "jax" not in path.parts
        for node in ast.parse(path.read_text(encoding="utf-8")).body
        if isinstance(node, ast.FunctionDef) and node.name in originals
    )
    assert defining == ["lanes/source.py", "lanes/source.py", "lanes/source_radau.py"]
