"""The one numba configuration every kernel uses: compiled once, cached on disk, fastmath off.

Set ``NUMBA_DISABLE_JIT=1`` to run the kernels as plain Python: ``make test`` runs the tests
marked ``jit_off`` (the DG kernel twin tests, test/solvers/dg) a second time that way.
"""

from numba import njit

jit = njit(cache=True, fastmath=False, nogil=True)
