"""Guard against stale numba caches of the hybrid solver's composed kernels (as solvers/dg/cache.py).

numba's on-disk cache of a function is invalidated only when *its own* source file changes; the
compiled node terms in catenary.py, rod.py, assembly.py and jacobian.py call kernels of kernels.py,
jac_env.py and physics/*.py, so an edit there (as the free surface made) would silently keep
running the old machine code. Before anything is compiled, cache files of this package older than
the newest source they may depend on are removed.
"""

import os

from tether_sim.numerics.kernel_cache import drop_stale

_HERE = os.path.dirname(os.path.abspath(__file__))
_ROOT = os.path.dirname(os.path.dirname(_HERE))  # tether_sim/
_DEPENDENCIES = (
    os.path.join(_HERE, "*.py"),
    os.path.join(_ROOT, "physics", "hydrodynamics.py"),
    os.path.join(_ROOT, "physics", "seabed.py"),
    os.path.join(_ROOT, "physics", "bodies.py"),
    os.path.join(_ROOT, "physics", "waves.py"),
    os.path.join(_ROOT, "numerics", "rotations.py"),
    os.path.join(_ROOT, "numerics", "jit.py"),
)
# modules without compiled code (editing them keeps the cache)
_PYTHON_ONLY = ("__init__.py", "cache.py", "chain.py", "initial.py", "newton.py", "solver.py", "state_io.py",
                "zoning.py")


def drop_stale_kernel_cache() -> int:
    """Delete this package's numba cache files older than any dependency; returns how many."""
    return drop_stale(_HERE, _DEPENDENCIES, _PYTHON_ONLY)
