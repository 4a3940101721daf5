"""One case of benchmarks/studies/slack_bending_ladder.py through the tether-sim-offline code path, recording
what its end snap detector is fed (every substep's end tensions, the relative end speed of every tick) and the
solver's state at chosen times, so that the detector can be replayed and the solver probed from a checkpoint
without running the case again (docs/dg_solver.md, "Slack with bending").

    PYTHONPATH=. python benchmarks/probes/slack_record.py OUT.npz [--save-at 7.5 ...]
    env: LL (200), FF (0.2), AL (alpha, 100), NN (N, 40), PERIODS (1.9), EXTRA (a dict of further overrides)
    --ladder DIR: also append the run's rows to a slack_bending_ladder.py output folder (its tables read them)

OUT.npz holds ``times`` (k,), ``tensions`` (k, 2: ship, cage), ``chunk`` (k,: the detector call each sample was
fed in), ``speed`` (one per call), ``static`` (2,) and the run's events as text; the states go to
OUT_<t>.pkl (``Solver.snapshot()``, restored by benchmarks/probes/slack_fold_probe.py with TAG/SNAP).
``replay(OUT.npz, config)`` feeds the recorded samples to a fresh detector of the current code.
"""
import argparse
import ast
import os
import pickle
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))


def case_key():
    """(L, f, alpha, N, periods) of the case the environment names."""
    return (float(os.environ.get("LL", 200)), float(os.environ.get("FF", 0.2)), float(os.environ.get("AL", 100)),
            int(os.environ.get("NN", 40)), float(os.environ.get("PERIODS", 1.9)))


def case():
    from benchmarks.studies.slack_bending_ladder import case_config

    return case_config(*case_key(), ast.literal_eval(os.environ.get("EXTRA", "{}")))


def replay(path, config=None, guard_element=None, t_end=None):
    """The events of a fresh end detector (the current code) fed the recorded samples of ``path`` as the run fed
    them (same calls, same speeds); with ``t_end`` only the calls whose samples all lie at or before it (a run
    recorded longer, cut to the ticks of a shorter one: the explicit solver's samples up to there are the same)."""
    from tether_sim.physics.snap import SnapDetector, snap_guard

    config = config or case()
    d = np.load(path)
    times, tensions, chunk, speeds = d["times"], d["tensions"], d["chunk"], d["speed"]  # each read once
    h = guard_element or config.cable.length / config.dg.n_elements
    det = SnapDetector(config.snap, ["ship", "vehicle"], list(d["static"]), [0.0, config.cable.length],
                       snap_guard(config, h))
    out = []
    bounds = np.searchsorted(chunk, np.arange(len(speeds) + 1))  # the samples are stored call by call
    for k, speed in enumerate(speeds):
        a, b = bounds[k], bounds[k + 1]
        if t_end is not None and b > a and times[a:b].max() > t_end + 1e-9:
            break
        if b > a:
            out += det.update(times[a:b], tensions[a:b], speed)
    return out + det.flush()


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("out", type=Path)
    ap.add_argument("--save-at", type=float, nargs="*", default=[])
    ap.add_argument("--ladder", type=Path, help="also append the run's rows to this slack_bending_ladder.py output folder")
    args = ap.parse_args()
    from tether_sim.physics import snap
    from tether_sim.ros import driver as drv
    from tether_sim.ros.offline import run_offline

    config = case()
    rec = {"times": [], "tensions": [], "chunk": [], "speed": [], "static": None}
    update = snap.SnapDetector.update

    def recording_update(self, times, tensions, relative_speed=None):
        if self.locations == ["ship", "vehicle"]:
            rec["static"] = self.static_tensions.copy()
            k = len(rec["speed"])
            speed = relative_speed() if callable(relative_speed) else relative_speed  # (the driver passes a function)
            rec["speed"].append(np.nan if speed is None else float(speed))
            rec["times"].append(np.array(times, float).reshape(-1))
            rec["tensions"].append(np.array(tensions, float).reshape(-1, 2))
            rec["chunk"].append(np.full(len(rec["times"][-1]), k))
        return update(self, times, tensions, relative_speed)

    pending = sorted(args.save_at)
    tick = drv.SimulationDriver.tick
    cpu0 = time.process_time()

    def saving_tick(self, now):
        report = tick(self, now)
        while pending and self.solver.time >= pending[0] - 1e-9:
            t = pending.pop(0)
            path = args.out.with_name(f"{args.out.stem}_{t:g}.pkl")
            with open(path, "wb") as fh:
                pickle.dump(self.solver.snapshot(), fh)
            print(f"state at {self.solver.time:.4f} s -> {path} (cpu {time.process_time() - cpu0:.0f} s)", flush=True)
        return report

    snap.SnapDetector.update = recording_update
    drv.SimulationDriver.tick = saving_tick
    summary = run_offline(config, None, progress=False)
    cpu = time.process_time() - cpu0
    args.out.parent.mkdir(parents=True, exist_ok=True)
    np.savez(args.out, times=np.concatenate(rec["times"]), tensions=np.concatenate(rec["tensions"]),
             chunk=np.concatenate(rec["chunk"]), speed=np.array(rec["speed"]), static=rec["static"],
             events=np.array([repr(e) for e in summary["events"]]), cpu=cpu, load=os.getloadavg()[0],
             divergences=int(summary["divergences"]), duration=float(summary["duration"]))
    if args.ladder:
        from benchmarks.studies.slack_bending_ladder import append_case, case_rows

        append_case(args.ladder, *case_rows(*case_key(), summary, cpu))
    for e in summary["events"]:
        if type(e).__name__ != "SlackStarted":
            print(e)
    print(f"cpu {cpu:.0f} s, divergences {summary['divergences']}, load {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
