"""Twin tests: each fast path of the DG kernels against a plain, obviously correct counterpart.

- the structure-of-arrays momentum rate (soa.py) against the element-wise one (kernels.momentum_rate),
  bit for bit as soa.py claims, and the element-wise one against a numpy transcription of
  PE2020 Eq. 4, 13, 14, 17, 23 (strong derivative, Morison drag, weight, added mass, projection);
- the tension and wave speed written out in kernels.tension_scalar against their composition
  (constitutive.axial_tension, kernels.local_speed), bit for bit;
- the no-compression clips (fluxes.clip_compression, stepper.clip_end_fluxes, damping_ops.clip_set)
  against plain numpy versions of the rule they implement.

Marked ``jit_off``: `make test` also runs them with NUMBA_DISABLE_JIT=1 (the kernels as plain
Python), so the compiled and the interpreted kernels are held to the same assertions.
"""

import numpy as np
import pytest

from tether_sim.config import SimConfig
from tether_sim.physics.boundary import EndCondition
from tether_sim.physics.cable import CableProperties
from tether_sim.physics.constitutive import axial_tension, buckled, cap_stiffness, compression_cap, elastic_tension
from tether_sim.physics.environment import Environment
from tether_sim.solvers.config import DGOptions, InitialState
from tether_sim.solvers.dg import layout as Y
from tether_sim.solvers.dg.fluxes import clip_compression
from tether_sim.solvers.dg.kernels import local_speed, momentum_rate
from tether_sim.solvers.dg.soa import SOA_MIN_ELEMENTS, TMP_HEAD, momentum_rate_soa, soa_momentum_applies
from tether_sim.solvers.dg.solver import DGCableSolver

pytestmark = pytest.mark.jit_off


def cable_solver(N=3, P=4, EI=0.0, law="bilinear", kinds=("prescribed", "free"), damping="explicit", seed=0,
                 compression="buckling"):
    """A 50 m cable in water with drag, anisotropic added mass and damping, on a curved state with
    slack and taut points and a random velocity (every branch of the point loads is visited). With bending the
    capped compression (cable.compression buckling) by default: its branches are the ones written out."""
    cab = CableProperties(length=50.0, EA=2e5, gamma0=3.0, diameter=0.03, density=7000.0, EI=EI, damping=300.0,
                          material=law, compression=compression, Cdn=1.2, Cdt=0.05, Cmn=1.0, Cmt=0.3,
                          table_strain=(0.0, 0.01, 0.05), table_tension=(0.0, 1e3, 2e4))
    cfg = SimConfig(cable=cab, environment=Environment(g=9.81, fluid_density=1025.0),
                    ship_end=EndCondition(kind=kinds[0], position=(0, 0, 0)),
                    vehicle_end=EndCondition(kind=kinds[1], position=(30.0, 0, -40.0)),
                    dg=DGOptions(n_elements=N, order=P, damping=damping), initial=InitialState(kind="straight"))
    s = DGCableSolver(cfg)
    rng = np.random.default_rng(seed)
    a = rng.uniform(0.5, 1.5, 3)
    s.set_shape(lambda x: (1.0 + 0.012 * np.sin(0.4 * x + a[0]))[:, None]
                * np.stack([0.6 * np.cos(0.05 * a[1] * x), 0.6 * np.sin(0.05 * a[1] * x), -0.8 + 0 * x], 1),
                velocity=lambda x: np.stack([np.sin(0.2 * x), 0.3 * np.cos(a[2] * x), 0.1 + 0 * x], 1))
    s.ws.U += 1e-3 * rng.standard_normal(s.ws.U.shape)
    s.ws.ends[:, 3:6] = rng.standard_normal((2, 3))
    return s


CASES = [dict(N=3, P=4), dict(N=2, P=4, EI=50.0), dict(N=5, P=2, kinds=("prescribed", "body")),
         dict(N=4, P=3, law="linear", kinds=("fixed", "force")), dict(N=8, P=4)]


def scalar_momentum(s):
    """dv/dt of kernels.momentum_rate on the element-wise path (scratch too short for soa.py)."""
    dU = s.ws.dU.copy()
    tmp = s.ws.tmp[:TMP_HEAD].copy()
    momentum_rate(s.ws.U, s.ws.ra, s.ws.prm, s.ws.iprm, s.ws.h, s.ws.V, s.ws.Pj, s.ws.D, s.ws.Lf, s.ws.Iq, s.ws.cz, s.ws.cx, s.ws.cy, s.ws.wq, s.ws.wm, s.ws.trc,
                  s.ws.fl, s.ws.rs, tmp, dU)
    return dU[:, :, 3:6]


@pytest.mark.parametrize("case", CASES)
@pytest.mark.parametrize("relax", [0.0, 0.7])
def test_soa_momentum_equals_the_elementwise_path_bit_for_bit(case, relax):
    s = cable_solver(**case)
    s.ws.prm[Y.P_RELAX] = relax
    assert soa_momentum_applies(s.ws.iprm, s.ws.V, s.ws.tmp) == (s.N >= SOA_MIN_ELEMENTS)  # the dispatch rule
    s._evaluate()  # fills the work arrays step 5 reads
    dU = s.ws.dU.copy()
    momentum_rate_soa(s.ws.prm, s.ws.iprm, s.ws.h, s.ws.V, s.ws.Pj, s.ws.D, s.ws.Lf, s.ws.wq, s.ws.wm, s.ws.trc, s.ws.fl, s.ws.tmp, dU)
    assert np.array_equal(scalar_momentum(s), dU[:, :, 3:6])
    assert np.array_equal(s.ws.dU[:, :, 3:6], dU[:, :, 3:6])  # whichever path the evaluation took


def numpy_momentum(s):
    """PE2020 Eq. 23 (strong form, modal) for dv/dt from the tension vector's modes, traces and fluxes
    left by the evaluation, plus Eq. 13, 14, 17 per Gauss point, written with numpy."""
    p, g0 = s.ws.prm, s.ws.prm[Y.P_GAMMA0]
    out = np.zeros((s.N, s.P + 1, 3))
    for e in range(s.N):
        f = s.ws.wm[e, :, Y.M_TV:Y.M_TV + 3]  # modes of T i + T_s
        jump_r = s.ws.fl[e + 1, Y.F_V:Y.F_V + 3] - s.ws.trc[e, 1, Y.T_TV:Y.T_TV + 3]
        jump_l = s.ws.fl[e, Y.F_V:Y.F_V + 3] - s.ws.trc[e, 0, Y.T_TV:Y.T_TV + 3]
        dT = (2.0 / s.ws.h[e]) * (np.triu(s.ws.D, 1) @ f) + (np.outer(s.ws.Lf[1], jump_r) - np.outer(s.ws.Lf[0], jump_l)) / s.ws.h[e]
        wq = s.ws.wq[e]
        i, l, v = wq[:, Y.W_I:Y.W_I + 3], wq[:, Y.W_L], wq[:, Y.W_V:Y.W_V + 3]
        w = -v / g0  # still water: relative flow = -cable velocity
        wt = np.sum(w * i, axis=1)
        wn = w - wt[:, None] * i
        pre = p[Y.P_HALF_RHO_D] * np.sqrt(l)
        drag = pre[:, None] * (p[Y.P_CDT] * (np.abs(wt) * wt)[:, None] * i
                               + p[Y.P_CDN] * np.linalg.norm(wn, axis=1)[:, None] * wn)
        F = s.ws.V @ dT + drag + np.array([0.0, 0.0, p[Y.P_FBZ]])
        Ft = np.sum(F * i, axis=1)[:, None] * i
        acc = g0 / (g0 + p[Y.P_MT]) * Ft + g0 / (g0 + p[Y.P_MN]) * (F - Ft) - p[Y.P_RELAX] * v
        out[e] = s.ws.Pj @ acc
    return out


@pytest.mark.parametrize("case", CASES)
def test_elementwise_momentum_matches_a_numpy_transcription(case):
    s = cable_solver(**case)
    s.ws.prm[Y.P_RELAX] = 0.3
    s._evaluate()
    fast, plain = scalar_momentum(s), numpy_momentum(s)
    # same terms summed in a different order: round-off of the largest term (EA-sized tension
    # divergence over short elements) times a few ulps
    assert np.max(np.abs(fast - plain)) <= 1e-12 * np.max(np.abs(plain))


@pytest.mark.parametrize("law", ["bilinear", "linear", "table"])
@pytest.mark.parametrize("N, P, EI", [(3, 4, 0.0), (2, 3, 0.0), (3, 4, 2000.0)])
def test_written_out_tension_and_wave_speed_equal_their_composition(law, N, P, EI):
    s = cable_solver(N=N, P=P, law=law, EI=EI)
    s.ws.iprm[Y.I_BENDING] = 0  # W_TV = T i alone (the cap depends on EI and P, not on this switch)
    s._evaluate()
    code, EA, zeta = s.law.code, s.ws.prm[Y.P_EA], s.ws.prm[Y.P_ZETA]
    wq = s.ws.wq
    eps = wq[:, :, Y.W_L] - 1.0
    assert eps.min() < 0.0 < eps.max()  # slack and taut points
    pc = [compression_cap(code, cap_stiffness(s.config.cable), P, h) for h in s.ws.h]
    if EI > 0.0 and law != "linear":  # strained compression and buckled points are both visited
        bk = np.array([[buckled(code, eps[e, j], EA, s.law.tab_eps, s.law.tab_T, pc[e])
                        for j in range(wq.shape[1])] for e in range(N)])
        assert bk.any() and ((eps < 0) & ~bk).any()
    T = np.array([[axial_tension(code, eps[e, j], wq[e, j, Y.W_EDOT], EA, zeta, s.law.tab_eps, s.law.tab_T, pc[e])
                   for j in range(wq.shape[1])] for e in range(N)])
    assert np.array_equal(wq[:, :, Y.W_TV:Y.W_TV + 3], T[:, :, None] * wq[:, :, Y.W_I:Y.W_I + 3])
    q = s.ws.trc[:, :, Y.T_Q:Y.T_Q + 3]
    lam = np.array([[local_speed(s.ws.prm, code, *q[e, side], s.law.tab_eps, s.law.tab_T, pc[e]) for side in range(2)]
                    for e in range(N)])
    assert np.array_equal(s.ws.trc[:, :, Y.T_LAM], lam)


def plain_clip(flux, q, pc=0.0):
    """T_hat with its axial part (T_hat . i) clipped at -pc along i = q / |q|."""
    n = np.linalg.norm(q)
    if n <= 1e-300:
        return flux.copy()
    i = q / n
    a = flux @ i
    return flux - (a + pc) * i if a < -pc else flux.copy()


@pytest.mark.parametrize("shear", [False, True])
@pytest.mark.parametrize("pc", [0.0, 3e3])
def test_clip_compression_removes_exactly_the_compressive_axial_part(pc, shear):
    """... of the flux without the bending shear trace T_TS when shear (a velocity end of a cable with bending)."""
    rng = np.random.default_rng(3)
    for trial in range(200):
        fl = np.zeros((3, Y.NFL))
        tr = np.zeros((2, 2, Y.NTR))
        fl[:, Y.F_V:Y.F_V + 3] = rng.standard_normal((3, 3)) * 1e4
        tr[:, :, Y.T_Q:Y.T_Q + 3] = rng.standard_normal((2, 2, 3)) * (0.0 if trial % 50 == 0 else 1.0)
        tr[:, :, Y.T_TS:Y.T_TS + 3] = rng.standard_normal((2, 2, 3)) * 1e4
        k, e, side = trial % 3, trial % 2, (trial // 2) % 2
        ts = tr[e, side, Y.T_TS:Y.T_TS + 3] if shear else np.zeros(3)
        want = ts + plain_clip(fl[k, Y.F_V:Y.F_V + 3] - ts, tr[e, side, Y.T_Q:Y.T_Q + 3], pc)
        if not shear or np.linalg.norm(tr[e, side, Y.T_Q:Y.T_Q + 3]) == 0:
            want = plain_clip(fl[k, Y.F_V:Y.F_V + 3], tr[e, side, Y.T_Q:Y.T_Q + 3], pc) if not shear else \
                fl[k, Y.F_V:Y.F_V + 3].copy()
        clip_compression(fl, tr, k, e, side, pc, shear)
        # same formula, the axial component recomputed by numpy's dot: a few ulps of |T_hat|
        assert np.allclose(fl[k, Y.F_V:Y.F_V + 3], want, rtol=0, atol=1e-15 * 1e4 * 10)
        q = tr[e, side, Y.T_Q:Y.T_Q + 3]
        if np.linalg.norm(q) > 0:  # never below -pc after (the flux without the shear)
            assert (fl[k, Y.F_V:Y.F_V + 3] - ts) @ q / np.linalg.norm(q) >= -pc - 1e-10


def evaluate(s, fdamp, implicit):
    """dg_evaluate with the stepper's parameters of dg.damping = implicit (damping zeroed)."""
    from tether_sim.solvers.dg.stepper import dg_evaluate
    from tether_sim.solvers.dg.workspace import views

    prm = s.ws.prm_step
    prm[:] = s.ws.prm
    prm[Y.P_ZETA] = prm[Y.P_ZETAB] = 0.0
    dg_evaluate(s.time, views(s.ws), prm, s.ws.iprm_step, fdamp, implicit)
    return s.ws.dU.copy(), s.ws.endf.copy()


@pytest.mark.parametrize("kinds", [("prescribed", "body"), ("prescribed", "free"), ("fixed", "clamped")])
def test_clip_end_fluxes_is_the_clip_of_the_total_end_flux(kinds):
    """Implicit damping: the end flux the explicit stages see is clip(T_el+ upwinded + T_d+) (the
    explicit scheme's rule), and its difference to dg_rhs's own flux is lifted into the end element."""
    s = cable_solver(N=3, P=3, kinds=kinds, damping="implicit", EI=10.0 if "clamped" in kinds else 0.0)
    rng = np.random.default_rng(7)
    g0 = s.ws.prm[Y.P_GAMMA0]
    ct = g0 / (g0 + s.ws.prm[Y.P_MT])
    cn = g0 / (g0 + s.ws.prm[Y.P_MN])
    clipped = 0
    for trial in range(12):
        fdamp = np.zeros((2, 4))
        fdamp[:, 0:3] = rng.standard_normal((2, 3)) * 3e3
        fdamp[:, 3] = rng.standard_normal(2)
        dU0, endf0 = evaluate(s, fdamp, False)
        fl, tr, vbc = s.ws.fl.copy(), s.ws.trc.copy(), s.ws.vbc.copy()
        dU1, endf1 = evaluate(s, fdamp, True)
        want_dU, want_endf = dU0.copy(), endf0.copy()
        want_endf[:, 0:3] += fdamp[:, 0:3]
        want_endf[:, 3] += fdamp[:, 3]
        for end in range(2):
            if not s.ends[end].kinematic:
                continue
            e, k, sgn = end * (s.N - 1), end * s.N, 1.0 if end == 0 else -1.0  # sgn = -n
            q = tr[e, end, Y.T_Q:Y.T_Q + 3]
            i = q / np.linalg.norm(q)
            lam = max(tr[e, end, Y.T_LAM], s.ws.prm[Y.P_LAMBDA_BC])
            elastic = tr[e, end, Y.T_TV:Y.T_TV + 3] - sgn * lam * (g0 * vbc[end, 3:6] - tr[e, end, Y.T_V:Y.T_V + 3])
            pc = compression_cap(s.law.code, cap_stiffness(s.config.cable), s.P, s.ws.h[e])  # > 0 with bending (clamped case)
            ts = tr[e, end, Y.T_TS:Y.T_TS + 3] if s.config.cable.EI > 0 else np.zeros(3)  # the clip leaves it out
            total = ts + plain_clip(elastic + sgn * fdamp[end, 0:3] - ts, q, pc)
            clipped += int(not np.array_equal(total, elastic + sgn * fdamp[end, 0:3]))
            d = total - fl[k, Y.F_V:Y.F_V + 3] - sgn * fdamp[end, 0:3]
            want_endf[end, 0:3] += sgn * d
            want_endf[end, 3] += d @ i
            lift = (-sgn / s.ws.h[e]) * (s.ws.V @ s.ws.Lf[end])[:, None] * d[None, :]  # strong-form lift at the points
            ip = s.ws.wq[e, :, Y.W_I:Y.W_I + 3]
            par = np.sum(lift * ip, axis=1)[:, None] * ip
            want_dU[e, :, 3:6] += s.ws.Pj @ (ct * par + cn * (lift - par))
            # the end force the bodies and outputs see is -n times the clipped total flux
            assert np.allclose(endf1[end, 0:3], sgn * total, rtol=1e-12, atol=1e-9)
        scale = np.max(np.abs(want_dU))
        assert np.allclose(dU1, want_dU, rtol=0, atol=1e-12 * scale)
        assert np.allclose(endf1, want_endf, rtol=1e-12, atol=1e-9)
    assert clipped > 0  # the compressive branch was exercised


@pytest.mark.parametrize("EI", [0.0, 0.3])
@pytest.mark.parametrize("law", ["bilinear", "table", "linear"])
def test_clip_set_marks_exactly_the_points_whose_total_tension_would_push(law, EI):
    """... below -p_c, the compression cap (0 without bending)."""
    from tether_sim.solvers.dg import damping_layout as DL
    from tether_sim.solvers.dg.damping_ops import clip_set, damping_geometry

    s = cable_solver(N=4, P=3, law=law, damping="implicit", EI=EI)
    dw = s._damp
    damping_geometry(s.ws.U, s.ws.V, dw.idp, dw.dprm, dw.wp, s.law.tab_eps, s.law.tab_T)
    wp = dw.wp
    rng = np.random.default_rng(11)
    wp[:, :, DL.WP_E0] = rng.standard_normal(wp.shape[:2]) * 20.0  # strain rates of either sign
    Z0 = wp[:, :, DL.WP_Z].copy()
    n = clip_set(dw.idp, dw.dprm, wp, s.law.tab_eps, s.law.tab_T)
    zeta = dw.dprm[DL.DP_ZETA]
    pc = np.array([compression_cap(s.law.code, cap_stiffness(s.config.cable), 3, h) for h in s.ws.h])[:, None] + 0.0 * wp[:, :, DL.WP_L]
    assert np.array_equal(wp[:, :, DL.WP_PC], pc) and (law == "linear" or (pc > 0).all() == (EI > 0))
    eps = wp[:, :, DL.WP_L] - 1.0
    tel = np.vectorize(lambda x, c: elastic_tension(s.law.code, x, s.law.EA, s.law.tab_eps, s.law.tab_T, c))(eps, pc)
    k0 = s.law.EA if law != "table" else s.law.tab_T[1] / s.law.tab_eps[1]
    strained = (eps > 0) | (law == "linear") | ((pc > 0) & (k0 * eps > -pc))
    assert np.array_equal(Z0 > 0, strained)
    push = (Z0 > 0) & (tel + zeta * wp[:, :, DL.WP_E0] < -pc) if law != "linear" else np.zeros(Z0.shape, bool)
    assert n == push.sum() and (law == "linear" or 0 < n < push.size)
    assert np.array_equal(wp[:, :, DL.WP_Z], np.where(push, 0.0, Z0))
    assert np.array_equal(wp[:, :, DL.WP_TC], np.where(push, -pc - tel, 0.0))
