"""Drop numba cache files older than the sources their compiled code may depend on.

numba invalidates a function's on-disk cache only when *its own* source file changes. A package
whose compiled functions inline kernels from other files (solvers/dg, solvers/hybrid) would
silently keep running old machine code after an edit of one of those files; each such package
calls :func:`drop_stale` on import, naming what its kernels read (its ``cache.py``).
"""

import glob
import os


def newest_source(package_dir: str, dependencies, python_only) -> float:
    """Latest modification time over the files matched by ``dependencies`` (glob patterns), leaving
    out the package's own modules named in ``python_only`` (no compiled code, no constants read by
    kernels: editing them keeps the cache)."""
    newest = 0.0
    for pattern in dependencies:
        for path in glob.glob(pattern):
            if os.path.dirname(path) == package_dir and os.path.basename(path) in python_only:
                continue
            try:
                newest = max(newest, os.path.getmtime(path))
            except OSError:
                pass
    return newest


def drop_stale(package_dir: str, dependencies, python_only) -> int:
    """Delete ``package_dir/__pycache__/*.nbi|nbc`` older than the newest dependency; returns how many."""
    newest = newest_source(package_dir, dependencies, python_only)
    removed = 0
    for path in glob.glob(os.path.join(package_dir, "__pycache__", "*.nb[ic]")):
        try:
            if os.path.getmtime(path) < newest:
                os.remove(path)
                removed += 1
        except OSError:
            pass  # another process got there first
    return removed
