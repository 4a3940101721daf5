"""Every column of the DG arrays, named once with its width, symbol and unit (solvers/columns.py).

State ``U`` (N, P+1, 6): modal coefficients of u = [q, v] per element [PE2020 Eq. 10-11].
Work arrays: ``wq`` (N, Q, NWQ) values at the Gauss points, ``wm`` (N, P+1, NWM) modal
coefficients, ``tr`` (N, 2, NTR) element traces (side 0 = left, xi = -1; 1 = right),
``fl`` (N+1, NFL) numerical fluxes at the N+1 interfaces (0 = ship end s = 0, N = vehicle end
s = L), ``bc`` (2, N_BC) end data, ``vbc`` (2, 6) end kinematics, ``endf`` (2, N_ENDF) end loads;
``prm`` / ``iprm`` the float / integer parameters (``prm`` is N_PRM + 6 n_w long: the wave components'
arrays amp, omega, k, cos_dir, sin_dir, phase of physics/waves.py, n_w = iprm[I_NWAVE] each, follow the table). Each table below gives every column's name
(a module constant = its offset, a compile-time constant in numba), width, symbol, unit and
meaning; a vector column of width 3 holds x, y, z (world frame, ENU). Symbols: l = |q| (stretch,
1 + eps), i = q / l (tangent), M* = M / l^2 [Eq. 19], T_s the bending shear force [Eq. 20].
``python -m tether_sim.solvers.dg.layout`` prints the tables (docs/dg_solver.md).
"""

from tether_sim.solvers.columns import define

define(globals(), "U", [
    ("U_Q", 3, "q = dr/ds", "-", "tangent stretch vector, modal coefficients"),
    ("U_V", 3, "v = gamma0 dr/dt", "kg/s", "momentum per unstretched metre, modal coefficients"),
], "N_U")

define(globals(), "prm", [
    ("P_GAMMA0", 1, "gamma0", "kg/m", "mass per unstretched metre"),
    ("P_EA", 1, "EA", "N", "axial stiffness"),
    ("P_ZETA", 1, "zeta", "N s", "axial material damping [Eq. 22]"),
    ("P_MT", 1, "m_t", "kg/m", "tangential added mass per metre"),
    ("P_MN", 1, "m_n", "kg/m", "normal added mass per metre"),
    ("P_FBZ", 1, "f_b,z", "N/m", "net vertical buoyancy per metre (negative: sinks) [Eq. 14]"),
    ("P_HALF_RHO_D", 1, "rho_f d / 2", "kg/m^2", "drag prefactor [Eq. 17]"),
    ("P_CDT", 1, "C_dt", "-", "tangential drag coefficient"),
    ("P_CDN", 1, "C_dn", "-", "normal drag coefficient"),
    ("P_ZG", 1, "z_g", "m", "seabed height"),
    ("P_KD", 1, "K_g d", "N/m^2", "seabed stiffness per metre [Eq. 15]"),
    ("P_CCRIT", 1, "2 sqrt(K_g d gamma0)", "N s/m^2", "critical seabed damping"),
    ("P_SBZETA", 1, "zeta_g", "-", "seabed damping ratio"),
    ("P_MU", 1, "mu", "-", "seabed friction coefficient [Eq. 16]"),
    ("P_VMU", 1, "v_mu", "m/s", "friction regularisation speed"),
    ("P_EI", 1, "EI", "N m^2", "bending stiffness"),
    ("P_EIC", 1, "EI_c", "N m^2", "bending stiffness of the compression cap (cable.compression buckling: EI; none: 0, Eq. 22)"),
    ("P_ZETAB", 1, "zeta_b", "N m^2 s", "bending damping [Eq. 19]"),
    ("P_BETA", 1, "beta", "-", "LDG flux bias [Eq. 29-30]"),
    ("P_TORQUE", 1, "GIp Omega_1", "N m", "torque [Eq. 21]"),
    ("P_RELAX", 1, "c_relax", "1/s", "linear momentum damping rate, dynamic relaxation only"),
    ("P_LAMBDA_FLOOR", 1, "lambda_min", "m/s", "lower bound of the Lax-Friedrichs speed"),
    ("P_LAMBDA_BC", 1, "c", "m/s", "upwind speed of the velocity-end fluxes (taut wave speed)"),
    ("P_QPEN", 1, "-", "-", "factor on the Lax-Friedrichs penalty lambda/2 [q] of the q equation (Eq. 24; dg.q_penalty_jump = strain)"),
    ("P_QPENT", 1, "-", "-", "factor on the tension-jump penalty [T_el]/(2 gamma0 lambda) of the q equation (dg.q_penalty_jump = tension)"),
    ("P_FBZ_AIR", 1, "f_b,z air", "N/m", "net vertical force per metre in air (free surface)"),
    ("P_HALF_RHO_D_AIR", 1, "rho_a d / 2", "kg/m^2", "air drag prefactor"),
    ("P_CDT_AIR", 1, "C_dt,air", "-", "tangential drag coefficient in air"),
    ("P_CDN_AIR", 1, "C_dn,air", "-", "normal drag coefficient in air"),
    ("P_SURF_B", 1, "L_s / 2", "m", "minimum half-width of the wetted-fraction ramp"),
    ("P_WL", 1, "L", "m", "winch: unstretched length in the domain (the stage value while stepping)"),
    ("P_WLDOT", 1, "dL/dt", "m/s", "winch: pay-out rate at the current (stage) time, > 0 pays out"),
    ("P_WR0", 1, "dL/dt_0", "m/s", "winch: pay-out rate at the start of the tick"),
    ("P_WR1", 1, "dL/dt_1", "m/s", "winch: pay-out rate at the end of the tick (linear ramp between)"),
    ("P_TIME", 1, "t", "s", "time of the right-hand-side evaluation (waves; written by stepper.dg_evaluate)"),
    ("P_RHO_AH", 1, "rho_f A", "kg/m", "Froude-Krylov mass per metre (waves; A = gamma0 / rho_c, the buoyancy's displaced area)"),
    ("P_WAVE_DEPTH", 1, "h", "m", "water depth of the wave kinematics (inf: deep water)"),
    ("P_WAVE_ZCUT", 1, "z_cut", "m", "below this height the wave kinematics are < 1e-4 of their surface value and skipped"),
    ("P_WAVE_STRETCH", 1, "-", "-", "stretching code of the wave kinematics (physics/waves.py STRETCHINGS index)"),
    ("P_BMR", 1, "-", "-", "bending multirate: 1 = this stage takes T_s from the records W_TSH (stepper.py), 0 = the nested LDG"),
    ("P_BMR_W", 3, "-", "-", "weights of the three records W_TSH in the extrapolated T_s (quadratic Lagrange, stepper.py)"),
], "N_PRM")

define(globals(), "iprm", [
    ("I_N", 1, "N", "-", "number of elements"),
    ("I_P", 1, "P", "-", "polynomial order"),
    ("I_Q", 1, "Q", "-", "Gauss points per element"),
    ("I_LAW", 1, "-", "-", "tension law code (physics/constitutive.py)"),
    ("I_SEABED", 1, "-", "-", "seabed contact on"),
    ("I_CURRENT", 1, "-", "-", "current table non-empty"),
    ("I_BENDING", 1, "-", "-", "nested LDG on (EI, zeta_b or torque nonzero)"),
    ("I_ANCHOR", 1, "-", "-", "end the positions are integrated from (0: s = 0, 1: s = L)"),
    ("I_KIND0", 1, "-", "-", "end kind code at s = 0 (physics/end_conditions.py)"),
    ("I_KIND1", 1, "-", "-", "end kind code at s = L"),
    ("I_NEEDPOS", 1, "-", "-", "positions at the Gauss points needed (current, seabed or free surface)"),
    ("I_BENDDAMP", 1, "-", "-", "bending damping on"),
    ("I_AXDAMP", 1, "-", "-", "any damping on: the strain-rate gradient is needed"),
    ("I_SURFACE", 1, "-", "-", "free surface on (wetted fraction per Gauss point)"),
    ("I_WINCH", 1, "-", "-", "winch end + 1 (0: no winch, 1: ship end s = 0, 2: vehicle end s = L)"),
    ("I_NWAVE", 1, "n_w", "-", "wave components; their arrays follow N_PRM in prm (amp, omega, k, cos, sin, phase: n_w each)"),
    ("I_BMR_K", 1, "K", "-", "bending multirate: the nested LDG every K substeps, T_s extrapolated between (0, 1: every stage; stepper.py)"),
], "N_IPRM")

define(globals(), "bc", [
    ("B_T0", 1, "t_0", "s", "start time of a driven end's Hermite segment"),
    ("B_T1", 1, "t_1", "s", "end time of the segment"),
    ("B_P0", 3, "r_0", "m", "position at t_0 (fixed ends: the fixed point)"),
    ("B_V0", 3, "dr/dt_0", "m/s", "velocity at t_0"),
    ("B_P1", 3, "r_1", "m", "position at t_1"),
    ("B_V1", 3, "dr/dt_1", "m/s", "velocity at t_1"),
    ("B_F", 3, "F_BC", "N", "applied point force (force ends)"),
    ("B_M", 3, "M_BC", "N m", "applied point moment (force ends)"),
    ("B_DIR", 3, "i_BC", "-", "held tangent direction (clamped ends)"),
], "N_BC")

define(globals(), "vbc", [
    ("VB_P", 3, "r_BC", "m", "position of a kinematic end at the stage time"),
    ("VB_V", 3, "v_BC", "m/s", "its velocity"),
], "N_VBC")

define(globals(), "wq", [
    ("W_Q", 3, "q", "-", "dr/ds"),
    ("W_V", 3, "v", "kg/s", "gamma0 dr/dt"),
    ("W_I", 3, "i", "-", "tangent q / l"),
    ("W_L", 1, "l", "-", "stretch |q| = 1 + eps"),
    ("W_EDOT", 1, "deps/dt", "1/s", "strain rate i . d(v/gamma0)/ds"),
    ("W_TV", 3, "T i + T_s", "N", "tension vector"),
    ("W_R", 3, "r", "m", "position (with current, seabed or free surface)"),
    ("W_ACC", 3, "dv/dt", "N/m", "momentum rate"),
    ("W_B", 3, "b", "-", "bending tangent: i where taut, 2 q / (1 + l^2) where the chord is short (ldg.py)"),
    ("W_IDOT", 3, "db/dt", "1/s", "bending tangent rate (bending damping)"),
    ("W_KAP", 3, "kappa", "1/m", "di/ds"),
    ("W_KDOT", 3, "dkappa/dt", "1/(m s)", "d(di/dt)/ds"),
    ("W_MS", 3, "M*", "N m", "M / l^2 [Eq. 19]"),
    ("W_TAU", 3, "tau", "N", "dM*/ds"),
    ("W_NUS", 3, "d(v/gamma0)/ds", "1/s", "velocity gradient with central fluxes (damping strain rate)"),
    ("W_WET", 1, "phi", "-", "wetted fraction (free surface on)"),
    ("W_TE", 3, "T(eps) i", "N", "elastic tension vector (no damping, no bending; q-equation penalty)"),
    ("W_SY", 3, "d(EI kappa + zeta_b dkappa/dt)/ds", "N", "bending shear of the short-chord form (ldg.py)"),
    ("W_TS", 3, "T_s", "N", "bending shear force (the part of W_TV from bending; ldg.py)"),
    ("W_TSH", 9, "T_s records", "N", "bending multirate: T_s of the last three nested-LDG evaluations (stepper.py)"),
], "NWQ")

define(globals(), "wm", [
    ("M_TV", 3, "T i + T_s", "N", "tension vector"),
    ("M_DT", 3, "dT/ds", "N/m", "strong derivative of the tension vector"),
    ("M_I", 3, "i", "-", "tangent"),
    ("M_KAP", 3, "kappa", "1/m", "curvature vector"),
    ("M_IDOT", 3, "di/dt", "1/s", "tangent rate"),
    ("M_KDOT", 3, "dkappa/dt", "1/(m s)", "curvature rate"),
    ("M_MS", 3, "M*", "N m", "M / l^2"),
    ("M_TAU", 3, "tau", "N", "dM*/ds"),
    ("M_NUS", 3, "d(v/gamma0)/ds", "1/s", "velocity gradient with central fluxes"),
    ("M_SX", 3, "EI kappa + zeta_b dkappa/dt", "N m", "bending moment vector of the short-chord form (ldg.py)"),
    ("M_SY", 3, "d(EI kappa + zeta_b dkappa/dt)/ds", "N", "its strong derivative"),
], "NWM")

define(globals(), "tr", [
    ("T_Q", 3, "q", "-", "trace of q"),
    ("T_V", 3, "v", "kg/s", "trace of v"),
    ("T_TV", 3, "T i + T_s", "N", "trace of the tension vector"),
    ("T_I", 3, "i", "-", "trace of the tangent"),
    ("T_IDOT", 3, "di/dt", "1/s", "trace of the tangent rate"),
    ("T_MS", 3, "M*", "N m", "trace of M*"),
    ("T_LAM", 1, "lambda", "m/s", "local wave speed [Eq. 25]"),
    ("T_TE", 3, "T(eps) i", "N", "trace of the projected elastic tension vector (q-equation penalty)"),
    ("T_SX", 3, "EI kappa + zeta_b dkappa/dt", "N m", "trace of M_SX"),
    ("T_TS", 3, "T_s", "N", "trace of the projected bending shear (end elements; the no-compression clip leaves it out)"),
], "NTR")

define(globals(), "fl", [
    ("F_Q", 3, "v_hat / gamma0", "m/s", "flux of the q equation"),
    ("F_V", 3, "T_hat", "N", "flux of the v equation"),
    ("F_I", 3, "i_hat", "-", "LDG flux of the tangent [Eq. 26, 29]"),
    ("F_IDOT", 3, "i_hat-dot", "1/s", "LDG flux of the tangent rate [Eq. 27]"),
    ("F_MS", 3, "M*_hat", "N m", "LDG flux of M* [Eq. 28, 30]"),
    ("F_NU", 3, "v_hat / gamma0 (central)", "m/s", "central velocity flux (damping strain rate)"),
    ("F_SX", 3, "(EI kappa + zeta_b dkappa/dt)_hat", "N m", "LDG flux of M_SX (bias -beta, as M*)"),
], "NFL")

define(globals(), "endf", [
    ("E_F", 3, "-n T_hat", "N", "force by the cable on the end"),
    ("E_T", 1, "T_hat . i+", "N", "axial end tension"),
    ("E_M", 3, "-n M*_hat", "N m", "moment by the cable on the end"),
    ("E_VHAT", 3, "v_hat / gamma0", "m/s", "flux velocity of the end"),
], "N_ENDF")

if __name__ == "__main__":
    from tether_sim.solvers.dg import damping_layout  # noqa: F401 (defines its tables)
    from tether_sim.solvers.columns import describe

    print(describe())
