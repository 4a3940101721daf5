"""Compiled winch terms of the DG cable: material entering and leaving the domain at one end.

The winch sits at end w (0: the ship, s = 0; 1: the vehicle, s = L) and pays out (dL/dt > 0) or
hauls in (dL/dt < 0) unstretched cable. The material coordinate of the wet cable is mapped onto
the fixed elements, sc = xi L(t), xi in [0, 1] (element sizes h_e = w_e L(t), w_e fixed), so the
state is u(xi, t) and (docs/dg_solver.md, "Winch")

    du/dt|_xi = du/dt|_s - a(sc) du/dsc,   a(sc) = dL/dt (1 - sc/L) (w = 0),  -dL/dt sc/L (w = 1)

with du/dt|_s the right-hand side of the fixed-length cable (kernels.dg_rhs). a is linear in sc,
zero at the far end (a material point) and +-dL/dt at the winch. Three pieces, each called only
while the winch moves (dL/dt != 0, so a fixed-length run is untouched):

- ``winch_end_velocity``: the kinematic end condition of the material at the sheave,
  v_BC = v_sheave - n dL/dt q+ (paid-out material moves along the tangent, hauled-in material
  against it), added to the end velocity the fluxes read;
- ``winch_transport``: the transport term -a du/dsc, exact in modal space (a u' is a polynomial of
  degree P), with upwind interface fluxes; at the winch the inflow state is (q+, gamma0 v_BC),
  outflow needs no data; the anchor position follows the sheave (dr_a/dt -= a q+);
- ``winch_stage`` / ``winch_update``: the stage length and element sizes, and the SSP-RK3 stage
  update done on W = L u (d W/dt = dL/dt u + L du/dt|_xi), so that the integrals of q and v over
  the domain change exactly by the boundary terms (linear invariants of a Runge-Kutta method).
"""

from tether_sim.numerics.jit import jit
from tether_sim.solvers.dg.layout import (
    I_ANCHOR, I_N, I_WINCH, P_GAMMA0, P_WL, P_WLDOT, P_WR0, P_WR1, T_Q, T_V,
)


@jit
def winch_moving(prm, iprm):
    """A winch is configured and its rate is not zero at both ends of this tick."""
    return iprm[I_WINCH] != 0 and (prm[P_WR0] != 0.0 or prm[P_WR1] != 0.0)


@jit
def winch_active(prm, iprm):
    """The winch terms apply at this evaluation (rate at the evaluation time nonzero)."""
    return iprm[I_WINCH] != 0 and prm[P_WLDOT] != 0.0


@jit
def winch_end_velocity(U, prm, iprm, Tr, vbc):
    """v_BC of the winch end += -n dL/dt q+ (the material at the sheave, q+ its trace of q)."""
    w = iprm[I_WINCH] - 1
    N = iprm[I_N]
    e = w * (N - 1)
    sgn = 1.0 if w == 0 else -1.0  # -n
    ld = sgn * prm[P_WLDOT]
    nm = U.shape[1]
    for c in range(3):
        q = 0.0
        for k in range(nm):
            q += Tr[w, k] * U[e, k, c]
        vbc[w, 3 + c] += ld * q


@jit
def winch_transport(U, prm, iprm, h, Lf, tr, vbc, dU, dra):
    """dU += -a(sc) du/dsc with upwind fluxes (module docstring); tr holds the traces of U.

    On element e (sc = s_e + h (1 + x)/2), a = alpha + beta x, u' = (2/h) du/dx; with the modal
    derivative d = D u (degree P - 1) and x phi_l = ((l + 1) phi_{l+1} + l phi_{l-1}) / (2l + 1),
    (a u')_k = (2/h) (alpha d_k + beta (k d_{k-1} / (2k - 1) + (k + 1) d_{k+1} / (2k + 3))),
    exactly; evaluated in O(P) per component with the even-offset sums E_k (no divisions; D is
    not read: the Legendre derivative has the closed form used there). Face terms of the strong form: + (1/h) Lf[1, k] a_R (u_R - u*_R)
    - (1/h) Lf[0, k] a_L (u_L - u*_L), u* the upwind state (own trace where the flow leaves)."""
    w = iprm[I_WINCH] - 1
    N = iprm[I_N]
    nm = U.shape[1]
    ld = prm[P_WLDOT]
    L = prm[P_WL]
    g0 = prm[P_GAMMA0]
    slope = -ld / L
    a0 = ld if w == 0 else 0.0  # a(sc) = a0 + slope sc
    s_left = 0.0
    for e in range(N):
        he = h[e]
        aL = a0 + slope * s_left
        aR = a0 + slope * (s_left + he)
        if w == 0 and e == N - 1:
            aR = 0.0  # the far end is a material point
        if w == 1 and e == 0:
            aL = 0.0
        alpha = 0.5 * (aL + aR)
        beta = 0.5 * (aR - aL)
        ih = 1.0 / he
        for c in range(6):
            ch = T_Q + c if c < 3 else T_V + c - 3
            # upwind jumps u - u* at the two faces (zero where the flow leaves the element)
            jR = 0.0
            if aR < 0.0:
                if e < N - 1:
                    jR = tr[e, 1, ch] - tr[e + 1, 0, ch]
                elif c >= 3:  # inflow at s = L (winch at the vehicle end): v* = gamma0 v_BC, q* = q+
                    jR = tr[e, 1, ch] - g0 * vbc[1, c]
            jL = 0.0
            if aL > 0.0:
                if e > 0:
                    jL = tr[e, 0, ch] - tr[e - 1, 1, ch]
                elif c >= 3:  # inflow at s = 0 (winch at the ship end)
                    jL = tr[e, 0, ch] - g0 * vbc[0, c]
            fR = ih * aR * jR
            fL = ih * aL * jL
            # d_k = (2k + 1) E_{k+1}, (x d)_k = k E_k + (k + 1) E_{k+2} with E_k = u_k + E_{k+2}
            # (the Legendre derivative d_k = (2k + 1) sum_{m > k, m - k odd} u_m), downwards in k
            e1 = 0.0
            e2 = 0.0
            for k in range(nm - 1, -1, -1):
                e0 = U[e, k, c] + e2
                fk = float(k)
                dU[e, k, c] += (-2.0 * ih * (alpha * (2.0 * fk + 1.0) * e1 + beta * (fk * e0 + (fk + 1.0) * e2))
                                + Lf[1, k] * fR - Lf[0, k] * fL)
                e2 = e1
                e1 = e0
        s_left += he
    if iprm[I_ANCHOR] == w:  # the anchor is the sheave: dr_a/dt = v_hat / gamma0 - a q+ = sheave velocity
        e = w * (N - 1)
        aw = ld if w == 0 else -ld
        for c in range(3):
            dra[c] -= aw * tr[e, w, T_Q + c]


@jit
def winch_rate(prm, t, t0, t1):
    """Pay-out rate at time t: linear ramp from P_WR0 at t0 to P_WR1 at t1."""
    r0 = prm[P_WR0]
    if t1 <= t0:
        return prm[P_WR1]
    return r0 + (prm[P_WR1] - r0) * (t - t0) / (t1 - t0)


@jit
def winch_length(prm, L0, t, t0, t1):
    """Length at time t of a tick that started at t0 with length L0 (the ramp integrated exactly):
    L0 + tau (r0 + (r1 - r0) tau / (2 (t1 - t0))), tau = t - t0; at t1 the trapezoid (r0 + r1) / 2."""
    r0 = prm[P_WR0]
    tau = t - t0
    if t1 <= t0:
        return L0 + tau * r0
    return L0 + tau * (r0 + 0.5 * (prm[P_WR1] - r0) * tau / (t1 - t0))


@jit
def winch_stage(prm, hw, h, t, t0, t1):
    """Before a stage at time t: the rate there and the element sizes of the stage length."""
    prm[P_WLDOT] = winch_rate(prm, t, t0, t1)
    L = prm[P_WL]
    for e in range(h.shape[0]):
        h[e] = hw[e] * L


@jit
def winch_update(a, b, dt, Ls, U, U0, dU, prm, L_end):
    """SSP-RK3 stage u = a u0 + b (u + dt du) done on W = L u and on L (dL/dt = rate):
    L_new = a L_s + b (L + dt Ldot), u = (a L_s u0 + b (L u + dt (Ldot u + L du))) / L_new.
    L_end > 0 (the last stage): L_new = L_end, the length of the ramp at the step's end, which
    the stages reproduce (SSP-RK3 integrates the linear ramp exactly) up to the round-off that
    would otherwise accumulate over the steps (5e-12 relative after 4e4 steps, measured)."""
    L = prm[P_WL]
    ld = prm[P_WLDOT]
    Ln = a * Ls + b * (L + dt * ld) if L_end <= 0.0 else L_end
    ca = a * Ls / Ln
    cb = b / Ln
    N, nm, nv = U.shape
    for e in range(N):
        for k in range(nm):
            for c in range(nv):
                u = U[e, k, c]
                U[e, k, c] = ca * U0[e, k, c] + cb * (L * u + dt * (ld * u + L * dU[e, k, c]))
    prm[P_WL] = Ln


@jit
def winch_finish(prm, prm_step, hw, h):
    """After a tick: the driver's length and rate (the rate reached stays), sizes of that length."""
    prm[P_WL] = prm_step[P_WL]
    prm[P_WR0] = prm[P_WR1]
    prm[P_WLDOT] = prm[P_WR1]
    L = prm[P_WL]
    for e in range(h.shape[0]):
        h[e] = hw[e] * L
