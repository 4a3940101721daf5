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
    waves = getattr(config, "waves", None)
    if config.solver == "hybrid" and waves is not None and waves.kind != "none":
        # never a silent still sea: the hybrid solver has no wave kinematics in its loads yet
        raise ValueError(f"waves.kind {waves.kind}: wave loads on the cable are implemented in the DG solver only; "
                         "use solver: dg (or waves.kind: none with the hybrid solver)")
    return getattr(import_module(module_name), class_name)(config)
