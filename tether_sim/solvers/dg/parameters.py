"""The DG solver's parameters and end data from the configuration: the float and int parameter
vectors prm / iprm (columns of layout.py), the wave components appended to prm, and the end data bc.
Plain Python, called once by DGCableSolver's set-up (editing this file keeps the kernel cache)."""

import math

import numpy as np

from tether_sim.physics.constitutive import cap_stiffness
from tether_sim.physics.end_conditions import KIND_CODES, anchor_end
from tether_sim.physics.hydrodynamics import added_mass_per_length, air_weight_per_length, net_weight_per_length
from tether_sim.physics.waves import wave_components
from tether_sim.solvers.dg import layout as Y


def parameters(cab, env, opt, law, mesh, kinds, n_current):
    """(prm, iprm) of layout.py: the cable, environment and dg keys, the tension law, the mesh (N, P, Q),
    the end kinds and the number of current table rows (no waves yet: with_waves)."""
    N, P, Q = mesh
    prm = np.zeros(Y.N_PRM)
    prm[Y.P_GAMMA0] = cab.gamma0
    prm[Y.P_EA] = cab.EA
    prm[Y.P_ZETA] = cab.damping
    mt, mn = added_mass_per_length(cab, env)
    prm[Y.P_MT], prm[Y.P_MN] = mt, mn
    prm[Y.P_FBZ] = -net_weight_per_length(cab, env)
    prm[Y.P_HALF_RHO_D] = 0.5 * env.fluid_density * cab.diameter
    prm[Y.P_CDT], prm[Y.P_CDN] = cab.Cdt, cab.Cdn
    prm[Y.P_ZG] = env.seabed_z
    kd = env.seabed_stiffness * cab.diameter
    prm[Y.P_KD] = kd
    prm[Y.P_CCRIT] = 2.0 * math.sqrt(kd * cab.gamma0)
    prm[Y.P_SBZETA] = env.seabed_damping
    prm[Y.P_MU] = env.seabed_friction
    prm[Y.P_VMU] = env.seabed_friction_speed
    prm[Y.P_EI] = cab.EI
    prm[Y.P_EIC] = cap_stiffness(cab)
    prm[Y.P_ZETAB] = cab.bending_damping
    prm[Y.P_BETA] = opt.beta
    prm[Y.P_TORQUE] = cab.torque
    prm[Y.P_LAMBDA_FLOOR] = opt.lambda_floor
    prm[Y.P_LAMBDA_BC] = math.sqrt(law.max_slope() / cab.gamma0)
    prm[Y.P_QPEN] = opt.q_penalty if opt.q_penalty_jump != "tension" else 0.0  # auto: solver._choose_q_penalty
    prm[Y.P_QPENT] = opt.q_penalty if opt.q_penalty_jump == "tension" else 0.0
    prm[Y.P_FBZ_AIR] = -air_weight_per_length(cab, env)
    prm[Y.P_HALF_RHO_D_AIR] = 0.5 * env.air_density * cab.diameter
    prm[Y.P_CDT_AIR], prm[Y.P_CDN_AIR] = env.air_Cdt, env.air_Cdn
    prm[Y.P_SURF_B] = 0.5 * env.surface_smoothing
    ip = np.zeros(Y.N_IPRM, dtype=np.int64)
    ip[Y.I_N], ip[Y.I_P], ip[Y.I_Q] = N, P, Q
    ip[Y.I_LAW] = law.code
    ip[Y.I_SEABED] = int(env.seabed)
    ip[Y.I_CURRENT] = int(n_current > 0)
    ip[Y.I_BENDING] = int(cab.EI > 0.0 or cab.bending_damping > 0.0 or cab.torque != 0.0)
    ip[Y.I_BENDDAMP] = int(cab.bending_damping > 0.0)
    ip[Y.I_AXDAMP] = int(cab.damping > 0.0 or cab.bending_damping > 0.0)
    ip[Y.I_KIND0], ip[Y.I_KIND1] = KIND_CODES[kinds[0]], KIND_CODES[kinds[1]]
    ip[Y.I_ANCHOR] = anchor_end(kinds)
    ip[Y.I_SURFACE] = int(env.free_surface)
    ip[Y.I_NEEDPOS] = int(env.seabed or n_current > 0 or env.free_surface)
    return prm, ip


def with_waves(config, cab, env, prm, ip):
    """prm with the wave components appended (layout.py), the Froude-Krylov mass and the depth
    below which the wave kinematics are negligible (< 1e-4 of their surface value: skipped)."""
    comps = wave_components(config)
    n = int(np.asarray(comps.amp).size)
    ip[Y.I_NWAVE] = n
    prm[Y.P_RHO_AH] = env.fluid_density * cab.area  # Froude-Krylov on the displaced volume (docs/waves.md)
    prm[Y.P_WAVE_DEPTH] = float(comps.depth)
    prm[Y.P_WAVE_STRETCH] = float(comps.stretch)
    prm[Y.P_WAVE_ZCUT] = math.inf
    if n == 0:
        return prm
    ip[Y.I_NEEDPOS] = 1
    amp = np.abs(np.asarray(comps.amp, float))
    kmin = float(np.min(np.asarray(comps.k, float)))
    zcut = -float(amp.sum()) - math.log(1e4) / kmin if kmin > 0.0 else -math.inf
    if math.isfinite(comps.depth) and kmin * comps.depth < math.log(1e4):
        zcut = -math.inf  # shallow for its longest component: the kinematics reach the bottom
    prm[Y.P_WAVE_ZCUT] = zcut
    tail = [np.asarray(getattr(comps, f), float) for f in ("amp", "omega", "k", "cos_dir", "sin_dir", "phase")]
    return np.ascontiguousarray(np.concatenate([prm] + tail))


def end_data(config, ends):
    """bc (2, layout.py B_*): the ends' positions, applied loads and held directions (ends: their EndKind)."""
    bc = np.zeros((2, Y.N_BC))
    for e, ec in enumerate((config.ship_end, config.vehicle_end)):
        bc[e, Y.B_P0:Y.B_P0 + 3] = ec.position
        bc[e, Y.B_P1:Y.B_P1 + 3] = ec.position
        bc[e, Y.B_F:Y.B_F + 3] = ec.force
        bc[e, Y.B_M:Y.B_M + 3] = ec.moment
        d = np.asarray(ec.direction, float)
        nd = np.linalg.norm(d)
        if ends[e].direction == "held" and nd == 0.0:
            raise ValueError(f"{('ship_end', 'vehicle_end')[e]}.direction: must be a nonzero vector")
        bc[e, Y.B_DIR:Y.B_DIR + 3] = d / nd if nd > 0 else d
    return bc
