"""What the CUDA lanes are compiled for: the sizes of the GPU lane's per-thread work arrays
(``cuda.local.array`` needs constants), and whether numba-cuda's simulator runs
(:func:`simulated`). Read by the driver (:mod:`jointplay._kernels.lanes.cuda`) and the
kernel (:mod:`jointplay._kernels.lanes.cuda_kernel`) alike, so that neither imports the other
for them.

A mechanism must fit the sizes (:func:`jointplay._kernels.lanes.cuda.run_batch` checks and
says which one it exceeds). The paper's four-bar with four clearance joints uses a state of
24, 11 quantities, 4 clearance joints and 9 coordinates."""

import os

#: Largest state size 2·3nb + 2 + nc.
MAX_STATE = 40
#: Largest number of quantities 2 nb + nj + 1.
MAX_Q = 24
#: Largest number of clearance joints.
MAX_CLEAR = 8
#: Largest number of constraint rows (2 per ideal joint, 1 for the driver): a four-bar's four
#: joints all ideal and its driver.
MAX_ROWS = 9
#: Largest number of coordinates 3 nb: the implicit lane's Newton matrices are that square
#: (the positions eliminated, RADAU5's M1): a four-bar's 9, a mechanism of four moving bodies.
MAX_COORDS = 12
#: Most work arrays an integrator's record may declare (its ``shapes``): the kernel's slots.
MAX_WORK_ARRAYS = 8


def simulated() -> bool:
    """Whether numba-cuda runs its simulator in this process (``NUMBA_ENABLE_CUDASIM=1``)."""
    return os.environ.get("NUMBA_ENABLE_CUDASIM", "0") not in ("", "0")
