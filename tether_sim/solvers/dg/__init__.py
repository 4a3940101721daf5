"""DG / nested-LDG cable solver [PE2020]. See ``solver.DGCableSolver`` and docs/dg_solver.md."""

from tether_sim.solvers.dg.cache import drop_stale_kernel_cache

drop_stale_kernel_cache()
