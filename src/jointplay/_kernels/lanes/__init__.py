"""The batch lanes written once for the CPU (Numba ``njit``) and NVIDIA GPUs (numba-cuda).

- :mod:`~jointplay._kernels.lanes.source`: the per-lane equations (contact laws, friction,
  ideal joints, driver) and the explicit lane, in the subset of Python both targets compile;
- :mod:`~jointplay._kernels.lanes.source_radau`: the implicit lane (Radau IIA, the
  production Radau kernel's algorithm and hooks, with a small LU per lane) in the same
  subset (every mechanism, outside the sustained-contact mode);
- :mod:`~jointplay._kernels.lanes.build`: compiles that source for one target;
- :mod:`~jointplay._kernels.lanes.cpu`: the CPU compilation and its batch drivers
  (what :func:`jointplay._kernels.batch.run_batch` runs for ``method="explicit"``; its
  implicit drivers are tested against the production implicit lanes, not used by them);
- :mod:`~jointplay._kernels.lanes.cuda_kernel`, :mod:`~jointplay._kernels.lanes.cuda`: the
  CUDA kernel, one thread per lane, and its ``run_batch`` (experimental: built and tested on
  numba-cuda's simulator, not yet measured on a GPU); :mod:`~jointplay._kernels.lanes.limits`
  the sizes of its per-thread arrays and whether the simulator runs (read by both);
- :mod:`~jointplay._kernels.lanes.contract`: :class:`BatchKernelOutput`, what every batch
  kernel returns (the CPU engine, the CUDA lanes and the JAX backend).

Each integrator of the lanes is one source module, found here by its name (``source*``):
:data:`SOURCES`. A module whose ``LANE`` record names an integrator is one for every engine
that compiles the source: the record says what the integrator is
(:data:`jointplay._kernels.integrators.INTEGRATORS` reads it), the lane's name, its steps'
prefix and its work: the CPU's allocator, and the shapes and dtypes of its arrays, which the
GPU kernel allocates (:mod:`~jointplay._kernels.lanes.build`, :mod:`~jointplay._kernels.lanes.cpu`
and :mod:`~jointplay._kernels.lanes.cuda_kernel` read them); nothing else names it. A batch
method runs one integrator per engine (:func:`~jointplay._kernels.lanes.build.lane_for`). NumPy only: the
command line and the JAX backend read the records without Numba.
"""

from __future__ import annotations

import importlib
import pkgutil
import types


def _sources() -> tuple[types.ModuleType, ...]:
    """The lane source's modules, ``source`` first (the equations and the loop), then the
    others by name."""
    names = sorted(m.name for m in pkgutil.iter_modules(__path__) if m.name.startswith("source"))
    return tuple(importlib.import_module(f"{__name__}.{name}") for name in names)


#: The lane source's modules: the equations and the loop (``source``, with DOPRI5's steps),
#: then each further integrator's steps in a module of its own.
SOURCES = _sources()
