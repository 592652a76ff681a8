"""Compile-time sizes of the GPU lane's per-thread work arrays (``cuda.local.array`` needs
constants): a mechanism must fit them (:func:`jointplay._kernels.lanes.cuda.run_batch`
checks and says which one it exceeds). The paper's four-bar with four clearance joints uses
a state of 24, 11 quantities and 4 clearance joints."""

#: Largest state size 2·3nb + 2 + nc.
MAX_STATE = 40
#: Largest number of quantities 2 nb + nj + 1.
MAX_Q = 24
#: Largest number of clearance joints.
MAX_CLEAR = 8
#: Largest number of constraint rows (2 per ideal joint, 1 for the driver): a four-bar's four
#: joints all ideal and its driver.
MAX_ROWS = 9
