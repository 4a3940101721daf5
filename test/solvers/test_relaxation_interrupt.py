"""A long initial relaxation (initial.relax_time up to its documented 1e5 s) runs in compiled calls
of about RELAX_CHUNK_WALL s each, so Ctrl-C stops it (before: one compiled call of ~300 CPU s that
no signal could interrupt), and the chunks leave the result bit-identical to one call."""

import os
import signal
import threading
import time

import numpy as np
import pytest

import tether_sim.solvers.dg.solver as dg_solver
from tether_sim.io.params import from_flat
from tether_sim.solvers.factory import build_solver
from tether_sim.stopping import SignalStop

# 55 m DG tether between a point and a fixed anchor (as test/ros/test_faults.py), relaxed from straight
FLAT = {"cable.length": 55.0, "cable.EA": 1.0e6, "cable.damping": 1.0e3,
        "ship_end.kind": "prescribed", "ship_end.position": (0.0, 0.0, 0.0),
        "vehicle_end.kind": "fixed", "vehicle_end.position": (30.0, 0.0, -40.0),
        "dg.n_elements": 6, "dg.order": 3, "initial.kind": "relax"}


def relaxed(monkeypatch, first, wall, **extra):
    monkeypatch.setattr(dg_solver, "RELAX_FIRST_CHUNK", first)
    monkeypatch.setattr(dg_solver, "RELAX_CHUNK_WALL", wall)
    return build_solver(from_flat({**FLAT, **extra}))


def test_the_relaxation_in_chunks_is_bit_identical_to_one_call(monkeypatch):
    for first, wall in ((1, 1e-9), (7, 1e-4), (dg_solver.RELAX_FIRST_CHUNK, dg_solver.RELAX_CHUNK_WALL)):
        one = relaxed(monkeypatch, 10**12, 1e9)  # a single compiled call, as before
        chunked = relaxed(monkeypatch, first, wall)
        assert chunked.time == one.time == 0.0
        for a, b in ((one.ws.U, chunked.ws.U), (one.ws.ra, chunked.ws.ra), (one.ws.bs, chunked.ws.bs)):
            assert np.array_equal(a, b)
        for solver in (one, chunked):  # and what follows the start
            solver.set_end_motion("ship", (0.0, 0.0, 0.1), (0.0, 0.0, 0.5))
            solver.advance_to(0.2)
        assert np.array_equal(one.state().tension, chunked.state().tension)


def test_ctrl_c_stops_a_long_relaxation_within_about_a_chunk(monkeypatch):
    """initial.relax_time 1000 s (1.5e6 substeps, ~70 s of CPU here): SIGINT half a second into the
    relaxation raises KeyboardInterrupt (what the programs turn into their one-line account) at the
    end of the running chunk, not at the end of the relaxation."""
    sent, timer = {}, None
    run = dg_solver.DGCableSolver._run

    def interrupt():
        sent["at"] = time.monotonic()
        os.kill(os.getpid(), signal.SIGINT)

    def run_and_arm(self, *args):  # the signal comes once the relaxation runs
        nonlocal timer
        if timer is None:
            timer = threading.Timer(0.5, interrupt)
            timer.start()
        return run(self, *args)

    monkeypatch.setattr(dg_solver.DGCableSolver, "_run", run_and_arm)
    with SignalStop("test"):
        try:
            with pytest.raises(KeyboardInterrupt, match="SIGINT"):
                build_solver(from_flat({**FLAT, "initial.relax_time": 1000.0}))
        finally:
            timer.cancel()
    # (generous for a loaded machine: in one compiled call the signal waited for the whole relaxation)
    assert time.monotonic() - sent["at"] < 10.0
