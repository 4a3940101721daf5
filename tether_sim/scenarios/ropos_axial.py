"""A 1-D (vertical) lumped-mass model of the ROPOS tether and cage, for cross-checking the DG runs.

This is the kind of model Driscoll et al. calibrated (PE2020 Sec. 6: "a one-dimensional (vertical
motion only) lumped mass model"): n axial springs-dashpots T = max(0, EA eps + zeta deps/dt)
[PE2020 Eq. 22, no compression], node masses gamma0 ds, submerged weight, tangential drag
0.5 rho_f Cdt pi d |v| v [PE2020 Eq. 17], and the cage (m + m_a, submerged weight, heave drag
0.5 rho_f Cd A_lid |v| v) at the bottom node. The ship node follows the vertical component of the
fairlead motion. Semi-implicit Euler with a step inside both the wave and the damping limits.
It has no transverse dynamics and no bending, so it cannot show the alpha effect; it gives an
independent value of the static tensions, the slack/snap pattern and the snap magnitudes.
"""

import numpy as np

from tether_sim.numerics.jit import jit_alloc
from tether_sim.physics.bodies import submerged_weight
from tether_sim.physics.boundary import END_NAMES
from tether_sim.physics.motion import build_motion
from tether_sim.physics.snap import SnapDetector


@jit_alloc
def axial_run(z, v, ship_z, ship_v, n_sub, dt, ds, EA, zeta, node_mass, cage_mass, w_node, w_cage,
              drag_node, drag_cage, out_ship, out_cage, out_acc):
    """Advance n_sub substeps per output interval; ship motion linear within each interval.

    z, v: (n+1,) node heights/velocities (node 0 = ship). ship_z, ship_v: (k+1,) ship heave at the
    output times. Writes the substep tensions of the top and bottom element into out_ship/out_cage
    ((k * n_sub,)) and the cage acceleration at every output time into out_acc ((k,)).
    """
    n = z.size - 1
    tension = np.zeros(n)
    acc = np.zeros(n + 1)
    j = 0
    for k in range(ship_z.size - 1):
        for m in range(n_sub):
            frac = (m + 1.0) / n_sub
            z[0] = ship_z[k] + frac * (ship_z[k + 1] - ship_z[k])
            v[0] = ship_v[k] + frac * (ship_v[k + 1] - ship_v[k])
            for e in range(n):
                eps = (z[e] - z[e + 1]) / ds - 1.0
                t = EA * eps + zeta * (v[e] - v[e + 1]) / ds
                tension[e] = t if (eps > 0.0 and t > 0.0) else 0.0
            for i in range(1, n + 1):
                below = tension[i] if i < n else 0.0
                f = tension[i - 1] - below
                if i < n:
                    acc[i] = (f - w_node - drag_node * abs(v[i]) * v[i]) / node_mass
                else:
                    f -= w_cage + 0.5 * w_node + (drag_cage + 0.5 * drag_node) * abs(v[i]) * v[i]
                    acc[i] = f / (cage_mass + 0.5 * node_mass)
            for i in range(1, n + 1):
                v[i] += dt * acc[i]
                z[i] += dt * v[i]
            out_ship[j] = tension[0]
            out_cage[j] = tension[n - 1]
            j += 1
        out_acc[k] = acc[n]


def run_axial(config, n_elements=50, output_rate=100.0, t_end=None):
    """Run the 1-D model for ``config`` (a ROPOS SimConfig); returns a dict of series and events."""
    cable, env, body = config.cable, config.environment, config.body
    L, n = cable.length, int(n_elements)
    ds = L / n
    rho_f, g = env.fluid_density, env.g
    w_node = cable.gamma0 * g * (1.0 - rho_f / cable.density) * ds
    w_cage = submerged_weight(body, env)
    drag_node = 0.5 * rho_f * cable.Cdt * np.pi * cable.diameter * ds
    drag_cage = 0.5 * rho_f * body.drag_coefficients[2] * body.drag_areas[2]
    node_mass = cable.gamma0 * ds
    cage_mass = body.mass + body.added_mass[2]
    # Static shape: T(s) = W_cage + w (L - s), eps = T / EA.
    s = np.linspace(0.0, L, n + 1)
    s_mid = 0.5 * (s[1:] + s[:-1])
    eps = (w_cage + w_node / ds * (L - s_mid)) / cable.EA
    z = np.r_[0.0, -np.cumsum(ds * (1.0 + eps))] + config.ship_end.position[2]
    v = np.zeros(n + 1)
    dt_max = 0.5 * min(ds / cable.wave_speed, node_mass * ds / (2.0 * max(cable.damping, 1e-12)))
    n_sub = max(1, int(np.ceil(1.0 / (output_rate * dt_max))))
    dt = 1.0 / (output_rate * n_sub)
    t_end = config.duration if t_end is None else t_end
    t_out = np.arange(0, int(round(t_end * output_rate)) + 1) / output_rate
    motion = build_motion(config.motion, config.ship_end.position)
    kin = [motion.at(t) for t in t_out]
    ship_z = np.array([p[0][2] for p in kin])
    ship_v = np.array([p[1][2] for p in kin])
    k = t_out.size - 1
    out_ship, out_cage, out_acc = np.zeros(k * n_sub), np.zeros(k * n_sub), np.zeros(k)
    axial_run(z, v, ship_z, ship_v, n_sub, dt, ds, cable.EA, cable.damping, node_mass, cage_mass, w_node, w_cage,
              drag_node, drag_cage, out_ship, out_cage, out_acc)
    t = dt * np.arange(1, k * n_sub + 1)
    static = (w_cage + w_node * (n - 0.5), w_cage + 0.5 * w_node)  # mid-element tensions of the end elements
    detector = SnapDetector(config.snap, list(END_NAMES), list(static), [0.5 * ds, L - 0.5 * ds])
    events = detector.update(t, np.c_[out_ship, out_cage]) + detector.flush()
    return {"t": t, "ship_tension": out_ship, "vehicle_tension": out_cage, "t_out": t_out[1:],
            "cage_acceleration": out_acc, "static": static, "events": events, "dt": dt}
