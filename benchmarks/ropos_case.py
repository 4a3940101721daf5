"""The ROPOS tether + cage benchmark case, defined once for every benchmark script.

Data: [PE2020 Sec. 6, Table 3]. Tether EA = 45.5 MN, gamma0 = 3.01 kg/m, d = 0.03 m,
rho_c = 7153 kg/m^3, zeta = 45.5 kN s (T = EA eps + zeta deps/dt, [PE2020 Eq. 22]),
Cdn = 1, Cdt = 0.02, Cmn = 1, Cmt = 0. Cage: 4995 kg, density 8448 kg/m^3, added mass 9200 kg,
heave drag 2.7 on the lid area pi/4 * 3.01^2, surge drag 1.3 on D * H = 3.01 * 4.2 m^2,
pitch inertia 19e3 kg m^2, tether attached 2.1 m above the centre of gravity.
Forcing: circular fairlead orbit in the vertical x-z plane, a = 2 m, f = 0.2 Hz [PE2020 Sec. 6.2],
which goes through slack and snap.

Two deliberate choices, identical for every code that runs the case:

* The orbit centre is ``ORBIT_DEPTH`` = 3 m below the still-water level (the paper puts the
  fairlead at z = 0), so that no cable node ever leaves the water: MoorDyn cuts buoyancy and drag
  of emerged segments, our solvers do not model the free surface.
* The orbit amplitude is ramped in over the first period (the project's C2 quintic ramp) so that
  the fairlead starts from rest (no velocity jump that would launch a spurious transverse wave).

The same forcing function :func:`fairlead_motion` drives our solvers (through
``set_end_motion`` / ``advance_to``) and MoorDyn (through its coupled point), so the snap peaks
are comparable.

MoorDyn mapping (see :func:`moordyn_line_type`): MoorDyn takes one diameter for buoyancy, added
mass and drag (volume pi/4 d^2 per metre), whereas the paper separates the material area
A = gamma0 / rho_c (weight, buoyancy) from the hydrodynamic diameter d (drag, added mass). We give
MoorDyn the volume-equivalent diameter d_v = sqrt(4 A / pi) and rescale its coefficients so that
every force per metre is the same: Cd_md = Cdn d / d_v, Ca_md = Cmn (d / d_v)^2,
CdAx_md = Cdt d / (pi d_v) (MoorDyn's tangential drag acts on the surface pi d l). MoorDyn's
internal damping BA enters as T_d = BA * (dl/dt) / l = BA * deps/dt, i.e. BA (N s) = zeta.
"""

import math

import numpy as np

from tether_sim.config import SimConfig
from tether_sim.physics.bodies import RigidBodyProperties
from tether_sim.physics.boundary import EndCondition
from tether_sim.physics.cable import CableProperties
from tether_sim.physics.environment import Environment
from tether_sim.physics.motion import MotionConfig, build_motion
from tether_sim.solvers.config import DGOptions, HybridOptions, InitialState

# ---- tether [PE2020 Table 3] ----
EA = 45.5e6  # N
GAMMA0 = 3.01  # kg/m
DIAMETER = 0.03  # m
RHO_C = 7153.0  # kg/m^3
ZETA = 45.5e3  # N s, axial material damping [PE2020 Eq. 22]
CDN, CDT, CMN, CMT = 1.0, 0.02, 1.0, 0.0
EI_STAR = 2.62e3  # N m^2, EI of the field-tested tether [PE2020 Sec. 6.2]
# ---- cage ----
CAGE_MASS = 4995.0  # kg
CAGE_DENSITY = 8448.0  # kg/m^3
CAGE_ADDED_MASS = 9200.0  # kg (empirical value used by PE2020)
CAGE_DIAMETER = 3.01  # m
CAGE_HEIGHT = 4.2  # m
CAGE_CD_SURGE, CAGE_CD_HEAVE = 1.3, 2.7
CAGE_LID_AREA = math.pi / 4.0 * CAGE_DIAMETER**2  # m^2
CAGE_SIDE_AREA = CAGE_DIAMETER * CAGE_HEIGHT  # m^2
CAGE_INERTIA = 19.0e3  # kg m^2
CAGE_ATTACH_HEIGHT = 2.1  # m, attachment above the centre of gravity (half the height)
# ---- environment and forcing ----
RHO_F = 1025.0
G = 9.81
ORBIT_AMPLITUDE = 2.0  # m
ORBIT_FREQUENCY = 0.2  # Hz
ORBIT_DEPTH = 3.0  # m, orbit centre below the surface (see module doc)
RAMP_TIME = 1.0 / ORBIT_FREQUENCY  # s, one period
LENGTHS = (200.0, 1730.0)


def motion_config():
    """The fairlead motion as the project configures it (``motion`` section of the SimConfig)."""
    return MotionConfig(kind="circle", amplitude=ORBIT_AMPLITUDE, frequency=ORBIT_FREQUENCY,
                        plane_azimuth=0.0, ramp_time=RAMP_TIME)


ORBIT_ORIGIN = (0.0, 0.0, -ORBIT_DEPTH)
_MOTION = build_motion(motion_config(), ORBIT_ORIGIN)


def fairlead_motion(t):
    """Fairlead position and velocity (world ENU) at time t (s): the project's own generator
    (``tether_sim.physics.motion.CircleMotion``: d = a r(t) (sin wt e_x + cos wt e_z) about the
    orbit centre, C2 quintic ramp r over one period), so the node, our solvers and MoorDyn all
    see the same forcing."""
    pos, vel, _ = _MOTION.at(t)
    return pos, vel


def cable_properties(length, alpha=0.0):
    """ROPOS tether of unstretched length L (m) and bending stiffness EI = alpha EI*."""
    return CableProperties(
        length=float(length), EA=EA, gamma0=GAMMA0, diameter=DIAMETER, density=RHO_C,
        EI=alpha * EI_STAR, damping=ZETA, material="bilinear", Cdn=CDN, Cdt=CDT, Cmn=CMN, Cmt=CMT,
    )


def cage_properties(top_z):
    """ROPOS cage hanging with its attachment point at height top_z (m)."""
    return RigidBodyProperties(
        mass=CAGE_MASS, density=CAGE_DENSITY, added_mass=(CAGE_ADDED_MASS,) * 3,
        drag_coefficients=(CAGE_CD_SURGE, CAGE_CD_SURGE, CAGE_CD_HEAVE),
        drag_areas=(CAGE_SIDE_AREA, CAGE_SIDE_AREA, CAGE_LID_AREA),
        inertia=(CAGE_INERTIA,) * 3, attachment=(0.0, 0.0, CAGE_ATTACH_HEIGHT),
        initial_position=(0.0, 0.0, top_z - CAGE_ATTACH_HEIGHT),
    )


def ropos_config(length, alpha=0.0, solver="dg", n_elements=20, order=4, duration=60.0,
                 hybrid_segments=100, hybrid_dt=0.01, cfl=0.5, cage="body", damping="explicit"):
    """SimConfig of the ROPOS case (ship end prescribed, cage as a simulated body).

    ``damping="implicit"`` sets dg.damping (implicit axial/bending damping, docs/dg_solver.md);
    "explicit" leaves DGOptions at its default.

    ``cage="force"`` replaces the cage by its submerged weight as a point load at s = L (no cage
    inertia or drag: a different snap, only for cost figures while a solver lacks body coupling).
    """
    p0, _ = fairlead_motion(0.0)
    top = tuple(float(v) for v in p0)
    bottom_z = p0[2] - float(length)
    if cage == "force":
        vehicle = EndCondition(kind="force", position=(0.0, 0.0, bottom_z), force=(0.0, 0.0, -cage_wet_weight()))
    elif cage == "body":
        vehicle = EndCondition(kind="body", position=(0.0, 0.0, bottom_z))
    else:
        raise ValueError(f"cage: 'body' or 'force', got {cage!r}")
    dg_extra = {} if damping == "explicit" else {"damping": damping}
    return SimConfig(
        solver=solver,
        duration=float(duration),
        cable=cable_properties(length, alpha),
        environment=Environment(g=G, fluid_density=RHO_F, seabed=False, seabed_z=-(float(length) + 500.0)),
        ship_end=EndCondition(kind="prescribed", position=top),
        vehicle_end=vehicle,
        body=cage_properties(bottom_z),
        dg=DGOptions(n_elements=int(n_elements), order=int(order), cfl=float(cfl), **dg_extra),
        hybrid=HybridOptions(n_segments=int(hybrid_segments), time_step=float(hybrid_dt)),
        initial=InitialState(kind="static"),
        motion=motion_config(),
    )


# ---------------------------------------------------------------- static reference values

def material_area():
    """A = gamma0 / rho_c (m^2) [PE2020 Eq. 14]."""
    return GAMMA0 / RHO_C


def wet_weight_per_metre():
    """Cable weight in water per unstretched metre, (gamma0 - rho_f A) g (N/m)."""
    return (GAMMA0 - RHO_F * material_area()) * G


def cage_wet_weight():
    """Cage weight minus buoyancy (N)."""
    return CAGE_MASS * G * (1.0 - RHO_F / CAGE_DENSITY)


def static_elongation(length):
    """Static elongation of the hanging tether (m): integral of T(s)/EA over the length."""
    return (cage_wet_weight() * length + 0.5 * wet_weight_per_metre() * length**2) / EA


def static_ship_tension(length):
    """Static top tension of the hanging tether + cage (N) (straight vertical, no current)."""
    return wet_weight_per_metre() * length + cage_wet_weight()


# ---------------------------------------------------------------- snap peak

PEAK_WINDOW = (20.0, 60.0)  # s; after the one-period ramp and the start-up transient
FIRST_SNAP_WINDOW = (5.0, 10.0)  # s; the first forcing period at full amplitude


def snap_peak(t, tension, t_start, t_end=None):
    """Largest ship tension in the window [t_start, t_end] (N) and its time (s)."""
    t = np.asarray(t)
    tension = np.asarray(tension)
    mask = t >= t_start
    if t_end is not None:
        mask &= t <= t_end
    if not np.any(mask):
        raise ValueError("snap_peak: no samples in the window")
    i = np.argmax(np.where(mask, tension, -np.inf))
    return float(tension[i]), float(t[i])


def snap_metrics(t, tension, window=PEAK_WINDOW, period=1.0 / ORBIT_FREQUENCY):
    """Snap-peak figures of one ship-tension record (N).

    ``first_peak`` (the accuracy metric): the largest tension of the first full-amplitude period
    (5-10 s), the first slack-snap event -- deterministic and cleanly convergent.
    ``mean_peak``: mean over the forcing periods in ``window`` of each period's largest tension --
    the later snaps vary from cycle to cycle (the slack phase differs), so they are sensitive to
    every detail; NaN when the record is shorter than one period of the window.
    ``max_peak``: the largest tension in ``window`` (NaN likewise).
    """
    t = np.asarray(t)
    tension = np.asarray(tension)
    end = min(window[1], float(t[-1]) + 1e-9)
    starts = np.arange(window[0], end - period + 1e-9, period)
    peaks = [snap_peak(t, tension, a, a + period)[0] for a in starts]
    return {
        "first_peak": snap_peak(t, tension, *FIRST_SNAP_WINDOW)[0],
        "mean_peak": float(np.mean(peaks)) if peaks else float("nan"),
        "cycle_peaks": [float(p) for p in peaks],
        "max_peak": snap_peak(t, tension, window[0], end)[0] if peaks else float("nan"),
    }


# ---------------------------------------------------------------- MoorDyn input

def moordyn_line_type(cable=None):
    """MoorDyn line coefficients giving the same forces per metre as our model (module doc);
    ``cable`` (CableProperties): another line's (default: the ROPOS tether)."""
    if cable is None:
        cable = cable_properties(1.0)
    area = cable.gamma0 / cable.density
    d_v = math.sqrt(4.0 * area / math.pi)
    ratio = cable.diameter / d_v
    return {
        "diam": d_v, "mass": cable.gamma0, "EA": cable.EA, "BA": cable.damping,
        "Cd": cable.Cdn * ratio, "Ca": cable.Cmn * ratio**2, "CdAx": cable.Cdt * ratio / math.pi,
        "CaAx": cable.Cmt * ratio**2,
    }


def moordyn_options(dt, scheme, depth, wave_kin=0, cfl=1000, tmax_ic=120, thresh_ic="1e-4", digits=8):
    """The OPTIONS section of a MoorDyn v2 input file as the comparisons here use it (one place for all).

    Output files and the log are off (``disableOutput``, ``writeLog 0``); the initial condition is MoorDyn's
    own dynamic relaxation (``dtIC`` 1 s, up to ``tmax_ic`` s, until the fairlead tensions change by less than
    ``thresh_ic``); ``cfl`` None leaves MoorDyn's own CFL rule at its default. ``digits`` significant digits
    for dt and the depth.
    """
    f = f".{digits}g"
    rows = ["0 writeLog", f"{dt:{f}} dtM"]
    if cfl is not None:
        rows.append(f"{cfl} CFL")
    rows += [f"{scheme} tScheme", f"{G} g", f"{RHO_F} rho", f"{depth:{f}} WtrDpth", f"{wave_kin} WaveKin",
             "0 Currents", "1 disableOutput", "1 disableOutTime", "1.0 dtIC", f"{tmax_ic} TmaxIC", f"{thresh_ic} threshIC"]
    return "---------------------- OPTIONS --------------------------------------------------------\n" + "\n".join(rows) + "\n"


def moordyn_input(length, n_segments, dt, alpha=0.0, scheme="RK2", cage="body"):
    """Text of a MoorDyn v2 input file for the ROPOS case.

    ``cage="body"``: Point 1 is the cage attachment (on free Body 1, 2.1 m above its CoG); body added
    mass 9200 kg = Ca rho V with V = m / rho_cage; drag CdA per axis, no rotational drag.
    ``cage="point"``: the cage is free Point 1 itself (3 DOF, at the attachment), with the same mass,
    volume (buoyancy), added mass (Ca rho V = 9200 kg, isotropic) and the heave drag area CdA =
    2.7 * pi/4 * 3.01^2 in every direction (a point has one CdA; the orbit heaves the cage, its
    surge drag area 1.3 * 3.01 * 4.2 differs by 15 %): the cheapest MoorDyn model of this heave.
    Point 2: the fairlead (coupled, driven by :func:`fairlead_motion`). Line 1 runs from the cage
    (end A) to the ship (end B).
    """
    lt = moordyn_line_type()
    p0, _ = fairlead_motion(0.0)
    top_z = p0[2]
    cg_z = top_z - length - static_elongation(length) - CAGE_ATTACH_HEIGHT
    volume = CAGE_MASS / CAGE_DENSITY
    ca = CAGE_ADDED_MASS / (RHO_F * volume)
    cda_h = CAGE_CD_SURGE * CAGE_SIDE_AREA
    cda_v = CAGE_CD_HEAVE * CAGE_LID_AREA
    ei = alpha * EI_STAR
    depth = length + 200.0
    point_head = ("---------------------- POINTS ---------------------------------------------------------\n"
                  "ID Attachment X Y Z Mass Volume CdA Ca\n(#) (word/ID) (m) (m) (m) (kg) (m^3) (m^2) (-)\n")
    if cage == "body":
        cage_rows = ("---------------------- BODIES ---------------------------------------------------------\n"
                     "ID Attachment X0 Y0 Z0 r0 p0 y0 Mass CG* I* Volume CdA* Ca*\n"
                     "(#) (word) (m) (m) (m) (deg) (deg) (deg) (kg) (m) (kg-m^2) (m^3) (m^2) (-)\n"
                     f"1 Free {p0[0]:.8g} {p0[1]:.8g} {cg_z:.8g} 0 0 0 {CAGE_MASS:.8g} 0 {CAGE_INERTIA:.8g} "
                     f"{volume:.8g} {cda_h:.8g}|{cda_h:.8g}|{cda_v:.8g}|0|0|0 {ca:.8g}\n"
                     + point_head + f"1 Body1 0 0 {CAGE_ATTACH_HEIGHT:.8g} 0 0 0 0")
    elif cage == "point":
        cage_rows = (point_head + f"1 Free {p0[0]:.8g} {p0[1]:.8g} {cg_z + CAGE_ATTACH_HEIGHT:.8g} "
                     f"{CAGE_MASS:.8g} {volume:.8g} {cda_v:.8g} {ca:.8g}")
    else:
        raise ValueError(f"cage must be 'body' or 'point', not {cage!r}")
    return f"""--------------------- MoorDyn Input File ------------------------------------
ROPOS tether and cage (tether_sim benchmarks/ropos_case.py), L = {length} m, {n_segments} segments
---------------------- LINE TYPES -----------------------------------------------------
TypeName  Diam  Mass/m  EA  BA/-zeta  EI  Cd  Ca  CdAx  CaAx
(name) (m) (kg/m) (N) (N-s/-) (N-m^2) (-) (-) (-) (-)
tether {lt['diam']:.8g} {lt['mass']:.8g} {lt['EA']:.8g} {lt['BA']:.8g} {ei:.8g} {lt['Cd']:.8g} {lt['Ca']:.8g} {lt['CdAx']:.8g} {lt['CaAx']:.8g}
{cage_rows}
2 Coupled {p0[0]:.8g} {p0[1]:.8g} {top_z:.8g} 0 0 0 0
---------------------- LINES ----------------------------------------------------------
ID LineType AttachA AttachB UnstrLen NumSegs LineOutputs
(#) (name) (ID) (ID) (m) (-) (-)
1 tether 1 2 {length:.8g} {int(n_segments)} -
{moordyn_options(dt, scheme, depth)}------------------------- need this line ----------------------------------------------
"""


def _rk_stable(z, scheme="RK2"):
    """|R(z)| <= 1 for the Runge-Kutta amplification R = sum z^k / k! to the scheme's order (RK2, RK4)."""
    order = {"RK2": 2, "RK4": 4}[scheme]
    term, r = 1.0, 1.0
    for k in range(1, order + 1):
        term = term * z / k
        r += term
    return abs(r) <= 1.0


def moordyn_stable_dt(length, n_segments, safety=0.9, EA=EA, zeta=ZETA, gamma0=GAMMA0, scheme="RK2"):
    """Largest stable RK2 (or ``scheme`` RK4) step (s) of MoorDyn's highest axial mode, times a safety factor.

    Neighbouring nodes moving in opposition: node mass gamma0 l, stiffness 4 EA / l, damping
    4 BA / l, so lambda solves gamma0 l lambda^2 + (4 BA / l) lambda + 4 EA / l = 0. Lightly
    damped (long segments) the limit is set by RK2's weak growth on the imaginary axis
    (y^3 < 8 zeta), heavily damped (short segments) by the real axis (|z| <= 2, dt ~ l^2).
    A slack segment keeps its damping but loses EA (bilinear law): lambda = -4 BA / (gamma0 l^2),
    the most negative real eigenvalue, so it is checked too. EA, zeta, gamma0: another line's
    (default: the ROPOS tether).
    """
    seg = length / n_segments
    m, c, k = gamma0 * seg, 4.0 * zeta / seg, 4.0 * EA / seg
    lam = list(np.roots([m, c, k])) + [-c / m]
    lo, hi = 0.0, 10.0 * seg / math.sqrt(EA / gamma0)
    for _ in range(60):  # bisection on the step; stability region is an interval along these rays
        mid = 0.5 * (lo + hi)
        if all(_rk_stable(mid * v, scheme) for v in lam):
            lo = mid
        else:
            hi = mid
    return safety * lo


def moordyn_time_step(length, n_segments, coupling_step):
    """Internal MoorDyn step dividing the coupling step exactly and below the stable step."""
    n_sub = math.ceil(coupling_step / moordyn_stable_dt(length, n_segments) - 1e-9)
    return coupling_step / max(n_sub, 1)
