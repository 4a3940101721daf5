"""A divergence forced through the solver interface, for the fault tests and the recovery-cost benchmark.

The next tick of one line gets one of its ends thrown 1e30 m away (finite, so it passes the end-motion
check) and its state blows up; the tick after that is the line's own again. What the network and the
node then do is what they would do after any line solver's divergence (docs/network.md, "Recovery
after a divergence")."""

import numpy as np

THROW = 1.0e30  # m added to every coordinate of the end's position for one tick


def throw_end_once(solver, end: str = "ship") -> None:
    """Make the next ``solver.tick`` put ``end`` ('ship', s = 0, or 'vehicle', s = L) THROW m away (once)."""
    tick = solver.tick

    def bad(t, ship=None, vehicle=None, drain=True):
        solver.tick = tick
        motion = {"ship": ship, "vehicle": vehicle}
        p, v = motion[end]
        motion[end] = (np.asarray(p, float) + THROW, v)
        return tick(t, drain=drain, **motion)
    solver.tick = bad
