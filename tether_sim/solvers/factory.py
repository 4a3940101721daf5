"""Build the solver a configuration names: one explicit table."""

from importlib import import_module

_SOLVERS = {
    "dg": ("tether_sim.solvers.dg.solver", "DGCableSolver"),
    "hybrid": ("tether_sim.solvers.hybrid.solver", "HybridRodCatenarySolver"),
}


def build_solver(config):
    """Return the solver selected by ``config.solver`` (a :class:`tether_sim.config.SimConfig`)."""
    try:
        module_name, class_name = _SOLVERS[config.solver]
    except KeyError:
        raise ValueError(f"solver: unknown solver {config.solver!r}; choose one of {sorted(_SOLVERS)}") from None
    return getattr(import_module(module_name), class_name)(config)
