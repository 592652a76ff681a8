"""JAX ports of the compiled kernels, for the batch engine's GPU backend.

:mod:`.eom` is the equations of motion of :mod:`jointplay._kernels.eom` written for one lane
(one sample) in ``jax.numpy``; :mod:`.integrate` holds the explicit (Dormand–Prince 5(4)) and
implicit (Radau IIA 5) batch integrators built on it. The entry point is
:func:`jointplay._kernels.jax_batch.run_batch`. Every module of this package imports JAX at
its top: import them only through :mod:`jointplay._kernels.jax_batch`, which does so when a
batch is run, so that ``import jointplay`` never imports JAX.
"""
