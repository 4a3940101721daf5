"""Hybrid rod-catenary solver (Goyal & Perkins); stale numba caches are dropped on import (cache.py)."""

from tether_sim.solvers.hybrid.cache import drop_stale_kernel_cache

drop_stale_kernel_cache()
