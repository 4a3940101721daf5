"""The stale-cache guard (numerics/kernel_cache.py): a cache older than a dependency goes, a newer one stays,
and edits of modules declared Python-only keep the cache."""

import os

from tether_sim.numerics.kernel_cache import drop_stale


def _touch(path, mtime):
    path.write_text("x")
    os.utime(path, (mtime, mtime))


def test_drop_stale_removes_only_caches_older_than_a_dependency(tmp_path):
    pkg = tmp_path / "pkg"
    (pkg / "__pycache__").mkdir(parents=True)
    other = tmp_path / "physics.py"
    _touch(pkg / "kernels.py", 1000.0)
    _touch(pkg / "solver.py", 5000.0)  # Python-only: newer, but does not count
    _touch(other, 2000.0)
    _touch(pkg / "__pycache__" / "k-1.nbi", 1500.0)  # older than physics.py: stale
    _touch(pkg / "__pycache__" / "k-1.0.nbc", 1500.0)
    _touch(pkg / "__pycache__" / "j-2.nbi", 2500.0)  # newer than every counted source: kept
    _touch(pkg / "__pycache__" / "m.pyc", 100.0)  # not a numba file: kept
    deps = (os.path.join(str(pkg), "*.py"), str(other))
    assert drop_stale(str(pkg), deps, ("solver.py",)) == 2
    assert sorted(p.name for p in (pkg / "__pycache__").iterdir()) == ["j-2.nbi", "m.pyc"]
    # counting solver.py as a kernel source makes the remaining cache stale too
    assert drop_stale(str(pkg), deps, ()) == 1
