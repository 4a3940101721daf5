"""The three numba configurations of the kernels: compiled once, cached on disk, fastmath off.

``jit``: the kernels. Compiled **without numba's runtime (NRT)**: no reference counting of arrays.
With NRT, every array passed to a compiled callee, sliced or reshaped costs an atomic
increment and decrement of its owner's count; the DG right-hand side passes ~25 arrays down
four call levels, and these counts were ~40 % of a substep at the live configurations' meshes
(measured 2026-11-25, BENCHMARKS.md "Kernels without reference counting": SSP-RK3 substep at
L = 1730 m, N = 6, P = 2: 10.6 -> 6.1 us; bit-identical results). What this asks of a kernel:
it allocates nothing (no np.empty/zeros/array..., no lists) and returns no array it created (a
view of an argument made inside may be used and passed down, not returned). numba refuses
both at compile time ("NRT required but not enabled", "Only accept returning of array passed
into the function"), never silently; test/numerics/test_jit_modes.py checks the sources for both, and for
returned arrays and calls from a ``jit`` kernel to a ``jit_alloc`` function (which would
unbalance the counts without an error).

``jit_inline``: uncounted and inlined into its caller at numba's IR level. (1) The arena binding of
solvers/dg/workspace.py, whose functions return views they make (allowed once inlined; the 0-substep
tick went 4.4 -> 2.6 us). (2) The DG helpers called per element or per stage with many array
arguments (elementops, fluxes, dg_rhs, internal_forces, momentum_rate, the LDG, the end kinematics):
a compiled call passes every array as ~7-9 machine words, ~50-70 ns for 30 arrays (measured
2026-11-25), which added up to ~20 % of a tick; inlined, the 1730 m tick went 16.9 -> 13.2 us,
bit-identical. Big functions called once per stage stay calls (tension_scalar inlined measured
no difference). dg_evaluate, called three times per substep, is inlined too since it takes the
whole workspace (one tuple of ~55 arrays, passed by value to a call): inlined, the tick of the
small live meshes went 0.89-0.98x (bench_tick.py against the call, 2026-11-27, load 0.1-1).
Inlining the small physics helpers too (drag, added mass, constitutive law, end-condition table,
body rotations) measured slower (0.76 against 0.57 ms/s at 1730 m): they stay ``jit``.

``jit_alloc``: the compiled functions that allocate (the hybrid solver's Newton work, a few
set-up kernels). Same options, with NRT. A ``jit`` kernel never calls one.

Arrays reaching a ``jit`` kernel are owned by the Python caller for the whole call (the
solvers' work arrays), so dropping the counts inside it cannot free anything early.

Set ``NUMBA_DISABLE_JIT=1`` to run the kernels as plain Python: ``make test`` runs the tests
marked ``jit_off`` (the DG kernel twin tests, test/solvers/dg) a second time that way.
"""

from numba import njit

OPTIONS = dict(cache=True, fastmath=False, nogil=True)

jit = njit(**OPTIONS, _nrt=False)
jit_alloc = njit(**OPTIONS)
jit_inline = njit(**OPTIONS, _nrt=False, inline="always")
