"""Numerical options of the two solvers and of the initial state."""

from dataclasses import dataclass

from tether_sim.spec import param


@dataclass(frozen=True)
class DGOptions:
    """Discontinuous Galerkin discretisation [PE2020 Sec. 3]."""

    n_elements: int = param(20, doc="number of elements N", min=1, max=2000)
    order: int = param(4, doc="polynomial order P of the Legendre modal basis", min=1, max=12)
    beta: float = param(0.0, doc="LDG flux bias beta [PE2020 Eq. 29-30]", min=-0.5, max=0.5)
    cfl: float = param(0.5, doc="safety factor on the stable time step (see docs/dg_solver.md)", min=0.01, max=2.0)
    fixed_time_step: float = param(0.0, unit="s", doc="fixed substep; 0 = automatic from the stability rule", min=0.0, max=10.0)
    element_lengths: tuple = param((), unit="-", doc="relative element sizes from s = 0 (N positive weights, scaled to L); empty = uniform")
    lambda_floor: float = param(0.0, unit="m/s", doc="lower bound of the Lax-Friedrichs speed (adds dissipation in slack parts; 0 = paper)", min=0.0, max=1e5)
    tension_buffer: int = param(65536, doc="capacity of the per-substep end-tension ring buffer (drain_end_tensions)", min=16, max=100000000)


@dataclass(frozen=True)
class HybridOptions:
    """Hybrid rod-catenary discretisation [GP Sec. 3]."""

    n_segments: int = param(100, doc="number of spatial grid segments", min=2, max=100000)
    time_step: float = param(0.01, unit="s", doc="implicit time step", min=1e-7, max=100.0)
    rho_inf: float = param(0.8, doc="generalized-alpha spectral radius at infinity (1 = no dissipation)", min=0.0, max=1.0)
    zoning: str = param("adaptive", doc="rod/catenary partition: adaptive, fixed, all_rod, all_catenary", choices=("adaptive", "fixed", "all_rod", "all_catenary"))
    joint_arc_length: float = param(0.0, unit="m", doc="s of the spherical joint for zoning=fixed (catenary below, rod above)", min=0.0, max=1e6)


@dataclass(frozen=True)
class InitialState:
    """How a run starts."""

    kind: str = param("static", doc="static (equilibrium solve), straight (line between ends), relax (straight + dynamic relaxation)", choices=("static", "straight", "relax"))
    relax_time: float = param(0.0, unit="s", doc="damped dynamic relaxation after the initial shape", min=0.0, max=1e5)
