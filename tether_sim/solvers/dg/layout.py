"""Index constants shared by the DG kernels and the Python driver (compile-time constants in numba).

State ``U`` (N, P+1, 6): modal coefficients of u = [q, v] per element [PE2020 Eq. 10-11]
(q = dr/ds, v = gamma0 * dr/dt). Work arrays: ``wq`` (N, Q, NWQ) values at the Gauss points,
``wm`` (N, P+1, NWM) modal work, ``tr`` (N, 2, NTR) element traces (0 = left xi=-1, 1 = right),
``fl`` (N+1, NFL) numerical fluxes at the N+1 interfaces (0 = ship end s=0, N = vehicle end s=L).
"""

# --- float parameters prm[...] ---
P_GAMMA0 = 0
P_EA = 1
P_ZETA = 2
P_MT = 3  # tangential added mass per metre
P_MN = 4  # normal added mass per metre
P_FBZ = 5  # net vertical buoyancy per metre (negative: sinks) [Eq. 14]
P_HALF_RHO_D = 6  # 0.5 rho_f d
P_CDT = 7
P_CDN = 8
P_ZG = 9
P_KD = 10
P_CCRIT = 11
P_SBZETA = 12
P_MU = 13
P_VMU = 14
P_EI = 15
P_ZETAB = 16
P_BETA = 17
P_TORQUE = 18
P_RELAX = 19  # artificial linear damping rate (1/s) on the momentum, dynamic relaxation only
P_LAMBDA_FLOOR = 20  # lower bound of the Lax-Friedrichs speed (m/s)
P_LAMBDA_BC = 21  # upwind speed of the velocity-end fluxes: the taut wave speed c (m/s)
P_QPEN = 22  # factor on the Lax-Friedrichs penalty of the q equation (1 = Eq. 24, 0 = central)
N_PRM = 23

# --- integer parameters iprm[...] ---
I_N = 0
I_P = 1
I_Q = 2
I_LAW = 3
I_SEABED = 4
I_CURRENT = 5
I_BENDING = 6
I_ANCHOR = 7  # 0: positions integrated from s = 0, 1: from s = L
I_KIND0 = 8  # end kind at s = 0
I_KIND1 = 9  # end kind at s = L
I_NEEDPOS = 10  # positions at the Gauss points needed (current or seabed)
I_BENDDAMP = 11  # bending damping active
I_AXDAMP = 12  # any damping (axial or bending): strain-rate gradient needed
N_IPRM = 13

# --- end kinds [PE2020 Table 1] ---
K_PRESCRIBED = 0
K_FIXED = 1
K_FREE = 2
K_FORCE = 3
K_CLAMPED = 4
K_BODY = 5
KIND_CODES = {"prescribed": K_PRESCRIBED, "fixed": K_FIXED, "free": K_FREE, "force": K_FORCE,
              "clamped": K_CLAMPED, "body": K_BODY}

# --- end data bc[end, ...] ---
B_T0 = 0
B_T1 = 1
B_P0 = 2
B_V0 = 5
B_P1 = 8
B_V1 = 11
B_F = 14
B_M = 17
B_DIR = 20
N_BC = 23

# --- channels at the Gauss points wq[e, j, ...] ---
W_Q = 0
W_V = 3
W_I = 6
W_L = 9
W_EDOT = 10
W_TV = 11  # tension vector T i + T_s
W_R = 14  # position
W_DQ = 17  # dq/dt
W_DT = 20  # dT/ds (DG derivative of the tension vector)
W_ACC = 23  # dv/dt
W_IDOT = 26  # di/dt
W_KAP = 29
W_KDOT = 32
W_MS = 35  # M* = M / l^2
W_TAU = 38
W_NUS = 41  # d(v/gamma0)/ds with central fluxes (strain rate for the damping terms)
NWQ = 44

# --- modal channels wm[e, k, ...] ---
M_DQ = 0
M_TV = 3
M_DT = 6
M_I = 9
M_KAP = 12
M_IDOT = 15
M_KDOT = 18
M_MS = 21
M_TAU = 24
M_NUS = 27
NWM = 30

# --- trace channels tr[e, side, ...] ---
T_Q = 0
T_V = 3
T_TV = 6
T_I = 9
T_IDOT = 12
T_MS = 15
T_DQ = 18
T_LAM = 21
NTR = 22

# --- interface flux channels fl[k, ...] ---
F_Q = 0  # v_hat / gamma0
F_V = 3  # T_hat
F_I = 6
F_IDOT = 9
F_MS = 12
F_NU = 15  # central velocity flux (damping strain rate)
NFL = 18

# --- end outputs endf[end, ...]: force by the cable on the end (3), axial tension, moment (3) ---
E_F = 0
E_T = 3
E_M = 4
E_VHAT = 7  # flux velocity of the end (m/s)
N_ENDF = 10
