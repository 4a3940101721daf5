"""The one numba configuration every kernel uses: compiled once, cached on disk, fastmath off.

Set ``NUMBA_DISABLE_JIT=1`` to run the kernels as plain Python (the tests do, once).
"""

from numba import njit

jit = njit(cache=True, fastmath=False, nogil=True)
