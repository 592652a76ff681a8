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
"""
