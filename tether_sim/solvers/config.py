"""Numerical options of the two solvers and of the initial state."""

from dataclasses import dataclass

from tether_sim.spec import param


# dg.damping values that split the damping off the SSP-RK3 step (stepper.py: D(dt/2) E(dt) D(dt/2))
SPLIT_DAMPING = ("implicit", "rkl2")

@dataclass(frozen=True)
class DGOptions:
    """Discontinuous Galerkin discretisation [PE2020 Sec. 3]."""

    n_elements: int = param(20, doc="number of elements N", min=1, max=2000)
    order: int = param(4, doc="polynomial order P of the Legendre modal basis", min=1, max=12)
    beta: float = param(0.0, doc="LDG flux bias beta [PE2020 Eq. 29-30]", min=-0.5, max=0.5)
    cfl: float = param(0.5, doc="safety factor on the stable time step (see docs/dg_solver.md)", min=0.01, max=2.0)
    resolution: str = param("manual", doc="manual: dg.n_elements, dg.order and dg.cfl as given; auto: chosen for dg.snap_tolerance from measured ladders (tether_sim/solvers/resolution.py, docs/performance.md), which then replace those three", choices=("manual", "auto"))
    snap_tolerance: float = param(0.01, doc="dg.resolution auto: tolerated relative error of the first snap peak (end tension); the rule keeps the measured error below half of it", min=0.001, max=0.2)
    fixed_time_step: float = param(0.0, unit="s", doc="fixed substep; 0 = automatic from the stability rule", min=0.0, max=10.0)
    element_lengths: tuple = param((), unit="-", doc="relative element sizes from s = 0 (N positive weights, scaled to L); empty = uniform")
    lambda_floor: float = param(0.0, unit="m/s", doc="lower bound of the Lax-Friedrichs speed (adds dissipation in slack parts; 0 = paper)", min=0.0, max=1e5)
    q_penalty: float = param(1.0, doc="factor on the jump penalty of the q equation (the dissipation of the Lax-Friedrichs flux in q; the v equation keeps its lambda/2 [v]); 0 = central q flux", min=0.0, max=1.0)
    q_penalty_jump: str = param("auto", doc="what the q-equation penalty acts on: strain = lambda/2 [q], PE2020 Eq. 24 as printed, which makes curved low-tension cables with EA/T > ~1e3 (EA of tens to hundreds of MN, tensions of kN) unstable; tension = the jump of the projected elastic tension vector over 2 gamma0 lambda (energy-dissipative for any law and geometry, equal to Eq. 24 on straight cables, but one order less accurate for tension-free bending); auto = tension when the static initial state has max slope dT/deps / min tension > dg.q_penalty_auto_ratio, else strain (docs/dg_solver.md)", choices=("auto", "tension", "strain"))
    q_penalty_auto_ratio: float = param(1500.0, doc="dg.q_penalty_jump auto: EA / T_min of the static state above which the tension-jump penalty is used (Eq. 24 measured unstable from 1.5e3 on curved cables, stable on ROPOS at 1.06e3)", min=1.0, max=1e12)
    quad_points: int = param(0, doc="Gauss points per element; 0 = automatic (3P+1)//2 + 1 (see docs/dg_solver.md)", min=0, max=64)
    damping: str = param("explicit", doc="material damping terms (axial zeta, bending zeta_b): explicit (in the SSP-RK3 step, whose substep they limit as h^-2 / h^-4) or split off by Strang splitting, the substep then set by the waves only: implicit (an L-stable SDIRK2 step of the damping) or rkl2 (axial damping only: an explicit Runge-Kutta-Legendre super-time-step, no matrix; docs/dg_solver.md)", choices=("explicit",) + SPLIT_DAMPING)
    damping_substeps: int = param(1, doc="1 (default): a damping step around every substep; 2 is faster on the paper's mesh with bending but invented snaps at small EI (alpha 0.01 and 0.1 at 200 m; docs/dg_solver.md \"Implicit damping\"), so it is not the default. dg.damping implicit with axial damping only (no bending damping), with bending (EI > 0) or the linear law: SSP-RK3 substeps per damping step, the splitting D(m dt/2) E(dt)^m D(m dt/2) with consecutive half steps merged (docs/dg_solver.md \"Implicit damping\"); 1 = a damping step around every substep", min=1, max=4)
    damping_correction: bool = param(True, doc="dg.damping implicit with axial damping only: each stage solve with a stored strain-rate LU (kept up to 64 damping steps, low-rank updated where the active set switched) takes one defect correction with the present geometry's operator (and refactors when it exceeds 1e-4 of the solution); false = the stored LU as it is (on the PE2020 Sec. 6.2 mesh 1.29x less CPU, but snaps moved by up to 0.14 %) (docs/dg_solver.md \"Implicit damping\")")
    bending_multirate: bool = param(True, doc="bending (EI > 0, no bending damping or torque): evaluate the nested LDG of the bending shear every K substeps and extrapolate it quadratically in between, K from a stability and accuracy rule (docs/dg_solver.md \"Bending multirate\"); false = at every Runge-Kutta stage, as PE2020")
    tension_buffer: int = param(65536, doc="capacity of the per-substep end-tension ring buffer (drain_end_tensions)", min=16, max=100000000)


@dataclass(frozen=True)
class HybridOptions:
    """Hybrid rod-catenary discretisation [GP Sec. 3]."""

    n_segments: int = param(100, doc="number of spatial grid segments", min=2, max=100000)
    time_step: float = param(0.01, unit="s", doc="implicit time step", min=1e-7, max=100.0)
    rho_inf: float = param(0.8, doc="generalized-alpha spectral radius at infinity (1 = no dissipation)", min=0.0, max=1.0)
    zoning: str = param("adaptive", doc="rod/catenary partition: adaptive, fixed, all_rod, all_catenary", choices=("adaptive", "fixed", "all_rod", "all_catenary"))
    joint_arc_length: float = param(0.0, unit="m", doc="s of the spherical joint for zoning=fixed (catenary below, rod above)", min=0.0, max=1e6)
    chi_on: float = param(0.3, doc="adaptive zoning: element becomes rod when sqrt(EI w^2/T^3) exceeds this (docs/hybrid_solver.md)", min=1e-6, max=1e6)
    chi_off: float = param(0.15, doc="adaptive zoning: rod element returns to catenary below this (hysteresis, < chi_on)", min=1e-6, max=1e6)
    min_zone_elements: int = param(4, doc="adaptive zoning: shortest rod or catenary zone, in elements", min=1, max=100000)
    zoning_interval: float = param(0.01, unit="s", doc="adaptive zoning: zones are re-evaluated after a step at most this often (every step if the step is longer)", min=0.0, max=1e6)
    end_rod_length: float = param(0.0, unit="m", doc="rod zone kept at an end that holds its tangent (clamped or hold_direction_*)", min=0.0, max=1e6)
    hold_direction_ship: bool = param(False, doc="force/free ship end also holds its tangent at ship_end.direction (frame fixed)")
    hold_direction_vehicle: bool = param(False, doc="force/free vehicle end also holds its tangent at vehicle_end.direction (GP benchmark)")
    rotary_inertia_bend: float = param(0.0, unit="kg m", doc="rotary inertia per length about a bending axis; 0 = gamma0*A/(4 pi)", min=0.0, max=1e6)
    rotary_inertia_torsion: float = param(0.0, unit="kg m", doc="rotary inertia per length about the tangent; 0 = 2 x bending value", min=0.0, max=1e6)
    jacobian: str = param("analytic", doc="Newton Jacobian: analytic (band LU; docs/hybrid_solver.md) or finite_difference (the forward-difference twin, sparse LU)", choices=("analytic", "finite_difference"))
    max_newton_iterations: int = param(25, doc="Newton iterations per implicit step before the step is halved", min=2, max=1000)
    newton_tolerance: float = param(1e-9, doc="Newton stops when every update is below this times its variable scale", min=1e-15, max=1e-2)
    reuse_factorisation: bool = param(True, doc="simplified Newton across steps: keep the factorised Newton matrix of the last step while the zones and the step size stay the same, refactorise when the scaled residual falls by less than 10x per iteration (as within a step), start the step again with a fresh one if it fails; converged to the same newton_tolerance (docs/hybrid_solver.md); false = a fresh Jacobian at the first iteration of every step")
    frames_from_curvature: bool = param(True, doc="re-derive rod frames from kappa along s after each step (else pure incremental rotations in time)")
    close_rod_shapes: str = param("evaluation", doc="adaptive zoning: turn and bend rod zones (least bending energy) so that their shape, re-derived from kappa, ends where their far end is held (body, driven end, joint): at every zone evaluation, only at zone changes (conversion), or off (docs/hybrid_solver.md)", choices=("evaluation", "conversion", "off"))
    compression_softening: float = param(10000.0, doc="material=bilinear/table: the law T = Phi(EA eps + zeta deps/dt) has slope 1/this in compression (a slack tether shortens almost freely; docs/hybrid_solver.md)", min=1.0, max=1e9)
    relax_time_step: float = param(1.0, unit="s", doc="step of the initial damped relaxation (large steps damp fastest); 0 = time_step", min=0.0, max=100.0)
    static_relax_time: float = param(60.0, unit="s", doc="initial.kind=static: duration of the damped (rho_inf=0) relaxation to rest", min=0.0, max=1e6)


@dataclass(frozen=True)
class InitialState:
    """How a run starts."""

    kind: str = param("static", doc="static (equilibrium solve), straight (line between ends), relax (straight + dynamic relaxation)", choices=("static", "straight", "relax"))
    relax_time: float = param(0.0, unit="s", doc="damped dynamic relaxation after the initial shape", min=0.0, max=1e5)
    relax_damping: float = param(0.0, unit="1/s", doc="momentum damping rate during relaxation; 0 = automatic (2 x lowest pendulum or bending frequency)", min=0.0, max=1e6)
