"""NetworkSolver: several lines, each its own solver of the one interface (dg or hybrid), joined at
points and rigid bodies; the coupling of docs/network.md.

Coupling (one coupling step dt from t_n to t_n+1, every body at once):

1. half kick: each body's velocities by dt/2 with its loads at t_n (line end loads F_n, wet
   weight, drag);
2. drift: positions by dt with the half-step velocities, orientations by the exact rotation;
3. each line advanced to t_n+1 by its own ``tick``: an end on a body is a ``prescribed`` end whose
   target is the attachment point's position at t_n+1 and its velocity predicted with F_n (the
   line's cubic Hermite end motion moves it there); an end on a driven point follows the point's
   targets, Hermite-interpolated over the tick;
4. half kick: each body's velocities by dt/2 with the new line end loads F_n+1 (drag and the
   gyroscopic moment at the end velocities of a trial kick: with the half-step velocities they
   would make the scheme first order).

The body thus receives the impulse dt (F_n + F_n+1) / 2 from each line, the trapezoidal rule of
the line's end force: velocity Verlet, second order, symplectic for the elastic part; the body's
momentum balance holds to round-off by construction and is checked (test/network). The explicit
kicks are stable while dt * Z / M < 2 for the stiffest line (Z = sqrt(max dT/deps * gamma0), the
axial impedance with which a kinematic end's force answers its velocity) and the spring part
dt * sqrt(k / M) < 2 (k = max dT/deps / L); :func:`max_coupling_step` takes half of the smaller
bound over every body and axis (rotations with I and Z r^2, k r^2).

A body whose state turns non-finite (its lines' loads blew up) raises
:class:`~tether_sim.errors.SolverDivergedError` before any line is given its motion, as a line
solver diverging does; ``snapshot()`` / ``restore()`` keep and put back the whole network (every
line's state with its winch, every body, every point's motion, the end loads): the node's
recovery after a divergence (tether_sim/ros/recovery.py).
"""

import math

import numpy as np

from tether_sim.errors import ConfigError, SolverDivergedError
from tether_sim.network.body import NetworkBody
from tether_sim.network.body_kernels import (BP_DRAG, BP_INERTIA, BP_MASS, BP_ROT_DAMPING, BP_WET, N_BP, body_loads,
                                            body_accelerations, kdk_close, kdk_open)
from tether_sim.network.spec import line_end_condition
from tether_sim.network.statics import solve_network_statics
from tether_sim.physics.boundary import END_NAMES
from tether_sim.physics.constitutive import TensionLaw
from tether_sim.physics.hydrodynamics import current_at, current_table
from tether_sim.solvers.base import LOAD_F, LOAD_M, LOAD_T
from tether_sim.solvers.factory import build_solver
from tether_sim.solvers.winch_link import WinchLink


def _hermite(p0, v0, p1, v1, T, tau):
    """Cubic Hermite position and velocity at tau in [0, T] from (p0, v0) to (p1, v1)."""
    if T <= 0.0:
        return p1.copy(), v1.copy()
    x = tau / T
    h00, h10, h01, h11 = 2 * x**3 - 3 * x**2 + 1, x**3 - 2 * x**2 + x, -2 * x**3 + 3 * x**2, x**3 - x**2
    d00, d10, d01, d11 = (6 * x**2 - 6 * x) / T, 3 * x**2 - 4 * x + 1, (-6 * x**2 + 6 * x) / T, 3 * x**2 - 2 * x
    a, b = h10 * T, h11 * T  # on plain floats, in numpy's order of the vector expressions (the same bits)
    p, v = [], []
    for q0, w0, q1, w1 in zip(p0.tolist(), v0.tolist(), p1.tolist(), v1.tolist()):
        p.append(h00 * q0 + a * w0 + h01 * q1 + b * w1)
        v.append(d00 * q0 + d10 * w0 + d01 * q1 + d11 * w1)
    return np.array(p), np.array(v)


class _Point:
    """A fixed or driven point: its state and, for a driven one, the target of the next tick."""

    def __init__(self, spec):
        self.spec = spec
        self.pos = np.asarray(spec.position, float).copy()
        self.vel = np.zeros(3)
        self.p0, self.v0 = self.pos.copy(), self.vel.copy()
        self.p1, self.v1 = self.pos.copy(), self.vel.copy()
        self.t0 = self.t1 = 0.0


def max_coupling_step(spec, bodies, safety=0.5):
    """The stability bound of the explicit kicks (module docstring), s."""
    best = math.inf
    for name, b in bodies.items():
        m_min = float(np.min(b.mass + b.added_mass))
        i_min = float(np.min(b.inertia))
        Z = K = Zr = Kr = 0.0
        for e, att in zip(spec.ends_on(name), b.attachments):
            cab = spec.lines[e.line].config.cable
            slope = TensionLaw(cab).max_slope()
            z, k = math.sqrt(slope * cab.gamma0), slope / cab.length
            r2 = float(att @ att)
            Z, K, Zr, Kr = Z + z, K + k, Zr + z * r2, Kr + k * r2
        bounds = [2.0 * m_min / Z if Z > 0 else math.inf, 2.0 * math.sqrt(m_min / K) if K > 0 else math.inf,
                  2.0 * i_min / Zr if Zr > 0 else math.inf, 2.0 * math.sqrt(i_min / Kr) if Kr > 0 else math.inf]
        best = min(best, *bounds)
    return safety * best


class NetworkSolver:
    """Lines, points and bodies of a :class:`tether_sim.network.spec.NetworkSpec`, stepped together.

    ``set_point_motion(point, position, velocity)`` gives a driven point's target at the next
    ``tick(t)``; ``tick`` advances everything to t in coupling steps and returns per line the
    drained end-tension samples and the end loads. ``line(name)`` is a line's own solver.
    """

    name = "network"

    def __init__(self, spec, statics=True, winches=None):
        """``winches``: {line: WinchLink} to carry on (a rebuild: each winch keeps its length, command
        and clock; the spec's line lengths should then be the winches' lengths), else new ones."""
        self.spec = spec
        self.env = spec.environment
        self.points = {n: _Point(p) for n, p in spec.points.items()}
        self.bodies = {n: NetworkBody(n, b.props, self.env, [e.attachment for e in spec.ends_on(n)])
                       for n, b in spec.bodies.items()}
        self._where = {}  # (line, end) -> (body, index of its attachment)
        for n in self.bodies:
            for k, e in enumerate(spec.ends_on(n)):
                self._where[(e.line, e.end)] = (n, k)
        # per line, its ends that move: (end, body, attachment index, None) or (end, None, 0, driven point)
        self._moving_ends = {name: [(e.end, *self._where[(name, e.end)], None) if e.kind == "body" else
                                    (e.end, None, 0, self.points[e.target]) for e in line.ends
                                    if e.kind == "body" or (e.kind == "point" and self.points[e.target].spec.kind == "prescribed")]
                             for name, line in spec.lines.items()}
        self.statics_residual = None
        if statics and self.bodies:
            self._statics, self.statics_residual = solve_network_statics(spec, self.bodies)
        else:
            from tether_sim.network.statics import NetworkStatics
            self._statics = NetworkStatics(spec, self.bodies)
        states = {n: b.state.copy() for n, b in self.bodies.items()}
        self.lines = {}
        self.winches = {}  # line -> WinchLink (winch.enabled in the line's keys)
        for name, line in spec.lines.items():
            cfg = self._statics.line_config(line, states)
            try:
                if cfg.winch.enabled:
                    link = (winches or {}).get(name) or WinchLink(cfg)
                    self.lines[name] = link.build(build_solver, cfg)
                    self.winches[name] = link
                else:
                    self.lines[name] = build_solver(cfg)
            except (ValueError, RuntimeError) as exc:
                raise ConfigError(f"network.lines.{name}: {exc}") from exc
        self.time = 0.0
        self.coupling_limit = max_coupling_step(spec, self.bodies) if self.bodies else math.inf
        # every line's end loads in one array (the compiled body step reads its rows); _loads[line] is a view
        self._load_table = np.zeros((len(self.lines), 2, 7))
        self._loads = {n: self._load_table[i] for i, n in enumerate(self.lines)}
        for n, s in self.lines.items():
            out = s.tick(0.0, drain=True)
            self._loads[n][:] = out.loads[:, :7]
        self._current = current_table(self.env)
        self._kernel = {n: self._body_arrays(n, b) for n, b in self.bodies.items()}
        self._motion_scratch = np.zeros((2, 13))  # body_motion's loads and accelerations
        self.samples = {n: [] for n in self.lines}
        self.coupling_steps = 0

    # ------------------------------------------------------------------ inputs
    def set_point_motion(self, point, position, velocity):
        """Target of a driven point at the next tick's time (position, velocity, world)."""
        try:
            p = self.points[point]
        except KeyError:
            raise ValueError(f"unknown point {point!r}; points: {', '.join(self.points)}") from None
        if p.spec.kind != "prescribed":
            raise ValueError(f"point {point!r} is {p.spec.kind}, not prescribed")
        p.p1, p.v1 = np.asarray(position, float).copy(), np.asarray(velocity, float).copy()
        p._set = True

    def line(self, name):
        return self.lines[name]

    def command_winch(self, line, mode, setpoint, source="topic"):
        """Queue a winch command (physics/winch.py modes) for the next tick of ``line``'s winch;
        returns the reason it is refused, or None."""
        if line not in self.winches:
            raise ValueError(f"line {line!r} has no winch; winches: {', '.join(self.winches) or 'none'}")
        return self.winches[line].request(mode, setpoint, source)

    def winch_state(self, line):
        """The :class:`tether_sim.physics.winch.WinchState` of ``line``'s winch."""
        return self.winches[line].winch.state()

    # ------------------------------------------------------------------ loads
    def _body_loads(self, name):
        rows = self.load_rows(name)
        F = np.array([r[LOAD_F:LOAD_F + 3] for r in rows]).reshape(-1, 3)
        M = np.array([r[LOAD_M:LOAD_M + 3] for r in rows]).reshape(-1, 3)
        return F, M

    def load_rows(self, name):
        """The load row (plain floats, columns LOAD_*) of every line end on point or body ``name``,
        in the order of spec.end_rows(name): what the outputs sum, without numpy on 3-vectors."""
        return [self._loads[line][row].tolist() for line, row in self.spec.end_rows(name)]

    def _fluid_velocity(self, body):
        cz, cx, cy = self._current
        out = np.zeros(3)
        if cz.size:
            current_at(body.state[2], cz, cx, cy, out)
        return out

    def _body_arrays(self, name, b):
        """The arrays of the compiled coupling step of body ``name`` (network/body_kernels.py):
        (parameters, (line, end) rows of its attachments in the load table, work, targets)."""
        prm = np.zeros(N_BP)
        prm[BP_MASS:BP_MASS + 3] = b.mass + b.added_mass
        prm[BP_INERTIA:BP_INERTIA + 3] = b.inertia
        prm[BP_ROT_DAMPING:BP_ROT_DAMPING + 3] = b.rot_damping
        prm[BP_DRAG:BP_DRAG + 3] = b.drag
        prm[BP_WET] = b.wet_weight
        index = {n: i for i, n in enumerate(self.lines)}
        rows = np.array([[index[line], row] for line, row in self.spec.end_rows(name)], dtype=np.int64).reshape(-1, 2)
        return prm, rows, np.zeros((3, 13)), np.zeros((len(rows), 6))

    # ------------------------------------------------------------------ stepping
    def tick(self, t, drain=True):
        """Advance to t (coupling steps of at most min(coupling_step, stability bound)); returns
        {line: TickOutput-like dict with 'samples' (3, k) and 'loads' (2, 7)}."""
        T = t - self.time
        if T < 0:
            raise ValueError(f"tick: time {t} is before the network time {self.time}")
        for p in self.points.values():
            if p.spec.kind == "prescribed":
                p.p0, p.v0, p.t0, p.t1 = p.pos.copy(), p.vel.copy(), self.time, t
                if not getattr(p, "_set", False):  # no new target: constant-velocity extrapolation
                    p.p1, p.v1 = p.pos + T * p.vel, p.vel.copy()
                p._set = False
        h = min(self.spec.coupling_step, self.coupling_limit)
        n = max(1, math.ceil(T / h - 1e-9)) if T > 0 else 0
        chunks = {k: [] for k in self.lines}
        t0 = self.time
        for i in range(n):
            tn = t0 + T * (i + 1) / n if i < n - 1 else t
            self._coupling_step(tn - self.time, tn, chunks)
        self.time = t
        out = {}
        for k in self.lines:
            c = chunks[k]  # (one chunk, a copy made for it, is the tick's samples as it is)
            s = c[0] if len(c) == 1 else np.concatenate(c, axis=1) if c else np.zeros((3, 0))
            if drain:
                out[k] = {"samples": s, "loads": self._loads[k].copy()}
            else:
                self.samples[k].append(s)
                out[k] = {"samples": np.zeros((3, 0)), "loads": self._loads[k].copy()}
        return out

    def _coupling_step(self, dt, t_new, chunks):
        fluid = {n: self._fluid_velocity(b) for n, b in self.bodies.items()}
        targets = {}
        loads = self._load_table
        for n, b in self.bodies.items():  # half kick, drift, end targets (NetworkBody.kick, drift, ...)
            prm, rows, work, tg = self._kernel[n]
            kdk_open(b.state, b.attachments, loads, rows, prm, fluid[n], dt, b.impulse_table, work, tg)
            if not math.isfinite(float(tg.sum())):  # (a NaN or inf anywhere makes the sum non-finite)
                raise SolverDivergedError(f"network body {n}: non-finite state at t = {t_new:.6g} s")
            targets[n] = tg
        for p in self.points.values():
            if p.spec.kind == "prescribed":
                p.pos, p.vel = _hermite(p.p0, p.v0, p.p1, p.v1, p.t1 - p.t0, t_new - p.t0)
        for name, solver in self.lines.items():
            motion = {}
            for end, body, k, p in self._moving_ends[name]:
                motion[end] = (targets[body][k, 0:3], targets[body][k, 3:6]) if body is not None else (p.pos, p.vel)
            try:
                out = solver.tick(t_new, ship=motion.get("ship"), vehicle=motion.get("vehicle"), drain=True)
            except SolverDivergedError as exc:  # (named: the node's log and diagnostics say which line)
                raise SolverDivergedError(f"network line {name}: {exc}") from exc
            self._loads[name][:] = out.loads[:, :7]
            if out.count:
                chunks[name].append(np.array(out.samples[:, :out.count]))
        for n, b in self.bodies.items():  # closing half kick with the new line loads
            prm, rows, work, tg = self._kernel[n]
            kdk_close(b.state, b.attachments, loads, rows, prm, fluid[n], dt, b.impulse_table, work)
        self.time = t_new
        self.coupling_steps += 1

    # ------------------------------------------------------------------ outputs
    def end_load(self, line, end):
        """(force (3,), axial tension, moment (3,)) by the line on its end 'ship' or 'vehicle'."""
        row = self._loads[line][END_NAMES.index(end)]
        return row[LOAD_F:LOAD_F + 3].copy(), float(row[LOAD_T]), row[LOAD_M:LOAD_M + 3].copy()

    def body_motion(self, name) -> dict:
        """Body ``name`` now, world frame, as plain float lists: ``velocity`` / ``omega`` (its
        state), ``acceleration`` / ``angular_acceleration`` under its present loads (the line ends'
        loads of the last coupling step, wet weight, drag; the coupling step's own compiled loads and
        accelerations, network/body_kernels.py), ``drag`` (the quadratic drag force at the centre of
        gravity, relative to the current) and ``damping_moment`` (the rotational damping moment)."""
        b = self.bodies[name]
        prm, rows, _, _ = self._kernel[name]
        scratch = self._motion_scratch
        lo, acc = scratch[0], scratch[1]
        body_loads(b.state, b.attachments, self._load_table, rows, prm, self._fluid_velocity(b), lo)
        body_accelerations(b.state, prm, lo, acc)
        s = b.state.tolist()
        R = b.rotation
        wb = R.T @ b.state[10:13]
        return {"velocity": s[7:10], "omega": s[10:13], "acceleration": acc[0:3].tolist(),
                "angular_acceleration": acc[3:6].tolist(), "drag": lo[9:12].tolist(),
                "damping_moment": (R @ (-prm[BP_ROT_DAMPING:BP_ROT_DAMPING + 3] * wb)).tolist()}

    def end_tensions(self, line):
        """(axial tension at s = 0, at s = L) of ``line`` as floats (end_load's tension, without its copies)."""
        ends = self._loads[line]
        return float(ends[0, LOAD_T]), float(ends[1, LOAD_T])

    def snapshot(self):
        return dict(time=self.time, lines={n: s.snapshot() for n, s in self.lines.items()},
                    bodies={n: (b.state.copy(), {k: v.copy() for k, v in b.impulse.items()}) for n, b in self.bodies.items()},
                    points={n: (p.pos.copy(), p.vel.copy()) for n, p in self.points.items()},
                    loads={n: v.copy() for n, v in self._loads.items()})

    def restore(self, snap):
        self.time = snap["time"]
        for n, s in snap["lines"].items():
            self.lines[n].restore(s)
        for n, (st, imp) in snap["bodies"].items():
            self.bodies[n].state[:] = st
            for k, v in imp.items():
                self.bodies[n].impulse[k][:] = v
        for n, (pp, pv) in snap["points"].items():
            self.points[n].pos[:], self.points[n].vel[:] = pp, pv
        for n, v in snap["loads"].items():
            self._loads[n][:] = v
