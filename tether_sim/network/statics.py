"""Static equilibrium of a line network: the pose of every body such that the loads of its line
ends (each line an elastic catenary of ``physics/statics.py`` between its end positions), its wet
weight and nothing else balance in force and moment about its centre of gravity.

Unknowns per body: the CoG position and a rotation vector from upright (6). Newton with a
central-difference Jacobian and least-squares steps (a body whose line ends all lie on one
vertical through its CoG has no moment about that axis: the rank-deficient direction is left at
its start value), with a trust region (a bounded rotation and shift per iteration: Newton stays
on the branch of the start, never jumps to the upside-down equilibrium), until the residual is
below ``tol`` of the body's load scale; a body that ends more than 90 degrees from upright is an
error. A body that no line holds yet (every line slack, e.g. started with its tether exactly at
its unstretched length: the Jacobian is zero there) creeps along its net force until one does.
"""

from dataclasses import replace

import numpy as np

from tether_sim.network.spec import line_end_condition
from tether_sim.numerics.rotations import quaternion_matrix
from tether_sim.physics.statics import solve_static


def end_forces_of(shape, length):
    """(force by the line on its s = 0 end, force on its s = L end) of a static shape."""
    if hasattr(shape, "force_at"):
        T = shape.force_at(np.array([0.0, length]))
        return T[0], -T[1]
    # dynamic-relaxation shape (a current): tension along the end tangents
    t = shape.tangent(np.array([0.0, length]))
    u = t / np.linalg.norm(t, axis=1)[:, None]
    T = shape.tension(np.array([0.0, length]))
    return T[0] * u[0], -T[1] * u[1]


class NetworkStatics:
    """Evaluates line shapes and body residuals for given body states (``bodies``: name -> NetworkBody)."""

    def __init__(self, spec, bodies):
        self.spec, self.bodies = spec, bodies
        self._attach_index = {}
        for name, b in bodies.items():
            for k, e in enumerate(spec.ends_on(name)):
                self._attach_index[(e.line, e.end)] = (name, k)

    def end_position(self, end, states):
        if end.kind == "point":
            return np.asarray(self.spec.points[end.target].position, float)
        if end.kind == "body":
            name, k = self._attach_index[(end.line, end.end)]
            return self.bodies[name].attachment_points(states[name])[0][k]
        return None

    def line_config(self, line, states):
        """The line's SimConfig with its ends where the points and bodies are."""
        pos = [self.end_position(e, states) for e in line.ends]
        for i, p in enumerate(pos):
            if p is None:  # a free end: start below the other end (the static solve hangs it)
                other = pos[1 - i]
                pos[i] = other - np.array([0.0, 0.0, line.config.cable.length]) * (1 if i == 1 else -1)
        conds = [line_end_condition(e, self.spec, p) for e, p in zip(line.ends, pos)]
        return replace(line.config, ship_end=conds[0], vehicle_end=conds[1])

    def shapes(self, states):
        """{line: (config, static shape, (force on s = 0 end, force on s = L end))}."""
        out = {}
        for name, line in self.spec.lines.items():
            cfg = self.line_config(line, states)
            shape = solve_static(cfg)
            out[name] = (cfg, shape, end_forces_of(shape, cfg.cable.length))
        return out

    def residual(self, states):
        """Per body (6,): net force and moment about the CoG (N, N m), and the scale of its loads."""
        sh = self.shapes(states)
        res, scale = {}, {}
        for name, b in self.bodies.items():
            ends = self.spec.ends_on(name)
            forces = np.array([sh[e.line][2][e.row] for e in ends])
            F, M, fl, fw, _ = b.loads(forces, np.zeros_like(forces), state=states[name])
            res[name] = np.concatenate([F, M])
            lever = float(np.max(np.linalg.norm(b.attachments, axis=1))) or 1.0
            sc = float(np.sum(np.linalg.norm(forces, axis=1)) + abs(b.wet_weight))
            scale[name] = np.array([sc] * 3 + [sc * lever] * 3)
        return res, scale


def _state_of(body, x):
    s = body.state.copy()
    keep = body.state.copy()
    body.place(x[0:3], x[3:6])
    s[:] = body.state
    body.state[:] = keep
    return s


MAX_TURN = 0.1  # rad, largest rotation of a body in one Newton iteration
MAX_SHIFT = 5.0  # m, largest move of a body in one Newton iteration
SLACK_CREEP = 0.5  # m, move of a body along its net force while no line holds it (zero Jacobian)


def solve_network_statics(spec, bodies, tol=1e-12, max_iter=200):
    """Place every body at its static equilibrium (bodies at rest); returns the :class:`NetworkStatics`
    and the final relative residual. Raises RuntimeError when Newton does not converge."""
    st = NetworkStatics(spec, bodies)
    names = list(bodies)
    if not names:
        return st, 0.0
    x = np.concatenate([np.concatenate([bodies[n].state[0:3], np.zeros(3)]) for n in names])

    def states_of(x):
        return {n: _state_of(bodies[n], x[6 * i:6 * i + 6]) for i, n in enumerate(names)}

    def F(x):
        res, scale = st.residual(states_of(x))
        return np.concatenate([res[n] / scale[n] for n in names])

    f = F(x)
    for _ in range(max_iter):
        if np.max(np.abs(f)) < tol:
            break
        J = np.empty((f.size, x.size))
        for k in range(x.size):  # central differences: a one-sided one is 0 at a slack/taut kink
            d = 1e-6 if k % 6 < 3 else 1e-7
            e = np.zeros_like(x)
            e[k] = d
            J[:, k] = (F(x + e) - F(x - e)) / (2.0 * d)
        step = np.linalg.lstsq(J, f, rcond=1e-10)[0]
        creep = False
        for i in range(len(names)):  # no stiffness along the net force (lines slack): move along it
            fi = f[6 * i:6 * i + 3]
            nf = np.linalg.norm(fi)
            if nf > tol and np.linalg.norm(J[6 * i:6 * i + 3, 6 * i:6 * i + 3] @ (fi / nf)) < 1e-6:
                step[6 * i:6 * i + 3] = -SLACK_CREEP * fi / np.linalg.norm(fi)
                creep = True
        # trust region: at most MAX_TURN of rotation and MAX_SHIFT of translation per body and
        # iteration, so Newton walks to the hanging equilibrium nearest the start, never jumps to
        # an upside-down one (also an equilibrium of forces and moments, an unstable one)
        for i in range(len(names)):
            turn = np.linalg.norm(step[6 * i + 3:6 * i + 6]) / MAX_TURN
            shift = np.linalg.norm(step[6 * i:6 * i + 3]) / MAX_SHIFT
            if max(turn, shift) > 1.0:
                step = step / max(turn, shift)
        alpha, fn = 1.0, f
        while alpha > 1e-4 and not creep:
            try:
                xn = x - alpha * step
                fn = F(xn)
                if np.linalg.norm(fn) < np.linalg.norm(f):
                    break
            except RuntimeError:
                pass
            alpha *= 0.5
        if creep:
            xn = x - step
            fn = F(xn)
        x, f = xn, fn
    err = float(np.max(np.abs(f)))
    if not err < max(tol, 1e-9):
        raise RuntimeError(f"network statics: Newton did not converge (relative residual {err:.3g})")
    for n, s in states_of(x).items():
        bodies[n].state[:] = s
        if quaternion_matrix(s[3:7])[2, 2] < 0.0:
            raise RuntimeError(f"network statics: body {n} ends upside down (an unstable equilibrium); "
                               "check its attachments and initial_position")
    return st, err
