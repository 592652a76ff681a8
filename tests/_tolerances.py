"""Tolerances shared by several test modules: one per kind of comparison, defined once.

Imported as ``from _tolerances import ...`` (``tests`` is on pytest's ``pythonpath``).

* The accuracy contract (issue 14): peaks of an integration at the default tolerances
  against a converged solution, or the batch engine against the single engine, agree to
  :data:`CONTRACT_OMEGA_RTOL` on angular velocities and :data:`CONTRACT_OTHER_RTOL` on
  angular accelerations, joint forces and the driver torque (relative).
* :data:`SAME_ALGORITHM_RTOL`: two implementations of one algorithm that take the same steps
  (the JAX kernel against the Numba kernel, the GPU backend against the CPU one): round-off
  carried through the steps, nothing else. Largest measured: 3.6e-9 (the alpha3 peak of
  ``tests/dynamics/test_batch.py``'s GPU/CPU lanes; the other peaks there ≤ 4.6e-10, a design
  on both backends ≤ 2.4e-10, the kernels' explicit four-bar ≤ 4e-11); about 10x that. A
  lane where round-off tips one step's acceptance goes its own way within the contract:
  such comparisons say so and use the contract.
"""

from __future__ import annotations

CONTRACT_OMEGA_RTOL = 1e-5
CONTRACT_OTHER_RTOL = 1e-3
SAME_ALGORITHM_RTOL = 3e-8


def contract_rtol(name: str) -> float:
    """The contract's relative bound for the peak ``name`` (``omega3``, ``F_A_peak``, ...)."""
    return CONTRACT_OMEGA_RTOL if name.startswith("omega") else CONTRACT_OTHER_RTOL
