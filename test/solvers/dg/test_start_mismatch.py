"""The DG solver says when its mesh cannot hold the static shape it starts from (start_warning), and
stays silent when it can. The kinked case that prompted it, a light tether in a current whose slack
streams past the vehicle and doubles back (config/rov_demo.yaml with the vehicle down-current, N = 8,
P = 3), projects to 1504 N where the static shape has 0.55 N (measured 2026-11-27, ~90 s to build: not
run here). Here the check itself: a smooth catenary on 10 elements gives no sentence; the same state
against a reference shape with half its tension gives one, naming the mesh and both tensions."""

import numpy as np
import pytest

from tether_sim.scenarios import harness
from test_catenary_statics import catenary_flat


class HalfTension:
    """A stand-in static shape: the solver's own tension halved (as if the mesh doubled it)."""

    def __init__(self, solver):
        self.solver = solver

    def tension(self, s):
        return 0.5 * self.solver.state(np.asarray(s)).tension


def test_a_mesh_that_holds_the_static_shape_says_nothing_and_one_that_doubles_it_says_so():
    _config, solver = harness.make_solver(catenary_flat((80.0, 0.0, -30.0)))
    assert solver.start_warning == ""
    said = solver._start_mismatch(HalfTension(solver))
    assert said.startswith("the mesh (N = 10, P = 4) cannot hold the static shape") and "refine dg.n_elements" in said
    T = solver.state(np.linspace(0.0, 100.0, 11)).tension
    assert f"{T.max():.4g} N" in said
