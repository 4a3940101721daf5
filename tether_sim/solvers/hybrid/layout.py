"""Every column of the hybrid solver's arrays, named once with its width, symbol and unit (solvers/columns.py).

``P`` (HP_SIZE + 6 n_w): the parameters of the kernels (kernels.pack_parameters); with waves the
component arrays amp, omega, k, cos_dir, sin_dir, phase of physics/waves.py (n_w = P[HP_NW] each)
follow the table. Node states ``Y`` (K, N_SLOTS), GP's field variables with the strain eps of the
tension law: a catenary node uses the first CAT_SLOTS columns, Y_c = (v, T, t) in world components
[GP Eq. 5]; a rod node ROD_SLOTS, Y_r = (v, omega, kappa, f) in the components of its body frame L,
axis 0 = the tangent [GP Eq. 11]. A vector column of width 3 holds x, y, z (world) or axes 0, 1, 2
(body). Adding a column is adding a row; the offsets after it follow.
``python -m tether_sim.solvers.hybrid.layout`` prints the tables (docs/hybrid_solver.md "State and
parameter columns").
"""

from tether_sim.solvers.columns import define

define(globals(), "P (hybrid)", [
    ("HP_M", 1, "gamma0", "kg/m", "mass per unstretched metre"),
    ("HP_CK", 1, "1/EA", "1/N", "axial compliance (0: inextensible)"),
    ("HP_G", 1, "g", "m/s^2", "gravitational acceleration"),
    ("HP_RHOF", 1, "rho_f", "kg/m^3", "fluid density"),
    ("HP_AREA", 1, "A", "m^2", "cross-section area (the displaced area of the buoyancy)"),
    ("HP_D", 1, "d", "m", "diameter (drag, seabed contact)"),
    ("HP_CDN", 1, "C_dn", "-", "normal drag coefficient [PE2020 Eq. 17]"),
    ("HP_CDT", 1, "C_dt", "-", "tangential drag coefficient"),
    ("HP_CMN", 1, "C_mn", "-", "normal added-mass coefficient [PE2020 Eq. 13]"),
    ("HP_CMT", 1, "C_mt", "-", "tangential added-mass coefficient"),
    ("HP_B0", 3, "B = (GJ, EI, EI)", "N m^2", "torsion and bending stiffness, body axes 0 (tangent), 1, 2 [GP Eq. 6]"),
    ("HP_I0", 3, "I = (I_t, I_b, I_b)", "kg m", "rotary inertia per metre, same axes [GP Eq. 9]"),
    ("HP_DT", 1, "dt", "s", "time step"),
    ("HP_AM", 1, "alpha_m", "-", "generalized-alpha rate level [GP Sec. 3]"),
    ("HP_AF", 1, "alpha_f", "-", "generalized-alpha field level"),
    ("HP_GAM", 1, "gamma", "-", "generalized-alpha gamma = 1/2 + alpha_m - alpha_f"),
    ("HP_SOFT", 1, "s", "-", "compression softening factor (1 for a linear law, > 1 for a no-compression material)"),
    ("HP_TW", 1, "W", "N", "width of the smooth transition into compression"),
    ("HP_EA", 1, "EA", "N", "axial stiffness (0: inextensible, eps = 0)"),
    ("HP_ZETA", 1, "zeta", "N s", "axial material damping [PE2020 Eq. 22]"),
    ("HP_SEABED", 1, "-", "-", "seabed contact on (1) or off (0)"),
    ("HP_ZG", 1, "z_g", "m", "seabed height"),
    ("HP_KD", 1, "K_g d", "N/m^2", "seabed stiffness per metre [PE2020 Eq. 15]"),
    ("HP_CCRIT", 1, "2 sqrt(K_g d gamma0)", "N s/m^2", "critical seabed damping"),
    ("HP_SBZETA", 1, "zeta_g", "-", "seabed damping ratio"),
    ("HP_MU", 1, "mu", "-", "seabed friction coefficient [PE2020 Eq. 16]"),
    ("HP_VMU", 1, "v_mu", "m/s", "friction regularisation speed"),
    ("HP_FBZ", 1, "f_b,z", "N/m", "net vertical buoyancy per metre in water, -(gamma0 - rho_f A) g [PE2020 Eq. 14]"),
    ("HP_FS", 1, "-", "-", "free surface on (1) or off (0)"),
    ("HP_RHOA", 1, "rho_a", "kg/m^3", "air density"),
    ("HP_CDN_A", 1, "C_dn,air", "-", "normal drag coefficient in air"),
    ("HP_CDT_A", 1, "C_dt,air", "-", "tangential drag coefficient in air"),
    ("HP_FSB", 1, "L_s / 2", "m", "half-width of the wetted-fraction ramp (at least half a node spacing)"),
    ("HP_TIME", 1, "t_n", "s", "start of the step being solved (the loads are at t_n + alpha_f dt)"),
    ("HP_NW", 1, "n_w", "-", "number of wave components (their arrays follow the table)"),
    ("HP_WDEPTH", 1, "h", "m", "water depth of the wave kinematics (inf: deep water)"),
    ("HP_WSTRETCH", 1, "-", "-", "surface stretching code (physics/waves.STRETCHINGS)"),
    ("HP_WZCUT", 1, "z_cut", "m", "below this height the wave kinematics are < 1e-4 of their surface value, skipped"),
], "HP_SIZE")

define(globals(), "Y catenary node", [
    ("CAT_V", 3, "v", "m/s", "velocity, world [GP Eq. 2-3]"),
    ("CAT_T", 1, "T", "N", "tension"),
    ("CAT_TAN", 3, "t", "-", "unit tangent, world [GP Eq. 4]"),
    ("CAT_EPS", 1, "eps", "-", "axial strain (the tension law's unknown)"),
], "CAT_SLOTS")

define(globals(), "Y rod node", [
    ("ROD_V", 3, "v", "m/s", "velocity, body frame [GP Eq. 7, 10]"),
    ("ROD_OMEGA", 3, "omega", "rad/s", "angular velocity, body frame (axis 0: twist rate)"),
    ("ROD_KAPPA", 3, "kappa", "1/m", "curvature and twist vector, body frame (axis 0: twist) [GP Eq. 6, 8]"),
    ("ROD_F", 3, "f", "N", "internal force, body frame (axis 0: tension, 1-2: shear) [GP Eq. 10]"),
    ("ROD_EPS", 1, "eps", "-", "axial strain (the tension law's unknown)"),
], "ROD_SLOTS")

N_SLOTS = 13  # the node arrays' width: a rigid-body node (13 states) fits

if __name__ == "__main__":
    from tether_sim.solvers.columns import describe

    print(describe(("P (hybrid)", "Y catenary node", "Y rod node")))
