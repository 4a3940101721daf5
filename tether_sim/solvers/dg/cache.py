"""Guard against stale numba caches of composed kernels.

numba's on-disk cache of a function is invalidated only when *its own* source file changes; the
compiled loop in stepper.py inlines kernels from kernels.py, ldg.py and physics/*.py, so an edit
there would silently keep running the old machine code. Before anything is compiled, cache files
of this package older than the newest source they may depend on are removed.
"""

import os

from tether_sim.numerics.kernel_cache import drop_stale

_HERE = os.path.dirname(os.path.abspath(__file__))
_ROOT = os.path.dirname(os.path.dirname(_HERE))  # tether_sim/
_DEPENDENCIES = (
    os.path.join(_HERE, "*.py"),
    os.path.join(_ROOT, "physics", "constitutive.py"),
    os.path.join(_ROOT, "physics", "hydrodynamics.py"),
    os.path.join(_ROOT, "physics", "seabed.py"),
    os.path.join(_ROOT, "physics", "waves.py"),
    os.path.join(_ROOT, "physics", "bodies.py"),
    os.path.join(_ROOT, "physics", "end_conditions.py"),
    os.path.join(_ROOT, "numerics", "banded.py"),
    os.path.join(_ROOT, "numerics", "jit.py"),
)


# modules without compiled code or constants the kernels read (editing them keeps the cache)
_PYTHON_ONLY = ("__init__.py", "cache.py", "solver.py", "stepping.py", "outputs.py", "inputs.py", "winch_driver.py",
                "equilibrium.py", "parameters.py")


def drop_stale_kernel_cache() -> int:
    """Delete this package's numba cache files older than any dependency; returns how many."""
    return drop_stale(_HERE, _DEPENDENCIES, _PYTHON_ONLY)
